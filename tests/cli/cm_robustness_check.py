#!/usr/bin/python3
"""`tumble cm` robustness (issue 17, deliverable 6), the parts the bad-input table cannot show.

The refusals themselves (memory, --islands/--orbits of another protocol, missing files) are rows
of bad_inputs.tsv. This script checks what needs files made with h5py, a run's output, or its
memory use:

  memory     each command's estimate (read from its refusal with --max-memory 1) is at least
             the peak resident memory a real run adds above a trivial one (os.wait4), and not
             absurdly above it (so that the refusals are not blanket ones);
  progress   long runs print "[cm <command>] <stage>: P%  elapsed h:mm:ss  ETA h:mm:ss" lines
             (forced with --progress-interval 0.01); the default interval (10 s) keeps short
             runs quiet;
  Pe         no drift and no diffusion prints "Pe = none" (never "nan") and stores peclet = NaN
             with peclet_text = "none"; drift without diffusion "infinite";
  files      an orbits file without protocol attributes (not written by Tumble) is used with a
             warning naming what is missing; a damaged islands table is refused (exit 3), its
             attributes copied by h5py read back whole; a drift grid with a NaN cell is refused
             (exit 2, the cell named); one written by h5py is read, string attribute included.
  signals    SIGTERM or SIGINT while the output is written removes its temporary.

usage: cm_robustness_check.py TUMBLE WORK_DIR     exit 0 when every check holds
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

TUMBLE, WORK = sys.argv[1], sys.argv[2]
os.makedirs(WORK, exist_ok=True)
failures = []


def run(args):
    """Runs tumble; returns (exit code, stdout, stderr, None)."""
    p = subprocess.run([TUMBLE] + args, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                       cwd=WORK, timeout=300)
    return p.returncode, p.stdout, p.stderr, None


def run_rss(args):
    """As run(), measuring the child's peak resident memory (Linux: ru_maxrss in KiB)."""
    p = subprocess.Popen([TUMBLE] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         stdin=subprocess.DEVNULL, cwd=WORK)
    out, err = p.stdout.read().decode(), p.stderr.read().decode()  # small: no pipe can fill
    _, status, usage = os.wait4(p.pid, 0)
    return os.waitstatus_to_exitcode(status), out, err, usage.ru_maxrss * 1024


def check(ok, what, detail=""):
    print("%-4s %s" % ("ok" if ok else "FAIL", what))
    if not ok:
        failures.append(what + ("\n" + detail if detail else ""))


def path(name):
    return os.path.join(WORK, name)


UNITS = {"B": 1, "KiB": 2**10, "MiB": 2**20, "GiB": 2**30, "TiB": 2**40}


def estimate(args):
    """The bytes a command says it needs, from its refusal under --max-memory 1 (one byte)."""
    rc, out, err, _ = run(args + ["--max-memory", "1"])
    m = re.search(r"need about ([0-9.e+]+) (B|KiB|MiB|GiB|TiB)", out + err)
    if rc != 2 or not m:
        failures.append("no estimate from tumble %s: rc %s\n%s" % (" ".join(args), rc, out + err))
        return None
    return float(m.group(1)) * UNITS[m.group(2)]


P57 = ["--theta-z", "57", "--theta-x", "57"]
rc, out, err, _ = run(["cm", "orbits"] + P57 + ["--max-period", "1", "--grid", "8", "--no-kam",
                                                "-o", path("o57.h5")])
assert rc == 0, out + err
ORBITS = path("o57.h5")

