#!/usr/bin/env bash
# What the per-scene specialisations gain (issue 8, "only what a scene needs"): the same run with
# the specialised kernels and with the general ones (TUMBLE_GENERAL_KERNELS=1), alternated REPEATS
# times from the same warmed-up state, one core. Specialisations measured:
#   one_species   a monodisperse bed (bst_small with f = 0): no species-pair table lookups
#   frictionless  the shared 10,522-particle bed with mu = mu_w = 0: no tangential history (always
#                 compiled out) and no rotation update in the integrator
# usage: jobs/bench/bench_specialisations.sh [STEPS=5000] [REPEATS=3] [one_species,frictionless]
set -euo pipefail
cd "$(dirname "$0")/../.."
STEPS=${1:-5000}
REPEATS=${2:-3}
source jobs/lib/bench_common.sh
make_work spec
pin=()
command -v taskset > /dev/null && pin=(taskset -c 0)
bench_header
echo "# $STEPS steps per timed run, $REPEATS runs per path, pinned: ${pin[*]:-no}"


bench() {  # label, scene, overrides...
  local label=$1 scene=$2
  shift 2
  local args=("$scene" --set scene.output_dir="$WORK/$label" --set fill.bed_cache=beds "$@")
  "${pin[@]}" "$BIN" run "${args[@]}" --max-steps 2000 > "$WORK/warm_$label.log"
  local spec=() gen=()
  for ((k = 0; k < REPEATS; ++k)); do
    "${pin[@]}" "$BIN" run "${args[@]}" --resume --max-steps "$STEPS" > "$WORK/s.log"
    spec+=("$(rate "$WORK/s.log")")
    TUMBLE_GENERAL_KERNELS=1 "${pin[@]}" "$BIN" run "${args[@]}" --resume --max-steps "$STEPS" \
      > "$WORK/g.log"
    gen+=("$(rate "$WORK/g.log")")
  done
  printf '%s\n' "${spec[@]}" | sort -g > "$WORK/s.txt"
  printf '%s\n' "${gen[@]}" | sort -g > "$WORK/g.txt"
  local ms mg
  ms=$(awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}' "$WORK/s.txt")
  mg=$(awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}' "$WORK/g.txt")
  awk -v l="$label" -v s="$ms" -v g="$mg" -v ss="${spec[*]}" -v gg="${gen[*]}" 'BEGIN {
    printf "%-13s specialised %.4g  general %.4g particle-steps/s (medians; runs: %s | %s)  gain %+.1f%%\n",
           l, s, g, ss, gg, 100 * (s / g - 1) }'
}

want=${3:-one_species,frictionless}
if [[ ,$want, == *,one_species,* ]]; then
  bench one_species scenes/bst_small.toml --set particles.large_fraction=0 \
    --set protocol.mode=single_axis --set protocol.axis=x --set protocol.duration=1000 \
    --set output.analysis_interval=0
fi
if [[ ,$want, == *,frictionless,* ]]; then
  bench frictionless jobs/bench/bst_R35_bench.toml --set contact.friction=0 \
    --set contact.wall_friction=0 --set output.analysis_interval=0
fi
