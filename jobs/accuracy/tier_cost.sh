#!/usr/bin/env bash
# Cost of each fidelity tier (docs/accuracy.md): the scene at every tier, its particles, time step
# and steps per protocol iteration, and the measured wall time per iteration on one core (STEPS
# timed steps of the rotating bed, after WARMUP untimed ones, extrapolated to a whole iteration),
# plus the continuum model's Poincaré section of the same protocol.
# usage: jobs/accuracy/tier_cost.sh [SCENE=scenes/bst_paper.toml] [STEPS=1000]
# BULKS="dynamic rigid" adds the rigid bulk (fidelity.bulk, issue 20): a second table, per tier,
# of one whole (57°, 57°) iteration dynamic and rigid, interleaved (jobs/accuracy/rigid_cost.sh,
# REPEATS pairs, default 1), their ratio and the rigid run's mean frozen share. A window of 1,000
# steps cannot stand for an iteration there: the share frozen changes along it (none in the first
# dwell, ~0.7 in the tilts, less in the flow, a thaw at each segment change). Tiers whose dynamic
# iteration the first table puts above FULL_MAX wall s (default 1800) are not timed; their line
# gives the resumable command that times one in chunks (jobs/accuracy/rigid_iteration_ab.sh).
# The reference tier starts from the standard tier's settled bed (fill.bed_file): settling 89k
# particles at t_c/100 costs hours, and the cost per step does not depend on which settled bed.
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_paper.toml}
STEPS=${2:-1000}
WARMUP=${WARMUP:-500}
source jobs/lib/bench_common.sh
make_work tiers
pin=()
command -v taskset > /dev/null && pin=(taskset -c 0)
bench_header
echo "# $SCENE: $STEPS timed steps per tier after $WARMUP warm-up steps, one core (${pin[*]:-unpinned})"
echo "| tier | particles | R/d_large | t_c (s) | δt (s) | skin (d_s) | rpm | Froude | iterations | steps/iteration | particle-steps/s | wall per iteration | wall for the tier's run |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
key() { sed -n "s/^$1 = //p" "$2" | head -1; }
: > "$WORK/per_iteration"
for tier in reference standard fast preview; do
  extra=()
  if [ "$tier" = reference ]; then  # the standard bed (see above)
    "$BIN" run "$SCENE" --set fill.bed_cache=beds --max-steps 0 --set protocol.repose=27 \
      --set scene.output_dir="$WORK/bedprobe" > "$WORK/probe.log"
    # (the path ends at .h5: a reused bed's line goes on with the ranks it settled on)
    bed=$(sed -n 's/.*\(reusing settled bed\|saved settled bed to\) \(.*\.h5\).*$/\2/p' "$WORK/probe.log" | tail -1)
    extra=(--set fill.bed_file="$bed")
  fi
  # β pinned at 27°: a "measured" tilt adds 80° of rotation once per bed (about a third of a
  # (57°, 57°) iteration) before the run, which these timings leave out.
  common=("$SCENE" --set fidelity.tier=$tier --set fill.bed_cache=beds "${extra[@]}"
          --set protocol.repose=27
          --set output.analysis_interval=0 --set output.snapshot_interval=1e6
          --set output.checkpoint_interval=1e6 --set scene.output_dir="$WORK/$tier")
  "$BIN" run "${common[@]}" --check > "$WORK/$tier.scene"
  "${pin[@]}" "$BIN" run "${common[@]}" --max-steps "$WARMUP" > "$WORK/$tier.warm"
  "${pin[@]}" "$BIN" run "${common[@]}" --resume --max-steps "$STEPS" > "$WORK/$tier.log"
  rate=$(sed -n 's/.*(\([0-9.e+]*\) particle-steps\/s.*/\1/p' "$WORK/$tier.log" | tail -1)
  n=$(sed -n 's/.*: \([0-9]*\) particles, dt.*/\1/p' "$WORK/$tier.log" | tail -1)
  total=$(sed -n 's/.* dt = [0-9.e+-]* s, \([0-9]*\) steps.*/\1/p' "$WORK/$tier.log" | tail -1)
  awk -v t=$tier -v n="$n" -v rate="$rate" -v total="$total" -v out="$WORK/per_iteration" \
      -v R="$(key tumbler.radius "$WORK/$tier.scene")" -v dl="$(key particles.d_large "$WORK/$tier.scene")" \
      -v tc="$(key contact.collision_time "$WORK/$tier.scene")" -v fr="$(key time.dt_fraction "$WORK/$tier.scene")" \
      -v skin="$(key neighbor.skin "$WORK/$tier.scene")" -v rpm="$(key protocol.rpm "$WORK/$tier.scene")" \
      -v it="$(key protocol.iterations "$WORK/$tier.scene")" -v g="$(key gravity.g "$WORK/$tier.scene")" 'BEGIN {
    w = 2 * 3.141592653589793 * rpm / 60; spi = total / it; wpi = spi * n / rate
    printf "| %s | %d | %.3g | %.3g | %.3g | %.2g | %.3g | %.2g | %g | %.0f | %.3g | %.0f s = %.2f h | %.1f h |\n",
           t, n, R / dl, tc, tc * fr, skin, rpm, w * w * R / g, it, spi, rate, wpi, wpi / 3600, wpi * it / 3600
    printf "%s %.0f\n", t, wpi >> out  # for the rigid table below
  }'
done
# The continuum model: its default Poincaré section (500 seeds, 1000 periods) of the same protocol.
tz=$(key protocol.theta_z "$WORK/standard.scene")
tx=$(key protocol.theta_x "$WORK/standard.scene")
start=$(date +%s.%N)
"$BIN" cm poincare --theta-z "$tz" --theta-x "$tx" --output "$WORK/cm.h5" > "$WORK/cm.log" 2>&1 || true
end=$(date +%s.%N)
awk -v a="$start" -v b="$end" -v tz="$tz" -v tx="$tx" 'BEGIN {
  printf "| cm (continuum model) | - | - | - | - | - | - | - | - | - | - | Poincaré section (%s°, %s°): %.1f s | |\n", tz, tx, b - a }'
case " ${BULKS:-dynamic} " in
  *" rigid "*)
    echo
    echo "# fidelity.bulk rigid against dynamic: one whole iteration each, interleaved, ${REPEATS:-1}" \
         "pair(s), one process each (jobs/accuracy/rigid_cost.sh; medians over the pairs)"
    echo "| tier | dynamic wall s per iteration | rigid wall s per iteration | dynamic / rigid | rigid's mean frozen share |"
    echo "|---|---|---|---|---|"
    while read -r tier wpi; do
      if [ "$wpi" -gt "${FULL_MAX:-1800}" ]; then
        echo "| $tier | not timed (~$wpi s by the table above; FULL_MAX=${FULL_MAX:-1800}) | | |" \
             "\`jobs/accuracy/rigid_iteration_ab.sh $SCENE $tier 20000 NP\` (resumable) |"
        continue
      fi
      TUMBLE=$BIN bash jobs/accuracy/rigid_cost.sh "$SCENE" "$tier" "${REPEATS:-1}" > "$WORK/$tier.rigid"
      awk -v t="$tier" -F'|' '
        / median wall s per iteration, dynamic:/ { split($0, a, ": "); d = a[2] }
        / median wall s per iteration, rigid:/ { split($0, a, ": "); r = a[2] }
        $3 ~ / rigid / { f += $8; n++ }
        END { printf "| %s | %.1f | %.1f | %.2f | %.2f |\n", t, d, r, d / r, n ? f / n : 0 }' \
        "$WORK/$tier.rigid"
    done < "$WORK/per_iteration"
    ;;
esac
