"""cli.corruption_flips (issue 21, D8): flipped bytes in files Tumble reads back are refused or
harmless, never silently accepted, never a crash.

Makes a real checkpoint (a short `tumble run` of scenes/bst_tiny.toml with a small checkpoint
interval) and a real partial result (a 1-slice run of a tiny campaign, 1 rank per case), then flips
one byte at each of N random offsets (fixed seed) of each file. Every variant is read back through
the code path that consumes it:
  checkpoint: `tumble run SCENE --restart VARIANT --max-steps S`; its final checkpoint and results.h5
              are compared with those of the restart from the unflipped file;
  partial:    `tumble merge DIR` with the variant as DIR/partials/slice_1_of_1.h5; its ensemble.h5
              is compared with the merge of the unflipped partial.
Random offsets mostly hit metadata and unused bytes of the small partial, so it also gets one flip
inside the stored data of every third table `tumble merge` reads. Then edits a checksum cannot see (a dataset rewritten whole, an attribute changed: species 1000000,
a duplicate id, a bulk state the engine does not know, a contact of a particle that does not exist, ...) must each be refused with exit 3
by the semantic checks. Each flipped variant must be refused (exit 3 or 2 with the file named in the message) or give output that
is bitwise equal to the reference (a flip in bytes HDF5 does not use). Anything else fails the
test: exit 0 with different values (silently accepted), a signal or exit >= 128 (a crash), any
other exit code (an unclear refusal). Prints the tally.

Outputs are compared with h5py: every dataset bit for bit (NaN payloads included) and every
attribute, except those that name the moment or the file of the run (written_utc, sources)."""
import argparse
import os
import random
import shutil
import subprocess
import sys

import h5py
import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("--tumble", required=True)
ap.add_argument("--source", required=True, help="repository root (scenes/, tests/campaign/)")
ap.add_argument("--work", default="corruption")
ap.add_argument("--flips", type=int, default=20)
ap.add_argument("--seed", type=int, default=2021)
a = ap.parse_args()

env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
work = os.path.abspath(a.work)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
scene = os.path.join(a.source, "scenes", "bst_tiny.toml")
# Attributes that name the moment or the speed of a run, or the file merged (not data read back).
IGNORED_ATTRS = {"written_utc", "sources", "particle_steps_per_second"}


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def tumble(args, cwd=work):
    return subprocess.run([a.tumble] + args, cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=120)


def must(r, what):
    if r.returncode != 0:
        fail("%s exited with %d:\n%s%s" % (what, r.returncode, r.stdout[-2000:], r.stderr[-2000:]))


def contents(path):
    """Every dataset (as raw bytes, so NaN payloads and -0 count) and attribute of an HDF5 file."""
    out = {}

    def attrs(name, obj):
        for k, v in obj.attrs.items():
            if k not in IGNORED_ATTRS:
                out["@%s/%s" % (name, k)] = np.asarray(v).tobytes()

    with h5py.File(path, "r") as f:
        attrs("/", f)

        def visit(name, obj):
            attrs(name, obj)
            if isinstance(obj, h5py.Dataset):
                out[name] = (obj.shape, str(obj.dtype), np.asarray(obj[()]).tobytes())

        f.visititems(visit)
    return out


def differences(a_, b_):
    keys = sorted(set(a_) | set(b_))
    return [k for k in keys if a_.get(k) != b_.get(k)]


def flip(src, dst, offset, rng):
    data = bytearray(open(src, "rb").read())
    data[offset] ^= rng.randrange(1, 256)
    open(dst, "wb").write(bytes(data))


tally = {}


def judge(kind, label, r, named, outputs, reference):
    """Classifies one variant's outcome; returns the category."""
    t = tally.setdefault(kind, {"variants": 0, "refused": 0, "read-back-equal": 0,
                                "silently accepted": 0, "crashes": 0, "unclear": 0})
    t["variants"] += 1
    rc = r.returncode
    message = (r.stdout + r.stderr).strip().splitlines()
    last = message[-1] if message else ""
    if rc < 0 or rc >= 128:
        cat = "crashes"
    elif rc in (2, 3) and named in r.stderr:
        cat = "refused"
    elif rc == 0:
        diff = []
        for out, ref in zip(outputs, reference):
            if not os.path.exists(out):
                diff.append(os.path.basename(out) + " missing")
            else:
                diff += differences(contents(out), ref)
        cat = "read-back-equal" if not diff else "silently accepted"
        if diff:
            last = "differs in " + ", ".join(diff[:6])
    else:
        cat = "unclear"
    t[cat] += 1
    print("  %-10s %-24s exit %3d  %-17s %s" % (kind, label, rc, cat, last[:150]))
    return cat


