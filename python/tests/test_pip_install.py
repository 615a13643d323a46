"""`pip install --no-build-isolation --no-deps --no-index .` works offline with Debian's tools.

Builds from a copy of the source tree (the test writes nothing into the checkout) into a
venv that sees the system's numpy, then imports the installed package from elsewhere.
"""
from __future__ import annotations

import shutil
import subprocess
import sys

import pytest

from conftest import PCAPS, SOURCE_DIR

IGNORE = shutil.ignore_patterns(".git", "build*", "out", "node_modules", "__pycache__",
                                "*.egg-info", ".cache")


def test_pip_installs_the_package_offline(tmp_path):
    if shutil.which("cmake") is None:
        pytest.skip("cmake not on the PATH")
    src = tmp_path / "src"
    shutil.copytree(SOURCE_DIR, src, ignore=IGNORE, symlinks=True)
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip",
                    str(venv)], check=True, timeout=60)
    python = venv / "bin" / "python"
    # The system pip installs into the venv when run by the venv's interpreter.
    proc = subprocess.run(
        [str(python), "-m", "pip", "install", "--no-build-isolation", "--no-deps",
         "--no-index", "--no-cache-dir", "--disable-pip-version-check", str(src)],
        capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    check = subprocess.run(
        [str(python), "-c",
         "import sys, vlpground, vlpground.batch; "
         "assert vlpground.__file__.startswith(sys.prefix), vlpground.__file__; "
         "import importlib.metadata as md; "
         "assert md.version('vlpground') == vlpground.__version__, md.version('vlpground'); "
         f"print(sum(1 for _ in vlpground.read_pcap({str(PCAPS / 'urban_demo.pcap')!r})))"],
        capture_output=True, text=True, timeout=60, cwd=tmp_path, env={"PATH": "/usr/bin:/bin"})
    assert check.returncode == 0, check.stderr
    assert check.stdout.strip() == "5"
    installed = list((venv / "lib").glob("python3*/site-packages/vlpground"))
    assert installed and (installed[0] / "py.typed").exists() and (installed[0] / "_core.pyi").exists()
