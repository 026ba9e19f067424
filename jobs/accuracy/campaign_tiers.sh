#!/usr/bin/env bash
# One campaign at several fidelity tiers, compared where its pattern is (docs/accuracy.md): the
# cases of CAMPAIGN rerun with `tier` set to each of TIERS (same seed, so the same replica seeds),
# each under OUT/TIER, analyzed by `tumble analyze campaign` (island enrichment), then
# jobs/accuracy/pattern_table.py compares the tiers at one point of the campaign.
# usage: jobs/accuracy/campaign_tiers.sh CAMPAIGN [NP=2]
#   TIERS       most accurate first (default "reference standard fast preview"); the first present
#               is the one the others are compared with
#   POINT       the point compared, as in the case params (default "theta_z=57;theta_x=57")
#   ACCURACY_OUT  (default results/accuracy_campaign/<campaign file name>)
# A tier whose OUT/TIER already holds finished cases of the same campaign resumes: copying a
# finished run of the campaign at that tier there (cp -r) reuses it.
{  # read to the closing brace before running: an edit or a `git pull` while it runs (hours)
   # cannot change what it does next
set -euo pipefail
cd "$(dirname "$0")/../.."
CAMPAIGN=${1:?usage: campaign_tiers.sh CAMPAIGN [NP]}
NP=${2:-2}
POINT=${POINT:-theta_z=57;theta_x=57}
source jobs/lib/bench_common.sh
OUT=$(realpath -m "${ACCURACY_OUT:-results/accuracy_campaign/$(basename "$CAMPAIGN" .toml)}")
mkdir -p "$OUT"
bench_header
# protocol.iterations of the campaign (its override, else 8), for the table's rows.
ITERATIONS=$(/usr/bin/python3 -c 'import sys, tomllib
print(tomllib.load(open(sys.argv[1], "rb")).get("overrides", {}).get("protocol.iterations", 8))' "$CAMPAIGN")
echo "# $CAMPAIGN at tiers: ${TIERS:-reference standard fast preview}; $ITERATIONS iterations; $NP ranks; point $POINT"
for tier in ${TIERS:-reference standard fast preview}; do
  dir=$OUT/$tier
  mkdir -p "$dir"
  # The campaign file with only its tier and output directory changed (and its scene path made
  # absolute: it is relative to the campaign file's folder).
  /usr/bin/python3 - "$CAMPAIGN" "$tier" "$dir" > "$dir/campaign.toml" <<'PY'
import os, re, sys, tomllib
src, tier, out = sys.argv[1:]
text = open(src).read()
spec = tomllib.loads(text)["campaign"]
scene = os.path.realpath(os.path.join(os.path.dirname(os.path.realpath(src)), spec["scene"]))
head, sep, rest = text.partition("[campaign]")
parts = re.split(r"(?m)^(?=\[)", rest, maxsplit=1)  # the [campaign] table, then the rest
body, tail = parts[0], (parts[1] if len(parts) > 1 else "")
body = re.sub(r"(?m)^[ \t]*(tier|output_dir|scene)[ \t]*=.*\n", "", body)
body = f'\nscene = "{scene}"\noutput_dir = "{out}"\ntier = "{tier}"' + body
print(f"# Written by jobs/accuracy/campaign_tiers.sh: {src} with tier = \"{tier}\" (the comments below\n"
      "# are the original's).\n" + head + sep + body + tail, end="")
PY
  run_tier_campaign "$dir" "$tier" "$NP"
done
/usr/bin/python3 jobs/accuracy/pattern_table.py "$OUT" "$ITERATIONS" --point "$POINT"
exit
}
