#!/usr/bin/env bash
# The rigid bulk's speed phase by phase (docs/accuracy.md, "Rigid bulk"): a whole iteration of a
# big bed costs hours here, so its cost is put together from the rates of its phases. One rigid
# run of SCENE's (57°, 57°) protocol (β = 27°) leaves a checkpoint at each time of TIMES (seconds
# of simulated time: by default 0.12, inside the first tilt with the bed frozen, and 3.5, 36° into
# the first rotation with the layer flowing); from each, STEPS steps run REPEATS times rigid and
# dynamic, interleaved (a rigid checkpoint restarts dynamic with everything thawed), on NP ranks.
# OTHER=path/to/tumble adds that binary's rigid run to each round (before/after a change).
# Checkpoints are kept in OUT (default results/rigid_phases/<scene>) and reused: rerunning skips
# the long first run.
# usage: jobs/accuracy/rigid_phases.sh [SCENE=scenes/bst_paper.toml] [STEPS=10000] [REPEATS=2]
#                                      [NP=2] [TIMES="0.12 3.5"]
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_paper.toml}
STEPS=${2:-10000}
REPEATS=${3:-2}
NP=${4:-2}
TIMES=${5:-0.12 3.5}
source jobs/lib/bench_common.sh
OUT=$(realpath -m "${OUT:-results/rigid_phases/$(basename "$SCENE" .toml)}")
mkdir -p "$OUT"
bench_header
echo "# $SCENE, (57, 57), beta = 27 deg, $STEPS steps from each checkpoint, $REPEATS rounds, $NP ranks"
common=("$SCENE" --set fill.bed_cache=beds --set protocol.repose=27
        --set output.analysis_interval=0.05 --set output.snapshot_interval=1e6
        --set output.progress_interval=10)
run() { ${MPIRUN:-mpirun} --bind-to none -n "$NP" "$@"; }
"$BIN" run "${common[@]}" --max-steps 0 --set scene.output_dir="$OUT/probe" > "$OUT/probe.log"
dt=$(sed -n 's/.* dt = \([0-9.e+-]*\) s,.*/\1/p' "$OUT/probe.log" | tail -1)
for t in $TIMES; do
  ckpt="$OUT/at_$t/checkpoint.h5"
  [ -f "$ckpt" ] && continue
  steps=$(awk -v t="$t" -v dt="$dt" 'BEGIN { printf "%d", t / dt + 0.5 }')
  echo "# rigid run to t = $t s ($steps steps) for its checkpoint"
  run "$BIN" run "${common[@]}" --set fidelity.bulk=rigid --set output.checkpoint_interval="$t" \
    --set scene.output_dir="$OUT/at_$t" --max-steps "$steps" > "$OUT/at_$t.log" 2>&1
done
echo "| from t (s) | round | run | wall s | particle-steps/s | frozen at the end |"
echo "|---|---|---|---|---|---|"
for t in $TIMES; do
  for r in $(seq 1 "$REPEATS"); do
    for variant in rigid dynamic ${OTHER:+other}; do
      bin=$BIN bulk=$variant
      [ "$variant" = other ] && bin=$OTHER bulk=rigid
      log="$OUT/run_${t}_${variant}_$r.log"
      run "$bin" run "${common[@]}" --set fidelity.bulk=$bulk --set output.checkpoint_interval=1e6 \
        --set scene.output_dir="$OUT/run" --restart "$OUT/at_$t/checkpoint.h5" \
        --max-steps "$STEPS" > "$log" 2>&1
      wall=$(sed -n 's/.*done: [0-9]* steps in \([0-9.e+]*\) s.*/\1/p' "$log" | tail -1)
      frozen=$(grep -o 'frozen [0-9.]*' "$log" | tail -1 | cut -d' ' -f2 || true)
      echo "| $t | $r | $variant | $wall | $(rate "$log") | ${frozen:--} |"
    done
  done
done
