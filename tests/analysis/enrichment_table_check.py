"""jobs/accuracy/enrichment_table.py on a constructed analysis.h5 (no engine run).

  /usr/bin/python3 enrichment_table_check.py SCRATCH_DIR

Two density points with known per-replica arrays: the printed geometric means, intervals,
one-sample p-values and their Holm adjustment, the shell ratio, the point-against-point rows (the
shell ratio's difference and Welch p, the ratio of geometric means and its Welch p on the logs,
Holm over the rows), and the replicas a 10% difference needs (pooled log SD weighted by n - 1), each recomputed here
with scipy and compared at the printed precision; --reference by a part of the label; an
enrichment of 0 and a missing dataset refused with the reason."""
import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np
from scipy import stats

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "..", "..", "jobs", "accuracy", "enrichment_table.py")
sys.path.insert(0, HERE)
from script_run import Checks  # noqa: E402

check = Checks()


def write(path, points):
    with h5py.File(path, "w") as f:
        for pid, (params, arrays) in points.items():
            g = f.create_group(f"points/{pid}")
            g.attrs["params"] = params
            g.attrs["mapped_species"] = 0
            g.attrs["species_0"], g.attrs["species_1"] = "light", "heavy"
            for k, v in arrays.items():
                g[k] = np.asarray(v, float)


