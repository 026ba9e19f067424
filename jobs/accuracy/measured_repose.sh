#!/usr/bin/env bash
# The tilt β that protocol.repose = "measured" gives (run/repose_measure.hpp), per fidelity tier
# and seed: the scene's settled bed turned 80° about z at the tier's own speed, the free surface's
# angle averaged over 40°-80° (docs/accuracy.md, "The repose tilt follows the scene"). Extra
# arguments are scene overrides (e.g. the density beds' particles.* keys). One run at a time.
# usage: jobs/accuracy/measured_repose.sh SCENE "TIERS" "SEEDS" [--set key=value ...]
#   e.g. jobs/accuracy/measured_repose.sh scenes/bst_paper.toml "fast preview" "1 2 3"
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:?scene}
TIERS=${2:-"fast preview"}
SEEDS=${3:-"1 2 3"}
shift $(( $# < 3 ? $# : 3 ))
source jobs/lib/bench_common.sh
make_work repose
bench_header
echo "# $SCENE $*: beta per tier and seed; SD = spread of the 41 samples of one run"
echo "| tier | seed | particles | rpm | beta (deg) | SD of samples | wall s |"
echo "|---|---|---|---|---|---|---|"
for tier in $TIERS; do
  for seed in $SEEDS; do
    log="$WORK/$tier.$seed.log"
    start=$(date +%s)
    "$BIN" run "$SCENE" "$@" --set fidelity.tier="$tier" --set fill.seed="$seed" \
      --set protocol.repose=measured --set fill.bed_cache="$WORK/beds" \
      --set scene.output_dir="$WORK/$tier.$seed" --max-steps 0 > "$log"
    beta=$(sed -n 's/^\[repose\] beta = \([0-9.]*\) degrees (mean of .*/\1/p' "$log")
    sd=$(sed -n 's/^\[repose\] beta = .*, SD \([0-9.e+-]*\);.*/\1/p' "$log")
    n=$(sed -n 's/^\[run\] [^:]*: \([0-9]*\) particles.*/\1/p' "$log")
    rpm=$("$BIN" run "$SCENE" "$@" --set fidelity.tier="$tier" --check | sed -n 's/^protocol.rpm = //p')
    echo "| $tier | $seed | $n | $rpm | $beta | $sd | $(( $(date +%s) - start )) |"
  done
done
