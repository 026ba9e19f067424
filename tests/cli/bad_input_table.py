#!/usr/bin/env python3
"""Bad input through the CLI, table-driven (issue 21, deliverable 8).

Each row of bad_inputs.tsv is one command line that Tumble must refuse before any work: the exit
code it must end with (src/base/exit_codes.hpp: 2 = bad input) and a word its message must hold.
Placeholders in a row: {scenes} (the shipped scenes), {fx} (fixture files this script writes:
empty and comment-only scenes, bad campaigns, directories, see FIXTURES; and files tumble writes
for it, orbits files of two protocols, see TUMBLE_FIXTURES). Leading NAME=value words of a
command set environment variables for that row only, as in a shell. A row is

  refused as expected  the exit code and the word match;
  crash                killed by a signal, an uncaught C++ exception (std::bad_alloc,
                       "terminate called"), or over --row-limit seconds (a hang);
  silently accepted    exit 0: the bad input was taken;
  mismatch             any other exit code, or the message lacks the word.

A few good inputs run first (--help, --version, a valid --check): a binary that refuses
everything must not pass. The test fails unless every row is refused as expected.

usage: bad_input_table.py --tumble BIN --table bad_inputs.tsv --source SRC [--work DIR]
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

import h5py

TINY_BODY = """
[tumbler]
radius = 0.020
[particles]
d_small = 0.002
d_large = 0.004
large_fraction = 0.15
[contact]
collision_time = 1e-3
[protocol]
mode = "biaxial"
theta_z = 57
theta_x = 57
rpm = 3
[time]
dt = 2e-5
"""

# name -> content ("/" at the end: a directory). Scenes and campaigns that are wrong in one way.
FIXTURES = {
    "empty.toml": "",
    "blank.toml": "\n   \n\t\n",
    "comments.toml": "# a scene that says nothing\n# [scene]\n# name = \"x\"\n",
    "noname.toml": TINY_BODY,
    "emptyname.toml": "[scene]\nname = \"  \"\n" + TINY_BODY,
    "sectiononly.toml": "[scene]\n" + TINY_BODY,
    "badtoml.toml": "[scene]\nname = \"x\"\n[tumbler\nradius = 0.02\n",
    "typo.toml": "[scene]\nname = \"x\"\n[tumbler]\nradus = 0.02\n",
    "array.toml": "[scene]\nname = \"x\"\n[tumbler]\nradius = [0.02]\n",
    "bigint.toml": "[scene]\nname = \"x\"\n[protocol]\nrepose = 9007199254740993\n",
    "adir/": None,
    "adir.toml/": None,
    "c_empty.toml": "",
    "c_comments.toml": "# nothing\n",
    "c_noscene.toml": "[campaign]\nname = \"c\"\n",
    "c_scene_dir.toml": "[campaign]\nname = \"c\"\nscene = \"adir\"\n",
    "c_scene_missing.toml": "[campaign]\nname = \"c\"\nscene = \"nowhere.toml\"\n",
    "c_scene_empty.toml": "[campaign]\nname = \"c\"\nscene = \"empty.toml\"\n",
    "c_scene_comments.toml": "[campaign]\nname = \"c\"\nscene = \"comments.toml\"\n",
    "c_scene_noname.toml": "[campaign]\nname = \"c\"\nscene = \"noname.toml\"\n",
    "c_unknown_top.toml": "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\n[sweeps]\n",
    "c_unknown_key.toml":
        "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\nreplica = 2\n",
    "c_slash_name.toml": "[campaign]\nname = \"a/b\"\nscene = \"{scenes}/bst_tiny.toml\"\n",
    "c_dotdot_name.toml": "[campaign]\nname = \"..\"\nscene = \"{scenes}/bst_tiny.toml\"\n",
    "c_badtoml.toml": "[campaign\nname = \"c\"\n",
    "c_replicas0.toml": "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\nreplicas = 0\n",
    "c_ranks0.toml":
        "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\nranks_per_case = 0\n",
    "c_name_number.toml": "[campaign]\nname = 3\nscene = \"{scenes}/bst_tiny.toml\"\n",
    "c_output_empty.toml":
        "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\noutput_dir = \"\"\n",
    "c_output_file.toml":
        "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\noutput_dir = \"{fx}/a_file\"\n",
    "c_bed_cache_file.toml":
        "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\noutput_dir = \"{fx}/c_bcf\"\n"
        "bed_cache = \"{fx}/a_file\"\n",
    "c_fields_twice.toml": "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\n"
        "[collect]\nfields = [\"series\", \"series\"]\n",
    "c_value_twice.toml": "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\n"
        "[sweep]\ntheta_z = [57, 30, 57.0]\ntheta_x = [57]\n",
    "c_zip_pair_twice.toml": "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\n"
        "[sweep]\nzip = true\ntheta_z = [57, 30, 57]\ntheta_x = [57, 57, 57]\n",
    # 2,000 x 1,000 points: two million cases (the expansion ran out of memory at 6e7)
    "c_too_many.toml": "[campaign]\nname = \"c\"\nscene = \"{scenes}/bst_tiny.toml\"\n"
        "[sweep]\ntheta_z = [%s]\ntheta_x = [%s]\n"
        % (", ".join("%.2f" % (0.05 * i) for i in range(2000)),
           ", ".join("%.1f" % (0.1 * i) for i in range(1000))),
    "a_file": "not a directory\n",
    "name_newline.toml": "[scene]\nname = \"two\\nlines\"\n" + TINY_BODY,
    "not_hdf5.h5": "these bytes are no HDF5 file\n",
    "campaign_dir/": None,
    "no_partials/": None,
    "empty_partials/partials/": None,
    "partials_file/partials": "a file where the folder of partial results goes\n",
    "ensemble_dir/partials/": None,
    "ensemble_dir/ensemble.h5/": None,
    # A stray file no slicing writes (it read as slice 3 of 2, or failed in std::stoi: exit 1).
    "stray_partials/partials/slice_3_of_2.h5": "stray\n",
    "huge_partials/partials/slice_1_of_99999999999.h5": "stray\n",
}


# name -> the tumble command that writes it (OUT: its path): input files only Tumble makes, such
# as the orbits files of two protocols for the `cm --islands/--orbits` protocol checks.
TUMBLE_FIXTURES = {
    "orbits_57.h5": "cm orbits --theta-z 57 --theta-x 57 --max-period 1 --grid 8 --no-kam -o OUT",
    "orbits_68.h5": "cm orbits --theta-z 68 --theta-x 68 --max-period 1 --grid 8 --no-kam -o OUT",
    "mcm_57.h5": "cm mcm --theta-z 57 --theta-x 57 --islands {fx}/orbits_57.h5 --tracers 10 "
                 "--snapshot 1 --cumulative 1,1 -o OUT",
    "drift_4.h5": "cm drift --n 4 -o OUT",
    # Snapshots of step 0 of a cylinder run and of a single-axis sphere run (the island analyses
    # refuse them), and of a biaxial one (they take it).
    "cyl_run": "run {scenes}/rapaport/mini/E.toml --max-steps 1 --set scene.output_dir=OUT "
               "--set fill.bed_cache={fx}/beds",
    "single_run": "run {scenes}/bst_tiny.toml --max-steps 1 --set protocol.mode=single_axis "
                  "--set scene.output_dir=OUT --set fill.bed_cache={fx}/beds",
    "sphere_run": "run {scenes}/bst_tiny.toml --max-steps 1 --set scene.output_dir=OUT "
                  "--set fill.bed_cache={fx}/beds",
}


def make_tumble_fixtures(tumble, fx, scenes, limit):
    for name, cmd in TUMBLE_FIXTURES.items():
        args = shlex.split(cmd.replace("{fx}", fx).replace("{scenes}", scenes)
                           .replace("OUT", os.path.join(fx, name)))
        rc, out, _ = run(tumble, args, limit)
        if rc != 0:
            sys.exit("fixture %s: tumble %s failed (rc %s):\n%s" % (name, " ".join(args), rc, out))


def damage_tumble_fixtures(fx):
    """Copies of Tumble's files with one value a reader must refuse."""
    # an island with a NaN vertex (it contained no point, silently)
    shutil.copy(os.path.join(fx, "orbits_57.h5"), os.path.join(fx, "orbits_nan.h5"))
    with h5py.File(os.path.join(fx, "orbits_nan.h5"), "r+") as f:
        g = f["islands"]
        square = [[0.1, 0.1], [0.2, 0.1], [float("nan"), 0.2], [0.1, 0.2]]
        for name, value in (("vertices", square), ("offsets", [0, 4]), ("center", [[0.15, 0.15]]),
                            ("launch", [[0.2, 0.15]]), ("r", [0.95]), ("area", [0.01]),
                            ("period", [1]), ("orbit", [0]), ("point", [0]),
                            ("parent_orbit", [-1])):
            dtype = g[name].dtype
            del g[name]
            g.create_dataset(name, data=value, dtype=dtype)
    # a snapshot with a position that is no number (an enrichment of 0 came out, exit 0), and one
    # whose x is a row short (read past its end)
    for name, edit in (("snap_nan.h5", lambda x: x.__setitem__((0, 0), float("nan"))),
                       ("snap_short.h5", None)):
        shutil.copy(os.path.join(fx, "sphere_run", "snap_000000.h5"), os.path.join(fx, name))
        with h5py.File(os.path.join(fx, name), "r+") as f:
            x = f["x"][()]
            if edit:
                edit(x)
            else:
                x = x[:-1]
            del f["x"]
            f.create_dataset("x", data=x)
    # a drift grid whose attribute n is not its datasets' n
    shutil.copy(os.path.join(fx, "drift_4.h5"), os.path.join(fx, "drift_n5.h5"))
    with h5py.File(os.path.join(fx, "drift_n5.h5"), "r+") as f:
        f.attrs["n"] = 5


