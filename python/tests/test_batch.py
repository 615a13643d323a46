"""vlpground.batch on a LocalCluster of 2 worker processes (loopback only)."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import vlpground
from vlpground import batch
from conftest import run

distributed = pytest.importorskip("distributed")

SCENES = ["flat", "urban", "slope", "hills", "jam", "fences"]


@pytest.fixture(scope="module")
def captures(tmp_path_factory):
    """Six small simulated captures and one corrupt file (a pcap header, then garbage)."""
    folder = tmp_path_factory.mktemp("captures")
    good = []
    for i, scene in enumerate(SCENES):
        out = vlpground.simulate(scene, folder / f"{scene}{i}", frames=2, seed=10 + i,
                                 mode="dual" if scene == "slope" else "strongest")
        good.append(out["pcap"])
    corrupt = folder / "corrupt.pcap"
    corrupt.write_bytes(good[0].read_bytes()[:24] + bytes(range(256)) * 8)
    (folder / "corrupt.labels").write_bytes(b"")
    return good, corrupt


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_label_on_the_cluster_reports_the_corrupt_capture_and_skips_on_rerun(
        captures, client, tmp_path):
    good, corrupt = captures
    paths = good[:3] + [corrupt] + good[3:]
    rows = batch.label_captures(paths, tmp_path, client=client, format="npz")
    assert [r["capture"] for r in rows] == [str(p) for p in paths]
    failed = rows[3]
    assert failed["status"] == "failed" and "corrupt.pcap" in failed["error"]
    for path, row in zip(good, rows[:3] + rows[4:]):
        assert row["status"] == "done" and row["frames"] >= 3, row
        columns = batch.read_npz(row["output"])
        # The file holds exactly what read_pcap yields in this process.
        frames = list(vlpground.read_pcap(path))
        assert len(columns["x"]) == row["returns"] == sum(f.returns for f in frames)
        assert (columns["label"] == 1).sum() == row["ground_returns"]
        expected = np.concatenate([f.to_numpy_points(["x", "label"]) for f in frames])
        assert np.array_equal(columns["x"], expected[:, 0].astype(np.float32))
        assert np.array_equal(columns["label"], expected[:, 1].astype(np.uint8))
    # Second run: every capture done before is skipped, the corrupt one fails again.
    again = batch.label_captures(paths, tmp_path, client=client, format="npz")
    assert [r["status"] for r in again] == ["skipped"] * 3 + ["failed"] + ["skipped"] * 3
    assert [r["returns"] for r in again] == [r["returns"] for r in rows]
    assert not list(tmp_path.glob("*.tmp-*"))  # no partial files left behind


def test_evaluate_table_equals_cli_eval_capture_by_capture(captures, client, cli, tmp_path):
    good, corrupt = captures
    pairs = [(p, p.with_suffix(".labels")) for p in good] + [(corrupt, corrupt.with_suffix(".labels"))]
    rows = batch.evaluate_captures(pairs, client=client, out_dir=tmp_path)
    assert len(rows) == len(pairs) + 1
    assert rows[-2]["status"] == "failed" and rows[-2]["error"]
    for (pcap, labels), row in zip(pairs[:-1], rows):
        want = json.loads(run(cli, "eval", pcap, "--labels", labels, "--json"))
        assert row["status"] == "done"
        for key, value in want.items():
            if key != "detect_ms_total":  # a wall time
                assert row[key] == pytest.approx(value, rel=1e-12, abs=0), (pcap, key)
    overall = rows[-1]
    assert overall["capture"] == "overall" and overall["status"] == "1 of 7 failed"
    for key in ("frames", "tp", "fp", "fn", "tn"):
        assert overall[key] == sum(r[key] for r in rows[:-2])
    tp, fp, fn = overall["tp"], overall["fp"], overall["fn"]
    assert overall["precision"] == pytest.approx(tp / (tp + fp))
    assert overall["f1"] == pytest.approx(2 * tp / (2 * tp + fp + fn))
    again = batch.evaluate_captures(pairs, client=client, out_dir=tmp_path)
    assert [r["status"] for r in again[:-2]] == ["skipped"] * len(good)
    assert [r["f1"] for r in again[:-2]] == [r["f1"] for r in rows[:-2]]


def test_csv_output_is_the_cli_csv(captures, cli, tmp_path):
    good, _ = captures
    rows = batch.label_captures(good[1:2], tmp_path / "out", format="csv")  # in-process
    assert rows[0]["status"] == "done"
    run(cli, "replay", good[1], "--csv", tmp_path / "cli.csv")
    assert (tmp_path / "cli.csv").read_bytes() == (tmp_path / "out" / f"{good[1].stem}.csv").read_bytes()


def test_parquet_without_pyarrow_is_a_clear_error(captures, tmp_path):
    if batch.parquet_available():
        pytest.skip("pyarrow is installed")
    with pytest.raises(ValueError, match="pyarrow"):
        batch.label_captures(captures[0], tmp_path, format="parquet")


def test_command_line_on_a_local_cluster(captures, tmp_path):
    good, corrupt = captures
    proc = subprocess.run(
        [sys.executable, "-m", "vlpground.batch", "eval", str(good[0]), str(corrupt),
         "--workers", "2", "--json"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1, proc.stderr  # the corrupt capture failed
    rows = json.loads(proc.stdout)
    assert [r["status"] for r in rows] == ["done", "failed", "1 of 2 failed"]
    assert rows[0]["f1"] == vlpground.evaluate(good[0], good[0].with_suffix(".labels"))["f1"]


def test_time_slices_lose_or_double_no_frame(captures, client, cli, tmp_path):
    """Slices of 2 frames, one task each, joined: the CSV equals the CLI's byte for byte."""
    good, corrupt = captures
    paths = [good[1], good[2], corrupt]  # urban (single return), slope (dual return)
    rows = batch.label_captures(paths, tmp_path, client=client, format="csv", slice_frames=2)
    assert [r["status"] for r in rows] == ["done", "done", "failed"], rows
    assert "corrupt.pcap" in rows[2]["error"]
    for path, row in zip(paths[:2], rows):
        assert row["slices"] == -(-vlpground.count_frames(path) // 2) >= 2
        run(cli, "replay", path, "--csv", tmp_path / "cli.csv")
        assert (tmp_path / "cli.csv").read_bytes() == open(row["output"], "rb").read(), path
        assert row["frames"] == vlpground.count_frames(path)
    assert not list(tmp_path.glob("*.part*")) and not list(tmp_path.glob("*.tmp-*"))
    again = batch.label_captures(paths, tmp_path, client=client, format="csv", slice_frames=2)
    assert [r["status"] for r in again] == ["skipped", "skipped", "failed"]


def test_time_slices_in_process_equal_the_whole_capture(captures, tmp_path):
    good, _ = captures
    whole = batch.label_captures(good[:1], tmp_path / "whole")[0]
    sliced = batch.label_captures(good[:1], tmp_path / "sliced", slice_frames=1)[0]
    assert sliced["slices"] == whole["frames"] >= 3
    a, b = batch.read_npz(whole["output"]), batch.read_npz(sliced["output"])
    assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def test_command_line_on_a_scheduler_address(captures, client, tmp_path):
    """--scheduler ADDR: the tasks run on an existing cluster (here the module's)."""
    good, _ = captures
    address = client.scheduler.address
    assert address.startswith("tcp://127.0.0.1:")
    proc = subprocess.run(
        [sys.executable, "-m", "vlpground.batch", "label", str(good[0]), str(good[1]),
         "--out", str(tmp_path), "--format", "npz", "--scheduler", address, "--json"],
        capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    rows = json.loads(proc.stdout)
    assert [r["status"] for r in rows] == ["done", "done"]
    assert sorted(p.name for p in tmp_path.glob("*.npz")) == sorted(f"{p.stem}.npz" for p in good[:2])
