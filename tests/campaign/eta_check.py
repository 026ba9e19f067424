"""campaign.mpi2_progress_eta: a campaign's ETA before any case has finished.

Four cases on 2 ranks (groups of 1: rank 0 computes one and dispatches, rank 1 computes the other
and reports to rank 0 by message), a progress line every second, an empty bed cache and a
measured beta, so that every case begins by preparing (settling the bed, measuring beta). Checks,
on the lines before the first case ends: lines with both cases preparing come before any share
of a protocol, at least one line gives an ETA (not --:--:--) and the progress of both running
cases (both reporting paths: rank 0's own case and a remote leader's), and the shares only grow.
The first ETA given, while the last two cases wait with their beds and betas still to make,
foresees the campaign's end within -20% / +25% (elapsed + ETA against the end): their
preparations are charged at the first two's measured cost. (6b91a2e's binary left them out: in a
run of 2026-11-29 its first ETA, 2 s at 37 s, put the end at 39 s; it came at 73 s.) The campaign
then ends with all four cases done."""
import re
import shutil

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
a = ap.parse_args()

shutil.rmtree("ci_eta", ignore_errors=True)
shutil.rmtree("beds_eta", ignore_errors=True)
run = cc.run_campaign_or_fail(a.mpiexec, a.np_flag, 2, a.tumble, a.campaign)

before_first_end = []
for line in run.stdout.splitlines():
    if line.startswith("[campaign] done: "):
        break
    before_first_end.append(line)
progress = [l for l in before_first_end if re.search(r"\| running \d", l)]
preparing = [k for k, l in enumerate(progress) if "running 2 (2 preparing)" in l]
with_share = [k for k, l in enumerate(progress) if "%" in l.split("| failed")[0]]
if not preparing:
    cc.fail("no progress line with both cases preparing (bed, beta)")
if with_share and min(with_share) < max(preparing):
    cc.fail("a line with both cases preparing after a protocol's share: %s"
            % progress[max(preparing)])
both = [l for l in before_first_end if re.search(r"running 2 \([0-9.]+%, [0-9.]+% of their steps\)", l)]
timed = [l for l in both if "ETA --:--:--" not in l and re.search(r"ETA \d+:\d\d:\d\d", l)]
if not timed:
    cc.fail("no progress line with both cases' shares and an ETA before the first case ended")
shares = [tuple(float(x) for x in re.findall(r"([0-9.]+)%", l)) for l in both]
for prev, cur in zip(shares, shares[1:]):
    if any(c < p for p, c in zip(prev, cur)):
        cc.fail("a running case's share went back: %s then %s" % (prev, cur))
if run.stdout.count("[campaign] done: ") != 4:
    cc.fail("expected all four cases done")


def seconds(hms):
    h, m, s = (int(x) for x in hms.split(":"))
    return 3600 * h + 60 * m + s


first = re.search(r"elapsed (\d+:\d\d:\d\d) \| ETA (\d+:\d\d:\d\d)", timed[0])
foreseen = seconds(first.group(1)) + seconds(first.group(2))
end = re.search(r"attempts run on 2 ranks in ([0-9.]+) s", run.stdout)
if not end:
    cc.fail("no 'finished slice' line with the campaign's wall time")
ratio = foreseen / float(end.group(1))
if not 0.8 <= ratio <= 1.25:
    cc.fail("the first ETA put the end at %d s; it came at %s s (ratio %.2f, want 0.8-1.25): %s"
            % (foreseen, end.group(1), ratio, timed[0]))
print("OK: %d lines with both cases preparing, then %d with both shares before the first case "
      "ended, %d of them with an ETA; first: %s; it put the end at %d s, which came at %s s "
      "(ratio %.2f)" % (len(preparing), len(both), len(timed), timed[0], foreseen,
                        end.group(1), ratio))