# name -> the root attributes of an HDF5 file the script writes (fields.h5 as a campaign's case
# leaves it, only what the refusal reads).
H5_FIXTURES = {
    "campaign_tumbler/cases/c1/fields.h5": {"frame": "tumbler"},
}


def write_fixtures(fx, scenes):
    for name, attrs in H5_FIXTURES.items():
        path = os.path.join(fx, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with h5py.File(path, "w") as f:
            for k, v in attrs.items():
                f.attrs[k] = v
    for name, text in FIXTURES.items():
        path = os.path.join(fx, name)
        if text is None:
            os.makedirs(path, exist_ok=True)
            continue
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text.replace("{scenes}", scenes).replace("{fx}", fx))


def read_table(path):
    rows = []
    with open(path) as f:
        for lineno, line in enumerate(f, 1):
            if not line.strip() or line.startswith("#"):
                continue
            parts = line.rstrip("\n").split("\t")
            if len(parts) != 4:
                sys.exit("%s:%d: need 4 tab-separated columns (id, exit code, word, command), got %d"
                         % (path, lineno, len(parts)))
            if any(r[0] == parts[0] for r in rows):
                sys.exit("%s:%d: row id %s is used twice" % (path, lineno, parts[0]))
            rows.append((parts[0], int(parts[1]), parts[2], parts[3], lineno))
    return rows


