#!/usr/bin/env bash
# The starts of the flow inside a biaxial run, rigid bulk against dynamic (issue 20;
# docs/accuracy.md, "The start at a segment change"): ITERATIONS iterations of the (57°, 57°)
# protocol on REPLICAS beds of SCENE at TIER, each bed run dynamic and then rigid on NP ranks, a
# sample of the series per degree of the wall's turn; then jobs/accuracy/segment_start_table.py
# compares each start (z1 from the settled bed; x1, z2, ... from a segment change) seed by seed.
# usage: jobs/accuracy/segment_start.sh [SCENE=scenes/bst_small.toml] [TIER=standard]
#                                       [REPLICAS=5] [ITERATIONS=1] [NP=2]
# BULK_SET="--set fidelity.bulk_calm_distance=0.02 ..." passes more keys to the rigid runs (give
# each setting its own OUT; copy the dynamic runs in to reuse them: runs are deterministic).
# BETA=27 pins the tilt (protocol.repose; "measured" measures each bed's own, once, cached in beds/
# as any run's; the onset windows of the table count from the tilt's start whatever beta is).
# Resumable: a run whose results.h5 says it is complete is kept; one stopped by SIGUSR1 or killed
# goes on from its last checkpoint when the script is run again. The runs come in the order
# seed 1 dynamic, seed 1 rigid, seed 2 dynamic, ..., so a job cut short has whole pairs.
{  # read to the closing brace before running: an edit while it runs (hours) cannot change it
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_small.toml}
TIER=${2:-standard}
REPLICAS=${3:-5}
ITERATIONS=${4:-1}
NP=${5:-2}
for v in REPLICAS NP; do
  [[ ${!v} =~ ^[1-9][0-9]*$ ]] || { echo "$v must be a whole number >= 1, not '${!v}'" >&2; exit 2; }
done
[[ $ITERATIONS =~ ^[1-9][0-9]*$ ]] || { echo "ITERATIONS must be a whole number >= 1, not '$ITERATIONS'" >&2; exit 2; }
source jobs/lib/bench_common.sh
OUT=${OUT:-results/segment_start/$(basename "$SCENE" .toml)_$TIER}
mkdir -p "$OUT"
read -ra bulk_set <<< "${BULK_SET:-}"
common=("$SCENE" --set fidelity.tier="$TIER" --set protocol.mode=biaxial
        --set protocol.theta_z=57 --set protocol.theta_x=57 --set protocol.repose="${BETA:-27}"
        --set protocol.iterations="$ITERATIONS" --set fill.bed_cache=beds
        --set output.snapshot_interval=1e6 --set output.checkpoint_interval=1e6
        --set output.checkpoint_wall=600 --set output.progress_interval=60)
rpm=$("$BIN" run "${common[@]}" --check | sed -n 's/^protocol.rpm = //p')
interval=$(awk -v r="$rpm" 'BEGIN {printf "%.6g", 1 / (6 * r)}')  # a sample per degree
bench_header | tee -a "$OUT/job.log"
echo "# $SCENE at $TIER, (57, 57), beta ${BETA:-27}, $ITERATIONS iteration(s), $REPLICAS beds," \
     "dynamic then rigid${BULK_SET:+ ($BULK_SET)}, $NP ranks, a sample every $interval s" |
  tee -a "$OUT/job.log"
complete() {
  [ -f "$1" ] && /usr/bin/python3 -c "import h5py, sys
sys.exit(0 if h5py.File(sys.argv[1], 'r').attrs['complete'] else 1)" "$1"
}
for ((k = 1; k <= REPLICAS; ++k)); do
  for bulk in dynamic rigid; do
    dir=$OUT/$bulk/seed$k
    if complete "$dir/results.h5"; then echo "$bulk seed $k: kept" | tee -a "$OUT/job.log"; continue; fi
    mkdir -p "$dir"
    extra=()
    [ "$bulk" = rigid ] && extra=("${bulk_set[@]}")
    ${MPIRUN:-mpirun} --bind-to none -n "$NP" "$BIN" run "${common[@]}" --set fill.seed="$k" \
      --set output.analysis_interval="$interval" --set fidelity.bulk="$bulk" "${extra[@]}" \
      --set scene.output_dir="$dir" --resume >> "$dir.log" 2>&1 ||
      { echo "$bulk seed $k: failed, see $dir.log" | tee -a "$OUT/job.log"; continue; }
    grep -h "\[run\] done" "$dir.log" | tail -1 | sed "s/^/$bulk seed $k: /;s/; results in.*//" |
      tee -a "$OUT/job.log"
  done
done
/usr/bin/python3 jobs/accuracy/segment_start_table.py "$OUT/dynamic" "$OUT/rigid" \
  --label dynamic "rigid${BULK_SET:+ ($BULK_SET)}" | tee -a "$OUT/job.log"
exit
}
