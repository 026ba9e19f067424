"""analysis.report_refuses_corrupt_ensemble: postproc reads an ensemble only if every table still
has the digest Tumble stored with it (docs/guarantees.md). The CI campaign's ensemble.h5 reads;
copies with one value of a table changed by 1e-9 (as a hand edit would, so HDF5 sees nothing
wrong) are refused with exit code 3 naming the table, for each of count, mean and ci95 of one
field."""
import os
import shutil
import subprocess
import sys

import h5py

ensemble, repo, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
load = ("import sys; sys.path.insert(0, %r); from postproc import report_data as r; "
        "r.load_ensemble(sys.argv[1])" % repo)


def read(path):
    return subprocess.run([sys.executable, "-c", load, path], capture_output=True, text=True)


r = read(ensemble)
if r.returncode != 0:
    print("FAIL: the intact ensemble does not read: %s" % r.stderr)
    sys.exit(1)
with h5py.File(ensemble, "r") as f:
    if "checksums" not in f.attrs:
        print("FAIL: %s has no checksums" % ensemble)
        sys.exit(1)
names = []
with h5py.File(ensemble, "r") as f:
    f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) and n.endswith("/mean") else None)
base = names[0][:-len("/mean")]
for stat in ("count", "mean", "ci95"):
    copy = os.path.join(work, "edited_%s.h5" % stat)
    shutil.copy(ensemble, copy)
    with h5py.File(copy, "r+") as f:
        d = f[base + "/" + stat]
        x = d[()]
        x.flat[0] = x.flat[0] + 1e-9 if x.flat[0] == x.flat[0] else 0.5  # NaN: any number
        d[...] = x
    r = read(copy)
    if r.returncode != 3 or (base + "/" + stat) not in r.stderr:
        print("FAIL: %s/%s changed: exit %d, %s" % (base, stat, r.returncode, r.stderr))
        sys.exit(1)
print("OK: the intact ensemble reads; %s/count, mean and ci95 changed by 1e-9 are each refused "
      "(exit 3)" % base)
