"""The mixing index against its expectation for a randomly mixed bed of the same particles.

The campaign's "mixing index" (series/mixing_index) is the intensity of segregation of the shell
map, src/analysis/concentration.cpp: with v_c the solid volume and c_c the large share of Lambert
cell c of the shell inner < r/R < 1 (lower hemisphere),

    I = sqrt(sum_c v_c (c_c − c̄)² / sum_c v_c) / sqrt(c̄ (1 − c̄)).

I = 0 for a perfectly even mix and 1 for complete segregation, but a *random* mix of a few
particles per cell is far from 0: each cell holds a handful of particles, so c_c scatters by
chance. The reference is therefore I of the same particles at the same positions with their
species shuffled (a permutation of the (species, radius) pairs among the particles of the
analysed shell): same counts, same volumes, no order. Computed here from a case's last snapshot,
binned exactly as the C++ code bins it (LambertGrid::cell_of_direction)."""
import tomllib

import h5py
import numpy as np


def disc_to_square(X, Z):
    """Inverse of the Shirley-Chiu concentric map (src/analysis/lambert.cpp: disc_to_square)."""
    r = np.hypot(X, Z)
    phi = np.arctan2(Z, X)
    phi = np.where(phi < -np.pi / 4, phi + 2 * np.pi, phi)
    q = np.pi / 4
    with np.errstate(invalid="ignore", divide="ignore"):
        a = np.select([phi < q, phi < 3 * q, phi < 5 * q],
                      [r, -(phi - 2 * q) * r / q, -r], (phi - 6 * q) * r / q)
        b = np.select([phi < q, phi < 3 * q, phi < 5 * q],
                      [phi * r / q, r, -(phi - np.pi) * r / q], -r)
    return np.where(r == 0, 0, a), np.where(r == 0, 0, b)


def cell_of_direction(u, n):
    """Flat Lambert cell i n + j of unit directions u [N][3], viewed from below; −1 above the
    equator or outside the disc (LambertGrid::cell_of_direction)."""
    s = np.sqrt(np.maximum(1.0 - u[:, 1], 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        X, Z = np.where(s > 0, u[:, 0] / s, 0), np.where(s > 0, u[:, 2] / s, 0)
    a, b = disc_to_square(X, Z)
    i = np.clip(np.floor((a + 1.0) * 0.5 * n).astype(int), 0, n - 1)
    j = np.clip(np.floor((b + 1.0) * 0.5 * n).astype(int), 0, n - 1)
    cell = i * n + j
    return np.where((u[:, 1] > 0) | (X * X + Z * Z > 1.0) | (s == 0), -1, cell)


def intensity(cell, large, vol, n):
    """I of the particles with their cells, species flags (large) and volumes; NaN if undefined."""
    k = cell >= 0
    vl = np.bincount(cell[k], weights=vol[k] * large[k], minlength=n * n)
    vt = np.bincount(cell[k], weights=vol[k], minlength=n * n)
    if vt.sum() <= 0:
        return np.nan
    mean = vl.sum() / vt.sum()
    if not 0 < mean < 1:
        return np.nan
    full = vt > 0
    d = vl[full] / vt[full] - mean
    return float(np.sqrt(np.sum(vt[full] * d * d) / vt.sum()) / np.sqrt(mean * (1 - mean)))


def random_bed_index(snapshot, grid_n, shell_inner=0.9, permutations=200, seed=0):
    """(I of the snapshot, mean and SD of I over `permutations` shuffles of the species among
    the particles of the analysed shell). Lab frame (the campaign's default, frame = "lab")."""
    with h5py.File(snapshot, "r") as f:
        x = f["x"][:]
        rad = f["radius"][:]
        large = (f["species"][:] == 1).astype(float)
        scene = f.attrs["scene"]
        scene = scene.decode() if isinstance(scene, bytes) else str(scene)
    R = tomllib.loads(scene)["tumbler"]["radius"]
    r = np.linalg.norm(x, axis=1)
    shell = (r > shell_inner * R) & (r < R)
    u = x[shell] / r[shell, None]
    cell = cell_of_direction(u, grid_n)
    vol = 4.0 / 3.0 * np.pi * rad[shell] ** 3
    lg = large[shell]
    observed = intensity(cell, lg, vol, grid_n)
    rng = np.random.default_rng(seed)
    keep = cell >= 0  # shuffle among the particles the index sees
    c, v, s = cell[keep], vol[keep], lg[keep]
    vals = []
    for _ in range(permutations):
        p = rng.permutation(len(c))
        vals.append(intensity(c, s[p], v[p], grid_n))
    vals = np.array(vals)
    return observed, float(np.nanmean(vals)), float(np.nanstd(vals, ddof=1))
