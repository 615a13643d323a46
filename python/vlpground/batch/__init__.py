"""Label or evaluate many captures in parallel on a Dask cluster.

    from dask.distributed import Client
    from vlpground import batch
    client = Client("tcp://scheduler:8786")          # or LocalCluster(...), or None
    rows = batch.label_captures(paths, "/shared/labels", client=client, format="npz")
    table = batch.evaluate_captures([(pcap, labels), ...], client=client)

One task per capture. Each task writes its result under ``out_dir``, which must be a path
every worker can write (a shared filesystem on a real cluster). A capture that fails is a
row with ``status == "failed"`` and its ``error``; the others complete. A re-run skips
captures whose output is complete (``status == "skipped"``). Without a client the current
default Dask client is used if there is one, else the captures run one by one in this
process. Command line: ``python3 -m vlpground.batch --help``.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable, List, Optional, Sequence, Tuple

import vlpground
from vlpground import _core

from ._tasks import evaluate_one, label_one
from ._writers import FORMATS, check_format, parquet_available, read_npz

__all__ = ["label_captures", "evaluate_captures", "format_table", "read_npz", "FORMATS",
           "parquet_available"]

# Figures of each row of evaluate_captures, as `vlpground eval --json`.
EVAL_FIELDS = ("capture", "method", "radius_m", "frames", "precision", "recall", "f1", "tp",
               "fp", "fn", "tn", "detect_ms_total", "high_obstacle_as_ground_rate")
_COUNTS = ("frames", "tp", "fp", "fn", "tn", "high_obstacles", "high_obstacles_as_ground")


def _default_client(client):
    if client is not None:
        return client
    try:
        from distributed import default_client
        return default_client()
    except (ImportError, ValueError):
        return None


def _run(client, fn, jobs: Sequence[tuple], keys: Sequence[str]) -> List[dict]:
    """Runs fn(*job) for every job, on `client` (one task each) or here; rows in job order."""
    client = _default_client(client)
    if client is None:
        return [fn(*job) for job in jobs]
    from distributed import as_completed
    futures = [client.submit(fn, *job, key=key, pure=False) for job, key in zip(jobs, keys)]
    index = {f.key: i for i, f in enumerate(futures)}
    rows: List[Optional[dict]] = [None] * len(futures)
    for future in as_completed(futures):
        i = index[future.key]
        try:
            rows[i] = future.result()
        except Exception as error:  # noqa: BLE001 (a worker died: KilledWorker, ...)
            rows[i] = {"capture": str(jobs[i][0]), "pcap": str(jobs[i][0]), "status": "failed",
                       "error": f"{type(error).__name__}: {error}"}
        future.release()
    return rows  # type: ignore[return-value]


def _task_key(kind: str, path: str) -> str:
    return f"vlpground-{kind}-{Path(path).name}-{os.urandom(4).hex()}"


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
                   client=None, method: str = "tangent", format: str = "npz",
                   **read_options) -> List[dict]:
    """Labels every capture into ``out_dir/STEM.{npz,csv,parquet}``.

    ``read_options`` are those of vlpground.read_pcap (extrinsics, calibration, model,
    cut_angle_deg, sensor_ip, port, detector, ...). Formats (all one row per valid return,
    in the CLI's CSV order): ``npz`` (a flat array per column: frame, laser_id, ring,
    return, time_ns, azimuth_deg, distance_m, x, y, z, intensity, label; read with
    vlpground.batch.read_npz or numpy.load), ``csv`` (exactly the CLI's --csv),
    ``parquet`` (same columns as npz; needs pyarrow, not packaged in Debian 12: a clear
    ValueError without it).

    Returns one row per capture, in order: capture, output, status ("done", "skipped" or
    "failed"), error, frames, returns, ground_returns, seconds.
    """
    check_format(format)
    paths = [os.fspath(p) for p in paths]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    outputs = _output_paths(paths, out, "." + format)
    options = dict(read_options, method=method)
    vlpground._detector(method, options.get("extrinsics"), options.get("detector"))  # validate
    jobs = [(p, os.fspath(o), format, options) for p, o in zip(paths, outputs)]
    return _run(client, label_one, jobs, [_task_key("label", p) for p in paths])


def evaluate_captures(pairs: Iterable[Tuple[os.PathLike | str, os.PathLike | str]], *,
                      client=None, method: str = "tangent", radius_m: float = 40.0,
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
    jobs = [(p, l, opts, c) for (p, l), c in zip(pairs, caches)]
    rows = _run(client, evaluate_one, jobs, [_task_key("eval", p) for p, _ in pairs])
    return rows + [_overall(rows, method, radius_m)]


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
                status="done" if len(ok) == len(rows) else
                f"{len(rows) - len(ok)} of {len(rows)} failed",
                error="")


def format_table(rows: Sequence[dict], columns: Sequence[str]) -> str:
    """Plain-text table of `rows` (missing values blank; floats with 4 decimals)."""
    def cell(v):
        return f"{v:.4f}" if isinstance(v, float) else ("" if v is None else str(v))
    text = [[c for c in columns]] + [[cell(r.get(c)) for c in columns] for r in rows]
    widths = [max(len(line[i]) for line in text) for i in range(len(columns))]
    return "\n".join("  ".join(v.ljust(w) for v, w in zip(line, widths)).rstrip()
                     for line in text)