def run(*args):
    r = subprocess.run([sys.executable, TABLE, *args], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


scratch = sys.argv[1]
os.makedirs(scratch, exist_ok=True)
rng = np.random.default_rng(13)
A = dict(enrichment_window=np.exp(rng.normal(0.15, 0.2, 8)),
         enrichment_map=np.exp(rng.normal(0.08, 0.1, 8)),
         shell_share_mapped=rng.uniform(0.7, 0.8, 8), shell_share_other=rng.uniform(0.24, 0.26, 8),
         repose_deg=rng.normal(30.4, 0.5, 8))
B = dict(enrichment_window=np.exp(rng.normal(0.25, 0.2, 7)),
         enrichment_map=np.exp(rng.normal(0.14, 0.1, 7)),
         shell_share_mapped=rng.uniform(0.85, 0.9, 7), shell_share_other=rng.uniform(0.24, 0.26, 7),
         repose_deg=rng.normal(30.1, 0.3, 7))
common = "theta_z=57;theta_x=57;f=0.98;size_ratio=1"
d = os.path.join(scratch, "two")
os.makedirs(d, exist_ok=True)
write(os.path.join(d, "analysis.h5"), {"b8": (f"{common};R_rho=8", B), "a3": (f"{common};R_rho=3", A)})
rc, out = run(d, "--reference", "R_rho=8")
print(out)
check("runs", rc == 0, f"exit {rc}")


def line_of(label, key):
    block = out.split(f"\n{label}  (N = ")[1]
    return next(l for l in block.splitlines() if l.strip().startswith(key))


def floats(s):
    return [float(x) for x in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", s)]


one = []
for label, arr in (("R_rho=3", A), ("R_rho=8", B)):
    for k in ("enrichment_window", "enrichment_map"):
        lv = np.log(arr[k])
        h = stats.t.ppf(0.975, len(lv) - 1) * lv.std(ddof=1) / math.sqrt(len(lv))
        want = [math.exp(lv.mean()), math.exp(lv.mean() - h), math.exp(lv.mean() + h)]
        got = floats(line_of(label, k))[:3]
        check(f"{label} {k}: geometric mean and interval", np.allclose(got, want, atol=6e-4),
              f"{got} vs {np.round(want, 4)}")
        one.append((label, k, stats.ttest_1samp(lv, 0).pvalue))
# Holm by hand over the four one-sample tests.
ps = sorted(one, key=lambda x: x[2])
adj, run_max = {}, 0.0
for i, (label, k, p) in enumerate(ps):
    run_max = max(run_max, min(1.0, (4 - i) * p))
    adj[(label, k)] = run_max
for (label, k), want in adj.items():
    m = re.search(r"Holm (\S+)", line_of(label, k))
    got = float(m.group(1))
    check(f"{label} {k}: Holm-adjusted p", abs(got - want) <= 0.051 * want, f"{got} vs {want:.3g}")
ratio = A["shell_share_mapped"] / A["shell_share_other"]
got = floats(line_of("R_rho=3", "shell ratio"))[0]
check("shell ratio per replica, averaged", abs(got - ratio.mean()) < 6e-3, f"{got} vs {ratio.mean()}")
m = re.search(r"R_rho=3: enrichment_map, ratio\s+(\S+) \[(\S+), (\S+)\]\s+p (\S+)", out)
want_r = math.exp(np.log(A["enrichment_map"]).mean() - np.log(B["enrichment_map"]).mean())
want_p = stats.ttest_ind(np.log(A["enrichment_map"]), np.log(B["enrichment_map"]),
                         equal_var=False).pvalue
check("R_rho=3 against R_rho=8: map ratio of geometric means and Welch p on the logs",
      m is not None and abs(float(m.group(1)) - want_r) < 6e-3
      and abs(float(m.group(4)) - want_p) <= 0.051 * want_p,
      f"{m.groups() if m else None} vs {want_r:.3g}, p {want_p:.2g}")
sd = math.sqrt((7 * np.log(A["enrichment_map"]).var(ddof=1) + 6 * np.log(B["enrichment_map"]).var(ddof=1))
               / 13)  # pooled over 8 + 7 replicas, weighted by n - 1
need = 2 * ((stats.norm.ppf(0.975) + stats.norm.ppf(0.8)) * sd / math.log(1.1)) ** 2
m = re.search(r"enrichment_map +pooled .*log SD (\S+): (\d+) replicas", out)
check("replicas for a 10% difference", m is not None and int(m.group(2)) == round(need),
      f"{m.groups() if m else None} vs {need:.1f}")

# The comparison rows: the shell ratio by Welch on the values, and Holm over the three rows.
rb = B["shell_share_mapped"] / B["shell_share_other"]
w = stats.ttest_ind(ratio, rb, equal_var=False)
m = re.search(r"R_rho=3: shell ratio, difference\s+(\S+) \[\S+, \S+\]\s+p (\S+)\s+Holm (\S+)", out)
check("shell ratio row: difference and Welch p", m is not None
      and abs(float(m.group(1)) - (ratio.mean() - rb.mean())) < 6e-3
      and abs(float(m.group(2)) - w.pvalue) <= 0.051 * w.pvalue, f"{m.groups() if m else None}")
pc = [w.pvalue] + [stats.ttest_ind(np.log(A[k]), np.log(B[k]), equal_var=False).pvalue
                   for k in ("enrichment_window", "enrichment_map")]
order = np.argsort(pc)
hand, run_max = [0.0] * 3, 0.0
for i, j in enumerate(order):
    run_max = max(run_max, min(1.0, (3 - i) * pc[j]))
    hand[j] = run_max
got = [float(x) for x in re.findall(r"R_rho=3: \S.*?Holm (\S+)", out)]
check("Holm over the three comparison rows", len(got) == 3 and all(
    abs(g - h) <= 0.051 * h for g, h in zip(got, hand)), f"{got} vs {np.round(hand, 4)}")

rc, out2 = run(d, "--reference", "R_rho=5")
check("--reference naming no point refused", rc != 0 and "names 0 points" in out2, out2.strip())
z = os.path.join(scratch, "zero")
os.makedirs(z, exist_ok=True)
A0 = dict(A, enrichment_map=np.r_[0.0, A["enrichment_map"][1:]])
write(os.path.join(z, "analysis.h5"), {"a": (f"{common};R_rho=3", A0), "b": (f"{common};R_rho=8", B)})
rc, out2 = run(z)
check("an enrichment of 0 refused (no logarithm)", rc != 0 and "enrichment of 0" in out2, out2.strip())
old = os.path.join(scratch, "old")
os.makedirs(old, exist_ok=True)
write(os.path.join(old, "analysis.h5"),
      {"a": (f"{common};R_rho=3", {k: v for k, v in A.items() if k != "shell_share_other"})})
rc, out2 = run(old)
check("a file without shell_share_other refused naming it", rc != 0 and "shell_share_other" in out2,
      out2.strip())
print(f"{check.failures} failure(s)")
sys.exit(1 if check.failures else 0)
