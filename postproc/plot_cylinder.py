#!/usr/bin/env python3
"""Plots of a rotating-cylinder run (Rapaport 2007): S_a and S_r against revolutions (Figs. 5, 9),
the axial and radial space-time plots (Figs. 1, 3, 8, 13) and the surface profiles (Fig. 15).

  /usr/bin/python3 postproc/plot_cylinder.py RESULTS.h5 [RESULTS2.h5 ...] --out DIR

RESULTS.h5 is a run's results.h5 or checkpoint.h5 (both hold the group `cylinder/`). Several files
are overlaid in the S_a/S_r plot (e.g. k_g = 500 against k_g = 0) and get one space-time figure
each. Colours as the paper: red big-rich, blue small-rich, relative to the bed's mean.
"""
import argparse
import os
import re

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path):
    with h5py.File(path, "r") as f:
        g = f["cylinder"]
        d = {k: g[k][()] for k in g}
        d["scene"] = f.attrs.get("scene", b"")
    d["label"] = os.path.basename(os.path.dirname(os.path.abspath(path))) or path
    return d


def space_time(ax, rev, rows, extent_hi, ylabel):
    data = np.where(rows < 0, np.nan, rows)
    mean = np.nanmean(data)
    im = ax.imshow((data - mean).T, origin="lower", aspect="auto", cmap="coolwarm",
                   vmin=-0.5, vmax=0.5, extent=[rev[0], rev[-1], 0, extent_hi])
    ax.set_ylabel(ylabel)
    return im


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("results", nargs="+")
    ap.add_argument("--out", default=".")
    ap.add_argument("--labels", nargs="*", help="legend labels, one per file")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    runs = [load(p) for p in a.results]
    if a.labels:
        for r, lab in zip(runs, a.labels):
            r["label"] = lab

    fig, ax = plt.subplots(figsize=(6.5, 3.6))
    for r in runs:
        ax.plot(r["revolutions"], r["Sr"], label=f"S_r {r['label']}")
        ax.plot(r["revolutions"], r["Sa"], "--", label=f"S_a {r['label']}")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("revolutions")
    ax.set_ylabel("segregation")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "cylinder_segregation.png"), dpi=130)
    plt.close(fig)

    for r in runs:
        rev = r["revolutions"]
        tag = re.sub(r"[^A-Za-z0-9_.-]+", "_", r["label"]).strip("_")
        fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.5, 5), sharex=True)
        n_ax = r["axial_profile"].shape[1]
        space_time(ax1, rev, r["axial_profile"], n_ax, "axial slice")
        im = space_time(ax2, rev, r["radial_profile"], r["radial_profile"].shape[1],
                        "depth below surface (bins)")
        ax2.set_xlabel("revolutions")
        ax1.set_title(f"{r['label']}: big-particle volume fraction minus mean")
        fig.colorbar(im, ax=[ax1, ax2], shrink=0.8)
        fig.savefig(os.path.join(a.out, f"cylinder_space_time_{tag}.png"), dpi=130)
        plt.close(fig)

        # Surface profiles averaged over the last ten samples (Fig. 15).
        k = min(10, len(rev))
        x = r["surface_x"]
        fig, ax = plt.subplots(figsize=(5, 3.4))
        ax.plot(x, np.nanmean(r["surface_large"][-k:], axis=0), "o", ms=4, label="big")
        ax.plot(x, np.nanmean(r["surface_small"][-k:], axis=0), ".", label="small")
        ax.set_xlabel("x (across the cylinder)")
        ax.set_ylabel("surface height (particle centres)")
        ax.set_title(f"{r['label']}: surface, last {k} samples")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, f"cylinder_surface_{tag}.png"), dpi=130)
        plt.close(fig)
    print("plots in", a.out)


if __name__ == "__main__":
    main()