# --- memory: the estimate covers the run ------------------------------------------------------
_, _, _, base = run_rss(["cm", "drift", "--n", "2", "-o", path("d2.h5")])
RUNS = {
    "poincare": ["cm", "poincare"] + P57 + ["--seeds", "100", "--periods", "20000",
                                            "-o", path("p.h5")],
    "mcm": ["cm", "mcm"] + P57 + ["--islands", ORBITS, "--tracers", "10000", "--snapshot", "1",
                                  "--cumulative", "1,30", "--stride", "1", "-o", path("m.h5")],
    "manifolds": ["cm", "manifolds"] + P57 + ["--orbits", ORBITS, "--kind", "unstable",
                                              "--max-points", "400000", "-o", path("mf.h5")],
}
for name, args in RUNS.items():
    est = estimate(args)
    rc, out, err, rss = run_rss(args)
    extra = rss - base
    print("     %-9s estimate %6.1f MiB, run added %6.1f MiB" % (name, (est or 0) / 2**20,
                                                                extra / 2**20))
    check(rc == 0, "%s runs" % name, out + err)
    if est is not None:
        check(extra <= est, "%s: the estimate covers the memory the run added" % name)
        check(est <= 6 * extra + 32 * 2**20, "%s: the estimate is not far above it" % name)

# --- progress lines ------------------------------------------------------------------------------
LINE = r"\[cm %s\] [^\n]+: [0-9.]+%%  elapsed \d+:\d\d:\d\d  ETA (\d+:\d\d:\d\d|--:--:--)"
PROGRESS = {
    # One ray: a run of ~1 s, well inside the default interval (16 rays take ~12 s).
    "orbits": ["cm", "orbits"] + P57 + ["--max-period", "3", "--grid", "16", "--no-kam",
                                        "--island-rays", "1", "-o", path("o3.h5")],
    "mcm": ["cm", "mcm"] + P57 + ["--islands", ORBITS, "--tracers", "2000", "-o", path("m2.h5")],
    "manifolds": ["cm", "manifolds"] + P57 + ["--orbits", ORBITS, "--max-points", "20000",
                                              "-o", path("mf2.h5")],
    "poincare": ["cm", "poincare"] + P57 + ["--seeds", "100", "--periods", "2000",
                                            "-o", path("p2.h5")],
}
for name, args in PROGRESS.items():
    rc, out, err, _ = run(args + ["--progress-interval", "0.01"])
    check(rc == 0 and re.search(LINE % name, out) is not None,
          "%s prints progress lines with an ETA on stdout" % name, out[-1500:] + err)
    rc, out, err, _ = run(args)
    check(rc == 0 and "[cm " not in out, "%s is quiet when shorter than the interval" % name,
          out[-1500:])

# --- Péclet number without drift -----------------------------------------------------------------
SHORT = ["--islands", ORBITS, "--tracers", "50", "--snapshot", "2", "--cumulative", "2,2"]
for flags, word, attr in ((["--no-drift", "--c", "0"], "none", np.isnan),
                          (["--c", "0"], "infinite", np.isinf)):
    out_file = path("pe_%s.h5" % word)
    rc, out, err, _ = run(["cm", "mcm"] + P57 + SHORT + flags + ["-o", out_file])
    check(rc == 0 and "Pe = %s" % word in out and "nan" not in out.lower(),
          "mcm %s prints Pe = %s" % (" ".join(flags), word), out + err)
    if rc == 0:
        with h5py.File(out_file, "r") as f:
            text = f.attrs["peclet_text"]
            text = text.decode() if isinstance(text, bytes) else text
            check(attr(f.attrs["peclet"]) and text == word,
                  "mcm %s stores peclet %s and peclet_text '%s'" % (" ".join(flags),
                                                                  f.attrs["peclet"], text))

# --- islands files without a protocol, damaged ones, bad drift grids ----------------------------
bare = path("bare.h5")
with h5py.File(ORBITS, "r") as src, h5py.File(bare, "w") as dst:
    for key in src:
        src.copy(key, dst)  # datasets only: no root attributes
rc, out, err, _ = run(["cm", "mcm"] + P57 + SHORT[2:] + ["--islands", bare, "-o", path("mb.h5")])
check(rc == 0 and "warning" in err and "does not record its protocol" in err
      and "theta_z_deg" in err, "an orbits file without its protocol is used, with a warning",
      out + err)

