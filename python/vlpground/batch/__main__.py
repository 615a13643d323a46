"""python3 -m vlpground.batch: label or evaluate captures on a Dask cluster.

    python3 -m vlpground.batch label CAPTURE.pcap... --out DIR [--format npz|csv|parquet]
                                     [--slice-frames N]
    python3 -m vlpground.batch eval CAPTURE.pcap... [--labels-dir DIR] [--out DIR] [--json]

Runs on the scheduler given by --scheduler ADDR (e.g. tcp://10.0.0.5:8786), else on a local
cluster of --workers N processes (loopback only). Exit status 1 when a capture failed.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from . import EVAL_FIELDS, FORMATS, evaluate_captures, format_table, label_captures

LABEL_COLUMNS = ("capture", "status", "frames", "returns", "ground_returns", "seconds", "error")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python3 -m vlpground.batch", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    for name, help_text in (("label", "write the labelled returns of each capture"),
                            ("eval", "score each capture against its .labels ground truth")):
        s = sub.add_parser(name, help=help_text)
        s.add_argument("captures", nargs="+", type=Path, help="pcap/pcapng files")
        s.add_argument("--method", default="tangent", choices=("tangent", "ransac", "lpr"))
        s.add_argument("--scheduler", metavar="ADDR",
                       help="Dask scheduler address (default: a local cluster)")
        s.add_argument("--workers", type=int, default=2, metavar="N",
                       help="worker processes of the local cluster (default 2)")
        s.add_argument("--json", action="store_true", help="print the rows as JSON")
        if name == "label":
            s.add_argument("--out", type=Path, required=True, metavar="DIR",
                           help="output folder, writable by every worker")
            s.add_argument("--format", default="npz", choices=FORMATS)
            s.add_argument("--slice-frames", type=int, metavar="N",
                           help="cut each capture into tasks of N frames (long captures)")
        else:
            s.add_argument("--labels-dir", type=Path, metavar="DIR",
                           help="where STEM.labels are (default: beside each capture)")
            s.add_argument("--radius", type=float, default=40.0, metavar="M")
            s.add_argument("--out", type=Path, metavar="DIR",
                           help="save each result there; a re-run skips those scored")
    return p


def _client(args):
    from distributed import Client, LocalCluster
    if args.scheduler:
        return Client(args.scheduler), None
    if args.workers < 1:
        raise SystemExit("--workers must be >= 1")
    cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    return Client(cluster), cluster


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    client, cluster = _client(args)
    try:
        if args.command == "label":
            rows = label_captures(args.captures, args.out, client=client, method=args.method,
                                  format=args.format, slice_frames=args.slice_frames)
            columns = LABEL_COLUMNS
        else:
            labels_dir = args.labels_dir
            pairs = [(c, (labels_dir / c.name if labels_dir else c).with_suffix(".labels"))
                     for c in args.captures]
            rows = evaluate_captures(pairs, client=client, method=args.method,
                                     radius_m=args.radius, out_dir=args.out)
            columns = EVAL_FIELDS + ("status", "error")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    if args.json:
        print(json.dumps([{k: v for k, v in r.items() if k != "traceback"} for r in rows],
                         indent=2, default=str))
    else:
        print(format_table(rows, columns))
    return 1 if any(r.get("status") == "failed" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
