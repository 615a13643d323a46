"""read_pcap, Frame, GroundDetector, evaluate and simulate against the C++ tools."""
from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import vlpground
from conftest import PCAPS, rss_bytes, run

HOUR_NS = 3_600_000_000_000
FIRING_NS = 2304

# pcaps/ holds a single-return and a dual-return capture.
CAPTURES = ["urban_demo", "slope_dual"]


def read_cli_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert header == ["frame", "laser_id", "ring", "return", "timestamp_us", "azimuth_deg",
                      "distance_m", "x", "y", "z", "intensity", "ground"]
    return body


@pytest.mark.parametrize("name", CAPTURES)
def test_points_equal_cli_csv(cli, tmp_path, name):
    """Every return of every frame: same order, label, coordinates and time as --csv."""
    out = tmp_path / "returns.csv"
    run(cli, "replay", PCAPS / f"{name}.pcap", "--csv", out)
    rows = read_cli_csv(out)
    fields = ["laser", "ring", "return", "azimuth_deg", "range_m", "x", "y", "z", "intensity",
              "label"]
    parts, times = [], []
    for frame in vlpground.read_pcap(PCAPS / f"{name}.pcap"):
        pts = frame.to_numpy_points(fields)
        parts.append(np.column_stack([np.full(len(pts), frame.meta.sequence), pts]))
        # Exact firing times of the valid cells, in the same (column, laser, layer) order.
        t = frame.time_ns
        for col in range(frame.columns):
            for laser in range(16):
                ring = int(np.flatnonzero(frame.laser[:, 0] == laser)[0])
                for layer in range(frame.return_layers):
                    if frame.layer(layer).valid[ring, col]:
                        times.append(int(t[ring, col]))
    ours = np.concatenate(parts)
    assert len(ours) == len(rows) > 10000
    theirs = np.array([[float(v) for v in r] for r in rows])
    assert np.array_equal(ours[:, 0], theirs[:, 0])  # frame
    assert np.array_equal(ours[:, 1:4], theirs[:, 1:4])  # laser, ring, return
    # Decimals as printed by the CLI: half a unit of the last digit, exactly rounded.
    for ours_col, their_col, decimals in ((4, 5, 3), (5, 6, 3), (6, 7, 4), (7, 8, 4), (8, 9, 4)):
        assert np.max(np.abs(ours[:, ours_col] - theirs[:, their_col])) <= 0.5 * 10.0**-decimals + 1e-9
    assert np.array_equal(ours[:, 9], theirs[:, 10])  # intensity
    assert np.array_equal(ours[:, 10] == 1, theirs[:, 11] == 1)  # ground label
    their_us = [int(r[4].replace(".", "")) for r in rows]  # timestamp_us has 3 decimals: ns
    assert [t % HOUR_NS for t in times] == their_us


@pytest.mark.parametrize("name", CAPTURES)
def test_frames_and_counters_equal_pipeline(pipeline_dump, name):
    """Frame count, per-frame metadata and label counts equal vlpground::Pipeline's."""
    expected = [json.loads(line) for line in run(pipeline_dump, PCAPS / f"{name}.pcap").splitlines()]
    frames = list(vlpground.read_pcap(PCAPS / f"{name}.pcap"))
    assert len(frames) == len(expected) >= 3
    for frame, want in zip(frames, expected):
        m = frame.meta
        got = {
            "sequence": m.sequence, "columns": frame.columns, "complete": m.complete,
            "start_time_ns": m.start_time_ns, "end_time_ns": m.end_time_ns,
            "packets_used": m.packets_used, "packets_lost": m.packets_lost,
            "packets_skipped": m.packets_skipped, "columns_lost": m.columns_lost,
            "columns_outside_fov": m.columns_outside_fov, "returns": frame.returns,
            "ground_returns": frame.ground_returns, "obstacle_returns": frame.obstacle_returns,
        }
        assert got == want


