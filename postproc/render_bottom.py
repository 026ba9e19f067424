#!/usr/bin/python3
"""Bottom view of the tumbler wall (Yu 2022 Fig. 2, Fig. 11(b)): large and small particles in two
colours, seen by a camera under the tumbler looking up, as PNG; a time-lapse from several
snapshots (one PNG per frame, and an animated GIF).

usage: postproc/render_bottom.py SNAP.h5 [SNAP.h5 ...] [-o out.png | --frames DIR] [--gif out.gif]
       [--frame lab|tumbler] [--view ortho|lambert] [--size 800]

A small native rasteriser (matplotlib, no POV-Ray): an orthographic view along +y, X to the
right and Z up, which is the unmirrored picture from below that the Lambert maps use
(src/projection/lambert.hpp). Spheres are drawn as shaded discs, farthest first (painter's
algorithm), so the particles at the wall hide those behind them as in a photograph. `--view
lambert` instead places particles of the shell 0.9 < r/R < 1 at the Lambert image of their
direction (Fig. 10(b)). Snapshot layout: src/io/snapshot.cpp.
"""
import argparse
import os
import re

import h5py
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402

LARGE = np.array([0.15, 0.35, 0.85])  # blue, as the paper's large particles
SMALL = np.array([0.85, 0.2, 0.15])   # red, the small ones


def tumbler_radius(scene_text):
    m = re.search(r"^tumbler\.radius = ([0-9.eE+-]+)", scene_text, re.M)
    return float(m.group(1)) if m else None


def load(path, frame):
    with h5py.File(path, "r") as f:
        x = f["x_tumbler" if frame == "tumbler" else "x"][:]
        scene = f.attrs["scene"]
        scene = scene.decode() if isinstance(scene, bytes) else str(scene)
        return dict(x=x, r=f["radius"][:], species=f["species"][:],
                    time=float(f.attrs["time"]), iteration=float(f.attrs["iteration"]),
                    R=tumbler_radius(scene) or float(np.max(np.linalg.norm(x, axis=1))) * 1.02)


def draw(ax, s, view):
    x, r, sp, R = s["x"], s["r"], s["species"], s["R"]
    if view == "lambert":
        d = np.linalg.norm(x, axis=1)
        keep = (d > 0.9 * R) & (x[:, 1] <= 0)
        u = x[keep] / d[keep, None]
        k = 1.0 / np.sqrt(1.0 - u[:, 1])
        px, pz, depth = u[:, 0] * k, u[:, 2] * k, -d[keep]
        size = 2 * r[keep] / R * 0.9  # a particle's angular size, roughly, on the unit disc
        sp = sp[keep]
        lim = 1.0
    else:
        px, pz, depth = x[:, 0] / R, x[:, 2] / R, x[:, 1]
        size = 2 * r / R
        lim = 1.0
    order = np.argsort(-depth)  # farthest from the camera (largest y) first
    base = np.where(sp[order, None] == 1, LARGE, SMALL)
    # Depth cue: particles deeper in the bed (away from the wall) are darker.
    dn = (depth[order] - depth.min()) / max(np.ptp(depth), 1e-12)
    shade = 1.0 - 0.55 * dn
    colours = np.clip(base * shade[:, None], 0, 1)
    ec = EllipseCollection(size[order], size[order], np.zeros(len(order)), units="xy",
                           offsets=np.column_stack([px[order], pz[order]]),
                           transOffset=ax.transData, facecolors=colours,
                           edgecolors=np.clip(colours * 0.6, 0, 1), linewidths=0.2)
    ax.add_collection(ec)
    ax.add_patch(plt.Circle((0, 0), lim, fill=False, color="0.3", lw=1.0))
    ax.set_xlim(-1.05 * lim, 1.05 * lim)
    ax.set_ylim(-1.05 * lim, 1.05 * lim)
    ax.set_aspect("equal")
    ax.set_facecolor("0.08")
    ax.set_xticks([])
    ax.set_yticks([])


def render(path, out, frame, view, size_px, title=True):
    s = load(path, frame)
    dpi = 100
    fig = plt.figure(figsize=(size_px / dpi, size_px / dpi), dpi=dpi)
    ax = fig.add_axes([0, 0, 1, 1])
    draw(ax, s, view)
    if title:
        nl = int(np.sum(s["species"] == 1))
        ax.text(0.02, 0.98, f"N = {s['iteration']:.2f}  t = {s['time']:.2f} s  "
                f"({len(s['r'])} particles, {nl} large)  view from below",
                transform=ax.transAxes, va="top", color="w", fontsize=9)
    fig.savefig(out, dpi=dpi, facecolor="0.08")
    plt.close(fig)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("snapshots", nargs="+")
    ap.add_argument("-o", "--output", help="PNG of the last snapshot (default bottom_view.png)")
    ap.add_argument("--frames", help="directory for one PNG per snapshot (time-lapse)")
    ap.add_argument("--gif", help="animated GIF of the frames (needs Pillow)")
    ap.add_argument("--frame", choices=["lab", "tumbler"], default="lab")
    ap.add_argument("--view", choices=["ortho", "lambert"], default="ortho")
    ap.add_argument("--size", type=int, default=800, help="pixels per side")
    a = ap.parse_args()
    if a.frames or a.gif:
        fdir = a.frames or os.path.splitext(a.gif)[0] + "_frames"
        os.makedirs(fdir, exist_ok=True)
        pngs = [render(p, os.path.join(fdir, f"frame_{k:04d}.png"), a.frame, a.view, a.size)
                for k, p in enumerate(a.snapshots)]
        print(f"wrote {len(pngs)} frames in {fdir}")
        if a.gif:
            from PIL import Image
            imgs = [Image.open(p).convert("P", palette=Image.ADAPTIVE) for p in pngs]
            imgs[0].save(a.gif, save_all=True, append_images=imgs[1:], duration=500, loop=0)
            print(f"wrote {a.gif}")
    if a.output or not (a.frames or a.gif):
        out = a.output or "bottom_view.png"
        render(a.snapshots[-1], out, a.frame, a.view, a.size)
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
