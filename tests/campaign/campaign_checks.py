"""Independent checks of a campaign directory, shared by the campaign tests.

Reads the manifest (JSON lines), the per-case fields files and ensemble.h5 with h5py/numpy only, so
that nothing here reuses the C++ code it checks. Run with Debian's /usr/bin/python3 (h5py)."""
import argparse
import glob
import json
import math
import os
import re
import signal
import subprocess
import sys

import h5py
import numpy as np


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def manifest(d):
    """Every manifest line in time order, and the latest record of every case."""
    lines = []
    for f in sorted(glob.glob(os.path.join(d, "manifest", "*.jsonl"))):
        with open(f) as fh:
            for line in fh:
                line = line.strip()
                if line:
                    lines.append(json.loads(line))
    lines.sort(key=lambda r: r["t"])  # Python's sort is stable, like the C++ reader
    latest = {}
    for r in lines:
        latest[r["case"]] = r
    return lines, latest


def fnv1a64(path):
    h = 1469598103934665603
    with open(path, "rb") as fh:
        for b in fh.read():
            h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return "fnv1a64:%016x" % h


def text(a):
    return a.decode() if isinstance(a, bytes) else str(a)


def t975(df):
    """Student t quantile 0.975 by bisection of the CDF (numpy only: no scipy needed)."""
    from math import lgamma, exp, log

    def betacf(a, b, x):
        c, d = 1.0, 1.0 - (a + b) * x / (a + 1)
        d = 1.0 / d
        h = d
        for m in range(1, 10000):
            m2 = 2 * m
            aa = m * (b - m) * x / ((a + m2 - 1) * (a + m2))
            d = 1 / (1 + aa * d); c = 1 + aa / c; h *= d * c
            aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1))
            d = 1 / (1 + aa * d); c = 1 + aa / c; h *= d * c
            if abs(d * c - 1) < 1e-16:
                break
        return h

    def ibeta(a, b, x):
        front = exp(lgamma(a + b) - lgamma(a) - lgamma(b) + a * log(x) + b * math.log1p(-x))
        if x < (a + 1) / (a + b + 2):
            return front * betacf(a, b, x) / a
        return 1 - front * betacf(b, a, 1 - x) / b

    lo, hi = 0.0, 100.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        tail = 0.5 * ibeta(0.5 * df, 0.5, df / (df + mid * mid))
        lo, hi = (mid, hi) if 1 - tail < 0.975 else (lo, mid)
    return 0.5 * (lo + hi)


