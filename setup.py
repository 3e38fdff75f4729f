"""Builds the extension module `sphib` with the project's CMake (target sphib_python) for the Python
that runs this (a venv's too), and hands the built file to setuptools. pyproject.toml says how to
call it. SPHIB_CMAKE_ARGS adds arguments to the CMake configuration (e.g. -DCMAKE_BUILD_TYPE=Debug)."""
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = Path(self.build_temp).resolve() / "cmake"
        config = ["cmake", "-S", str(SOURCE), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                  "-DSPHIB_BUILD_TESTS=OFF", "-DSPHIB_BUILD_BENCH=OFF", f"-DPython_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja"):
            config += ["-G", "Ninja"]
        config += shlex.split(os.environ.get("SPHIB_CMAKE_ARGS", ""))
        subprocess.run(config, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "--target", "sphib_python", "--parallel", jobs], check=True)
        suffix = Path(self.get_ext_filename(ext.name)).name
        module = build / "python" / suffix
        if not module.exists():
            sys.exit(f"sphib: the CMake build made no {module} (are pybind11-dev and python3-dev installed?)")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(module, target)


# Its own build directory (build/ is the CMake build of scripts/run_main.sh).
setup(ext_modules=[CMakeExtension("sphib")], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build-pip"}})
