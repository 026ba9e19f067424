#!/usr/bin/env bash
# Before/after of one change on one core: two tumble binaries from the same warm state of a scene
# ($SCENE, default the shared R35 bed jobs/bench/bst_R35_bench.toml, flowing after WARMUP steps),
# run in turns A B A B ... on core 0, STEPS steps each, ROUNDS rounds. Prints each run's
# particle-steps/s, the medians and the per-round ratio B/A (median, min-max): on a shared machine
# the ratio within a round is the figure that counts.
# usage: [SCENE=...] [WARM=dir] jobs/bench/bench_ab.sh BIN_A BIN_B [STEPS=20000] [ROUNDS=8]
#                                                     [WARMUP=200000]
# The warm state (the run's final checkpoint) is made once with BIN_A and kept in $WARM (default
# results/bench/<scene name>_warm<WARMUP>).
set -euo pipefail
cd "$(dirname "$0")/../.."
A=${1:?usage: bench_ab.sh BIN_A BIN_B [STEPS] [ROUNDS] [WARMUP]}
B=${2:?usage: bench_ab.sh BIN_A BIN_B [STEPS] [ROUNDS] [WARMUP]}
STEPS=${3:-20000}
ROUNDS=${4:-8}
WARMUP=${5:-200000}
TUMBLE=$A source jobs/lib/bench_common.sh
SCENE=${SCENE:-jobs/bench/bst_R35_bench.toml}
WARM=$(realpath -m "${WARM:-results/bench/$(basename "$SCENE" .toml)_warm$WARMUP}")
make_work ab
bench_header
echo "# A = $A ($("$A" --version)), B = $B ($("$B" --version))"
echo "# $SCENE from $WARMUP warm-up steps, $STEPS steps per run, $ROUNDS rounds, core 0"
if [ ! -f "$WARM/checkpoint.h5" ]; then
  # (a run ends with a checkpoint)
  taskset -c 0 "$A" run "$SCENE" --max-steps "$WARMUP" --set scene.output_dir="$WARM" \
    > "$WORK/warm.log" 2>&1
  [ -f "$WARM/checkpoint.h5" ] || { echo "the warm-up left no checkpoint: $WORK/warm.log" >&2; exit 1; }
fi
echo "| round | A particle-steps/s | B particle-steps/s | B / A |"
echo "|---|---|---|---|"
for r in $(seq 1 "$ROUNDS"); do
  for v in A B; do
    bin=$A
    [ "$v" = B ] && bin=$B
    taskset -c 0 "$bin" run "$SCENE" --restart "$WARM/checkpoint.h5" --max-steps "$STEPS" \
      --set scene.output_dir="$WORK/run" > "$WORK/$v$r.log" 2>&1
  done
  a=$(rate "$WORK/A$r.log") b=$(rate "$WORK/B$r.log")
  echo "| $r | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", b / a }') |"
  echo "$a $b" >> "$WORK/rates"
done
/usr/bin/python3 - "$WORK/rates" <<'PY'
import statistics, sys
rows = [tuple(map(float, line.split())) for line in open(sys.argv[1])]
a, b = [r[0] for r in rows], [r[1] for r in rows]
q = [y / x for x, y in rows]
print(f"median A {statistics.median(a):.4g} ({min(a):.4g}-{max(a):.4g}), "
      f"B {statistics.median(b):.4g} ({min(b):.4g}-{max(b):.4g}); "
      f"B / A per round: median {statistics.median(q):.3f} ({min(q):.3f}-{max(q):.3f}), "
      f"B faster in {sum(x > 1 for x in q)} of {len(q)} rounds")
PY
