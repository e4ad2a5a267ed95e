#!/usr/bin/python3
"""`cmake --install` puts the package where the prefix's Python finds it: installed into a
fresh ~/.local (HOME a temporary folder), `import cdpowder` works in a clean environment, with
the engine and the pure-Python modules, and runs a short deposit.
    check_install.py BUILD_DIR"""
import pathlib
import subprocess
import sys
import tempfile

build = pathlib.Path(sys.argv[1])
with tempfile.TemporaryDirectory() as home:
    prefix = pathlib.Path(home) / ".local"
    subprocess.run(["cmake", "--install", str(build), "--prefix", str(prefix)], check=True,
                   stdout=subprocess.DEVNULL)
    script = ("import cdpowder, cdpowder.summary, cdpowder.tables; "
              "w = cdpowder.deposit(cdpowder.Scene.from_keys({'deposition.spheres': 20, "
              "'system.lx': 6, 'system.ly': 6})); print(cdpowder.__file__, len(w))")
    clean = {"HOME": home, "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}
    done = subprocess.run(["/usr/bin/python3", "-c", script], env=clean, capture_output=True,
                          text=True, cwd=home)
    if done.returncode != 0 or not done.stdout.strip().endswith(" 20"):
        sys.exit(f"import cdpowder from {prefix} failed:\n{done.stdout}{done.stderr}")
    where = pathlib.Path(done.stdout.split()[0])
    if prefix not in where.parents:
        sys.exit(f"cdpowder was imported from {where}, not from the install in {prefix}")
    print(f"installed and imported from {where.parent}")
