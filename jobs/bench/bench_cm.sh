#!/usr/bin/env bash
# Continuum-model benchmark (docs/cm.md "Speed"): wall time of the CM tools on one core.
# The issue's figure of merit is the 500-seed x 1000-period Poincare section.
#   TUMBLE=build/tumble jobs/bench/bench_cm.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
tumble=${TUMBLE:-build/tumble}
[[ -x $tumble ]] || { echo "no executable at $tumble (build first, or set TUMBLE)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
pin=()
command -v taskset > /dev/null && pin=(taskset -c 0)  # one core, as the figure is quoted
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

run() {  # label, then the cm subcommand and its options
  local label=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "${pin[@]}" "$tumble" cm "$@" -o "$out/$label.h5" > "$out/$label.log"
  t1=$(date +%s.%N)
  printf '%-44s %8.2f s\n' "$label" "$(echo "$t1 - $t0" | bc -l)"
}

echo "tumble cm benchmark on $(hostname), $(nproc) cores visible, pinned: ${pin[*]:-no}"
run poincare_57_57_500seeds_1000periods poincare --theta-z 57 --theta-x 57 --seeds 500 --periods 1000
run poincare_57_57_500seeds_100periods_integrated poincare --theta-z 57 --theta-x 57 --seeds 500 \
  --periods 100 --model integrated
run orbits_57_57_period6_kam orbits --theta-z 57 --theta-x 57
run manifolds_57_57_period3 manifolds --theta-z 57 --theta-x 57 --max-period 3 --max-points 100000
run mcm_57_57_2000tracers_45iterations mcm --theta-z 57 --theta-x 57 --c 1
