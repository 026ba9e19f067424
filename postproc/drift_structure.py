#!/usr/bin/python3
"""The structure of a measured drift grid (`tumble cm drift --merge`, docs/cm.md "Drift-grid
file"), as docs/validation.md reports it for issue 17 D4:

  /usr/bin/python3 postproc/drift_structure.py DRIFT.h5 [--quarters 4]

* the poleward component v_ax sign(z) of the samples in each streamwise band of the layer's
  footprint x^2 + z^2 < 1 (x: downstream, in R), sample-weighted, with 1.96 standard errors of
  the samples (consecutive samples of one particle are correlated, so this is too narrow), and
  pooled over the whole footprint: App. A's synthetic field is poleward everywhere;
* <|v_ax|> over the footprint cells with >= 2 samples (v_ax = 0 elsewhere, as the MCM reads it),
  against what sampling noise alone would give, sqrt(2/pi) sigma / sqrt(count) per cell: how
  much of the mean drift speed is the estimate's noise.
"""
import argparse
import sys

import h5py
import numpy as np


def structure(count, total, total2, bands):
    """Per band (x_lo, x_hi, poleward mean, 1.96 se, samples), the pooled poleward mean,
    <|v_ax|> and its noise-only expectation."""
    n = count.shape[0]
    c = (np.arange(n) + 0.5) / n * 2 - 1
    x, z = np.meshgrid(c, c, indexing="ij")
    foot = x * x + z * z < 1
    pole = np.sign(z)
    rows = []
    edges = np.linspace(-1, 1, bands + 1)
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = foot & (x >= lo) & (x < hi) & (count > 0)
        k = count[m].sum()
        if k <= 1:
            rows.append((lo, hi, np.nan, np.nan, k))
            continue
        mean = (total * pole)[m].sum() / k
        var = max(total2[m].sum() / k - mean * mean, 0.0) * k / (k - 1)
        rows.append((lo, hi, mean, 1.96 * np.sqrt(var / k), k))
    m = foot & (count > 0)
    pooled = (total * pole)[m].sum() / count[m].sum()
    ok = foot & (count >= 2)
    mean = np.where(count > 0, total / np.maximum(count, 1), 0.0)
    var = np.where(ok, (total2 - count * mean * mean) / np.maximum(count - 1, 1), 0.0)
    speed = np.mean(np.abs(np.where(ok, mean, 0.0))[foot])
    noise = np.mean(np.where(ok, np.sqrt(2 / np.pi * np.maximum(var, 0) / np.maximum(count, 1)), 0.0)[foot])
    return rows, pooled, speed, noise


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("grid")
    ap.add_argument("--quarters", type=int, default=4, help="streamwise bands (default 4)")
    a = ap.parse_args()
    if not 1 <= a.quarters <= 100:
        sys.exit(f"--quarters must be in [1, 100] (got {a.quarters})")
    with h5py.File(a.grid, "r") as f:
        if "count" not in f:
            sys.exit(f"{a.grid}: no per-cell statistics (count, sum, sum2): a synthetic grid has "
                     "no samples; give a measured one (output.drift_grid = on, or cm drift --merge)")
        count, total, total2 = f["count"][:], f["sum"][:], f["sum2"][:]
    rows, pooled, speed, noise = structure(count, total, total2, a.quarters)
    print(f"{a.grid}: {int(count.sum())} samples; median {np.median(count[count > 0]):g} per sampled cell")
    print("| streamwise band x/R | poleward v_ax sign(z) [omega R] | samples |")
    print("|---|---|---|")
    for lo, hi, m, h, k in rows:
        print(f"| [{lo:+.2f}, {hi:+.2f}) | {m:+.3f} ± {h:.3f} | {int(k)} |")
    print(f"pooled over the footprint: {pooled:+.3f} omega R (> 0: poleward)")
    print(f"<|v_ax|> = {speed:.3f} omega R; sampling noise alone would give {noise:.3f}")


if __name__ == "__main__":
    main()