rng = random.Random(a.seed)

# --- a real checkpoint -------------------------------------------------------------------------
# bst_tiny: ~2,000 particles; a checkpoint every 0.002 s of simulated time (100 steps), 150 steps.
run_dir = os.path.join(work, "run")
common = ["--set", "scene.output_dir=%s" % run_dir, "--set", "fill.bed_cache=%s/beds" % work,
          "--set", "fill.settle_rms_speed=0.005"]
r = tumble(["run", scene, "--set", "output.checkpoint_interval=0.001", "--max-steps", "150"]
           + common)
must(r, "the run that writes the checkpoint")
ckpt = os.path.join(run_dir, "checkpoint.h5")
if not os.path.exists(ckpt):
    fail("no checkpoint.h5 in %s: %s" % (run_dir, os.listdir(run_dir)))
original_ckpt = os.path.join(work, "original_checkpoint.h5")
shutil.copy(ckpt, original_ckpt)
with h5py.File(original_ckpt, "r") as f:
    step0 = int(f.attrs["step"])


def restart(from_file, out_dir):
    """Restarts from `from_file` for 5 steps into out_dir; returns the result and its outputs."""
    shutil.rmtree(out_dir, ignore_errors=True)
    args = ["run", scene, "--restart", from_file, "--max-steps", "5"]
    args += [x.replace(run_dir, out_dir) for x in common]
    args += ["--set", "output.checkpoint_interval=0.0001"]
    return tumble(args), [os.path.join(out_dir, "checkpoint.h5"),
                          os.path.join(out_dir, "results.h5")]


# Every restart writes into one directory (the scene attribute of its outputs names it).
restart_dir = os.path.join(work, "restart")
r, ref_outputs = restart(original_ckpt, restart_dir)
must(r, "the restart from the unflipped checkpoint")
ref = [contents(p) for p in ref_outputs]
with h5py.File(ref_outputs[0], "r") as f:  # the restart ran: the comparison is not vacuous
    if int(f.attrs["step"]) != step0 + 5:
        fail("the reference restart's checkpoint is at step %d, not %d" % (f.attrs["step"],
                                                                            step0 + 5))
size = os.path.getsize(original_ckpt)
print("checkpoint: %s, %d bytes, step %d" % (original_ckpt, size, step0))
for k, off in enumerate(sorted(rng.sample(range(size), a.flips))):
    variant = os.path.join(work, "ckpt_flip_%02d.h5" % k)
    flip(original_ckpt, variant, off, rng)
    r, outs = restart(variant, restart_dir)
    judge("checkpoint", "byte %d" % off, r, os.path.basename(variant), outs, ref)

# Edits a checksum cannot catch (the dataset rewritten whole, as by h5py, with no checksum of its
# own): the semantic checks must refuse each, exit 3. The species edit segfaulted before issue 21.
def edit_dataset(name, change):
    def apply(f):
        data = f[name][()]
        changed = change(data)  # edits in place (None) or returns the new array
        data = data if changed is None else changed
        del f[name]
        f.create_dataset(name, data=data)
    return apply


def edit_attr(name, value):
    def apply(f):
        f.attrs[name] = value
    return apply


