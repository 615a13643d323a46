"""examples/notebook_birdseye.py runs and prints the F1 (kept honest as the C++ example is)."""
from __future__ import annotations

import re
import subprocess
import sys

import pytest

import vlpground
from conftest import PCAPS, SOURCE_DIR

pytest.importorskip("matplotlib")


def test_notebook_example_draws_and_scores(tmp_path):
    out = tmp_path / "view.png"
    proc = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "notebook_birdseye.py"),
                           "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    f1 = float(re.search(r"F1 ([0-9.]+)", proc.stdout).group(1))
    want = vlpground.evaluate(PCAPS / "urban_demo.pcap", PCAPS / "urban_demo.labels")["f1"]
    assert f1 == pytest.approx(want, abs=5e-5)