def test_arrays_are_views_with_the_row_stride():
    frame = next(iter(vlpground.read_pcap(PCAPS / "urban_demo.pcap")))
    rows, cols = 16, frame.columns
    assert frame.stride >= cols
    for name in ("range_m", "x", "y", "z", "azimuth_deg", "time_offset_us", "height_m"):
        a = getattr(frame, name)
        assert a.shape == (rows, cols) and a.dtype == np.float32
        assert a.strides == (frame.stride * 4, 4), name
        assert not a.flags.writeable and not a.flags.owndata
    for name in ("intensity", "label"):
        a = getattr(frame, name)
        assert a.dtype == np.uint8 and a.strides == (frame.stride, 1) and not a.flags.owndata
    assert frame.valid.dtype == np.bool_ and not frame.valid.flags.owndata
    # Two accesses see the same memory (a view, not a copy).
    assert np.shares_memory(frame.range_m, frame.range_m)
    with pytest.raises(ValueError):
        frame.range_m[0, 0] = 1.0
    # xyz: one copy, NaN exactly where there is no return.
    xyz = frame.xyz
    assert xyz.shape == (rows, cols, 3) and xyz.dtype == np.float32 and xyz.flags.owndata
    valid = frame.valid
    assert np.isnan(xyz[~valid]).all() and not np.isnan(xyz[valid]).any()
    assert np.array_equal(xyz[..., 0][valid], frame.x[valid])
    assert np.array_equal(frame.ring, np.repeat(np.arange(16, dtype=np.uint8)[:, None], cols, 1))
    labels = frame.label
    assert set(np.unique(labels[valid])) <= {1, 2} and (labels[~valid] == 0).all()
    assert (labels == 1).sum() == frame.ground_returns
    # A view outlives its frame and reader.
    r = frame.range_m
    del frame
    assert np.isfinite(r).all()


def test_meta_planes_and_points_fields():
    frames = list(vlpground.read_pcap(PCAPS / "urban_demo.pcap"))
    f = frames[1]
    assert f.meta.complete and f.meta.mode == "strongest" and f.meta.model == "vlp16"
    assert f.meta.end == "cut" and 500 < f.meta.rpm < 700
    # The demo captures send position packets with PPS locked and a valid $GPRMC.
    gps = f.meta.gps
    assert gps.has_position and gps.pps == "locked" and gps.gprmc == "valid"
    assert abs(gps.utc_ns - f.meta.start_time_ns) < 2_000_000_000
    assert gps.sentence.startswith("$GPRMC") and abs(gps.latitude_deg - 48.1173) < 1e-3
    assert f.meta.time_source == "gps_pps" and f.meta.calibration == "built-in"
    assert f.meta.counters["source"]["data_packets"] >= f.meta.packets_used
    assert frames[-1].meta.counters["assembler"]["frames"] == len(frames)
    assert len(f.planes) == 4 and any(s.has_ground for s in f.planes)
    ground = f.planes[0].plane
    assert ground.nz > 0.9
    pts = f.to_numpy_points(["x", "y", "z", "label"])
    assert pts.shape == (f.returns, 4)
    assert (pts[:, 3] == 1).sum() == f.ground_returns
    with pytest.raises(ValueError, match="unknown point field"):
        f.to_numpy_points(["nope"])
    assert np.allclose(f.time_s, f.time_ns * 1e-9)
    assert f.time_ns[0, 0] == f.meta.start_time_ns


def test_dual_return_layers():
    frame = list(vlpground.read_pcap(PCAPS / "slope_dual.pcap"))[1]
    assert frame.meta.mode == "dual" and frame.return_layers == 2
    last = frame.layer(1)
    assert last.range_m.shape == frame.range_m.shape
    assert last.valid.sum() > 0 and frame.same_echo is not None
    # Where both layers hold the same echo the ranges agree.
    same = frame.same_echo & frame.valid & last.valid
    assert np.array_equal(frame.range_m[same], last.range_m[same])
    pts = frame.to_numpy_points(["return"])
    assert (pts[:, 0] == 1).sum() == last.valid.sum()
    with pytest.raises(IndexError):
        frame.layer(2)
    single = next(iter(vlpground.read_pcap(PCAPS / "urban_demo.pcap")))
    assert single.return_layers == 1 and single.same_echo is None


def test_detect_again_with_other_settings():
    frame = list(vlpground.read_pcap(PCAPS / "urban_demo.pcap", frames=2))[1]
    again = vlpground.GroundDetector(vlpground.DetectorConfig()).detect(frame)
    assert np.array_equal(again.label, frame.label)  # same settings: same labels
    ransac = vlpground.GroundDetector(vlpground.DetectorConfig(method="ransac")).detect(frame)
    assert ransac.method == "ransac" and frame.method == "tangent"
    assert not np.array_equal(ransac.label, frame.label)
    assert np.shares_memory(ransac.range_m, frame.range_m)  # decoded data shared, not copied
    assert ransac.meta.sequence == frame.meta.sequence


