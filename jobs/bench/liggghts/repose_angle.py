#!/usr/bin/env python3
"""Dynamic repose angle of the bed in each frame of a LIGGGHTS dump
(columns id type radius x y z ...; rotation about x, gravity -z, sphere centred
at the origin).

Two estimates per frame:
  com:     a flat free surface in a sphere cuts a cap that is symmetric about
           the surface normal through the centre, so the bed's centre of mass
           lies on that normal: angle = atan2(|y_com|, -z_com) (mass ~ d^3).
  surface: the free surface as the highest particle top (z + r) in each
           3 mm x 3 mm (x, y) column within --rfit of the rotation axis line
           (x = 0 plane projection), least-squares plane z = a x + b y + c;
           angle = atan(|b|) (tilt across the rotation axis).

Usage: repose_angle.py DUMPFILE [--rfit 0.02]
"""
import argparse
import math


def frames(path):
    """Yield (timestep, rows) with rows = list of (radius, x, y, z)."""
    with open(path) as fh:
        while True:
            line = fh.readline()
            if not line:
                return
            if not line.startswith("ITEM: TIMESTEP"):
                continue
            step = int(fh.readline())
            fh.readline()  # ITEM: NUMBER OF ATOMS
            n = int(fh.readline())
            for _ in range(4):  # box bounds
                fh.readline()
            cols = fh.readline().split()[2:]
            ir, ix, iy, iz = (cols.index(c) for c in ("radius", "x", "y", "z"))
            rows = []
            for _ in range(n):
                s = fh.readline().split()
                rows.append((float(s[ir]), float(s[ix]), float(s[iy]), float(s[iz])))
            yield step, rows


def com_angle(rows):
    m = [r ** 3 for r, _, _, _ in rows]
    mt = sum(m)
    yc = sum(mi * y for mi, (_, _, y, _) in zip(m, rows)) / mt
    zc = sum(mi * z for mi, (_, _, _, z) in zip(m, rows)) / mt
    return math.degrees(math.atan2(abs(yc), -zc)), yc, zc


def solve3(A, b):
    """Solve a 3x3 linear system by Cramer's rule."""
    def det(M):
        return (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1])
                - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0])
                + M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]))
    d = det(A)
    out = []
    for k in range(3):
        M = [row[:] for row in A]
        for i in range(3):
            M[i][k] = b[i]
        out.append(det(M) / d)
    return out


def surface_angle(rows, rfit, cell=0.003):
    top = {}
    for r, x, y, z in rows:
        key = (math.floor(x / cell), math.floor(y / cell))
        top[key] = max(top.get(key, -1.0), z + r)
    pts = []
    for (i, j), zt in top.items():
        xc, yc = (i + 0.5) * cell, (j + 0.5) * cell
        if xc * xc + yc * yc < rfit * rfit:
            pts.append((xc, yc, zt))
    # normal equations for z = a x + b y + c
    A = [[0.0] * 3 for _ in range(3)]
    rhs = [0.0] * 3
    for x, y, z in pts:
        v = (x, y, 1.0)
        for i in range(3):
            rhs[i] += v[i] * z
            for j in range(3):
                A[i][j] += v[i] * v[j]
    a, b, c = solve3(A, rhs)
    return math.degrees(math.atan(abs(b))), a, b, c, len(pts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dump")
    ap.add_argument("--rfit", type=float, default=0.02, help="fit columns within this radius [m]")
    ap.add_argument("--dt", type=float, default=1e-5)
    a = ap.parse_args()
    print("%8s %7s %10s %12s %10s %8s" % ("step", "t_s", "com_deg", "surface_deg", "y_com_mm", "columns"))
    for step, rows in frames(a.dump):
        ac, yc, zc = com_angle(rows)
        asurf, _, _, _, ncol = surface_angle(rows, a.rfit)
        print("%8d %7.3f %10.2f %12.2f %10.3f %8d" % (step, step * a.dt, ac, asurf, yc * 1e3, ncol))


if __name__ == "__main__":
    main()
