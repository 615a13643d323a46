"""Label or evaluate many captures in parallel on a Dask cluster.

    from dask.distributed import Client
    from vlpground import batch
    client = Client("tcp://scheduler:8786")          # or LocalCluster(...), or None
    rows = batch.label_captures(paths, "/shared/labels", client=client, format="npz")
    table = batch.evaluate_captures([(pcap, labels), ...], client=client)

One task per capture (or per slice of N frames with ``slice_frames=N``). Each task writes its result under ``out_dir``, which must be a path
every worker can write (a shared filesystem on a real cluster). A capture that fails is a
row with ``status == "failed"`` and its ``error``; the others complete. A re-run skips
captures whose output is complete (``status == "skipped"``). Without a client the current
default Dask client is used if there is one, else the captures run one by one in this
process. Command line: ``python3 -m vlpground.batch --help``.
"""
from __future__ import annotations

import os
from collections import deque
from math import ceil
from pathlib import Path
from typing import Callable, Iterable, List, Optional, Sequence, Tuple

import vlpground
from vlpground import _core

from . import _tasks
from ._tasks import count_one, done_row, evaluate_one, label_one, label_row, merge_parts, part_path
from ._writers import FORMATS, check_format, parquet_available, read_npz

__all__ = ["label_captures", "evaluate_captures", "format_table", "read_npz", "FORMATS",
           "EVAL_FIELDS", "parquet_available"]

# Figures of each row of evaluate_captures, as `vlpground eval --json`.
EVAL_FIELDS = ("capture", "method", "radius_m", "frames", "precision", "recall", "f1", "tp",
               "fp", "fn", "tn", "detect_ms_total", "high_obstacle_as_ground_rate",
               "high_obstacle_terrain")
_COUNTS = ("frames", "tp", "fp", "fn", "tn", "high_obstacles", "high_obstacles_as_ground")


def _default_client(client):
    if client is not None:
        return client
    try:
        from distributed import default_client
        return default_client()
    except (ImportError, ValueError):
        return None


# A job: (function, arguments, tag); the first argument names the capture.
Job = Tuple[Callable, tuple, object]


def _drive(client, jobs: Sequence[Job],
           handle: Callable[[object, object, Optional[BaseException]], Iterable[Job]]) -> None:
    """Runs every job, on `client` (one task each) or here, one by one; ``handle(tag, result,
    error)`` receives each outcome as it completes and may return further jobs."""
    client = _default_client(client)
    if client is None:
        queue = deque(jobs)
        while queue:
            fn, args, tag = queue.popleft()
            try:
                result, error = fn(*args), None
            except Exception as e:  # noqa: BLE001 (handed to `handle`)
                result, error = None, e
            queue.extend(handle(tag, result, error))
        return
    if not jobs:
        return
    from distributed import as_completed
    tags = {}

    def submit(job: Job):
        fn, args, tag = job
        key = f"vlpground-{fn.__name__}-{Path(str(args[0])).name}-{os.urandom(4).hex()}"
        future = client.submit(fn, *args, key=key, pure=False)
        tags[future.key] = tag
        return future

    pending = as_completed([submit(job) for job in jobs])
    for future in pending:
        tag = tags.pop(future.key)
        try:
            result, error = future.result(), None
        except Exception as e:  # noqa: BLE001 (a worker died: KilledWorker, ...)
            result, error = None, e
        future.release()
        for job in handle(tag, result, error):
            pending.add(submit(job))


def _run(client, fn: Callable, jobs: Sequence[tuple]) -> List[dict]:
    """fn(*args) for every args (first = the capture) as one task each; rows in order."""
    rows: List[dict] = [{} for _ in jobs]

    def handle(i, result, error):
        rows[i] = result if error is None else _tasks.failed(
            {"capture": str(jobs[i][0]), "status": "failed"}, error, with_traceback=False)
        return ()

    _drive(client, [(fn, args, i) for i, args in enumerate(jobs)], handle)
    return rows


def _output_paths(paths: Sequence[str], out_dir: Path, suffix: str) -> List[Path]:
    outputs = [out_dir / (Path(p).stem + suffix) for p in paths]
    seen = {}
    for p, o in zip(paths, outputs):
        if o in seen:
            raise ValueError(f"{p} and {seen[o]} would both be written to {o}: give captures "
                             "distinct file names")
        seen[o] = p
    return outputs


def label_captures(paths: Iterable[os.PathLike | str], out_dir: os.PathLike | str, *,
                   client=None, method: str = vlpground.DEFAULT_METHOD, format: str = "npz",
                   slice_frames: Optional[int] = None, **read_options) -> List[dict]:
    """Labels every capture into ``out_dir/STEM.{npz,csv,parquet}``.

    ``read_options`` are those of vlpground.read_pcap (extrinsics, calibration, model,
    cut_angle_deg, sensor_ip, port, detector, ...). Formats (all one row per valid return,
    in the CLI's CSV order): ``npz`` (a flat array per column: frame, laser_id, ring,
    return, time_ns, azimuth_deg, distance_m, x, y, z, intensity, label; read with
    vlpground.batch.read_npz or numpy.load), ``csv`` (exactly the CLI's --csv),
    ``parquet`` (same columns as npz; needs pyarrow, not packaged in Debian 12: a clear
    ValueError without it).

    ``slice_frames=N`` cuts each capture into slices of N frames, one task each, then joins
    them in a last task: frames are cut where the whole capture is cut (every slice decodes
    the capture from its start and labels only its own frames), so none is lost or doubled
    and the output equals the unsliced one. The frames of a capture are counted first (a
    decoding-only task). Worth it for long captures on many workers.

    Returns one row per capture, in order: capture, output, status ("done", "skipped" or
    "failed"), error, frames, returns, ground_returns, seconds (summed over slices).
    """
    check_format(format)
    for key in ("loop", "first_frame") + (("frames",) if slice_frames is not None else ()):
        if key in read_options:
            raise ValueError(f"label_captures does not take {key}= (it labels whole captures)")
    paths = [os.fspath(p) for p in paths]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    outputs = _output_paths(paths, out, "." + format)
    options = dict(read_options, method=method)
    vlpground._detector(method, options.get("extrinsics"), options.get("detector"))  # validate
    if slice_frames is None:
        return _run(client, label_one, [(p, os.fspath(o), format, options)
                                        for p, o in zip(paths, outputs)])
    if slice_frames < 1:
        raise ValueError(f"slice_frames must be >= 1, got {slice_frames}")
    return _label_sliced(client, paths, [os.fspath(o) for o in outputs], format, options,
                         int(slice_frames))