edits = [
    ("species 1000000", edit_dataset("particles/species", lambda a: a.__setitem__(5, 1000000))),
    ("duplicate id", edit_dataset("particles/id", lambda a: a.__setitem__(7, a[8]))),
    ("bulk_state -7", edit_dataset("particles/bulk_state", lambda a: a.__setitem__(4, -7))),
    ("pair id 10^9", edit_dataset("contacts/pair_ids", lambda a: a.__setitem__((0, 1), 10**9))),
    ("particle outside", edit_dataset("particles/x", lambda a: a.__setitem__((3, 0), 1.0))),
    ("radius negative", edit_dataset("particles/radius", lambda a: a.__setitem__(2, -a[2]))),
    ("x one row short", edit_dataset("particles/x", lambda a: a[:-1])),
    ("step -5", edit_attr("step", np.int64(-5))),
    ("snapshots 10^15", edit_attr("snapshots_written", np.int64(10**15))),
]
for k, (label, apply) in enumerate(edits):
    variant = os.path.join(work, "ckpt_edit_%02d.h5" % k)
    shutil.copy(original_ckpt, variant)
    with h5py.File(variant, "r+") as f:
        apply(f)
    r, outs = restart(variant, restart_dir)
    if judge("edited", label, r, os.path.basename(variant), outs, ref) != "refused" or \
            r.returncode != 3:
        fail("the edit '%s' was not refused as corrupt input (exit 3)" % label)

# --- a real partial result ---------------------------------------------------------------------
camp = os.path.join(a.source, "tests", "campaign", "groups_campaign.toml")
cdir = os.path.join(work, "campaign")
r = tumble(["campaign", camp, "--output", cdir, "--slice", "1/1", "--ranks-per-case", "1",
            "--quiet"])  # in the work directory: its bed cache ("beds") lands there
must(r, "the 1-slice campaign")
partial = os.path.join(cdir, "partials", "slice_1_of_1.h5")
if not os.path.exists(partial):
    fail("no partial result %s" % partial)
original_partial = os.path.join(work, "original_partial.h5")
shutil.copy(partial, original_partial)


def merge(partial_file, mdir):
    shutil.rmtree(mdir, ignore_errors=True)
    os.makedirs(os.path.join(mdir, "partials"))
    shutil.copy(partial_file, os.path.join(mdir, "partials", "slice_1_of_1.h5"))
    return tumble(["merge", mdir]), [os.path.join(mdir, "ensemble.h5")]


merge_dir = os.path.join(work, "merge")
r, outs = merge(original_partial, merge_dir)
must(r, "the merge of the unflipped partial")
ref = [contents(p) for p in outs]
size = os.path.getsize(original_partial)
print("partial: %s, %d bytes" % (original_partial, size))
for k, off in enumerate(sorted(rng.sample(range(size), a.flips))):
    variant = os.path.join(work, "partial_flip_%02d.h5" % k)
    flip(original_partial, variant, off, rng)
    r, outs = merge(variant, merge_dir)
    judge("partial", "byte %d" % off, r, "slice_1_of_1.h5", outs, ref)

# Random offsets mostly land in metadata and in datasets merge does not read (variance and ci95
# are recomputed): also one flip inside the stored data of every third table merge reads.
with h5py.File(original_partial, "r") as f:
    targets = []

    def data_offset(name, obj):
        if isinstance(obj, h5py.Dataset) and name.rsplit("/", 1)[-1] in ("count", "mean", "m2",
                                                                         "time", "iteration"):
            if obj.chunks:
                info = obj.id.get_chunk_info(0)
                targets.append((name, info.byte_offset, info.size))
            elif obj.id.get_offset() is not None:
                targets.append((name, obj.id.get_offset(), obj.id.get_storage_size()))

    f.visititems(data_offset)
for k, (name, start, length) in enumerate(targets[::3]):  # a third of them: the time budget
    variant = os.path.join(work, "partial_data_%02d.h5" % k)
    flip(original_partial, variant, start + rng.randrange(length), rng)
    r, outs = merge(variant, merge_dir)
    judge("partial", "in " + name, r, "slice_1_of_1.h5", outs, ref)

print("\ntally:")
bad = 0
for kind, t in tally.items():
    print("  %-10s variants %d, refused %d, read-back-equal %d, silently accepted %d, crashes %d, "
          "unclear exit %d" % (kind, t["variants"], t["refused"], t["read-back-equal"],
                               t["silently accepted"], t["crashes"], t["unclear"]))
    bad += t["silently accepted"] + t["crashes"] + t["unclear"]
    if kind != "edited" and t["variants"] < 20:
        fail("%s: only %d variants" % (kind, t["variants"]))
if bad:
    fail("%d variants were accepted with changed values, crashed or exited unclearly" % bad)
print("PASS")
