#!/usr/bin/env bash
# Before/after of one change on one core: two tumble binaries from the same warm state of a scene
# ($SCENE, default the shared R35 bed jobs/bench/bst_R35_bench.toml, flowing after WARMUP steps),
# run in turns A B A B ... on core 0, STEPS steps each, ROUNDS rounds. Prints each run's
# particle-steps/s, the medians and the per-round ratio B/A (median, min-max): on a shared machine
# the ratio within a round is the figure that counts.
# usage: [SCENE=...] [WARM=dir] [NP=1] jobs/bench/bench_ab.sh BIN_A BIN_B [STEPS=20000] [ROUNDS=8]
#                                                     [WARMUP=200000]
# The warm state (the run's final checkpoint) is made once with BIN_A and kept in $WARM (default
# results/bench/<scene name>_warm<WARMUP>).
# NP=2 (or more): a parallel before/after: each round runs A on 1 rank (core 0) and on NP ranks
# (mpiexec --bind-to core), then B the same way, and prints each binary's parallel efficiency
# rate(NP) / (NP rate(1)) per round beside the NP-rank ratio B/A.
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
NP=${NP:-1}
if [ "$NP" -gt 1 ]; then
  once() {  # binary ranks log
    local launch=(taskset -c 0)
    [ "$2" -gt 1 ] && launch=(mpiexec --bind-to core -n "$2")
    "${launch[@]}" "$1" run "$SCENE" --restart "$WARM/checkpoint.h5" --max-steps "$STEPS" \
      --set scene.output_dir="$WORK/run" --set output.snapshot_interval=1e6 > "$3" 2>&1
  }
  echo "# NP = $NP: each round A on 1 rank, A on $NP, B on 1, B on $NP"
  echo "| round | A 1 rank | A $NP ranks | A efficiency | B 1 rank | B $NP ranks | B efficiency | B / A at $NP |"
  echo "|---|---|---|---|---|---|---|---|"
  for r in $(seq 1 "$ROUNDS"); do
    once "$A" 1 "$WORK/A1_$r.log"
    once "$A" "$NP" "$WORK/An_$r.log"
    once "$B" 1 "$WORK/B1_$r.log"
    once "$B" "$NP" "$WORK/Bn_$r.log"
    a1=$(rate "$WORK/A1_$r.log") an=$(rate "$WORK/An_$r.log")
    b1=$(rate "$WORK/B1_$r.log") bn=$(rate "$WORK/Bn_$r.log")
    awk -v r="$r" -v np="$NP" -v a1="$a1" -v an="$an" -v b1="$b1" -v bn="$bn" 'BEGIN {
      printf "| %d | %s | %s | %.1f%% | %s | %s | %.1f%% | %.3f |\n", r, a1, an, 100 * an / (np * a1),
             b1, bn, 100 * bn / (np * b1), bn / an }'
    echo "$a1 $an $b1 $bn" >> "$WORK/rates"
  done
  /usr/bin/python3 - "$WORK/rates" "$NP" <<'PY'
import statistics, sys
rows = [tuple(map(float, line.split())) for line in open(sys.argv[1])]
np_ = int(sys.argv[2])
def spread(v, f=".4g"):
    return f"{statistics.median(v):{f}} ({min(v):{f}}-{max(v):{f}})"
ea = [100 * an / (np_ * a1) for a1, an, _, _ in rows]
eb = [100 * bn / (np_ * b1) for _, _, b1, bn in rows]
q = [bn / an for _, an, _, bn in rows]
print(f"A: 1 rank {spread([r[0] for r in rows])}, {np_} ranks {spread([r[1] for r in rows])}, "
      f"efficiency per round {spread(ea, '.1f')}%")
print(f"B: 1 rank {spread([r[2] for r in rows])}, {np_} ranks {spread([r[3] for r in rows])}, "
      f"efficiency per round {spread(eb, '.1f')}%")
print(f"B / A at {np_} ranks per round: median {statistics.median(q):.3f} ({min(q):.3f}-{max(q):.3f}), "
      f"B faster in {sum(x > 1 for x in q)} of {len(q)} rounds")
PY
  exit 0
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
