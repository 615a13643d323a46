"""The work of one task (runs on a Dask worker, or in-process without a client).

Task functions never raise: a capture that fails becomes a row with status "failed" and its
error, so one bad file does not take down the batch.
"""
from __future__ import annotations

import json
import os
import time
import traceback
from pathlib import Path

import vlpground

from ._writers import WRITERS

DONE_SUFFIX = ".done.json"


def done_marker(output: Path) -> Path:
    return output.with_name(output.name + DONE_SUFFIX)


def _failed(row: dict, error: BaseException) -> dict:
    row.update(status="failed", error=f"{type(error).__name__}: {error}",
               traceback=traceback.format_exc(limit=5))
    return row


def label_one(pcap: str, output: str, fmt: str, reader_options: dict) -> dict:
    """Labels every frame of `pcap` into `output`; skips a capture already done."""
    out = Path(output)
    row = {"capture": pcap, "output": output, "status": "done", "error": "", "frames": 0,
           "returns": 0, "ground_returns": 0, "seconds": 0.0}
    marker = done_marker(out)
    if out.exists() and marker.exists():
        try:
            row.update(json.loads(marker.read_text()), status="skipped")
            return row
        except (OSError, ValueError):
            pass  # unreadable marker: label again
    start = time.monotonic()
    tmp = out.with_name(out.name + f".tmp-{os.getpid()}")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        writer = WRITERS[fmt](tmp)
        try:
            for frame in vlpground.read_pcap(pcap, **reader_options):
                writer.write(frame)
                row["frames"] += 1
                row["returns"] += frame.returns
                row["ground_returns"] += frame.ground_returns
        finally:
            writer.close()
        os.replace(tmp, out)
        row["seconds"] = time.monotonic() - start
        summary = {k: row[k] for k in ("frames", "returns", "ground_returns", "seconds")}
        marker_tmp = marker.with_name(marker.name + f".tmp-{os.getpid()}")
        marker_tmp.write_text(json.dumps(dict(summary, capture=pcap, format=fmt,
                                              method=reader_options.get("method"))))
        os.replace(marker_tmp, marker)
    except Exception as error:  # noqa: BLE001 (reported in the result table)
        for leftover in tmp.parent.glob(tmp.name + "*"):
            leftover.unlink(missing_ok=True)
        return _failed(row, error)
    return row


def evaluate_one(pcap: str, labels: str, options: dict, cache: str | None) -> dict:
    """vlpground.evaluate on one capture; with `cache`, a result saved there is reused."""
    row = {"capture": Path(pcap).stem, "pcap": pcap, "labels": labels, "status": "done",
           "error": ""}
    if cache and Path(cache).exists():
        try:
            row.update(json.loads(Path(cache).read_text()), status="skipped")
            return row
        except (OSError, ValueError):
            pass
    try:
        row.update(vlpground.evaluate(pcap, labels, **options))
        if cache:
            Path(cache).parent.mkdir(parents=True, exist_ok=True)
            tmp = Path(cache + f".tmp-{os.getpid()}")
            tmp.write_text(json.dumps({k: v for k, v in row.items()
                                       if k not in ("status", "error")}))
            os.replace(tmp, cache)
    except Exception as error:  # noqa: BLE001 (reported in the result table)
        return _failed(row, error)
    return row
