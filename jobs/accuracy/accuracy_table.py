#!/usr/bin/env python3
"""Table of each fidelity tier's error against the reference tier (docs/accuracy.md).

Reads OUT/<tier>/seed<k>/results.h5 written by jobs/accuracy/flow_accuracy.sh. Per run: the means
of the repose angle, the surface speed (also divided by the tumbler's speed omega R) and the
large-particle fraction of the wall shell over the samples at 40-80 degrees of rotation, and the
wall time of the protocol phase. Per tier: mean and 95% CI over replicas (Student t); the error
against the reference (or, without reference runs, the standard tier) is the difference of means
with its Welch 95% CI.
"""
import glob
import math
import os
import sys

import h5py
import numpy as np

T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262,
       10: 2.228, 15: 2.131, 20: 2.086, 30: 2.042}


def t95(dof):
    if dof <= 0:
        return float("nan")
    keys = sorted(T95)
    for k in keys:
        if dof <= k:
            return T95[k]
    return 1.96


def run_means(path):
    with h5py.File(path, "r") as f:
        t = f["series/time"][:]
        scene = f.attrs["scene"]
        scene = scene.decode() if isinstance(scene, bytes) else scene
        kv = dict(line.split(" = ", 1) for line in scene.splitlines() if " = " in line)
        rpm = float(kv["protocol.rpm"])
        radius = float(kv["tumbler.radius"])
        omega = 2 * math.pi * rpm / 60
        angle = np.degrees(omega * t)
        win = (angle >= 40) & (angle <= 80)
        rep = f["series/repose_angle"][:][win]
        spd = f["series/surface_speed"][:][win]
        wall = f["series/shell_large_fraction"][:][win]
        wall_s = float(f.attrs["particles"]) * float(f.attrs["steps"]) / float(
            f.attrs["particle_steps_per_second"])
        return {
            "repose angle (deg)": np.nanmean(rep),
            "surface speed (m/s)": np.nanmean(spd),
            "surface speed / (omega R)": np.nanmean(spd) / (omega * radius),
            "wall large fraction": np.nanmean(wall),
            "wall s": wall_s,
            "particles": int(f.attrs["particles"]),
            "rpm": rpm,
        }


def ci(values):
    v = np.asarray(values, float)
    n = len(v)
    m = v.mean()
    if n < 2:
        return m, float("nan"), v.var()
    sd = v.std(ddof=1)
    return m, t95(n - 1) * sd / math.sqrt(n), sd * sd


def welch(a, b):
    ma, _, va = ci(a)
    mb, _, vb = ci(b)
    na, nb = len(a), len(b)
    se2 = va / na + vb / nb
    dof = se2 * se2 / ((va / na) ** 2 / (na - 1) + (vb / nb) ** 2 / (nb - 1)) if se2 > 0 else 1
    return mb - ma, t95(int(dof)) * math.sqrt(se2)


def main():
    out = sys.argv[1]
    tiers = ["reference", "standard", "fast", "preview"]
    data = {}
    for tier in tiers:
        runs = [run_means(p) for p in sorted(glob.glob(os.path.join(out, tier, "seed*", "results.h5")))]
        if runs:
            data[tier] = runs
    base = "reference" if "reference" in data else "standard"
    if base not in data:
        sys.exit("no reference (or standard) runs in " + out)
    obs = ["repose angle (deg)", "surface speed (m/s)", "surface speed / (omega R)",
           "wall large fraction"]
    print("| tier | N | particles | rpm | wall s per run (1 core) | " +
          " | ".join(f"{o}: mean ± CI | error vs {base} ± CI" for o in obs) + " |")
    print("|---" * (5 + 2 * len(obs)) + "|")
    for tier in tiers:
        if tier not in data:
            continue
        runs = data[tier]
        cells = [tier, str(len(runs)), str(runs[0]["particles"]), f"{runs[0]['rpm']:.3g}",
                 f"{np.mean([r['wall s'] for r in runs]):.0f}"]
        for o in obs:
            m, h, _ = ci([r[o] for r in runs])
            cells.append(f"{m:.4g} ± {h:.2g}")
            if tier == base:
                cells.append("—")
            else:
                d, hd = welch([r[o] for r in data[base]], [r[o] for r in runs])
                cells.append(f"{d:+.3g} ± {hd:.2g}")
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
