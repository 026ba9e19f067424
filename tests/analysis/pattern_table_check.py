"""jobs/accuracy/pattern_table.py on constructed campaigns (no engine run): the fairness of its
pattern correlation and its multiplicity control.

  /usr/bin/python3 pattern_table_check.py SCRATCH_DIR

1. One campaign whose cases are split by a swept key into two columns with *identical* maps and
   series on the same beds (replicas): every difference must be 0, the correlation's included.
   (Correlating the second column with the mean of all N reference maps, and the reference's own
   replicas with the other N - 1, made the copy look +0.1 to +0.4 better correlated.) The wall per
   iteration counts every call of a stopped and resumed case, not only the last; the frozen share
   (a rigid bulk's results.h5 series) is reported for the rigid column only and not tested.
2. The same with one observable of the second column shifted by far more than the replicas'
   scatter (radial segregation after iteration 2) and small noise elsewhere: the
   Benjamini-Hochberg line counts exactly that one difference (both tests of it), not the others.
3. --tier LABEL=DIR reads two campaign folders as columns in the order given, the first the
   reference, and refuses a folder that is not there.
4. --split with a value that names a second swept key (rigid+fidelity.bulk_segment_thaw=off):
   three columns of 3 replicas each, the plain "rigid" column without the other's cases (its
   differences 0), the third's planted shift seen in its column only; without the third value
   the "rigid" column would hold two points' cases, and that is refused.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "..", "..", "jobs", "accuracy", "pattern_table.py")
ITERATIONS = 4
sys.path.insert(0, HERE)
from script_run import Checks  # noqa: E402

check = Checks()


def write_case(out, cid, replica, params, c_l, radial):
    d = os.path.join(out, "cases", cid)
    os.makedirs(d, exist_ok=True)
    if "rigid" in params:  # a rigid bulk's run series holds its frozen share (mean 0.5 + replica / 100)
        with h5py.File(os.path.join(d, "results.h5"), "w") as f:
            f.create_dataset("series/frozen_fraction", data=[0.4 + replica / 100, 0.6 + replica / 100])
    with h5py.File(os.path.join(d, "fields.h5"), "w") as f:
        f.attrs["case_id"] = cid
        f.attrs["replica"] = replica
        f.attrs["params"] = params
        f.create_dataset("concentration/c_L", data=c_l)
        f.create_dataset("series/iteration", data=np.arange(0.0, ITERATIONS + 0.5, 0.5))
        f.create_dataset("series/radial_segregation", data=np.repeat(radial, 2)[:2 * ITERATIONS + 1])
    # A run of 2000 steps made of two calls: stopped by a signal after 1000 steps in 50 + replica
    # s, resumed and done in 150 s: (200 + replica) s over 4 iterations (the last call alone
    # would say 75 s an iteration).
    header = (f"[run] case: 100 particles, dt = 0.01 s, 2000 steps (20 s simulated, {ITERATIONS} iterations, "
              "beta = 27 deg), pair loop: scalar, output in x\n")
    with open(os.path.join(d, "log.txt"), "w") as f:
        f.write(header)
        f.write(f"[case] stopped by SIGUSR1 at step 1000 of 2000 (t = 10 s): checkpoint written to x; this call "
                f"ran 1000 steps in {50.0 + replica} s (2.0e+03 particle-steps/s) after 51 s\n")
        f.write(header)
        f.write("[run] done: 1000 steps in 150 s (6.7e+02 particle-steps/s); results in x\n")


def campaign(out, columns, shift=0.0, noise=0.0, seed=1, shifted=None):
    """Three replicas per column value; every column the first's maps and series (+ shift of the
    radial segregation at iteration 2 in the columns `shifted`, default all but the first, and a
    little noise in the others' series)."""
    rng = np.random.default_rng(seed)
    pattern = np.sin(np.linspace(0, 3, 256)).reshape(16, 16)
    for r in range(3):
        c_l = pattern + 0.3 * rng.standard_normal((16, 16))
        radial = np.concatenate([[0.0], 0.05 * np.arange(1, ITERATIONS + 1) + 0.01 * rng.standard_normal(ITERATIONS)])
        for k, (key, value) in enumerate(columns):
            rad = radial.copy()
            if k and (shifted is None or k in shifted):
                rad[2] += shift
                rad[1:] += noise * rng.standard_normal(ITERATIONS)
            # (a value "rigid;k=v" writes a second swept key into the params)
            cid = value.replace(";", "_").replace("=", "_")
            write_case(out, f"{cid}{r}", r, f"theta_z=57;theta_x=57;{key}={value}", c_l, rad)


