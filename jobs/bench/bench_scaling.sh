#!/usr/bin/env bash
# Strong scaling of one realization (issue 3): the same rotating bed on 1 rank and on NP ranks
# (mpiexec, one core each), from one warmed-up checkpoint, alternated REPEATS times. Prints
# particle-steps/s, parallel efficiency E = rate(NP) / (NP rate(1)), the load imbalance (max/mean
# particles per rank), ghosts per rank and peak memory per rank.
# usage: jobs/bench/bench_scaling.sh [SCENE=scenes/bst_paper.toml] [STEPS=2000] [REPEATS=3] [NP=2]
# NP may be a list, e.g. "2 4 8 16": each round then runs 1 rank and every NP in turn, and each NP
# gets its line against the same one-rank median (a scaling curve on a many-core node).
# MPIEXEC_OPTS (default "--bind-to core") replaces the binding options, e.g. "--bind-to none".
# The settled bed is cached in beds/ (settled on the largest NP if missing); the warm-up rotates it
# for WARMUP=2000 steps (flowing layer started) before the timed runs.
# SIDE_BY_SIDE=1: each round also runs NP one-rank runs at once (one per core, taskset), the same
# restart: the machine's own ceiling for NP ranks (shared caches, memory bandwidth, clock), and the
# efficiency against it, rate(NP) / (NP x side-by-side one-rank rate), is what the decomposition
# itself costs. (Only for NP <= cores; with a list of NP, the largest.)
# Peer: with SCENE=jobs/bench/bst_R35_bench.toml (the shared reference bed) and LIGGGHTS installed,
# LIGGGHTS runs the same bed on 1 and NP ranks in the same job (jobs/bench/liggghts/run.sh).
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_paper.toml}
STEPS=${2:-2000}
REPEATS=${3:-3}
NP=${4:-2}
WARMUP=${WARMUP:-2000}
source jobs/lib/bench_common.sh
command -v /usr/bin/time > /dev/null || { echo "needs GNU time (apt-get install time)" >&2; exit 1; }
read -r -a NPS <<< "$NP"
NPMAX=$(printf '%s\n' "${NPS[@]}" | sort -n | tail -1)
read -r -a BIND <<< "${MPIEXEC_OPTS:---bind-to core}"
launcher() {  # the mpiexec command for $1 ranks
  if [ "$1" -gt "$(nproc)" ]; then MPI=(mpiexec --oversubscribe -n "$1"); else MPI=(mpiexec "${BIND[@]}" -n "$1"); fi
}
make_work scaling
name=$(basename "$SCENE" .toml)
bench_header
echo "# $name: $STEPS timed steps per run after $WARMUP warm-up steps; $REPEATS runs per rank count (1, ${NPS[*]})"

# protocol.repose pinned: the timing does not depend on it, a measurement would cost 80 degrees.
common=(--set fill.bed_cache=beds --set output.analysis_interval=0 --set output.progress_interval=1e6
        --set protocol.repose=27)
# Warm-up on the largest NP (also settles and caches the bed if needed); its checkpoint starts
# every run.
launcher "$NPMAX"
"${MPI[@]}" "$BIN" run "$SCENE" "${common[@]}" --set scene.output_dir="$WORK/warm" \
  --max-steps "$WARMUP" > "$WORK/warm.log"

