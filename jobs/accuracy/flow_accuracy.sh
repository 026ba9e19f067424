#!/usr/bin/env bash
# Error of each fidelity tier against the reference tier on the flowing-layer observables
# (docs/accuracy.md): every tier of SCENE rotated about x from its settled bed (REPLICAS seeds
# each, run JOBS at a time on one core each) through 80° of rotation at the tier's own speed;
# repose angle, surface speed and the large-particle wall fraction averaged over 40°-80° (the
# flow is established after ~35°); then jobs/accuracy/accuracy_table.py prints the table.
# usage: jobs/accuracy/flow_accuracy.sh [SCENE=scenes/bst_tiny.toml] [REPLICAS=3] [JOBS=2]
# TIERS="standard fast preview" leaves the reference out (the errors are then against standard).
# BULK=rigid also runs each tier with fidelity.bulk = "rigid" (runs in OUT/<tier>-rigid; the
# table then has a row for each, against the first tier that ran dynamic: docs/accuracy.md,
# "Rigid bulk"); BULK_SET="--set fidelity.bulk_margin=4 ..." passes more keys to those runs.
# RANKS=k runs each run on k ranks (${MPIRUN:-mpirun} -n k; pair it with JOBS=1): the runs then
# come one at a time in the order seed 1 dynamic, seed 1 rigid, seed 2 dynamic, ..., so a job cut
# short has whole pairs and the two bulks alternate on the same cores (their wall times compare).
# A run whose results.h5 says it is complete is not run again (runs are deterministic: copy the
# dynamic runs of an earlier OUT in to compare another rigid setting against them); one stopped
# by SIGUSR1 (its checkpoint kept) goes on from its checkpoint when the script is run again.
{  # read to the closing brace before running: an edit while it runs (hours) cannot change it
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_tiny.toml}
REPLICAS=${2:-3}
JOBS=${3:-2}
source jobs/lib/bench_common.sh
OUT=${ACCURACY_OUT:-results/accuracy/$(basename "$SCENE" .toml)}
mkdir -p "$OUT"
bench_header
echo "# $SCENE: tiers x $REPLICAS replicas, 80 degrees of rotation about x, $JOBS runs at a time"
launch=
if [ -n "${RANKS:-}" ]; then
  [[ $RANKS =~ ^[1-9][0-9]*$ ]] || { echo "RANKS must be a whole number >= 1, not '$RANKS'" >&2; exit 2; }
  launch="${MPIRUN:-mpirun} --bind-to none -n $RANKS"
fi
runs=()
for tier in ${TIERS:-reference standard fast preview}; do
  rpm=$("$BIN" run "$SCENE" --set fidelity.tier=$tier --set protocol.mode=single_axis --check |
        sed -n 's/^protocol.rpm = //p')
  duration=$(awk -v r="$rpm" 'BEGIN {printf "%.6g", 80 / (6 * r)}')  # 80° at rpm * 6 °/s
  interval=$(awk -v d="$duration" 'BEGIN {printf "%.6g", d / 80}')   # a sample per degree
  for ((k = 1; k <= REPLICAS; ++k)); do
    runs+=("$tier $k $duration $interval dynamic")
    [ -n "${BULK:-}" ] && runs+=("$tier $k $duration $interval $BULK")
  done
done
printf '%s\n' "${runs[@]}" | xargs -P "$JOBS" -L 1 bash -c '
  tier=$0 seed=$1 duration=$2 interval=$3 bulk=$4
  name=$tier
  [ "$bulk" = dynamic ] || name=$tier-$bulk
  dir='"$OUT"'/$name/seed$seed
  extra=
  [ "$bulk" = dynamic ] || extra="'"${BULK_SET:-}"'"
  if [ -f $dir/results.h5 ] && /usr/bin/python3 -c "import h5py, sys
sys.exit(0 if h5py.File(sys.argv[1], \"r\").attrs[\"complete\"] else 1)" $dir/results.h5; then
    echo "$name seed $seed: kept"; exit 0
  fi
  mkdir -p "$dir"
  '"$launch $BIN"' run '"$SCENE"' --set fidelity.tier=$tier --set fill.seed=$seed \
    --set protocol.mode=single_axis --set protocol.axis=x --set protocol.duration=$duration \
    --set output.analysis_interval=$interval --set output.snapshot_interval=1e6 \
    --set output.checkpoint_interval=1e6 --set fill.bed_cache=beds --set fidelity.bulk=$bulk $extra \
    --set scene.output_dir=$dir --resume >> $dir.log 2>&1 || echo "run $name $seed failed: see $dir.log"
  grep -h "\[run\] done" $dir.log | tail -1 | sed "s/^/$name seed $seed: /;s/; results in.*//"'
/usr/bin/python3 jobs/accuracy/accuracy_table.py "$OUT"
exit
}