def run(*args):
    p = subprocess.run([sys.executable, TABLE, *args], capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def main():
    scratch = sys.argv[1]
    # 1. identical columns on common beds
    same = os.path.join(scratch, "same")
    campaign(same, [("fidelity.bulk", "dynamic"), ("fidelity.bulk", "rigid")])
    rc, text = run(same, str(ITERATIONS), "--split", "fidelity.bulk=dynamic,rigid")
    print(text)
    deltas = re.findall(r"; Δ ([-+0-9.e]+) ± ", text)
    paired = re.findall(r"paired Δ ([-+0-9.e]+) ± ", text)
    check("identical columns: table printed", rc == 0 and len(deltas) == 1 + ITERATIONS, f"{len(deltas)} differences")
    check("identical columns: every Welch difference 0 (the correlation's too)",
          all(float(d) == 0 for d in deltas), " ".join(deltas))
    check("identical columns: every paired difference 0", all(float(d) == 0 for d in paired), " ".join(paired))
    check("identical columns: N = 3 warned", "few replicas" in text)
    wall = next((line for line in text.splitlines() if line.startswith("| wall per iteration [s] |")), "")
    frozen = next((line for line in text.splitlines() if line.startswith("| frozen share")), "")
    check("frozen share: the rigid column's run mean, none for the dynamic one, not tested",
          frozen.split(" | ")[1:] == ["–", "0.51 [0.485, 0.535] (N = 3) |"], frozen)
    check("wall per iteration summed over a case's stopped and finished calls (50.25 s, not the last call's 75)",
          wall.count("| 50.2 ± 0.62 (N = 3)") == 2, wall)
    # 2. one large shift among small noise
    shifted = os.path.join(scratch, "shifted")
    campaign(shifted, [("fidelity.bulk", "dynamic"), ("fidelity.bulk", "rigid")], shift=0.2, noise=0.005)
    rc, text = run(shifted, str(ITERATIONS), "--split", "fidelity.bulk=dynamic,rigid")
    print(text)
    m = re.search(r"(\d+) tests; Benjamini-Hochberg at q = 0.05: (\d+) significant", text)
    starred = re.findall(r"#   (.*) \((Welch|paired)\): p = .* \*$", text, re.M)
    check("one shifted observable: BH line", m is not None)
    check("one shifted observable: only radial segregation after 2 iterations significant",
          bool(starred) and all(s[0] == "radial segregation after 2 iterations" for s in starred),
          f"{starred}")
    # 3. --tier columns from two folders
    a, b = os.path.join(scratch, "tier_a"), os.path.join(scratch, "tier_b")
    campaign(a, [("fidelity.bulk", "dynamic")], seed=2)
    campaign(b, [("fidelity.bulk", "dynamic")], seed=3)
    rc, text = run("-", str(ITERATIONS), "--tier", f"standard={a}", "--tier", f"fast={b}",
                   "--point", "fidelity.bulk=dynamic")
    print(text)
    check("--tier: columns in the order given, the first the reference",
          rc == 0 and "| observable | standard | fast |" in text and "reference tier: standard" in text)
    rc, text = run("-", str(ITERATIONS), "--tier", f"standard={a}", "--tier", "fast=/nonexistent/x")
    check("--tier: a missing folder refused", rc != 0 and "LABEL=DIR" in text, text.strip())
    # 4. a column named by two swept keys
    three = os.path.join(scratch, "three")
    off = "rigid;fidelity.bulk_segment_thaw=off"
    campaign(three, [("fidelity.bulk", "dynamic"), ("fidelity.bulk", "rigid"), ("fidelity.bulk", off)],
             shift=0.2, noise=0.005, shifted={2})
    label = "rigid+fidelity.bulk_segment_thaw=off"
    rc, text = run(three, str(ITERATIONS), "--split", f"fidelity.bulk=dynamic,rigid,{label}")
    print(text)
    row = next((line for line in text.splitlines() if line.startswith("| radial segregation after 2 iterations |")), "")
    cells = row.split(" | ")[1:]
    check("two keys: three columns", rc == 0 and f"| observable | dynamic | rigid | {label} |" in text)
    check("two keys: every column N = 3 (the plain rigid column without the other's cases)",
          len(cells) == 3 and all("(N = 3)" in c for c in cells), row)
    check("two keys: the planted shift in its own column only",
          len(cells) == 3 and "Δ +0.2" not in cells[1] and re.search(r"; Δ \+0\.2\d* ±", cells[2]) is not None, row)
    rc, text = run(three, str(ITERATIONS), "--split", "fidelity.bulk=dynamic,rigid")
    check("two keys: a column of two points refused", rc != 0 and "holds cases of 2 points" in text,
          text.strip().splitlines()[0] if text.strip() else "")
    sys.exit(1 if check.failures else 0)


if __name__ == "__main__":
    main()
