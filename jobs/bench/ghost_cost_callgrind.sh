#!/usr/bin/env bash
# What a ghost costs, counted in instructions rather than timed: one realization from the same
# warm state on P = 1, 2, 4, ... ranks under callgrind (oversubscribed: instruction counts do not
# depend on how many cores there are), the engine's own instructions per step (the `tumble`
# binary's, so not Open MPI's polling, whose count is the time a rank waited) against the ghosts
# each decomposition holds. The halo model (halo_model.py) charges a decomposed rank c_g per
# ghost-step and o per particle-step beyond the one-rank cost; jobs/bench/ghost_cost_fit.py fits
# both to these counts and says whether one straight line holds from few ghosts per particle to
# as many as a 1,024-rank domain of a 10M-particle bed holds (0.4-0.7).
#
# usage: [SCENE=jobs/bench/bst_R35_bench.toml] [WARM=dir] [TUMBLE=build/tumble] [SET="key=value ..."]
#        jobs/bench/ghost_cost_callgrind.sh [RANKS="1 2 4 8"] [STEPS=1000] [BASE=100] [OUT=dir]
# SET: scene keys for every run (e.g. SET="parallel.newton=off": border pairs on both sides).
# Each P runs BASE and BASE + STEPS steps from the warm state; the difference is STEPS steps
# without the start-up (reading, first bisection, first list). The warm state is made like
# bench_ab.sh's (200,000 steps of the R35 bed: flowing) if WARM has no checkpoint.h5.
set -euo pipefail
cd "$(dirname "$0")/../.."
source jobs/lib/bench_common.sh
RANKS=${1:-1 2 4 8}
STEPS=${2:-1000}
BASE=${3:-100}
OUT=$(realpath -m "${4:-results/bench/ghost_cost}")
SCENE=${SCENE:-jobs/bench/bst_R35_bench.toml}
WARM=$(realpath -m "${WARM:-results/bench/$(basename "$SCENE" .toml)_warm200000}")
command -v valgrind > /dev/null || { echo "valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
mkdir -p "$OUT"
extra=()
for kv in ${SET:-}; do extra+=(--set "$kv"); done
if [ ! -f "$WARM/checkpoint.h5" ]; then
  echo "# making the warm state: 200,000 steps into $WARM"
  "$BIN" run "$SCENE" --max-steps 200000 --set scene.output_dir="$WARM" > "$OUT/warm.log" 2>&1
fi
bench_header
echo "# $SCENE from $WARM, $STEPS steps counted (runs of $BASE and $((BASE + STEPS)) steps), ranks: $RANKS${SET:+, set: $SET}"
TSV="$OUT/counts.tsv"
printf "ranks\tparticles\tghosts\tsteps\tengine_ir\tall_ir\tlist_pairs_max_over_mean\n" > "$TSV"
for p in $RANKS; do
  for s in "$BASE" "$((BASE + STEPS))"; do
    dir="$OUT/p$p.s$s"
    rm -rf "$dir" && mkdir -p "$dir"
    # Open MPI yields while it waits, so that oversubscribed ranks do not spin through each
    # other's time slices (the waiting is not counted anyway: it runs in Open MPI's code).
    OMPI_MCA_mpi_yield_when_idle=1 ${MPIRUN:-mpirun} -n "$p" --oversubscribe --bind-to none \
      valgrind --tool=callgrind --callgrind-out-file="$dir/cg.%p" \
      "$BIN" run "$SCENE" --restart "$WARM/checkpoint.h5" --max-steps "$s" \
      --set scene.output_dir="$dir/run" "${extra[@]}" > "$dir/log" 2>&1 ||
      { echo "P = $p, $s steps failed: $dir/log" >&2; exit 1; }
  done
  a="$OUT/p$p.s$BASE" b="$OUT/p$p.s$((BASE + STEPS))"
  eng=$(( $(/usr/bin/python3 jobs/bench/callgrind_objects.py "$b"/cg.* --object tumble) -
          $(/usr/bin/python3 jobs/bench/callgrind_objects.py "$a"/cg.* --object tumble) ))
  all=$(( $(/usr/bin/python3 jobs/bench/callgrind_objects.py "$b"/cg.* | awk '/ all$/ {gsub(",", "", $1); print $1}') -
          $(/usr/bin/python3 jobs/bench/callgrind_objects.py "$a"/cg.* | awk '/ all$/ {gsub(",", "", $1); print $1}') ))
  n=$(sed -n 's/.*: \([0-9]*\) particles, dt.*/\1/p' "$b/log" | head -1)
  # Ghosts at the end of each of the two runs (both ranks' sum; 0 on one rank), averaged.
  g=$(cat "$a/log" "$b/log" | sed -n 's/.*, \([0-9]*\) ghosts,.*/\1/p' | awk '{s += $1; k++} END {print k ? s / k : 0}')
  lp=$(sed -n 's/.*(list pairs \([0-9.]*\)).*/\1/p' "$b/log" | tail -1)
  printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\n" "$p" "$n" "$g" "$STEPS" "$eng" "$all" "${lp:-1}" >> "$TSV"
  echo "P = $p: $(( eng / STEPS / n )) engine instructions per particle-step, ghosts $g"
done
/usr/bin/python3 jobs/bench/ghost_cost_fit.py "$TSV"
