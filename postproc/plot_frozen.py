#!/usr/bin/python3
"""The rigid bulk's frozen share over a run (fidelity.bulk = "rigid", docs/accuracy.md): the share
of the bed frozen at each analysis sample, against the protocol's iteration, with the biaxial
protocol's segment changes marked (tilt by beta, rotate theta_z, tilt back, then the same about x:
each change thaws the bed, which refreezes one dwell later).

usage: postproc/plot_frozen.py RUN_DIR [RUN_DIR ...] [-o out.png]
Reads RUN_DIR/results.h5 (series/frozen_fraction, series/iteration) and the resolved scene text
stored with it (protocol.mode, theta_z, theta_x and the repose tilt used). Prints the mean frozen
share per segment and writes the plot.
"""
import argparse
import os
import re

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def scene_value(text, key):
    m = re.search(r"^" + re.escape(key) + r" = (.*)$", text, re.M)
    return m.group(1).strip().strip('"') if m else None


def load(run_dir):
    path = os.path.join(run_dir, "results.h5")
    if not os.path.exists(path):
        raise SystemExit(f"{run_dir}: no results.h5")
    with h5py.File(path, "r") as f:
        if "series/frozen_fraction" not in f:
            raise SystemExit(f"{path}: no series/frozen_fraction (a run with fidelity.bulk = 'dynamic'?)")
        frozen = f["series/frozen_fraction"][:]
        iteration = f["series/iteration"][:]
        text = f.attrs.get("scene", b"")
        text = text.decode() if isinstance(text, bytes) else str(text)
    return frozen, iteration, text


def segment_edges(text):
    """Fractions of an iteration where the biaxial protocol's six segments end (all run at the
    same angular speed, so the fractions are the angles' shares). The stored scene is the
    resolved one: a measured tilt is written there as its number."""
    if scene_value(text, "protocol.mode") != "biaxial":
        return []
    tz = float(scene_value(text, "protocol.theta_z"))
    tx = float(scene_value(text, "protocol.theta_x"))
    try:
        beta = float(scene_value(text, "protocol.repose"))
    except (TypeError, ValueError):
        return []
    angles = np.cumsum([beta, tz, beta, beta, tx, beta])
    return list(angles / angles[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("-o", "--output", default="frozen.png")
    args = ap.parse_args()
    fig, ax = plt.subplots(figsize=(7, 3.2))
    edges = []
    for run in args.runs:
        frozen, iteration, text = load(run)
        ax.plot(iteration, frozen, lw=1, label=os.path.basename(os.path.normpath(run)))
        edges = segment_edges(text) or edges
        print(f"{run}: {len(frozen)} samples, mean frozen share {frozen.mean():.3f}")
        if edges:
            lo = 0.0
            for k, hi in enumerate(edges):
                m = (iteration % 1 >= lo) & (iteration % 1 < hi)
                if m.any():
                    print(f"  segment {k + 1} ({lo:.3f}-{hi:.3f} of an iteration): mean {frozen[m].mean():.3f}")
                lo = hi
    for e in edges[:-1]:
        ax.axvline(e, color="0.6", lw=0.6, ls=":")
    ax.set_xlabel("protocol iteration")
    ax.set_ylabel("share of the bed frozen")
    ax.set_ylim(0, 1)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.output, dpi=130)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
