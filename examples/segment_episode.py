#!/usr/bin/python3
"""Segment the pushed object of an episode (Motion-Likelihood, thesis Ch 4) and show the mask.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/segment_episode.py [EPISODE_DIR]
           [--out figure.png]

Without EPISODE_DIR, a push is first recorded with the simulated robot into a temporary
directory. The figure shows the first-touch frame, the probability map and the mask; it is saved
to --out (default segment.png), and shown on screen when there is a display.
"""
import argparse
import os
import tempfile

import matplotlib
import numpy as np

if not os.environ.get("DISPLAY"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from proprio.episode import Episode  # noqa: E402
from proprio.segmentation import MlOptions, segment_ml  # noqa: E402


def record_push(directory):
    from proprio.sim import SimulatedRobot, TableOptions
    with SimulatedRobot(TableOptions(objects=2, seed=3, width=320, height=240)) as robot:
        x, y, _ = robot.ground_truth()[0]["centre"]
        report = robot.push([x - 0.1, y], [x + 0.05, y], episode_dir=directory)
        print(report["message"])
    return directory


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("episode", nargs="?")
    ap.add_argument("--out", default="segment.png")
    a = ap.parse_args()
    path = a.episode or record_push(os.path.join(tempfile.mkdtemp(), "episode"))

    episode = Episode.read(path)
    result = segment_ml(episode, MlOptions())
    print(result["message"])
    if result["scored_frame"] < 0:
        return
    frame = episode.frame(result["scored_frame"])  # H x W x 3 uint8, RGB

    fig, axes = plt.subplots(1, 3, figsize=(12, 3.5))
    axes[0].imshow(frame)
    axes[0].set_title(f"frame {result['scored_frame']} (first touch)")
    axes[1].imshow(result["map"], cmap="magma", vmin=0, vmax=1)
    axes[1].set_title("motion likelihood")
    axes[2].imshow(frame)
    axes[2].imshow(np.ma.masked_where(result["mask"] == 0, result["mask"]), alpha=0.6,
                   cmap="autumn")
    axes[2].set_title("mask")
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)
    print(f"wrote {a.out}")
    if os.environ.get("DISPLAY"):
        plt.show()


if __name__ == "__main__":
    main()
