#!/usr/bin/env bash
# Tumble against LIGGGHTS on the shared reference bed, in the same job on the same machine:
# particle-steps per second on 1 core and peak memory (jobs/bench/bst_R35_bench.toml: the settled
# 10,522-particle bed of jobs/bench/data in a 35 mm sphere rotating at 3 rpm, the exact contact
# parameters LIGGGHTS was measured with).
#
# usage: jobs/bench/bench_bst_small.sh [STEPS=20000] [WARMUP=200000]
# Both codes rotate the bed for WARMUP untimed steps (2 s: the flowing layer is established and the
# repose angle reached), then run STEPS timed steps. LIGGGHTS runs if installed (apt-get install
# liggghts). TUMBLE_NATIVE_BUILD=DIR also times a -DTUMBLE_NATIVE=ON build found in DIR.
set -euo pipefail
cd "$(dirname "$0")/../.."
STEPS=${1:-20000}
WARMUP=${2:-200000}
BUILD=${TUMBLE_BUILD:-build}
[ -x "$BUILD/tumble" ] || TUMBLE_BUILD=$BUILD bash jobs/build.sh > /dev/null
command -v /usr/bin/time > /dev/null || { echo "needs GNU time (apt-get install time)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
WORK=$(mktemp -d "${TMPDIR:-/tmp}/tumble_bench.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
echo "# $(lscpu | awk -F: '/Model name/ {gsub(/^ +/, "", $2); print $2}'), $(nproc) cores;" \
     "$(date -u +%Y-%m-%dT%H:%MZ); git $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo "# $STEPS timed steps after $WARMUP warm-up steps of rotation, 1 core each"

run_tumble() {  # $1 = label, $2 = binary
  local label=$1 bin=$2 out="$WORK/tumble_$1"
  "$bin" run jobs/bench/bst_R35_bench.toml --set scene.output_dir="$out" --max-steps "$WARMUP" \
    > "$WORK/warm_$label.log"
  /usr/bin/time -v -o "$WORK/time_$label" "$bin" run jobs/bench/bst_R35_bench.toml \
    --set scene.output_dir="$out" --resume --max-steps "$STEPS" > "$WORK/run_$label.log"
  awk -v label="$label" -v steps="$STEPS" '
    FILENAME ~ /run_/ && /particles, dt/ {n = $3}
    FILENAME ~ /run_/ && /\[run\] done/ {for (i = 1; i <= NF; ++i) if ($i ~ /particle-steps/) r = substr($(i-1), 2)}
    FILENAME ~ /time_/ && /Maximum resident/ {split($0, a, ": "); rss = a[2] / 1024}
    END {printf "Tumble[%s] nprocs=1 particles=%d steps=%d psteps_per_s=%.4g peak_rss_mb=%.1f bytes_per_particle=%.0f\n",
                label, n, steps, r, rss, rss * 1048576 / n}' "$WORK/run_$label.log" "$WORK/time_$label"
}

{
  run_tumble generic "$BUILD/tumble"
  if [ -n "${TUMBLE_NATIVE_BUILD:-}" ]; then run_tumble native "$TUMBLE_NATIVE_BUILD/tumble"; fi
  if command -v liggghts > /dev/null; then
    LIGGGHTS_WARMUP=$WARMUP bash jobs/bench/liggghts/run.sh 1 "$STEPS" 2> "$WORK/liggghts.err" | tail -n 1
  else
    echo "LIGGGHTS not installed: no peer run (apt-get install liggghts)"
  fi
} | tee "$WORK/summary"
awk '/^Tumble\[generic\]/ {for (i = 1; i <= NF; ++i) if ($i ~ /^psteps_per_s=/) t = substr($i, 14)}
     /^LIGGGHTS nprocs/ {for (i = 1; i <= NF; ++i) if ($i ~ /^psteps_per_s=/) l = substr($i, 14)}
     END {if (t && l) printf "ratio Tumble/LIGGGHTS (1 core, generic build): %.2f\n", t / l}' "$WORK/summary"
