"""analysis.cli_mapped_species: `tumble analyze classify` and `enrichment` count the mixture's
mapped species, as `analyze campaign` does, not species 1 whatever the bed.

  /usr/bin/python3 cli_mapped_species_check.py TUMBLE SNAPSHOT_DIR WORK_DIR ISLANDS_CACHE

Two snapshots of the CLI's bst_tiny run (size-bidisperse: 2040 small, 45 large) are copied with
their stored scene rewritten to a density-bidisperse bed of equal sizes: with density_ratio = 3
species 0 is the light one, with 1/3 species 1 is. The classification must then count "light"
particles, as many as that species has; the original snapshots, "large", species 1; and the
section (Fig. 5) through two islands maps that species' share. (Before
2026-11-29 the command line counted species 1 in every bed: in a density bed with R_rho > 1, the
heavy majority reported as the mapped particles.)"""
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

tumble, snaps, work, cache = sys.argv[1:5]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
names = ["snap_000000.h5", "snap_000002.h5"]
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg)


def species_counts(path):
    with h5py.File(path, "r") as f:
        return np.bincount(f["species"][()], minlength=2)


def run(args):
    p = subprocess.run([tumble, "analyze"] + args + ["--islands-cache", cache],
                       capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        fail("%s: exit %d\n%s" % (args, p.returncode, p.stdout + p.stderr))
    return p.stdout


def rewrite(src, dst, density_ratio):
    """A copy of snapshot `src` whose scene says: equal sizes, this density ratio."""
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        text = f.attrs["scene"]
        text = text.decode() if isinstance(text, bytes) else text
        d_small = re.search(r"^particles\.d_small = (\S+)$", text, re.M).group(1)
        text = re.sub(r"^particles\.d_large = \S+$", "particles.d_large = " + d_small, text,
                      flags=re.M)
        text = re.sub(r"^particles\.density_ratio = \S+$",
                      "particles.density_ratio = %r" % density_ratio, text, flags=re.M)
        f.attrs["scene"] = text


counts = species_counts(os.path.join(snaps, names[0]))
sections = {}
cases = [("original", None, "large", 1)]
cases += [("density_ratio_3", 3.0, "light", 0), ("density_ratio_third", 1 / 3, "light", 1)]
for label, ratio, word, species in cases:
    paths = [os.path.join(snaps, n) for n in names]
    if ratio is not None:
        paths = [os.path.join(work, label + "_" + n) for n in names]
        for n, p in zip(names, paths):
            rewrite(os.path.join(snaps, n), p, ratio)
    out = run(["classify"] + paths)
    m = re.search(r"(\d+) (\w+) particles: persistent", out)
    if not m:
        fail("%s: no count line in classify's output:\n%s" % (label, out))
        continue
    n, name = int(m.group(1)), m.group(2)
    print("%s: classify counted %d %s particles (species %d has %d)"
          % (label, n, name, species, counts[species]))
    if name != word or n != counts[species]:
        fail("%s: classify counted %d %s particles; want %d %s (species %d)"
             % (label, n, name, counts[species], word, species))
    # Fig. 5's section through the same islands: the mapped species' share, so a bed whose
    # mapped species is species 0 shows 1 - the original's share in every binned cell.
    section = os.path.join(work, label + "_section.h5")
    run(["section", paths[1], "-o", section])
    with h5py.File(section, "r") as f:
        sections[label] = f["c_L"][()]
    out = run(["enrichment"] + paths)
    got = re.findall(r"inside [0-9.]+ of (\d+) (\w+),", out)
    print("%s: enrichment counted %s" % (label, got))
    if len(got) != 2 or any(w != word for _, w in got) or \
            any(int(k) > counts[species] or int(k) == 0 for k, _ in got):
        fail("%s: enrichment counted %s; want up to %d %s each" % (label, got, counts[species], word))

base = sections.get("original")
for label, species in (("density_ratio_3", 0), ("density_ratio_third", 1)):
    c = sections.get(label)
    if base is None or c is None:
        continue
    want = 1 - base if species == 0 else base
    seen = ~np.isnan(base)
    if not np.array_equal(np.isnan(c), ~seen) or np.max(np.abs(c[seen] - want[seen])) > 1e-12:
        fail("%s: the section's share is not species %d's (max difference %.3g)"
             % (label, species, np.nanmax(np.abs(c - want))))
    else:
        print("%s: section = species %d's share in all %d binned cells" % (label, species, seen.sum()))

if failures:
    sys.exit(1)
print("OK: the mapped species counted in all %d beds" % len(cases))
