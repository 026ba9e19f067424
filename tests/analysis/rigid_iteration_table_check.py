"""jobs/accuracy/rigid_iteration_table.py on a constructed job (no engine run): the per-segment
and whole-iteration ratios of the chunks' wall times, the twin estimate of a half not run, and
--base for a job without a dynamic run.

  /usr/bin/python3 rigid_iteration_table_check.py SCRATCH_DIR

A (57°, 57°) iteration with beta = 27° of 2,220 steps (segments end at steps 270, 840, 1110,
1380, 1950, 2220: the angles' shares) in chunks of 30 steps. The planted wall times per chunk:
the base 3 s in the tilts and 4 s in the rotations, the rigid run 1 s and 2 s; so the tilts'
ratio is 3, the rotations' 2, and the iteration's 260 / 112 = 2.32 (36 tilt chunks, 38 rotation
chunks).
"""
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_run import Checks, script_stdout  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "..", "..", "jobs", "accuracy", "rigid_iteration_table.py")
STEPS, CHUNK = 2220, 30
EDGES = [270, 840, 1110, 1380, 1950, 2220]
check = Checks()


def write_job(out, base, last_step=STEPS):
    os.makedirs(os.path.join(out, "rigid"), exist_ok=True)
    with open(os.path.join(out, "rigid.log"), "w") as f:
        f.write(f"[run] 100 particles, dt = 1e-05 s, {STEPS} steps (0.0222 s simulated, 1 iterations)\n")
    with h5py.File(os.path.join(out, "rigid", "results.h5"), "w") as f:
        f.attrs["scene"] = ('protocol.mode = "biaxial"\nprotocol.theta_z = 57\nprotocol.theta_x = 57\n'
                            "protocol.repose = 27\n")
        it = np.linspace(0, last_step / STEPS, 50, endpoint=False)
        f.create_dataset("series/iteration", data=it)
        f.create_dataset("series/frozen_fraction", data=np.full(50, 0.6))
    with open(os.path.join(out, "chunks.tsv"), "w") as f:
        f.write("variant\tfirst_step\tsteps\twall_s\tfrozen\tutc\n")
        for first in range(0, last_step, CHUNK):
            seg = int(np.searchsorted(EDGES, first + CHUNK / 2, side="right"))
            rotation = seg in (1, 4)
            f.write(f"{base}\t{first}\t{CHUNK}\t{4.0 if rotation else 3.0}\t-\t00:00Z\n")
            f.write(f"rigid\t{first}\t{CHUNK}\t{2.0 if rotation else 1.0}\t0.6\t00:00Z\n")


def table(out, *extra):
    return script_stdout(TABLE, out, *extra)


def segment_ratios(text):
    return [float(x) for x in re.findall(r"\| \*\*([0-9.]+)\*\* \|", text)]


work = sys.argv[1]
shutil.rmtree(work, ignore_errors=True)

# 1. The whole iteration, dynamic against rigid.
out = os.path.join(work, "whole")
write_job(out, "dynamic")
text = table(out)
check("whole: 74 paired chunks, 100% of the iteration", "74 paired chunks, 2220 of 2220 steps (100.0%" in text)
check("whole: the segments' ratios are the planted 3, 2, 3, 3, 2, 3",
      segment_ratios(text) == [3.0, 2.0, 3.0, 3.0, 2.0, 3.0], str(segment_ratios(text)))
m = re.search(r"dynamic 260 s, rigid 112 s, \*\*dynamic / rigid = 2\.32\*\* \(95% bootstrap interval over"
              r" the paired chunks ([0-9.]+)-([0-9.]+)\)", text)
check("whole: the iteration's ratio 260 / 112 = 2.32", m is not None)
check("whole: no scatter within a segment, so the interval is the point",
      m is not None and m.group(1) == m.group(2) == "2.32", m.group(0) if m else "")

# 2. The z half alone (steps 0-1110): the x half taken from its twins gives the same iteration.
out = os.path.join(work, "half")
write_job(out, "dynamic", last_step=EDGES[2])
text = table(out)
check("half: 37 paired chunks", "37 paired chunks, 1110 of 2220 steps" in text)
check("half: the x half's segments estimated from their twins, 2.32x overall",
      "tilt by beta (2), rotate about x, tilt back (2) taken from their twins" in text
      and "dynamic 260 s, rigid 112 s, **2.32x**" in text)

# 3. A job without a dynamic run (VARIANTS="rigid rigid_before"): --base names the other run.
out = os.path.join(work, "base")
write_job(out, "rigid_before")
text = table(out, "--base", "rigid_before")
check("--base: the header and the total name the base run",
      "| rigid_before wall s | rigid wall s | rigid_before / rigid |" in text
      and "**rigid_before / rigid = 2.32**" in text)
r = subprocess.run([sys.executable, TABLE, out], capture_output=True, text=True)
check("without --base, a job with no dynamic run is refused with the runs named",
      r.returncode != 0 and "no paired chunks of dynamic and rigid" in r.stderr, r.stderr.strip())

# 4. Piped to a reader that stops after the first line (`| head -1`): no traceback.
p = subprocess.Popen([sys.executable, TABLE, os.path.join(work, "whole")], stdout=subprocess.PIPE,
                     stderr=subprocess.PIPE, text=True)
p.stdout.readline()
p.stdout.close()  # the reader is gone: the table's next write meets a closed pipe
err = p.stderr.read()
p.wait()
check("piped to a reader that stops, it ends without a traceback", "Traceback" not in err, err)

print(f"{check.failures} failure(s)")
sys.exit(1 if check.failures else 0)
