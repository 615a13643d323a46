"""Shared fixtures of the Python tests (run by ctest: python/CMakeLists.txt sets the paths)."""
from __future__ import annotations

import os
import shutil
import socket
import subprocess
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("VLPGROUND_SOURCE_DIR", Path(__file__).resolve().parents[2]))
PCAPS = SOURCE_DIR / "pcaps"


def _tool(env_name: str, fallback: str, missing: str) -> Path:
    """A program of this build (path from ctest's environment); skips the test without it."""
    path = os.environ.get(env_name) or shutil.which(fallback)
    if not path or not Path(path).exists():
        pytest.skip(missing)
    return Path(path)


@pytest.fixture(scope="session")
def cli() -> Path:
    """The vlpground executable."""
    return _tool("VLPGROUND_CLI", "vlpground", "vlpground CLI not built (VLPGROUND_BUILD_APPS=OFF)")


@pytest.fixture(scope="session")
def pipeline_dump() -> Path:
    """Prints vlpground::Pipeline's per-frame metadata as JSON lines."""
    return _tool("VLPGROUND_PIPELINE_DUMP", "vlpground_pipeline_dump",
                 "vlpground_pipeline_dump not built (VLPGROUND_BUILD_TESTS=OFF)")


def run(*args: object, timeout: float = 120) -> str:
    """Runs a command, returns its stdout; fails the test with stderr on a non-zero exit."""
    proc = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, f"{args} exited {proc.returncode}: {proc.stderr}"
    return proc.stdout


def free_udp_port() -> int:
    """A UDP port free on 127.0.0.1 right now (the kernel picks it)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def rss_bytes() -> int:
    """Resident set size of this process."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