timed() {  # ranks, label
  local n=$1 out="$WORK/run_$2"
  local launch=()
  launcher "$n"
  [ "$n" -gt 1 ] && launch=("${MPI[@]}")
  rm -rf "$out"
  mkdir -p "$out"
  # GNU time inside mpiexec: one peak-RSS line per rank.
  "${launch[@]}" /usr/bin/time -f "rss_kb %M" -a -o "$WORK/rss_$2" "$BIN" run "$SCENE" "${common[@]}" \
    --set scene.output_dir="$out" --set output.snapshot_interval=1e6 \
    --restart "$WORK/warm/checkpoint.h5" --max-steps "$STEPS" > "$WORK/$2.log"
}
side() {  # round: NPMAX one-rank runs at once, one per core
  local c pids=()
  for ((c = 0; c < NPMAX; ++c)); do
    local out="$WORK/run_side_$1_$c"
    rm -rf "$out"
    mkdir -p "$out"
    taskset -c "$c" "$BIN" run "$SCENE" "${common[@]}" --set scene.output_dir="$out" \
      --set output.snapshot_interval=1e6 --restart "$WORK/warm/checkpoint.h5" \
      --max-steps "$STEPS" > "$WORK/side_$1_$c.log" &
    pids+=($!)
  done
  wait "${pids[@]}"
}
r1=()
rs=()
declare -A rn
for ((k = 0; k < REPEATS; ++k)); do
  timed 1 "1_$k"
  r1+=("$(rate "$WORK/1_$k.log")")
  for n in "${NPS[@]}"; do
    timed "$n" "n${n}_$k"
    rn[$n]="${rn[$n]:-} $(rate "$WORK/n${n}_$k.log")"
  done
  if [ "${SIDE_BY_SIDE:-0}" = 1 ] && [ "$NPMAX" -le "$(nproc)" ]; then
    side "$k"
    for ((c = 0; c < NPMAX; ++c)); do rs+=("$(rate "$WORK/side_${k}_$c.log")"); done
  fi
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
m1=$(median "${r1[@]}")
particles=$(sed -n 's/.*: \([0-9]*\) particles, dt.*/\1/p' "$WORK/warm.log" | tail -1)
rss1=$(awk '{print $2}' "$WORK/rss_1_0" | sort -g | tail -1)
for n in "${NPS[@]}"; do
  read -r -a runs <<< "${rn[$n]}"
  mn=$(median "${runs[@]}")
  last="$WORK/n${n}_$((REPEATS - 1)).log"
  rssn=$(awk '{print $2}' "$WORK/rss_n${n}_0" | sort -g | tail -1)
  awk -v s="$name" -v np="$n" -v m1="$m1" -v mn="$mn" -v r1="${r1[*]}" -v rn="${runs[*]}" \
   -v imb="$(sed -n 's/.*imbalance \([0-9.]*\).*/\1/p' "$last" | tail -1)" \
      -v gh="$(sed -n 's/.*, \([0-9]*\) ghosts.*/\1/p' "$last" | tail -1)" -v n="$particles" -v k1="$rss1" -v kn="$rssn" 'BEGIN {
    printf "%s  particles=%d  1 rank: %.4g  %d ranks: %.4g particle-steps/s (medians; runs %s | %s)\n",
           s, n, m1, np, mn, r1, rn
    printf "%s  efficiency=%.1f%%  speedup=%.2f  imbalance=%s  ghosts(total)=%s (%.1f%% of particles)  peak_rss_mb 1 rank=%.1f, per rank at %d=%.1f\n",
           s, 100 * mn / (np * m1), mn / m1, imb, gh, 100 * gh / n, k1 / 1024, np, kn / 1024
    # Round by round (each NP-rank run against the one-rank run just before it): on a shared
    # machine whose load drifts, the figure the drift disturbs least.
    k = split(r1, a, " "); split(rn, b, " ")
    for (i = 1; i <= k; ++i) e[i] = 100 * b[i] / (np * a[i])
    for (i = 1; i <= k; ++i) for (j = i + 1; j <= k; ++j) if (e[j] < e[i]) { t = e[i]; e[i] = e[j]; e[j] = t }
    printf "%s  efficiency per round: median %.1f%% (%.1f-%.1f%%, %d rounds)\n", s, e[int((k + 1) / 2)], e[1], e[k], k
  }'
  echo "# last $n-rank run: $(grep '\[run\] done' "$last" | sed 's/; results in.*//')"
  if [ "${#rs[@]}" -gt 0 ] && [ "$n" = "$NPMAX" ]; then
    ms=$(median "${rs[@]}")
    awk -v s="$name" -v np="$n" -v ms="$ms" -v mn="$mn" -v m1="$m1" -v runs="${rs[*]}" 'BEGIN {
      printf "%s  side by side: %d one-rank runs at once, %.4g particle-steps/s each (median; runs %s), %.1f%% of one alone\n", s, np, ms, runs, 100 * ms / m1
      printf "%s  efficiency against the side-by-side ceiling=%.1f%%\n", s, 100 * mn / (np * ms)
    }'
  fi
done

if [ "$SCENE" = jobs/bench/bst_R35_bench.toml ]; then
  if command -v liggghts > /dev/null; then
    l1=$(LIGGGHTS_WARMUP=$WARMUP bash jobs/bench/liggghts/run.sh 1 "$STEPS" 2> /dev/null | tail -n 1)
    ln=$(LIGGGHTS_WARMUP=$WARMUP bash jobs/bench/liggghts/run.sh "$NPMAX" "$STEPS" 2> /dev/null | tail -n 1)
    echo "$l1"
    echo "$ln"
    printf '%s\n%s\n' "$l1" "$ln" | awk -v np="$NPMAX" '{for (i = 1; i <= NF; ++i) if ($i ~ /^psteps_per_s=/) r[NR] = substr($i, 14)}
      END {if (r[1] && r[2]) printf "LIGGGHTS  efficiency=%.1f%%  speedup=%.2f (same bed, same machine, same job)\n", 100 * r[2] / (np * r[1]), r[2] / r[1]}'
  else
    echo "LIGGGHTS not installed: no peer run (apt-get install liggghts)"
  fi
fi
