"""postproc/drift_structure.py on a constructed drift grid with known answers.

  /usr/bin/python3 drift_structure_check.py SCRATCH_DIR

A 20 x 20 grid, 10 samples in every cell: upstream (x < 0) every sample moves poleward at 0.1
omega R, downstream (x > 0) towards the equator at 0.2: the bands say +0.1 and -0.2 with zero
spread, the pool their sample-weighted mean, <|v_ax|> the footprint mean of |v| and the noise 0
(every cell's samples are equal). A grid without statistics (a synthetic one) is refused.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "postproc", "drift_structure.py")
out = sys.argv[1]
os.makedirs(out, exist_ok=True)
n = 20
c = (np.arange(n) + 0.5) / n * 2 - 1
x, z = np.meshgrid(c, c, indexing="ij")
v = np.where(x < 0, 0.1, -0.2) * np.sign(z)
count = np.full((n, n), 10.0)
path = os.path.join(out, "grid.h5")
with h5py.File(path, "w") as f:
    f["count"], f["sum"], f["sum2"] = count, 10 * v, 10 * v * v
r = subprocess.run([sys.executable, SCRIPT, path, "--quarters", "2"], capture_output=True, text=True)
print(r.stdout + r.stderr)
bands = re.findall(r"\| \[([-+0-9.]+), ([-+0-9.]+)\) \| ([-+0-9.]+) ± ([0-9.]+) \| (\d+) \|", r.stdout)
foot = x * x + z * z < 1
pooled = (v * np.sign(z))[foot].mean()  # the poleward component, -0.05
ok = (r.returncode == 0 and len(bands) == 2
      and [float(b[2]) for b in bands] == [0.1, -0.2] and all(float(b[3]) == 0 for b in bands)
      and f"pooled over the footprint: {pooled:+.3f}" in r.stdout
      and f"<|v_ax|> = {np.abs(v[foot]).mean():.3f} omega R; sampling noise alone would give 0.000" in r.stdout)
with h5py.File(os.path.join(out, "synthetic.h5"), "w") as f:
    f["v_ax"] = v
s = subprocess.run([sys.executable, SCRIPT, os.path.join(out, "synthetic.h5")], capture_output=True, text=True)
refused = s.returncode != 0 and "no per-cell statistics" in s.stderr
print(("ok  " if ok else "FAIL") + " constructed grid: bands +0.1 / -0.2, pool, speed, zero noise")
print(("ok  " if refused else "FAIL") + " a grid without statistics refused: " + s.stderr.strip())
sys.exit(0 if ok and refused else 1)
