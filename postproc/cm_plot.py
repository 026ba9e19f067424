#!/usr/bin/env python3
"""Pictures of the continuum model's HDF5 files (layouts in docs/cm.md).

Every panel is the Lambert projection viewed from below (X right, Z up): the bulk part of the
shell fills the disc |v| < rim, the flowing-layer cap the thin ring rim < |v| < outer.

  cm_plot.py section POINCARE.h5 [--orbits ORBITS.h5] -o section.png   (Yu 2022 Fig. 1(a))
  cm_plot.py kam ORBITS.h5 -o kam.png                                   (Fig. 1(b))
  cm_plot.py manifolds MANIFOLDS.h5 [--orbits ORBITS.h5] -o manifolds.png
  cm_plot.py mcm MCM.h5 [--orbits ORBITS.h5] -o mcm.png                 (Fig. 9 column)
"""
import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_islands(path, r=None):
    """Island polygons [(r, period, vertices)] of an orbits file, optionally of one shell."""
    with h5py.File(path, "r") as f:
        verts = f["islands/vertices"][()].reshape(-1, 2)
        offs = f["islands/offsets"][()]
        radii = f["islands/r"][()]
        period = f["islands/period"][()]
    out = []
    for k in range(len(radii)):
        if r is None or abs(radii[k] - r) < 1e-9:
            out.append((radii[k], period[k], verts[offs[k]:offs[k + 1]]))
    return out


def read_points(path):
    with h5py.File(path, "r") as f:
        return f["points/chart"][()].reshape(-1, 2), f["points/type"][()], f["points/period"][()]


def frame(ax, f, title):
    """Unit-less chart axes with the rim (interface) and outer circle drawn."""
    t = np.linspace(0, 2 * np.pi, 400)
    rim, outer = f.attrs["chart_rim"], f.attrs["chart_outer"]
    ax.plot(rim * np.cos(t), rim * np.sin(t), color="0.6", lw=0.6)
    ax.plot(outer * np.cos(t), outer * np.sin(t), color="0.6", lw=0.6, ls=":")
    ax.set_aspect("equal")
    ax.set_xlim(-1.08, 1.08)
    ax.set_ylim(-1.08, 1.08)
    ax.set_xlabel("X (Lambert, from below)")
    ax.set_ylabel("Z")
    ax.set_title(title, fontsize=10)


def protocol_title(f):
    return "(%g°, %g°), eps = %g, r = %g" % (
        f.attrs["theta_z_deg"], f.attrs["theta_x_deg"], f.attrs["eps"], f.attrs["r"])


def peclet_text(pe):
    """Pe as `tumble cm mcm` prints it: NaN (neither drift nor diffusion) is "none"."""
    if np.isnan(pe):
        return "none"
    if np.isinf(pe):
        return "infinite"
    return "%.3g" % pe


def overlay(ax, orbits, r, with_points=True):
    if not orbits:
        return
    for _, _, v in read_islands(orbits, r):
        ax.fill(v[:, 0], v[:, 1], fill=False, ec="red", lw=1.0)
    if with_points:
        pts, typ, _ = read_points(orbits)
        ell, hyp = pts[typ == 0], pts[typ == 1]
        ax.plot(ell[:, 0], ell[:, 1], "o", ms=3, mfc="red", mec="red", label="elliptic")
        ax.plot(hyp[:, 0], hyp[:, 1], "x", ms=4, color="tab:blue", label="hyperbolic")
        ax.legend(loc="lower right", fontsize=7, framealpha=0.8)


def cmd_section(a):
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    with h5py.File(a.file, "r") as f:
        colors = {"first": "k", "second": "tab:blue"}
        for name in ("first", "second"):
            if name not in f:
                continue
            b = f[name + "/bulk"][()].reshape(-1, 2)
            ax.plot(b[:, 0], b[:, 1], ",", color=colors[name], alpha=0.6)
            if a.layer:
                lc = f[name + "/layer_chart"][()].reshape(-1, 2)
                ax.plot(lc[:, 0], lc[:, 1], ",", color="tab:orange", alpha=0.6)
        frame(ax, f, "Poincaré section " + protocol_title(f))
        overlay(ax, a.orbits, f.attrs["r"])
    fig.tight_layout()
    fig.savefig(a.output, dpi=a.dpi)


def cmd_kam(a):
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    with h5py.File(a.file, "r") as f:
        isl = read_islands(a.file)
        radii = sorted({round(r, 9) for r, _, _ in isl})
        cmap = plt.get_cmap("viridis")
        for r, _, v in isl:
            c = cmap((r - min(radii)) / max(max(radii) - min(radii), 1e-9))
            ax.fill(v[:, 0], v[:, 1], fill=False, ec=c, lw=0.8)
        frame(ax, f, "KAM-tube islands, r = %s" % ", ".join("%g" % r for r in radii))
    fig.tight_layout()
    fig.savefig(a.output, dpi=a.dpi)


def cmd_manifolds(a):
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    with h5py.File(a.file, "r") as f:
        for k in f["manifolds"]:
            g = f["manifolds/" + k]
            c = g["chart"][()].reshape(-1, 2)
            col = "tab:red" if g.attrs["kind"] == "unstable" else "tab:green"
            ax.plot(c[:, 0], c[:, 1], ",", color=col)
        frame(ax, f, "manifolds (red unstable, green stable) " + protocol_title(f))
        overlay(ax, a.orbits, f.attrs["r"], with_points=False)
    fig.tight_layout()
    fig.savefig(a.output, dpi=a.dpi)


def cmd_mcm(a):
    fig, axs = plt.subplots(1, 3, figsize=(15, 5.2))
    with h5py.File(a.file, "r") as f:
        rim = f.attrs["chart_rim"]
        panels = [("initial/chart", "initial"), ("snapshot/chart", "N = %d" % f.attrs["snapshot_iteration"]),
                  ("cumulative/chart", "cumulative")]
        for ax, (ds, label) in zip(axs, panels):
            c = f[ds][()].reshape(-1, 2)
            c = c[np.hypot(c[:, 0], c[:, 1]) < rim]  # bulk tracers only, as in Fig. 9
            ax.plot(c[:, 0], c[:, 1], ".", ms=1.5, color="tab:blue")
            frame(ax, f, label)
            overlay(ax, a.orbits, f.attrs["r"], with_points=False)
        fig.suptitle("MCM %s, c = %g, drift %s: in islands %.3f (island area %.3f), Pe = %s" % (
            protocol_title(f), f.attrs["c"], "on" if f.attrs["drift"] else "off",
            f.attrs["bulk_inside_fraction"], f.attrs["island_bulk_area_fraction"],
            peclet_text(f.attrs["peclet"])))
    fig.tight_layout()
    fig.savefig(a.output, dpi=a.dpi)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    for name, fn in (("section", cmd_section), ("kam", cmd_kam), ("manifolds", cmd_manifolds), ("mcm", cmd_mcm)):
        s = sub.add_parser(name)
        s.add_argument("file")
        s.add_argument("-o", "--output", required=True)
        s.add_argument("--dpi", type=int, default=120)
        if name != "kam":
            s.add_argument("--orbits", help="orbits file for island overlays")
        if name == "section":
            s.add_argument("--layer", action="store_true", help="also draw layer iterates (ring)")
        s.set_defaults(fn=fn)
    a = p.parse_args()
    a.fn(a)


if __name__ == "__main__":
    main()
