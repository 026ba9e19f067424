#!/usr/bin/env bash
# Tumble against LIGGGHTS on the shared reference bed (jobs/bench/bst_R35_bench.toml), same job,
# same machine: particle-steps per second on 1 core and peak memory.
#
# usage: jobs/bench/bench_bst_small.sh [STEPS=20000] [WARMUP=2000]
# Both codes run WARMUP untimed steps of rotation from the settled bed, then STEPS timed steps.
# LIGGGHTS runs only if installed (apt-get install liggghts).
set -euo pipefail
cd "$(dirname "$0")/../.."
STEPS=${1:-20000}
WARMUP=${2:-2000}
BUILD=${TUMBLE_BUILD:-build}
[ -x "$BUILD/tumble" ] || bash jobs/build.sh > /dev/null
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
WORK=$(mktemp -d "${TMPDIR:-/tmp}/tumble_bench.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
echo "# machine: $(lscpu | awk -F: '/Model name/ {gsub(/^ +/, "", $2); print $2}'), $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
echo "# git: $(git rev-parse --short HEAD 2>/dev/null || echo unknown); steps $STEPS after $WARMUP warm-up"

run_tumble() {  # $1 = extra label, rest = extra --set overrides
  local label=$1; shift
  local out="$WORK/tumble_$label"
  "$BUILD/tumble" run jobs/bench/bst_R35_bench.toml --set scene.output_dir="$out" "$@" \
    --max-steps "$WARMUP" > "$WORK/warm_$label.log"
  /usr/bin/time -v -o "$WORK/time_$label" "$BUILD/tumble" run jobs/bench/bst_R35_bench.toml \
    --set scene.output_dir="$out" "$@" --resume --max-steps "$STEPS" > "$WORK/run_$label.log"
  local rate n rss
  rate=$(awk '/\[run\] done/ {for (i = 1; i <= NF; ++i) if ($i ~ /particle-steps/) print substr($(i-1), 2)}' "$WORK/run_$label.log")
  n=$(awk '/particles, dt/ {print $3}' "$WORK/run_$label.log")
  rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.1f", $2/1024}' "$WORK/time_$label")
  echo "Tumble[$label] nprocs=1 particles=$n steps=$STEPS psteps_per_s=$rate peak_rss_mb=$rss bytes_per_particle=$(awk -v r="$rss" -v n="$n" 'BEGIN {printf "%.0f", r*1048576/n}')"
}

command -v /usr/bin/time > /dev/null || { echo "needs GNU time (apt-get install time)"; exit 1; }
run_tumble default
T=$(awk '/psteps_per_s/ {print}' /dev/null)
if command -v liggghts > /dev/null; then
  LIGGGHTS_WARMUP=$WARMUP bash jobs/bench/liggghts/run.sh 1 "$STEPS" 2> "$WORK/liggghts.err" | tail -n 1
else
  echo "LIGGGHTS not installed: no peer run (apt-get install liggghts)"
fi
