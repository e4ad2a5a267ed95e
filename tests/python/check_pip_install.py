#!/usr/bin/python3
"""`pip install .` as docs/python.md says, on Debian and without a download: a venv made with
--system-site-packages (Debian's NumPy), pip with --no-build-isolation (Debian's setuptools),
building through the configured build folder (CDPOWDER_BUILD_DIR, setup.py); then
`import cdpowder` from the venv in a clean environment.
    check_pip_install.py SOURCE_DIR BUILD_DIR"""
import os
import pathlib
import subprocess
import sys
import tempfile

source, build = (pathlib.Path(a).resolve() for a in sys.argv[1:3])
with tempfile.TemporaryDirectory() as scratch:
    venv = pathlib.Path(scratch) / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)],
                   check=True)
    environment = {**os.environ, "CDPOWDER_BUILD_DIR": str(build), "PIP_NO_INDEX": "1"}
    environment.pop("PYTHONPATH", None)
    pip = subprocess.run([str(venv / "bin/pip"), "install", "--no-build-isolation", str(source)],
                         env=environment, capture_output=True, text=True, cwd=scratch)
    if pip.returncode != 0:
        sys.exit(f"pip install failed:\n{pip.stdout}{pip.stderr}")
    clean = {"HOME": scratch, "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}
    done = subprocess.run([str(venv / "bin/python"), "-c",
                           "import cdpowder, cdpowder.tables; print(cdpowder.__file__); "
                           "print(len(cdpowder.Scene.from_keys({'deposition.spheres': 5}).toml))"],
                          env=clean, capture_output=True, text=True, cwd=scratch)
    if done.returncode != 0 or str(venv) not in done.stdout:
        sys.exit(f"import cdpowder from the venv failed:\n{done.stdout}{done.stderr}")
    print("pip installed and imported from", done.stdout.split()[0])
