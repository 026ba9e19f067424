#!/usr/bin/env bash
# Wall time of fidelity.bulk = "rigid" against "dynamic" (docs/accuracy.md, "Rigid bulk"): the
# scene at one tier for STEPS steps of its protocol from its settled bed (default: one whole
# iteration, tilts included: the share frozen changes along it), REPEATS times each, interleaved
# (dynamic, rigid, dynamic, rigid, ...) so that load from other work on a shared machine falls on
# both alike; each run's wall seconds come from its "[run] done" line, scaled to a whole iteration,
# and the share frozen is the mean over the rigid run's progress lines (sampled every 2 wall s).
# Prints every run and the medians.
# usage: jobs/accuracy/rigid_cost.sh [SCENE=scenes/bst_tiny.toml] [TIER=standard] [REPEATS=2]
#        [STEPS=0: one iteration] [extra --set arguments for both, e.g. --set fidelity.bulk_dwell=0.1]
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_tiny.toml}
TIER=${2:-standard}
REPEATS=${3:-2}
STEPS=${4:-0}
shift $(( $# < 4 ? $# : 4 ))
source jobs/lib/bench_common.sh
make_work rigid_cost
bench_header
echo "# $SCENE at $TIER, beta = 27 deg, $REPEATS x (dynamic, rigid) interleaved, extra: $*"
common=("$SCENE" --set fidelity.tier="$TIER" --set fill.bed_cache=beds --set protocol.repose=27
        --set protocol.iterations=1 --set output.analysis_interval=0
        --set output.snapshot_interval=1e6 --set output.checkpoint_interval=1e6
        --set output.progress_interval=2 "$@")
"$BIN" run "${common[@]}" --max-steps 0 --set scene.output_dir="$WORK/probe" > "$WORK/probe.log"
total=$(sed -n 's/.* dt = [0-9.e+-]* s, \([0-9]*\) steps.*/\1/p' "$WORK/probe.log" | tail -1)
[ "$STEPS" -gt 0 ] || STEPS=$total
echo "| run | bulk | steps | wall s | wall s per iteration | particle-steps/s | mean frozen |"
echo "|---|---|---|---|---|---|---|"
for r in $(seq 1 "$REPEATS"); do
  for bulk in dynamic rigid; do
    log="$WORK/$bulk.$r.log"
    "$BIN" run "${common[@]}" --set fidelity.bulk=$bulk --set scene.output_dir="$WORK/$bulk.$r" \
      --max-steps "$STEPS" > "$log"
    wall=$(sed -n 's/.*done: [0-9]* steps in \([0-9.e+]*\) s.*/\1/p' "$log" | tail -1)
    frozen=$(awk '/frozen/ {for (i = 1; i < NF; ++i) if ($i == "frozen") {s += $(i + 1); n++}}
                  END {if (n) printf "%.3f", s / n; else printf "-"}' "$log")
    awk -v r="$r" -v b="$bulk" -v s="$STEPS" -v w="$wall" -v t="$total" -v rate="$(rate "$log")" \
        -v f="$frozen" 'BEGIN { printf "| %d | %s | %d | %.1f | %.1f | %.3g | %s |\n", r, b, s, w, w * t / s, rate, f }' \
      | tee -a "$WORK/rows"
  done
done
for bulk in dynamic rigid; do
  awk -v b="$bulk" -F'|' '$3 ~ " "b" " {print $6}' "$WORK/rows" | sort -g |
    awk -v b="$bulk" '{v[NR] = $1} END {m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2;
                      printf "# median wall s per iteration, %s: %.1f\n", b, m}'
done
