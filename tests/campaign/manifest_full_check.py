"""campaign.mpi2_manifest_full: rank 0 cannot write the manifest (a full disk) mid-campaign.

Before, the error ended the job with MPI_Abort: every running case lost its steps since its last
checkpoint, and the lines of the cases that had finished were lost with them. Now the campaign
halts (no case starts any more, the running ones run to their end), keeps the lines it could not
write, and writes them as soon as it can. The test hook TUMBLE_TEST_MANIFEST_FULL="<first>:<count>"
fails the manifest writer's appends number first .. first+count-1 as on a full disk.
1. Appends from the 3rd on fail (the disk never gets room): exit 1 on every rank within the
   timeout, the halt said once, no MPI_Abort, the manifest holds its first 2 lines, the lines not
   written are printed, and each printed "done" carries its case's fields file checksum.
2. Those lines appended to the manifest (what the message asks for), a rerun without the hook
   takes their done cases as done before, exits 4 (the CI campaign's failed cases), and its
   ensemble.h5 has the same tables as the uninterrupted ci_full's.
3. Appends 3 and 4 fail, then the disk has room: exit 1, "every line was written in the end",
   nothing printed, and every case with a "running" line has its end line in the manifest."""
import json
import os
import re
import shutil

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--full", required=True, help="the finished CI campaign's directory")
a = ap.parse_args()


def run(out, hook):
    """The CI campaign into `out` on 2 ranks (hook: the test hook's value, or None); fails the
    test if it has not ended within 60 s. Returns (exit code, stdout and stderr)."""
    cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [a.tumble, "campaign", a.campaign,
                                                          "--output", out, "--quiet"]
    env = dict(os.environ)
    env.pop("TUMBLE_TEST_MANIFEST_FULL", None)
    if hook:
        env["TUMBLE_TEST_MANIFEST_FULL"] = hook
    print("TUMBLE_TEST_MANIFEST_FULL=%s" % hook)
    return cc.run_or_fail_on_hang(cmd, 60, "the campaign with hook %s" % hook, env)


def manifest_lines(out):
    with open(os.path.join(out, "manifest", "slice_1_of_1.jsonl")) as fh:
        return [json.loads(line) for line in fh if line.strip()]


def done_before(text):
    m = re.search(r"(\d+) done before", text)
    if not m:
        cc.fail("no 'done before' count in the rerun's output")
    return int(m.group(1))


# 1. The disk never gets room.
out = "manifest_full"
shutil.rmtree(out, ignore_errors=True)
rc, text = run(out, "3:1000000")
if rc != 1:
    cc.fail("a campaign whose manifest cannot be written exited %d, not 1" % rc)
if text.count("HALTED:") != 1 or text.count("No space left on device") < 2:
    cc.fail("the halt is not said once, with the system's reason")
if "MPI_ABORT" in text or "MPI_Abort" in text:
    cc.fail("the halt aborted the job")
written = manifest_lines(out)
if len(written) != 2:
    cc.fail("the manifest holds %d lines, want the 2 written before the disk was full"
            % len(written))
printed = [json.loads(line) for line in text.splitlines() if line.startswith("{")]
if not printed:
    cc.fail("the lines not written are not printed")
done = {r["case"]: r for r in printed if r["status"] == "done"}
if not done:
    cc.fail("no case ran to its end after the halt (its running cases were dropped)")
for case, r in done.items():
    if cc.fnv1a64(os.path.join(out, r["output"], "fields.h5")) != r["checksum"]:
        cc.fail("case %s: its printed line's checksum is not its fields file's" % case)
if os.path.exists(os.path.join(out, "ensemble.h5")):
    cc.fail("a halted campaign wrote statistics")

# 2. The printed lines appended, the rerun keeps their cases.
with open(os.path.join(out, "manifest", "slice_1_of_1.jsonl"), "a") as fh:
    for line in text.splitlines():
        if line.startswith("{"):
            fh.write(line + "\n")
rc, text2 = run(out, None)
if rc != 4:
    cc.fail("the rerun exited %d, not 4 (the CI campaign's failed cases)" % rc)
if done_before(text2) != len(done):
    cc.fail("the rerun took %d cases as done before, the printed lines record %d"
            % (done_before(text2), len(done)))
tables = cc.same_tables(os.path.join(out, "ensemble.h5"), os.path.join(a.full, "ensemble.h5"))

# 3. Two appends fail, then the disk has room again.
out3 = "manifest_full_recovers"
shutil.rmtree(out3, ignore_errors=True)
rc, text3 = run(out3, "3:2")
if rc != 1 or "Every line was written in the end" not in text3:
    cc.fail("a campaign whose manifest recovered: exit %d (want 1), or not said" % rc)
if any(line.startswith("{") for line in text3.splitlines()):
    cc.fail("lines printed as not written, though the manifest recovered")
lines = manifest_lines(out3)
ran = {r["case"] for r in lines}
ended = {r["case"] for r in lines if r["status"] != "running"}
if not ran or ran != ended:
    cc.fail("cases without their end line in the recovered manifest: %s" % sorted(ran - ended))
if [r["t"] for r in lines] != sorted(r["t"] for r in lines):
    cc.fail("the lines written late are out of time order")
print("OK: a manifest that cannot be written halts the campaign (exit 1, said once, no abort); "
      "%d lines kept and printed, %d cases done after the halt kept by the rerun, whose ensemble "
      "has the same %d tables as ci_full's; a manifest that recovers gets every line (%d, in "
      "order)" % (len(printed), len(done), tables, len(lines)))