damaged = path("damaged.h5")
with h5py.File(ORBITS, "r") as src, h5py.File(damaged, "w") as dst:
    for key in src:
        src.copy(key, dst)
    for k, v in src.attrs.items():
        dst.attrs[k] = v
    for name, data in (("offsets", np.array([0, 50], dtype=np.int64)),
                       ("r", np.array([0.95]))):
        del dst["islands/" + name]
        dst["islands/" + name] = data
rc, out, err, _ = run(["cm", "mcm"] + P57 + SHORT[2:] + ["--islands", damaged,
                                                          "-o", path("md.h5")])
check(rc == 3 and "corrupt input" in err, "a damaged islands table is refused (exit 3)",
      "rc %s\n%s" % (rc, out + err))

nan_grid = path("nan_drift.h5")
with h5py.File(nan_grid, "w") as f:
    v = np.zeros((30, 30))
    v[4, 7] = np.nan
    f["v_ax"], f["sigma_ax"] = v, np.ones((30, 30))
rc, out, err, _ = run(["cm", "mcm"] + P57 + SHORT + ["--drift", nan_grid, "-o", path("mn.h5")])
check(rc == 2 and "cell [4][7]" in err, "a drift grid with a NaN cell is refused (exit 2)",
      "rc %s\n%s" % (rc, out + err))

# A grid written by h5py: its string attribute is variable-length (Tumble's are fixed-length).
h5py_grid = path("h5py_drift.h5")
with h5py.File(h5py_grid, "w") as f:
    f["v_ax"], f["sigma_ax"] = np.full((30, 30), 0.01), np.ones((30, 30))
    f.attrs["source"] = "measured by hand"
rc, out, err, _ = run(["cm", "mcm"] + P57 + SHORT + ["--drift", h5py_grid, "-o", path("mh.h5")])
check(rc == 0 and "drift grid: measured by hand," in out,
      "a drift grid written by h5py is read with its source attribute", out + err)

# --- no hyperbolic point: said, and the file keeps its layout ----------------------------------
# (180°, 180°) is the identity map: no hyperbolic points. Before, nothing was said and the file had
# no /manifolds group (the plot script failed on it).
empty = path("m180.h5")
rc, out, err, _ = run(["cm", "manifolds", "--theta-z", "180", "--theta-x", "180", "--max-period",
                       "2", "--grid", "10", "-o", empty])
with h5py.File(empty, "r") as f:
    has_group = "manifolds" in f and len(f["manifolds"]) == 0
check(rc == 0 and "no hyperbolic periodic point" in out and has_group,
      "manifolds without hyperbolic points: said, an empty /manifolds", out + err)

# --- a signal while the output is being written ------------------------------------------------
# SIGTERM (or Ctrl-C) while the output's temporary is open: it is removed, and the final name is
# never made (it stayed behind, NAME.tmp.<pid>, up to gigabytes, before 2026-11-29).
import glob  # noqa: E402
import signal  # noqa: E402
import time  # noqa: E402

for sig in (signal.SIGTERM, signal.SIGINT):
    final = path("signalled_%d.h5" % sig)
    proc = subprocess.Popen([TUMBLE, "cm", "manifolds"] + P57 +
                            ["--orbits", ORBITS, "--max-points", "5000000", "--iterations", "30",
                             "-o", final], cwd=WORK, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while not glob.glob(final + ".tmp.*") and proc.poll() is None and time.time() < deadline:
        time.sleep(0.02)
    if proc.poll() is not None or not glob.glob(final + ".tmp.*"):
        proc.kill()
        check(False, "%s: no temporary seen while the command ran" % signal.Signals(sig).name)
        continue
    proc.send_signal(sig)
    rc = proc.wait(timeout=120)
    left = glob.glob(final + "*")
    check(rc == -sig and not left, "%s while writing: the temporary removed, no final file"
          % signal.Signals(sig).name, "rc %s, left %s" % (rc, left))

print("\n%d failures" % len(failures))
for f in failures:
    print("FAILED: " + f)
sys.exit(1 if failures else 0)