def close(a, b, tol):
    """Equal to tol (relative to max(1, |b|)), NaN where the other is NaN."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return False, float("inf")
    nan_a, nan_b = np.isnan(a), np.isnan(b)
    if not np.array_equal(nan_a, nan_b):
        return False, float("inf")
    ok = ~nan_a
    if not ok.any():
        return True, 0.0
    err = np.abs(a[ok] - b[ok]) / np.maximum(1.0, np.abs(b[ok]))
    return bool(err.max() <= tol), float(err.max())


STATS = ("count", "mean", "m2", "variance", "ci95")


def point_row(e, pid, name, stat):
    """The statistic `stat` of field `name` for point `pid` (its row, without padding)."""
    p = e["points"][pid]
    row = e["fields"][name][stat][int(p.attrs["row"])]
    if name.startswith("series/"):
        row = row[: int(p.attrs["series_length"])]
    return np.asarray(row, float)


def check_against_cases(d, tol=1e-12):
    """ensemble.h5 against a recomputation from the per-case fields files of the done cases."""
    _, latest = manifest(d)
    done = {c: r for c, r in latest.items() if r["status"] == "done"}
    failed = {c: r for c, r in latest.items() if r["status"] == "failed"}
    worst = 0.0
    with h5py.File(os.path.join(d, "ensemble.h5"), "r") as e:
        points = e["points"]
        for pid in points:
            p = points[pid]
            members = sorted(c for c, r in done.items() if r["point"] == pid)
            listed = [m for m in text(p.attrs["members"]).split(",") if m]
            if listed != members:
                fail("point %s: members %s, manifest says %s" % (pid, listed, members))
            for c in members:
                f = os.path.join(d, done[c]["output"], "fields.h5")
                if fnv1a64(f) != done[c]["checksum"]:
                    fail("case %s: fields.h5 checksum differs from the manifest" % c)
            excluded = text(p.attrs["failed"])
            for c, r in failed.items():
                if r["point"] == pid and c not in excluded:
                    fail("point %s does not say that failed case %s is excluded" % (pid, c))
            if not members:
                continue
            names = [n for n in text(p.attrs["fields"]).split(",") if n]
            for name in names:
                stack = []
                for c in members:
                    with h5py.File(os.path.join(d, done[c]["output"], "fields.h5"), "r") as f:
                        stack.append(np.asarray(f[name][()], float).ravel())
                x = np.array(stack)
                n = np.sum(~np.isnan(x), axis=0).astype(float)
                with np.errstate(invalid="ignore", divide="ignore"):
                    mean = np.where(n > 0, np.nansum(x, axis=0) / np.maximum(n, 1), np.nan)
                    dev = np.where(np.isnan(x), 0.0, x - mean)
                    var = np.where(n >= 2, (dev ** 2).sum(axis=0) / (n - 1), np.nan)
                if not np.array_equal(point_row(e, pid, name, "count"), n):
                    fail("%s/%s: count differs" % (pid, name))
                for stat, want in (("mean", mean), ("variance", var)):
                    ok, err = close(point_row(e, pid, name, stat), want, tol)
                    worst = max(worst, err)
                    if not ok:
                        fail("%s/%s/%s differs from the recomputation by %g" % (pid, name, stat, err))
                half = np.full_like(var, np.nan)
                for k in np.unique(n[n >= 2]):
                    sel = n == k
                    half[sel] = t975(k - 1) * np.sqrt(var[sel] / k)
                ok, err = close(point_row(e, pid, name, "ci95"), half, 1e-9)
                if not ok:
                    fail("%s/%s/ci95 differs by %g" % (pid, name, err))
    return done, failed, worst


def compare_ensembles(a, b, tol):
    """Two ensemble files: the same points, members, exclusions and counts; statistics to tol."""
    worst = 0.0
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        pa, pb = sorted(fa["points"]), sorted(fb["points"])
        if pa != pb:
            fail("points differ: %s vs %s" % (pa, pb))
        for pid in pa:
            ga, gb = fa["points"][pid], fb["points"][pid]
            for key in ("members", "params", "fields", "n_failed", "n_missing", "series_length"):
                if text(ga.attrs[key]) != text(gb.attrs[key]):
                    fail("point %s: attribute %s differs" % (pid, key))
            ids = lambda s: sorted(line.split(":")[0] for line in text(s).split("\n") if line)
            if ids(ga.attrs["failed"]) != ids(gb.attrs["failed"]):
                fail("point %s: excluded cases differ" % pid)
            for name in [n for n in text(ga.attrs["fields"]).split(",") if n]:
                for stat in STATS:
                    x, y = point_row(fa, pid, name, stat), point_row(fb, pid, name, stat)
                    if stat == "count":
                        if not np.array_equal(x, y):
                            fail("%s/%s/count differs" % (pid, name))
                        continue
                    ok, err = close(x, y, tol)
                    worst = max(worst, err)
                    if not ok:
                        fail("%s/%s/%s differs by %g (> %g)" % (pid, name, stat, err, tol))
            if int(ga.attrs["series_length"]) > 0:
                for axis in ("time", "iteration"):
                    ra, rb = int(ga.attrs["row"]), int(gb.attrs["row"])
                    k = int(ga.attrs["series_length"])
                    if not np.array_equal(fa["series"][axis][ra][:k], fb["series"][axis][rb][:k]):
                        fail("%s: series %s differs" % (pid, axis))
    return worst


def running_within_groups(out, text, groups, expect_held=False):
    """Every progress line counts at most one running case per group (a group's next case, held
    while it finishes the last, is "next"), and the counts add up to the total; the running cases'
    shares of their steps, where they reported, and the cases preparing (bed, beta) are no more
    than the running cases, the shares within 0-100%; every held case gets its own "start" line later (expect_held: and there is at least
    one)."""
    seen = 0
    for m in re.finditer(r"\[campaign\] done (\d+) \| running (\d+)(?: \(([^)]*)\))?"
                         r"(?: \| next (\d+))? \| failed (\d+) \| left (\d+) of (\d+)", text):
        shares = [float(x) for x in re.findall(r"([0-9.]+)%", m.group(3) or "")]
        preparing = re.search(r"(\d+) preparing", m.group(3) or "")
        preparing = int(preparing.group(1)) if preparing else 0
        done, running, nxt, failed, left, total = (int(m.group(k) or 0) for k in (1, 2, 4, 5, 6, 7))
        seen += 1
        if running > groups or done + running + nxt + failed + left != total:
            fail("%s: progress line '%s' (%d groups)" % (out, m.group(0), groups))
        if len(shares) + preparing > running or any(not 0 <= x <= 100 for x in shares):
            fail("%s: progress line '%s': shares of the running cases' steps" % (out, m.group(0)))
    if not seen:
        fail("%s: no progress line" % out)
    # A case held as a group's "next" gets its own "start" line when the group's case ends.
    held = re.findall(r"\[campaign\] next (\w+) ", text)
    started = set(re.findall(r"\[campaign\] start (\w+) .*held until now", text))
    if expect_held and not held:
        fail("%s: no case was held as a group's next (expected with more cases than groups)" % out)
    if sorted(set(held) - started):
        fail("%s: held cases without a start line: %s" % (out, sorted(set(held) - started)))


def campaign_arguments(doc):
    """The options every campaign test takes (CMakeLists.txt's MPI_ARGS and --campaign); the
    caller adds its own and calls parse_args()."""
    ap = argparse.ArgumentParser(description=doc)
    ap.add_argument("--tumble", required=True)
    ap.add_argument("--mpiexec", required=True)
    ap.add_argument("--np-flag", default="-n")
    ap.add_argument("--campaign", required=True)
    return ap


def same_tables(mine, theirs):
    """Fails unless ensemble file `mine` holds tables and each equals, bit for bit (NaN for NaN),
    the same table of `theirs`. Returns how many tables there are."""
    with h5py.File(mine, "r") as m, h5py.File(theirs, "r") as t:
        tables = []
        m.visit(lambda name: tables.append(name) if isinstance(m[name], h5py.Dataset) else None)
        if not tables:
            fail("%s holds no table" % mine)
        for name in tables:
            if name not in t or not np.array_equal(m[name][()], t[name][()], equal_nan=True):
                fail("table %s of %s differs from %s's" % (name, mine, theirs))
    return len(tables)


def mpiexec_command(mpiexec, np_flag, n):
    cmd = [mpiexec, np_flag, str(n)]
    out = subprocess.run([mpiexec, "--version"], capture_output=True, text=True).stdout
    if "Open MPI" in out or "OpenRTE" in out:
        cmd.append("--oversubscribe")  # a CI machine may have fewer cores than ranks
    return cmd


def run_or_fail_on_hang(cmd, timeout, hang, env=None):
    """Runs `cmd` (printed) in a session of its own, so that a job that hangs is killed with all
    its ranks; fails the test with `hang` if it has not ended within `timeout` s. Returns (exit
    code, stdout and stderr together), the output printed."""
    print(" ".join(cmd), flush=True)
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         env=env, start_new_session=True)
    try:
        text, _ = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        fail("no end within %d s: %s" % (timeout, hang))
    print(text)
    return p.returncode, text


def run_campaign_or_fail(mpiexec, np_flag, n, tumble, campaign):
    """`tumble campaign CAMPAIGN` on n ranks, its output printed; fails the test unless it exits 0.
    Returns the completed process (stdout holds the campaign's lines)."""
    cmd = mpiexec_command(mpiexec, np_flag, n) + [tumble, "campaign", campaign]
    print(" ".join(cmd), flush=True)
    run = subprocess.run(cmd, capture_output=True, text=True)
    print(run.stdout)
    if run.returncode != 0:
        print(run.stderr)
        fail("campaign failed")
    return run
