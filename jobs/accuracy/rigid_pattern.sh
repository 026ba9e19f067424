#!/usr/bin/env bash
# The rigid bulk where there is a pattern (docs/accuracy.md, "Rigid bulk"): one campaign of SCENE
# at TIER and one protocol point (default (57°, 57°)) with `fidelity.bulk` swept over dynamic and
# rigid, REPLICAS replicas on common beds (the bulk option does not enter the seed), ITERATIONS
# iterations, NP ranks (cases on 1-rank groups, side by side, so both options see the same load);
# then `tumble analyze campaign` (island enrichment) and jobs/accuracy/pattern_table.py --split:
# wall per iteration, island enrichment, c_L pattern correlation with dynamic's mean map, radial
# segregation at the end of every iteration, each with rigid − dynamic by Welch and paired.
# usage: jobs/accuracy/rigid_pattern.sh [SCENE=scenes/bst_small.toml] [TIER=fast] [REPLICAS=3]
#                                       [ITERATIONS=8] [NP=2]
#   THETA="57 57" the point; ACCURACY_OUT (default results/rigid_pattern/<scene>_<tier>)
#   SEED=57 the campaign's seed: another seed gives every replica another bed and mixed start
#   (fill.seed hashes it with the replica), fresh realizations for a test planned on earlier ones
#   VARIANT="fidelity.bulk_segment_thaw=off": a third point, rigid with that key=value (on the same
#   beds; its cases join a campaign that ran without it, whose cases keep their ids). Several
#   points, separated by blanks, each one key=value or several joined by "+":
#   VARIANT="fidelity.bulk_segment_thaw=omega fidelity.bulk_still_slope=measured+fidelity.bulk_calm_distance=0.02".
#   A campaign's folder holds one campaign: a later call names every point of the earlier ones
#   (the campaign refuses a folder whose cases it would leave out; ACCURACY_OUT gives another).
#   RANKS_PER_CASE=k (default 1): each case on a group of k ranks (NP = 6k runs a 3-replica
#   campaign at once: bst_paper at standard on a node of 48 cores with k = 8). The group size is
#   not part of a case's id and a checkpoint restarts on any group size, so a campaign begun on
#   1-rank groups goes on with k; its wall times per iteration then mix group sizes.
# Rerunning resumes: the campaign skips its finished cases.
{  # read to the closing brace before running: an edit or a `git pull` while it runs (hours)
   # cannot change what it does next
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_small.toml}
TIER=${2:-fast}
REPLICAS=${3:-3}
ITERATIONS=${4:-8}
NP=${5:-2}
SEED=${SEED:-57}
read -r TZ TX <<< "${THETA:-57 57}"
source jobs/lib/bench_common.sh
OUT=$(realpath -m "${ACCURACY_OUT:-results/rigid_pattern/$(basename "$SCENE" .toml)_$TIER}")
mkdir -p "$OUT"
bench_header
echo "# $SCENE at $TIER, ($TZ, $TX), dynamic vs rigid, $REPLICAS replicas (seed $SEED), $ITERATIONS iterations, $NP ranks"
# The maps average the stroboscopic samples from iteration 3 on (the pattern, not the mixing
# transient: docs/report.md Sec. 5b), on the 16 x 16 lab-frame grid of campaign/bst_small_islands.
from=$(( ITERATIONS < 6 ? ITERATIONS / 2 : 3 ))
cat > "$OUT/campaign.toml" <<EOF
# Written by jobs/accuracy/rigid_pattern.sh.
[campaign]
name = "rigid_pattern"
scene = "$(realpath "$SCENE")"
output_dir = "$OUT"
seed = $SEED
replicas = $REPLICAS
tier = "$TIER"
bed_cache = "$(realpath -m beds)"
progress_interval = 120
ranks_per_case = ${RANKS_PER_CASE:-1}

[overrides]
"protocol.iterations" = $ITERATIONS

[[sweep]]
theta_z = $TZ
theta_x = $TX
"fidelity.bulk" = ["dynamic", "rigid"]
$(for v in ${VARIANT:-}; do
    printf '\n[[sweep]]\ntheta_z = %s\ntheta_x = %s\n"fidelity.bulk" = "rigid"\n' "$TZ" "$TX"
    IFS=+ read -ra kvs <<< "$v"
    for kv in "${kvs[@]}"; do printf '"%s" = "%s"\n' "${kv%%=*}" "${kv#*=}"; done
  done)

[collect]
fields = ["concentration", "series"]
iterations = [$from, $ITERATIONS]
samples_per_iteration = 1
grid = 16
frame = "lab"
EOF
run_tier_campaign "$OUT" "$TIER" "$NP"
/usr/bin/python3 jobs/accuracy/pattern_table.py "$OUT" "$ITERATIONS" \
  --split "fidelity.bulk=dynamic,rigid$(for v in ${VARIANT:-}; do printf ',rigid+%s' "$v"; done)"
exit
}
