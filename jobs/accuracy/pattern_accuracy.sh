#!/usr/bin/env bash
# Error of each fidelity tier against the reference tier on the segregation-pattern observables
# (docs/accuracy.md): one campaign per tier of SCENE's own protocol, REPLICAS seeds, ITERATIONS
# protocol iterations, on NP ranks; then `tumble analyze campaign` (island enrichment) and
# jobs/accuracy/pattern_table.py: wall time per iteration, radial segregation at the end of every
# iteration, island enrichment, and the correlation of each replica's c_L map with the reference
# tier's mean map, each with 95% CIs over replicas and the differences from the reference by
# Welch's t.
# usage: jobs/accuracy/pattern_accuracy.sh [SCENE=scenes/bst_tiny.toml] [REPLICAS=3]
#                                          [ITERATIONS=4] [NP=2]
# TIERS="standard fast preview" leaves the reference out (the errors are then against standard).
# Rerunning resumes: each tier's campaign skips its finished cases.
{  # read to the closing brace before running: an edit or a `git pull` while it runs (hours)
   # cannot change what it does next
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_tiny.toml}
REPLICAS=${2:-3}
ITERATIONS=${3:-4}
NP=${4:-2}
source jobs/lib/bench_common.sh
OUT=$(realpath -m "${ACCURACY_OUT:-results/accuracy_pattern/$(basename "$SCENE" .toml)}")
mkdir -p "$OUT"
bench_header
echo "# $SCENE: tiers x $REPLICAS replicas, $ITERATIONS iterations, $NP ranks"
half=$(awk -v n="$ITERATIONS" 'BEGIN {printf "%.6g", n / 2}')
for tier in ${TIERS:-reference standard fast preview}; do
  dir=$OUT/$tier
  mkdir -p "$dir"
  # The c_L maps average the stroboscopic samples of the second half (the pattern, not the
  # mixing transient); the series cover the whole run.
  cat > "$dir/campaign.toml" <<EOF
[campaign]
name = "pattern_$tier"
scene = "$(realpath "$SCENE")"
output_dir = "$dir"
seed = 8
replicas = $REPLICAS
tier = "$tier"
bed_cache = "$(realpath -m beds)"
progress_interval = 120

[overrides]
"protocol.iterations" = $ITERATIONS

[collect]
fields = ["concentration", "series"]
iterations = [$half, $ITERATIONS]
samples_per_iteration = 1
grid = 12
frame = "lab"
EOF
  run_tier_campaign "$dir" "$tier" "$NP"
done
/usr/bin/python3 jobs/accuracy/pattern_table.py "$OUT" "$ITERATIONS"
exit
}
