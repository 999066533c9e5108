"""The Python package's build (pyproject.toml): CMake builds the native module _froth, and
setuptools puts it beside python/froth/*.py in the wheel.

Environment: FROTH_BUILD_JOBS (default 2) parallel compile jobs; FROTH_CMAKE_ARGS more -D
options for CMake, split on spaces.
"""
import glob
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))
os.makedirs(os.path.join(ROOT, "build-pip"), exist_ok=True)  # setuptools' files, apart from CMake's build/


def cmake_version():
    """The version CMakeLists.txt's project() states: the package's, so they cannot differ."""
    text = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    return re.search(r"project\(froth VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.path.abspath(os.path.join(self.build_temp, "cmake"))
        configure = ["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DFROTH_PYTHON=ON",
                     "-DFROTH_BUILD_TESTS=OFF", "-DFROTH_BUILD_BENCH=OFF", "-DPython_EXECUTABLE=" + sys.executable,
                     *os.environ.get("FROTH_CMAKE_ARGS", "").split()]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("FROTH_BUILD_JOBS", "2")
        subprocess.run(["cmake", "--build", build, "--target", "_froth", "-j", jobs], check=True)
        built = glob.glob(os.path.join(build, "python", "froth", "_froth*.so"))
        if len(built) != 1:
            sys.exit("froth: CMake built %d native modules in %s/python/froth, not 1" % (len(built), build))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    version=cmake_version(),
    packages=["froth"],
    package_dir={"froth": "python/froth"},
    package_data={"froth": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("froth._froth", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build-pip"}, "egg_info": {"egg_base": "build-pip"}},
)
