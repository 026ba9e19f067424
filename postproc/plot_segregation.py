#!/usr/bin/python3
"""Radial segregation over protocol iterations: the large-particle volume fraction among particles
whose centres lie in the shell 0.9 < r/R < 1, against the bed average (Yu 2022 Sec. II).

usage: postproc/plot_segregation.py RUN_DIR [RUN_DIR ...] [-o out.png]
Reads RUN_DIR/results.h5, or RUN_DIR/checkpoint.h5 for a run still in progress. Prints a table
(iteration, shell fraction, bed fraction, enrichment) and writes the plot.
"""
import argparse
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(run_dir):
    for name in ("results.h5", "checkpoint.h5"):
        path = os.path.join(run_dir, name)
        if os.path.exists(path):
            with h5py.File(path, "r") as f:
                s = {k: f["series/" + k][:] for k in f["series"]}
            return s, path
    raise SystemExit(f"{run_dir}: no results.h5 or checkpoint.h5")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("-o", "--output", default="segregation.png")
    args = ap.parse_args()
    fig, ax = plt.subplots(figsize=(6.4, 4))
    for run in args.runs:
        s, path = load(run)
        label = os.path.basename(os.path.normpath(run))
        print(f"# {path}\n# iteration  shell_large_fraction  bed_large_fraction  enrichment")
        for it, sh, bd in zip(s["iteration"], s["shell_large_fraction"], s["bed_large_fraction"]):
            print(f"{it:9.3f}  {sh:20.4f}  {bd:18.4f}  {sh / bd if bd > 0 else float('nan'):10.3f}")
        ax.plot(s["iteration"], s["shell_large_fraction"], label=f"{label}: shell 0.9 < r/R < 1")
        ax.plot(s["iteration"], s["bed_large_fraction"], "--", label=f"{label}: whole bed")
    ax.set_xlabel("protocol iteration N")
    ax.set_ylabel("large-particle volume fraction")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
