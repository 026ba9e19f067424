#!/usr/bin/env python3
"""Write an ASCII STL of a closed sphere (the tumbler wall) for LIGGGHTS.

Geodesic icosphere: each of the 20 icosahedron faces is split into n*n
triangles on a barycentric grid, every grid point is projected onto the
sphere. The smallest n whose facets deviate less than --tol from the sphere
is used. Normals point outwards (vertex order counter-clockwise seen from
outside).

Placement (--fit):
  outside (default): all vertices are scaled by R/h_min (h_min = smallest
      distance of a facet plane from the centre), so no facet plane is closer
      than R to the centre: a sphere of radius <= R touching the ideal wall
      does not overlap the mesh. The settled bed in bst_R35_settled.txt has
      every particle surface >= 2 um inside R, so the bed starts without
      wall overlaps (no start-up kick); vertices then lie up to ~tol outside R.
  vertices: vertices exactly on the sphere (facets up to tol inside R).

Usage: make_sphere_stl.py OUT.stl [--radius 0.035] [--tol 2.5e-5] [--fit outside]
Units: metres (LIGGGHTS is run with `units si`).
"""
import argparse
import math


def icosahedron():
    """12 unit vertices and 20 outward-oriented faces."""
    p = (1.0 + math.sqrt(5.0)) / 2.0
    v = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0),
         (0, -1, p), (0, 1, p), (0, -1, -p), (0, 1, -p),
         (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    v = [normalize(a) for a in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
         (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
         (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
         (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return v, f


def normalize(a):
    n = math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)
    return (a[0] / n, a[1] / n, a[2] / n)


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def geodesic(n):
    """Unit-sphere triangles (tuples of 3 points) of the frequency-n icosphere."""
    verts, faces = icosahedron()
    tris = []
    for ia, ib, ic in faces:
        A, B, C = verts[ia], verts[ib], verts[ic]

        def pt(i, j):  # grid point i steps towards B, j steps towards C
            w = (n - i - j) / n, i / n, j / n
            return normalize(tuple(w[0] * A[k] + w[1] * B[k] + w[2] * C[k] for k in range(3)))

        for i in range(n):
            for j in range(n - i):
                tris.append((pt(i, j), pt(i + 1, j), pt(i, j + 1)))  # same orientation as ABC
                if i + j < n - 1:
                    tris.append((pt(i + 1, j), pt(i + 1, j + 1), pt(i, j + 1)))
    return tris


def plane_distance(t):
    """Unit normal of triangle t and distance of its plane from the origin."""
    nrm = normalize(cross(sub(t[1], t[0]), sub(t[2], t[0])))
    return nrm, dot(nrm, t[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--radius", type=float, default=0.035)
    ap.add_argument("--tol", type=float, default=2.5e-5, help="max facet-to-sphere deviation [m]")
    ap.add_argument("--fit", choices=["outside", "vertices"], default="outside")
    a = ap.parse_args()

    n = 1
    while True:  # smallest frequency meeting the tolerance
        tris = geodesic(n)
        hmin = min(plane_distance(t)[1] for t in tris)
        if a.radius * (1.0 - hmin) < a.tol:
            break
        n += 1
    scale = a.radius / hmin if a.fit == "outside" else a.radius

    with open(a.out, "w") as fh:
        fh.write("solid tumbler\n")
        for t in tris:
            nrm, h = plane_distance(t)
            assert h > 0.0, "facet normal not pointing outwards"
            fh.write(" facet normal %.9e %.9e %.9e\n  outer loop\n" % nrm)
            for p in t:
                fh.write("   vertex %.12e %.12e %.12e\n" % tuple(scale * c for c in p))
            fh.write("  endloop\n endfacet\n")
        fh.write("endsolid tumbler\n")
    dev = a.radius * (1.0 - hmin)
    print("sphere STL: %s frequency=%d facets=%d max_dev=%.2f um fit=%s vertex_radius=%.6f m"
          % (a.out, n, len(tris), dev * 1e6, a.fit, scale))


if __name__ == "__main__":
    main()