def test_method_keyword_and_detector_config():
    path = PCAPS / "urban_demo.pcap"
    ransac = vlpground.DetectorConfig(method="ransac", min_sensor_height_m=0.3)
    assert next(iter(vlpground.read_pcap(path, detector=ransac))).method == "ransac"
    assert next(iter(vlpground.read_pcap(path, detector=ransac, method="lpr"))).method == "lpr"
    assert next(iter(vlpground.read_pcap(path, method="ransac"))).method == "ransac"
    assert next(iter(vlpground.read_pcap(path))).method == "tangent"
    assert vlpground.evaluate(path, path.with_suffix(".labels"), detector=ransac)["method"] == "ransac"


def test_errors_are_clear(tmp_path):
    with pytest.raises(RuntimeError, match="missing.pcap"):
        vlpground.read_pcap(tmp_path / "missing.pcap")
    junk = tmp_path / "junk.pcap"
    junk.write_bytes(b"this is not a capture" * 10)
    with pytest.raises(RuntimeError):
        list(vlpground.read_pcap(junk))
    with pytest.raises(ValueError, match="method"):
        vlpground.read_pcap(PCAPS / "urban_demo.pcap", method="magic")
    with pytest.raises(ValueError, match="extrinsics"):
        vlpground.read_pcap(PCAPS / "urban_demo.pcap", extrinsics=(1, 2))
    with pytest.raises(TypeError, match="unexpected keyword"):
        vlpground.DetectorConfig(no_such_field=1)
    with pytest.raises(ValueError):
        vlpground.DetectorConfig(hypotheses=-3).validate()


def test_evaluate_equals_cli_eval(cli):
    pcap, labels = PCAPS / "urban_demo.pcap", PCAPS / "urban_demo.labels"
    want = json.loads(run(cli, "eval", pcap, "--labels", labels, "--json"))
    got = vlpground.evaluate(pcap, labels)
    for key, value in want.items():
        if key == "detect_ms_total":  # a wall time
            continue
        assert got[key] == pytest.approx(value, rel=1e-12, abs=0), key
    assert got["f1"] > 0.99


def test_evaluate_refuses_labels_of_another_capture():
    """As `vlpground eval`: labels (or a simulator JSON) of another capture are an error."""
    with pytest.raises(RuntimeError, match="labels cover 283 packets .*, the capture has 135"):
        vlpground.evaluate(PCAPS / "hills_demo.pcap", PCAPS / "urban_demo.labels")


def test_simulate_writes_a_readable_capture(tmp_path):
    out = vlpground.simulate("flat", tmp_path / "sub" / "flat", frames=2, seed=3)
    for key in ("pcap", "labels", "heights", "json"):
        assert out[key].exists()
    assert out["heights"].stat().st_size == 2 * out["labels"].stat().st_size
    assert out["data_packets"] > 0 and out["returns"] > out["ground_returns"] > 0
    frames = list(vlpground.read_pcap(out["pcap"]))
    assert sum(f.meta.complete for f in frames) == 2
    score = vlpground.evaluate(out["pcap"], out["labels"])
    assert score["frames"] == len(frames) and score["f1"] > 0.95
    assert score["high_obstacle_terrain"] == "exact"  # the heights beside the labels
    with pytest.raises(ValueError, match="unknown scene"):
        vlpground.simulate("moon", tmp_path / "m")


def test_memory_stays_flat_over_a_long_read():
    """300 frames (the demo capture looped): resident memory does not grow per frame."""
    reader = vlpground.read_pcap(PCAPS / "urban_demo.pcap", loop=True, frames=300)
    samples = {}
    for i, frame in enumerate(reader):
        frame.to_numpy_points()
        _ = frame.xyz, frame.label
        if i in (30, 299):
            samples[i] = rss_bytes()
    assert reader.frames == 300
    growth = samples[299] - samples[30]
    # A frame (+ labels) is about 5 MB: growth per frame would show as hundreds of MB.
    assert growth < 4 * 1024 * 1024, f"RSS grew by {growth / 1e6:.1f} MB over 270 frames"