def _label_sliced(client, paths: List[str], outputs: List[str], fmt: str, options: dict,
                  slice_frames: int) -> List[dict]:
    """count -> one label task per slice -> merge, per capture, all captures at once."""
    rows: List[Optional[dict]] = [done_row(p, o) for p, o in zip(paths, outputs)]
    parts: dict = {}
    waiting: dict = {}

    def fail(i: int, error: str) -> None:
        if rows[i] is None:
            rows[i] = dict(label_row(paths[i], outputs[i]), status="failed", error=error)

    def handle(tag, result, error):
        kind, i, k = tag
        if error is not None:
            fail(i, f"{type(error).__name__}: {error}")
            return ()
        if kind == "count":
            frames = int(result)
            parts[i] = [os.fspath(part_path(Path(outputs[i]), s))
                        for s in range(ceil(frames / slice_frames))]
            waiting[i] = len(parts[i])
            return [(label_one, (paths[i], part, fmt,
                                 dict(options, first_frame=s * slice_frames,
                                      frames=min(slice_frames, frames - s * slice_frames))),
                     ("slice", i, s)) for s, part in enumerate(parts[i])]
        if kind == "slice":
            if result["status"] == "failed":
                fail(i, f"slice {k}: {result['error']}")
                return ()
            waiting[i] -= 1
            if waiting[i] == 0 and rows[i] is None:
                return [(merge_parts, (paths[i], outputs[i], fmt, parts[i]), ("merge", i, 0))]
            return ()
        rows[i] = result  # merge
        return ()

    _drive(client, [(count_one, (p, options), ("count", i, 0))
                    for i, p in enumerate(paths) if rows[i] is None], handle)
    return rows  # type: ignore[return-value]


def evaluate_captures(pairs: Iterable[Tuple[os.PathLike | str, os.PathLike | str]], *,
                      client=None, method: str = vlpground.DEFAULT_METHOD, radius_m: float = 40.0,
                      out_dir: os.PathLike | str | None = None, **options) -> List[dict]:
    """Scores each (pcap, labels) pair as ``vlpground eval`` does; one task per capture.

    Returns one row per capture (EVAL_FIELDS plus status and error) followed by an
    ``overall`` row: counts summed over the captures that succeeded and precision, recall,
    F1 of the summed confusion counts (the library's definitions). With ``out_dir`` each
    result is also saved there (STEM.eval.json) and a re-run skips captures already scored.
    """
    pairs = [(os.fspath(p), os.fspath(l)) for p, l in pairs]
    caches = [None] * len(pairs)
    if out_dir is not None:
        Path(out_dir).mkdir(parents=True, exist_ok=True)
        caches = [os.fspath(c) for c in
                  _output_paths([p for p, _ in pairs], Path(out_dir), ".eval.json")]
    opts = dict(options, method=method, radius_m=radius_m)
    resolved = vlpground._detector(method, options.get("extrinsics"), options.get("detector"))
    rows = _run(client, evaluate_one, [(p, l, opts, c) for (p, l), c in zip(pairs, caches)])
    return rows + [_overall(rows, resolved.method, radius_m)]


def _overall(rows: Sequence[dict], method: str, radius_m: float) -> dict:
    ok = [r for r in rows if r.get("status") in ("done", "skipped")]
    total = {k: sum(int(r.get(k, 0)) for r in ok) for k in _COUNTS}
    precision, recall, f1 = _core._confusion_scores(total["tp"], total["fp"], total["fn"],
                                                    total["tn"])
    high = total["high_obstacles"]
    return dict(total, capture="overall", method=method, radius_m=radius_m,
                precision=precision, recall=recall, f1=f1,
                detect_ms_total=sum(float(r.get("detect_ms_total", 0.0)) for r in ok),
                high_obstacle_as_ground_rate=(total["high_obstacles_as_ground"] / high
                                              if high else 0.0),
                high_obstacle_terrain=_overall_terrain(ok),
                status="done" if len(ok) == len(rows) else
                f"{len(rows) - len(ok)} of {len(rows)} failed",
                error="")


def _overall_terrain(rows: Sequence[dict]) -> str:
    """How the terrain under the high obstacles of all rows was known: one way, or mixed."""
    ways = {r.get("high_obstacle_terrain", "none") for r in rows} - {"none"}
    return ways.pop() if len(ways) == 1 else ("mixed" if ways else "none")


def format_table(rows: Sequence[dict], columns: Sequence[str]) -> str:
    """Plain-text table of `rows` (missing values blank; floats with 4 decimals)."""
    def cell(v):
        return f"{v:.4f}" if isinstance(v, float) else ("" if v is None else str(v))
    text = [[c for c in columns]] + [[cell(r.get(c)) for c in columns] for r in rows]
    widths = [max(len(line[i]) for line in text) for i in range(len(columns))]
    return "\n".join("  ".join(v.ljust(w) for v, w in zip(line, widths)).rstrip()
                     for line in text)
