#!/usr/bin/env python3
"""Convert the settled bed (columns: id type diameter x y z, SI) into a LIGGGHTS
data file for `atom_style granular` (Atoms columns: id type diameter density x y z).

The data file declares 3 atom types: 1 = small, 2 = large particles, 3 = wall
material (used only by the STL mesh). Velocities are left at zero (the bed is
settled, rms speed < 1 mm/s).

Usage: make_data.py SETTLED.txt OUT.data [--density 2500] [--half-box 0.0365]
"""
import argparse


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("settled")
    ap.add_argument("out")
    ap.add_argument("--density", type=float, default=2500.0)
    ap.add_argument("--half-box", type=float, default=0.0365,
                    help="box is [-h, h]^3; must contain the whole mesh (R = 35 mm)")
    a = ap.parse_args()

    rows = []
    with open(a.settled) as fh:
        for line in fh:
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            pid, ptype, d, x, y, z = int(s[0]), int(s[1]), float(s[2]), float(s[3]), float(s[4]), float(s[5])
            assert ptype in (1, 2)
            rows.append((pid, ptype, d, x, y, z))

    h = a.half_box
    with open(a.out, "w") as fh:
        fh.write("LIGGGHTS data file from %s\n\n" % a.settled)
        fh.write("%d atoms\n3 atom types\n\n" % len(rows))
        for ax in "xyz":
            fh.write("%.6f %.6f %slo %shi\n" % (-h, h, ax, ax))
        fh.write("\nAtoms\n\n")
        for pid, ptype, d, x, y, z in rows:
            fh.write("%d %d %.9e %.6g %.15e %.15e %.15e\n" % (pid, ptype, d, a.density, x, y, z))
    print("data file: %s atoms=%d" % (a.out, len(rows)))


if __name__ == "__main__":
    main()
