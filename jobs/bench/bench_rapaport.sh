#!/usr/bin/env bash
# Rotating-cylinder benchmark (Rapaport 2007): revolutions per hour of a Table I run on one core,
# against the paper's 23,000 steps/h = 3.7 revolutions/h at Omega = 0.2 for 47,000 particles
# (dual 3.6 GHz Xeon, 2006). Settles (or reuses) the run's bed, rotates WARMUP steps so the flow is
# established, then times STEPS steps; prints particle-steps/s, steps/h, revolutions/h and peak RSS.
#   jobs/bench/bench_rapaport.sh [RUN=L] [STEPS=3000] [WARMUP=6283]
# (#L: 47,300 particles, L = 160, D = 40, Omega = 0.2, the paper's "47,000"-particle class.)
set -euo pipefail
cd "$(dirname "$0")/../.."
run=${1:-L}
steps=${2:-3000}
warmup=${3:-6283}
tumble=${TUMBLE:-build/tumble}
[[ -x $tumble ]] || { echo "no executable at $tumble (build first, or set TUMBLE)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
pin=()
command -v taskset > /dev/null && pin=(taskset -c 0)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scene=scenes/rapaport/$run.toml
common=(--set "scene.output_dir=$out/run" --set fill.bed_cache=beds --set output.snapshot_interval=1e9
  --set output.analysis_interval=0 --set output.progress_interval=1e6)
echo "Rapaport 2007 run #$run on $(hostname), $(nproc) cores visible, pinned: ${pin[*]:-no}"
# Warm-up (settles the bed on first use, then rotates into steady flow; ends with a checkpoint).
"${pin[@]}" "$tumble" run "$scene" "${common[@]}" --set output.checkpoint_interval=1e9 \
  --max-steps "$warmup" > "$out/warmup.log"
grep -E "\[fill\] (settled|reusing)" "$out/warmup.log" || true
# Timed segment, continued from the warm-up's checkpoint.
/usr/bin/time -v "${pin[@]}" "$tumble" run "$scene" "${common[@]}" \
  --set output.checkpoint_interval=1e9 --resume --max-steps "$steps" > "$out/timed.log" 2> "$out/time.txt"
omega=$(awk -F' = ' '/^omega =/{print $2}' "$scene")
ps=$(sed -n 's/.*(\([0-9.e+]*\) particle-steps\/s).*/\1/p' "$out/timed.log" | tail -1)
n=$(sed -n 's/.*: \([0-9]*\) particles, dt.*/\1/p' "$out/timed.log" | head -1)
awk -v ps="$ps" -v n="$n" -v steps="$steps" -v omega="$omega" -v run="$run" 'BEGIN {
  sph = ps / n * 3600; rph = sph * 0.005 * omega / (2 * 3.141592653589793)
  printf "Tumble run=%s particles=%d steps=%d psteps_per_s=%.4g steps_per_hour=%.4g revolutions_per_hour=%.3g (paper: 23000 steps/h, 3.7 rev/h)\n", run, n, steps, ps, sph, rph
}'
awk '/Maximum resident/{printf "peak_rss_mb=%.1f\n", $6/1024}' "$out/time.txt"
