# %% [markdown]
# # vlpground from Python: a capture, its bird's-eye view and the F1 score
#
# Notebook-style script (cells marked `# %%`; runs as a plain script too):
#
#     PYTHONPATH=build/python python3 examples/notebook_birdseye.py [CAPTURE.pcap] [--out view.png]
#
# Default capture: pcaps/urban_demo.pcap (with its .labels ground truth beside it).

# %%
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files, no window; drop this line in a notebook
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import vlpground  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("capture", nargs="?", type=Path,
                    default=Path(__file__).resolve().parents[1] / "pcaps" / "urban_demo.pcap")
parser.add_argument("--out", type=Path, default=Path("birdseye.png"))
args = parser.parse_args()

# %% Read the capture: one labelled frame per rotation; keep the first complete one.
frames = list(vlpground.read_pcap(args.capture))
frame = next(f for f in frames if f.meta.complete)
print(f"{len(frames)} frames; frame {frame.meta.sequence}: {frame.columns} columns, "
      f"{frame.returns} returns, {frame.ground_returns} ground, {frame.meta.rpm:.0f} rpm")

# %% Bird's-eye view: ground green, obstacles red, within 30 m.
pts = frame.to_numpy_points(["x", "y", "label"])
near = np.hypot(pts[:, 0], pts[:, 1]) < 30
ground = pts[near & (pts[:, 2] == 1)]
obstacle = pts[near & (pts[:, 2] == 2)]
fig, ax = plt.subplots(figsize=(7, 7))
ax.scatter(ground[:, 0], ground[:, 1], s=0.5, c="tab:green", label="ground")
ax.scatter(obstacle[:, 0], obstacle[:, 1], s=0.5, c="tab:red", label="obstacle")
cx, cy = frame.partition_centre
ax.plot([cx], [cy], "k+", markersize=12)
ax.annotate("partition centre", (cx, cy), textcoords="offset points", xytext=(6, 6))
ax.set(aspect="equal", xlabel="x (m, forward)", ylabel="y (m, left)",
       title=f"{args.capture.name}, frame {frame.meta.sequence} ({frame.method})")
ax.legend(loc="upper right", markerscale=10)
fig.savefig(args.out, dpi=120, bbox_inches="tight")
print(f"bird's-eye view: {args.out}")

# %% F1 against the ground truth (the same figures as `vlpground eval --json`).
labels = args.capture.with_suffix(".labels")
if labels.exists():
    score = vlpground.evaluate(args.capture, labels)
    print(f"F1 {score['f1']:.4f} (precision {score['precision']:.4f}, recall "
          f"{score['recall']:.4f}) over {score['frames']} frames")
else:
    print(f"no ground truth ({labels.name}) beside the capture: F1 not computed")
