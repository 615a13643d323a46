"""Builds vlpground._core with the project's CMake (settings in pyproject.toml).

No download: CMake, a C++20 compiler, pybind11 and the libraries of scripts/setup.sh must be
installed. CMake runs in build-pip/ (kept between builds; ccache is used when installed).
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = ROOT / "build-pip"
        env = dict(os.environ)
        if shutil.which("ccache") and "CMAKE_CXX_COMPILER_LAUNCHER" not in env:
            env.update(CMAKE_CXX_COMPILER_LAUNCHER="ccache", CCACHE_BASEDIR=str(ROOT))
        subprocess.run(
            ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
             "-DVLPGROUND_BUILD_PYTHON=ON", "-DVLPGROUND_BUILD_TESTS=OFF",
             "-DVLPGROUND_BUILD_APPS=OFF", "-DVLPGROUND_BUILD_BENCHMARKS=OFF",
             f"-DPython3_EXECUTABLE={sys.executable}"], check=True, env=env)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "vlpground_python",
                        "-j", str(os.cpu_count() or 2)], check=True, env=env)
        built = next((build_dir / "python" / "vlpground").glob("_core*.so"))
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


def project_version() -> str:
    """The version of `project(vlpground VERSION x.y.z ...)`: one place for it."""
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(vlpground\s+VERSION\s+([0-9.]+)", text).group(1)


setup(version=project_version(), ext_modules=[CMakeExtension("vlpground._core")],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build-pip/setuptools"}})
