"""The build of `pip install .` (pyproject.toml): CMake builds the engine (the target
cdpowder_python, the module cdpowder._core) and setuptools packages it with python/cdpowder/.

CDPOWDER_BUILD_DIR names a configured build folder to build in (its build of the module is
reused, as the test of this path does); otherwise a Release build is configured under
setuptools' build folder, without the tests."""
import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def version():
    """project(cdpowder VERSION x.y.z) of CMakeLists.txt."""
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(cdpowder VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("CDPOWDER_BUILD_DIR")
        if build:
            build = pathlib.Path(build).resolve()
        else:
            build = pathlib.Path(self.build_temp).resolve() / "cmake"
            subprocess.check_call(
                ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                 "-DCDPOWDER_BUILD_TESTS=OFF", f"-DPython3_EXECUTABLE={sys.executable}"])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "cdpowder_python"])
        built = sorted((build / "python" / "cdpowder").glob("_core*.so"))
        if not built:
            sys.exit(f"setup.py: no cdpowder/_core module in {build / 'python'}: is pybind11-dev "
                     "installed, and the build without sanitizers?")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[-1], target)


setup(version=version(),
      packages=["cdpowder", "cdpowder.report"],
      package_dir={"": "python"},
      ext_modules=[Extension("cdpowder._core", sources=[])],
      cmdclass={"build_ext": CMakeBuild})
