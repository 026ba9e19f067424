#!/usr/bin/env bash
# The engine's memory on the shared R35 bed (issue 16, docs/performance.md "Memory"): the heap of
# STEPS steps of the flowing bed under valgrind's massif, split by jobs/bench/massif_summary.py
# into the engine, the libraries (Open MPI, HDF5, PETSc) and the rest, at the stepping phase's peak;
# and the engine's own count of its arrays (the run's "[run] memory" line).
# usage: jobs/bench/memory_massif.sh [STEPS=300] [WARMUP=200000]
#   MASSIF_BUILD  a build with symbols (default build-massif: configured Release with -g, which
#                 changes no code, and built here if missing)
#   WARM_DIR      an output directory of this scene already rotated WARMUP steps (kept: reused)
# Needs valgrind (apt-get install valgrind).
set -euo pipefail
cd "$(dirname "$0")/../.."
STEPS=${1:-300}
WARMUP=${2:-200000}
BUILD=${MASSIF_BUILD:-build-massif}
command -v valgrind > /dev/null || { echo "valgrind is missing: apt-get install valgrind" >&2; exit 1; }
if [ ! -x "$BUILD/tumble" ]; then
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-g > "$BUILD.configure.log" 2>&1
  cmake --build "$BUILD" --target tumble -j "$(nproc)" > "$BUILD.build.log" 2>&1
fi
TUMBLE="$BUILD/tumble" source jobs/lib/bench_common.sh
WORK=$(mktemp -d "${TMPDIR:-/tmp}/tumble_massif.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
WARM=${WARM_DIR:-$WORK/warm}
bench_header
echo "# jobs/bench/bst_R35_bench.toml, $WARMUP warm-up steps, $STEPS steps under massif, $BUILD/tumble"
if [ ! -f "$WARM/checkpoint.h5" ]; then
  "$BUILD/tumble" run jobs/bench/bst_R35_bench.toml --set scene.output_dir="$WARM" \
    --max-steps "$WARMUP" > "$WORK/warm.log" 2>&1
fi
cp -a "$WARM" "$WORK/run"
valgrind --tool=massif --threshold=0.01 --detailed-freq=1 --max-snapshots=400 \
  --massif-out-file="$WORK/massif.out" "$BUILD/tumble" run jobs/bench/bst_R35_bench.toml \
  --set scene.output_dir="$WORK/run" --resume --max-steps "$STEPS" > "$WORK/run.log" 2>&1
grep '^\[run\] memory' "$WORK/run.log"
particles=$(grep -o '[0-9]* particles' "$WORK/run.log" | head -1 | cut -d' ' -f1)
/usr/bin/python3 jobs/bench/massif_summary.py "$WORK/massif.out" "$particles"