ENV_WORD = re.compile(r"^[A-Z_][A-Z0-9_]*=")


def split_env(args):
    """The leading NAME=value words of a command (its environment) and the rest."""
    env = {}
    while args and ENV_WORD.match(args[0]):
        name, value = args.pop(0).split("=", 1)
        env[name] = value
    return env, args


def run(tumble, args, limit, extra_env=None, cwd=None):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", **(extra_env or {}))
    t0 = time.monotonic()
    try:
        p = subprocess.run([tumble] + args, capture_output=True, text=True, timeout=limit,
                           env=env, stdin=subprocess.DEVNULL, cwd=cwd)
        return p.returncode, p.stdout + p.stderr, time.monotonic() - t0
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"").decode(errors="replace") + (e.stderr or b"").decode(errors="replace")
        return None, out, time.monotonic() - t0


CRASH_WORDS = ("terminate called", "std::bad_alloc", "Segmentation fault", "core dumped",
               "MPI_ABORT")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tumble", required=True)
    ap.add_argument("--table", required=True)
    ap.add_argument("--source", required=True, help="source tree (for scenes/)")
    ap.add_argument("--work", help="where fixtures go (default: a temporary directory)")
    ap.add_argument("--row-limit", type=float, default=10.0,
                    help="seconds after which a row counts as a hang")
    a = ap.parse_args()
    a.tumble, a.source = os.path.abspath(a.tumble), os.path.abspath(a.source)
    scenes = os.path.join(a.source, "scenes")
    work = os.path.abspath(a.work or tempfile.mkdtemp(prefix="tumble_bad_input_"))
    fx = os.path.join(work, "fx")
    os.makedirs(fx, exist_ok=True)
    # Every row runs in an empty folder of its own: a refusal writes nothing, and a row accepted
    # by mistake leaves its default outputs (relative paths) there, not in the caller's folder.
    cwd = os.path.join(work, "cwd")
    shutil.rmtree(cwd, ignore_errors=True)
    write_fixtures(fx, scenes)
    make_tumble_fixtures(a.tumble, fx, scenes, 60)
    damage_tumble_fixtures(fx)
    failures = []

    # Controls: good input is still accepted (a binary that refuses everything must not pass).
    for args, word in ((["--help"], "Usage"), (["--version"], "("),
                       (["run", os.path.join(scenes, "bst_tiny.toml"), "--check"], "particles")):
        rc, out, dt = run(a.tumble, args, a.row_limit)
        ok = rc == 0 and word in out
        print("control %-50s rc %s %.2fs %s" % (" ".join(args)[-50:], rc, dt, "ok" if ok else "FAIL"))
        if not ok:
            failures.append("control %s: rc %s, output:\n%s" % (args, rc, out[-2000:]))

    rows = read_table(a.table)
    counts = {"refused as expected": 0, "crash": 0, "silently accepted": 0, "mismatch": 0}
    slow = []
    for rid, want_rc, word, cmd, lineno in rows:
        row_env, args = split_env(shlex.split(
            cmd.replace("{scenes}", scenes).replace("{fx}", fx).replace("{source}", a.source)))
        row_cwd = os.path.join(cwd, rid)
        os.makedirs(row_cwd)
        rc, out, dt = run(a.tumble, args, a.row_limit, row_env, row_cwd)
        left = sorted(os.listdir(row_cwd))
        if left:  # (refused before any work: nothing written)
            failures.append("row %s (line %d): left %s in its working directory %s"
                            % (rid, lineno, ", ".join(left), row_cwd))
        if rc is None or rc < 0 or rc >= 128 or any(w in out for w in CRASH_WORDS):
            kind = "crash"
        elif rc == 0:
            kind = "silently accepted"
        elif rc == want_rc and word.lower() in out.lower():
            kind = "refused as expected"
        else:
            kind = "mismatch"
        counts[kind] += 1
        if dt > 1.0:
            slow.append((rid, dt))
        msg = out.strip().splitlines()
        shown = msg[0] if msg else ""
        for m in msg:  # the line that holds the word, if any
            if word.lower() in m.lower():
                shown = m
                break
        print("%-4s %-34s rc %-4s want %d %5.2fs  %-19s %s"
              % (rid, cmd[:34], rc, want_rc, dt, kind, shown[:160]))
        if kind != "refused as expected":
            failures.append("row %s (line %d): %s\n  command: tumble %s\n  want exit %d and '%s'; "
                            "got exit %s after %.2f s:\n%s"
                            % (rid, lineno, kind,
                               " ".join(["%s=%s" % e for e in row_env.items()] + args), want_rc,
                               word, rc, dt,
                               out[-2000:]))

    print("\nrows %d: refused as expected %d, crashes %d, silently accepted %d, mismatches %d"
          % (len(rows), counts["refused as expected"], counts["crash"],
             counts["silently accepted"], counts["mismatch"]))
    if slow:
        print("rows slower than 1 s (the machine may be loaded): " +
              ", ".join("%s %.2fs" % s for s in slow))
    if failures:
        print("\n".join(["", "FAILED:"] + failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
