"""The work of one task (runs on a Dask worker, or in-process without a client).

Label and evaluate tasks never raise: a capture that fails becomes a row with status
"failed" and its error, so one bad file does not take down the batch. Every file is
written under a temporary name and renamed when complete; a `.done.json` marker beside it,
written last, says it is whole and holds its counts.
"""
from __future__ import annotations

import json
import os
import time
import traceback
from pathlib import Path
from typing import List, Optional

import vlpground

from ._writers import WRITERS

DONE_SUFFIX = ".done.json"
COUNTS = ("frames", "returns", "ground_returns", "seconds")


def done_marker(output: Path) -> Path:
    return output.with_name(output.name + DONE_SUFFIX)


def part_path(output: Path, index: int) -> Path:
    """Where slice `index` of a capture labelled into `output` is written."""
    return output.with_name(f"{output.name}.part{index:05d}")


def failed(row: dict, error: BaseException, with_traceback: bool = True) -> dict:
    row.update(status="failed", error=f"{type(error).__name__}: {error}")
    if with_traceback:
        row["traceback"] = traceback.format_exc(limit=5)
    return row


def _tmp(path: Path) -> Path:
    return path.with_name(f"{path.name}.tmp-{os.getpid()}")


def _remove_tmp(path: Path) -> None:
    for leftover in path.parent.glob(_tmp(path).name + "*"):
        leftover.unlink(missing_ok=True)


def _write_marker(output: Path, summary: dict) -> None:
    marker = done_marker(output)
    tmp = _tmp(marker)
    tmp.write_text(json.dumps(summary))
    os.replace(tmp, marker)


def label_row(pcap: str, output: str) -> dict:
    return {"capture": pcap, "output": output, "status": "done", "error": "", "frames": 0,
            "returns": 0, "ground_returns": 0, "seconds": 0.0}


def done_row(pcap: str, output: str) -> Optional[dict]:
    """The row of a capture labelled before (status "skipped"), or None."""
    out = Path(output)
    marker = done_marker(out)
    if not (out.exists() and marker.exists()):
        return None
    try:
        summary = json.loads(marker.read_text())
    except (OSError, ValueError):
        return None  # unreadable marker: label again
    row = label_row(pcap, output)
    row.update({k: summary[k] for k in COUNTS if k in summary}, status="skipped")
    return row


def label_one(pcap: str, output: str, fmt: str, reader_options: dict) -> dict:
    """Labels the frames of `pcap` (all, or the slice the options select) into `output`;
    skips it when done before."""
    previous = done_row(pcap, output)
    if previous is not None:
        return previous
    out = Path(output)
    row = label_row(pcap, output)
    start = time.monotonic()
    tmp = _tmp(out)
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
        _write_marker(out, dict({k: row[k] for k in COUNTS}, capture=pcap, format=fmt,
                                method=reader_options.get("method")))
    except Exception as error:  # noqa: BLE001 (reported in the result table)
        _remove_tmp(out)
        return failed(row, error)
    return row


def count_one(pcap: str, reader_options: dict) -> int:
    """Frames of `pcap` (decoding only); raises on an unreadable capture."""
    return vlpground.count_frames(pcap, **reader_options)


def merge_parts(pcap: str, output: str, fmt: str, parts: List[str]) -> dict:
    """Joins the slices of a capture, in order, into `output`; removes them when done."""
    out = Path(output)
    row = label_row(pcap, output)
    tmp = _tmp(out)
    try:
        writer = WRITERS[fmt](tmp)
        try:
            for part in parts:
                writer.append_part(Path(part))
                summary = json.loads(done_marker(Path(part)).read_text())
                for k in COUNTS:
                    row[k] += summary[k]
        finally:
            writer.close()
        os.replace(tmp, out)
        _write_marker(out, dict({k: row[k] for k in COUNTS}, capture=pcap, format=fmt,
                                slices=len(parts)))
        for part in parts:
            Path(part).unlink(missing_ok=True)
            done_marker(Path(part)).unlink(missing_ok=True)
    except Exception as error:  # noqa: BLE001 (reported in the result table)
        _remove_tmp(out)
        return failed(row, error)
    row["slices"] = len(parts)
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
            tmp = _tmp(Path(cache))
            tmp.write_text(json.dumps({k: v for k, v in row.items()
                                       if k not in ("status", "error")}))
            os.replace(tmp, cache)
    except Exception as error:  # noqa: BLE001 (reported in the result table)
        return failed(row, error)
    return row
