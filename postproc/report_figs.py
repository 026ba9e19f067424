"""Figures of the report: maps on the equal-area Lambert grid with the CM islands overlaid, time
series with confidence bands, convergence with the number of replicas, Fig. 8 fates. Every map
of one field shares one colour scale, so points can be compared by eye."""
import math
import textwrap

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

FATE_NAMES = ["persistent", "captured", "dispersed", "other", "switched island"]
# Fig. 8: orange, blue, green, black; "switched" (in an island at both times, not the same one;
# not a class of the paper's figure) purple
FATE_COLOURS = ["#f39c12", "#2e6fd8", "#1e8449", "#222222", "#8e44ad"]


def square_to_disc(a, b):
    """Shirley-Chiu concentric map, as src/projection/lambert.cpp."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    q = math.pi / 4
    with np.errstate(divide="ignore", invalid="ignore"):
        big_a = np.abs(a) > np.abs(b)
        r = np.where(big_a, a, b)
        phi = np.where(big_a, q * (b / np.where(a == 0, 1, a)),
                       2 * q - q * (a / np.where(b == 0, 1, b)))
    phi = np.where((a == 0) & (b == 0), 0, phi)
    return r * np.cos(phi), r * np.sin(phi)


def lambert_cells(n, sub=4):
    """Polygon of every cell, flat index i n + j (cell (i, j): a along X, b along Z)."""
    h = 2.0 / n
    t = np.linspace(0, 1, sub + 1)[:-1]
    polys = []
    for i in range(n):
        for j in range(n):
            a0, b0 = -1 + i * h, -1 + j * h
            a = np.concatenate([a0 + h * t, np.full(sub, a0 + h), a0 + h - h * t, np.full(sub, a0)])
            b = np.concatenate([np.full(sub, b0), b0 + h * t, np.full(sub, b0 + h), b0 + h - h * t])
            X, Z = square_to_disc(a, b)
            polys.append(np.column_stack([X, Z]))
    return polys


_CELLS = {}


def draw_map(ax, values, n, vmin, vmax, cmap="viridis", islands=(), mask=None, title="",
             excluded=None, other_islands=()):
    """One Lambert map: NaN (never visited) and masked cells light grey, excluded cells (not
    tested) dark grey; islands in red, other_islands (a baseline's) black dashed."""
    if n not in _CELLS:
        _CELLS[n] = lambert_cells(n)
    v = np.asarray(values, float).ravel()
    bad = ~np.isfinite(v)
    if mask is not None:
        bad |= np.asarray(mask, bool).ravel()
    cm = plt.get_cmap(cmap)
    norm = matplotlib.colors.Normalize(vmin, vmax)
    colours = cm(norm(np.where(bad, vmin, v)))
    colours[bad] = (0.85, 0.85, 0.85, 1)
    if excluded is not None:
        colours[np.asarray(excluded, bool).ravel()] = (0.55, 0.55, 0.55, 1)
    ax.add_collection(PolyCollection(_CELLS[n], facecolors=colours, edgecolors="none"))
    for poly in other_islands:
        p = np.vstack([poly, poly[:1]])
        ax.plot(p[:, 0], p[:, 1], color="k", lw=1.2, ls="--")
    disc_frame(ax, islands, "red", "0.3")
    if title:
        ax.set_title(title, fontsize=10)
    return matplotlib.cm.ScalarMappable(norm=norm, cmap=cm)


def disc_frame(ax, islands, island_colour, rim_colour):
    """The Lambert disc's frame: island outlines, the unit rim, equal axes, no ticks."""
    for poly in islands:
        p = np.vstack([poly, poly[:1]])
        ax.plot(p[:, 0], p[:, 1], color=island_colour, lw=1.0)
    ax.add_patch(plt.Circle((0, 0), 1, fill=False, color=rim_colour, lw=0.8))
    ax.set_xlim(-1.03, 1.03)
    ax.set_ylim(-1.03, 1.03)
    ax.set_aspect("equal")
    ax.axis("off")


def finite_range(arrays, symmetric=False, floor=None):
    vals = np.concatenate([np.asarray(a, float).ravel() for a in arrays] or [np.zeros(1)])
    vals = vals[np.isfinite(vals)]
    if vals.size == 0:
        return (0.0, 1.0)
    lo, hi = float(vals.min()), float(vals.max())
    if symmetric:
        m = max(abs(lo), abs(hi), 1e-12)
        return (-m, m)
    if floor is not None:
        lo = min(lo, floor)
    return (lo, hi if hi > lo else lo + 1e-12)


def map_grid(rows, columns, out, suptitle, cmaps, ranges, cbar_labels, panel_in=5.0):
    """rows: [(label, n, islands, [values per column], [mask per column or None]
    [, [excluded per column or None], other_islands])]. Each panel is panel_in inches at 100
    dpi, one colour bar per column: two columns make a 1200-px figure whose discs, shown in
    the report's 1200-px column, are larger than the 420-px bottom views."""
    nr, nc = len(rows), len(columns)
    fig, axes = plt.subplots(nr, nc, figsize=(panel_in * nc + 1.0 * nc, panel_in * nr + 0.7),
                             squeeze=False, layout="constrained")
    mappables = [None] * nc
    for r, row in enumerate(rows):
        label, n, islands, values, masks = row[:5]
        excluded = row[5] if len(row) > 5 else None
        other = row[6] if len(row) > 6 else ()
        # Point labels carry every swept key and the mixture: wrapped to the panel's width
        # (about 12 characters an inch at the title's size) so that neighbours do not overlap.
        wrapped = textwrap.fill(label, width=int(12 * panel_in))
        for c in range(nc):
            mappables[c] = draw_map(axes[r][c], values[c], n, *ranges[c], cmap=cmaps[c],
                                    islands=islands, mask=masks[c] if masks else None,
                                    title=f"{wrapped}\n{columns[c]}",
                                    excluded=excluded[c] if excluded else None,
                                    other_islands=other)
    for c in range(nc):
        cb = fig.colorbar(mappables[c], ax=[axes[r][c] for r in range(nr)], shrink=0.6,
                          aspect=30, pad=0.02)
        cb.set_label(cbar_labels[c], fontsize=10)
        cb.ax.tick_params(labelsize=9)
    fig.suptitle(suptitle, fontsize=12)
    fig.savefig(out, dpi=100)
    plt.close(fig)


def series_fig(curves, ylabel, out, title):
    """curves: [(label, x, mean, lower, upper)]; the band is the 95% interval."""
    fig, ax = plt.subplots(figsize=(6.4, 3.4))
    for label, x, m, lower, upper in curves:
        line, = ax.plot(x, m, label=label, lw=1.4)
        ok = np.isfinite(lower) & np.isfinite(upper)
        ax.fill_between(np.asarray(x)[ok], lower[ok], upper[ok], color=line.get_color(),
                        alpha=0.25, lw=0)
    ax.set_xlabel("protocol iteration N")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def convergence_fig(panels, out):
    """panels: [(title, ylabel, [(label, k, mean_k, lower_k, upper_k)])]: running mean over the
    first k replicas with its 95% CI."""
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.2), squeeze=False)
    for ax, (title, ylabel, curves) in zip(axes[0], panels):
        for label, k, m, lower, upper in curves:
            line, = ax.plot(k, m, "o-", label=label, ms=3)
            ok = np.isfinite(lower) & np.isfinite(upper)
            ax.fill_between(np.asarray(k)[ok], lower[ok], upper[ok],
                            color=line.get_color(), alpha=0.2, lw=0)
        ax.set_xlabel("replicas k")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def lambert_points(x):
    """Lambert image (viewed from below) of positions; NaN on the upper hemisphere."""
    d = np.linalg.norm(x, axis=1)
    u = x / d[:, None]
    k = np.where(u[:, 1] <= 0, 1.0 / np.sqrt(np.maximum(1.0 - u[:, 1], 1e-12)), np.nan)
    return u[:, 0] * k, u[:, 2] * k


def fates_fig(panels, out):
    """panels: [(title, islands, fate, x_start, x_end)]: large particles at the start and end of
    the interval coloured by fate (Yu 2022 Fig. 8); the legend under each row, off the discs."""
    fig, axes = plt.subplots(len(panels), 2, figsize=(9.2, 5.0 * len(panels)), squeeze=False,
                             layout="constrained")
    for r, (title, islands, fate, xs, xe) in enumerate(panels):
        for c, (x, when) in enumerate(((xs, "start"), (xe, "end"))):
            ax = axes[r][c]
            X, Z = lambert_points(x)
            for k in (3, 4, 2, 1, 0):  # "other" underneath, as the paper's small black dots
                sel = fate == k
                ax.scatter(X[sel], Z[sel], s=5 if k == 3 else 14, c=FATE_COLOURS[k],
                           label=f"{FATE_NAMES[k]} ({int(sel.sum())})", lw=0)
            disc_frame(ax, islands, "k", "0.4")
            ax.set_title(f"{title}\n{when}", fontsize=10)
        handles, labels = axes[r][0].get_legend_handles_labels()
        axes[r][0].legend(handles[::-1], labels[::-1], fontsize=9, loc="upper left",
                          bbox_to_anchor=(0.0, 0.0), ncol=3, markerscale=1.5, frameon=False)
    fig.savefig(out, dpi=100)
    plt.close(fig)


def section_grid(rows, out, rng_mean, rng_ci):
    """rows: [(title, mean[n, n], ci[n, n], tubes[m, 3] = (r, s1, s2))]: Fig. 5 sections, bin
    (i, j) = (s1, s2) in [-1, 1]², the tumbler's circle and the KAM-tube boundary points."""
    fig, axes = plt.subplots(len(rows), 2, figsize=(11.0, 4.6 * len(rows) + 0.5), squeeze=False,
                             layout="constrained")
    ims = [None, None]
    for r, (title, mean, ci, tubes) in enumerate(rows):
        for c, (v, rng, cmap) in enumerate(((mean, rng_mean, "viridis"), (ci, rng_ci, "YlOrBr"))):
            ax = axes[r][c]
            cmap_obj = plt.get_cmap(cmap).copy()
            cmap_obj.set_bad((0.85, 0.85, 0.85, 1))
            ims[c] = ax.imshow(np.ma.masked_invalid(np.asarray(v, float).T), origin="lower",
                               extent=(-1, 1, -1, 1), vmin=rng[0], vmax=rng[1], cmap=cmap_obj)
            ax.add_patch(plt.Circle((0, 0), 1, fill=False, color="0.3", lw=0.8))
            if len(tubes):
                ax.scatter(tubes[:, 1], tubes[:, 2], s=4, c="red", lw=0)
            ax.set_xlim(-1.03, 1.03)
            ax.set_ylim(-1.03, 1.03)
            ax.set_aspect("equal")
            ax.set_xlabel("s1 / R", fontsize=9)
            ax.set_ylabel("s2 / R", fontsize=9)
            ax.tick_params(labelsize=8)
            ax.set_title(title + ("\nmean c_L" if c == 0 else "\n95% CI half-width"), fontsize=10)
    for c, label in enumerate(("c_L", "± c_L")):
        fig.colorbar(ims[c], ax=[axes[r][c] for r in range(len(rows))], shrink=0.6, label=label)
    fig.savefig(out, dpi=100)
    plt.close(fig)
