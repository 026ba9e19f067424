#!/usr/bin/env bash
# The rigid bulk's speed (`fidelity.bulk = "rigid"`, issue 20) as a benchmark: rigid against the
# dynamic engine of the same binary from the same state, in turns, and optionally against another
# binary's rigid bulk (OTHER=path/to/tumble: a change to the rigid path timed before it is
# trusted) and LIGGGHTS (if installed: the dynamic peer on the shared bed).
#
# usage: [NP=2] [OTHER=bin] [TUMBLE=build/tumble] [SCENE=... FROM=checkpoint SET="--set k=v ..."]
#        jobs/bench/bench_rigid.sh [STEPS=10000] [ROUNDS=4] [WARMUP=200000] [FREEZE=20000]
# By default the shared R35 bed (jobs/bench/bst_R35_bench.toml, 10,522 particles rotating about x
# at 3 rpm): its dynamic warm-up (WARMUP steps, shared with bench_ab.sh, kept in results/bench/),
# then FREEZE rigid steps from it (0.2 s: the bulk frozen after its 0.05 s dwell; kept too).
# SCENE with FROM (a rigid checkpoint of that scene) and SET (keys the checkpoint's run was given)
# time a bed of another size from its own state instead; a bed of 10^4 particles does not show a
# cost that grows with the particle count squared (docs/performance.md, "The rigid bulk in a
# benchmark"), bst_paper's flowing state does:
#   SCENE=scenes/bst_paper.toml FROM=results/rigid_phases/bst_paper/at_3.5/checkpoint.h5 \
#   SET="--set fill.bed_cache=beds --set protocol.repose=27 --set output.snapshot_interval=1e6
#   --set output.checkpoint_interval=1e6 --set output.analysis_interval=0.05" \
#   jobs/bench/bench_rigid.sh 2000 3
# (the checkpoint from jobs/accuracy/rigid_phases.sh).
# Each round runs, from the rigid state, STEPS steps rigid, dynamic (everything thawed at the
# restart: the dynamic engine's own flow of the same bed) and OTHER's rigid, the order rotating
# from round to round, on NP ranks (default 2: the decomposed path, where the rigid bulk's dormant
# springs travel between ranks; NP=1 on core 0 times the serial path). Prints each run's
# particle-steps/s and frozen share (its last progress line), then the medians (min-max) and
# the per-round ratios: on a shared machine the ratio within a round is the figure that counts.
set -euo pipefail
cd "$(dirname "$0")/../.."
STEPS=${1:-10000}
ROUNDS=${2:-4}
WARMUP=${3:-200000}
FREEZE=${4:-20000}
NP=${NP:-2}
for v in STEPS ROUNDS WARMUP FREEZE NP; do
  [[ ${!v} =~ ^[0-9]+$ ]] && [ "${!v}" -gt 0 ] ||
    { echo "bench_rigid.sh: $v must be a positive integer, got '${!v}'" >&2; exit 2; }
done
[ -z "${OTHER:-}" ] || [ -x "$OTHER" ] || { echo "bench_rigid.sh: OTHER=$OTHER is not executable" >&2; exit 2; }
source jobs/lib/bench_common.sh
SCENE=${SCENE:-jobs/bench/bst_R35_bench.toml}
[ -f "$SCENE" ] || { echo "bench_rigid.sh: no scene file $SCENE" >&2; exit 2; }
[ -z "${FROM:-}" ] || [ -f "$FROM" ] || { echo "bench_rigid.sh: FROM=$FROM: no such checkpoint" >&2; exit 2; }
read -r -a extra <<< "${SET:-}"
name=$(basename "$SCENE" .toml)
WARM=$(realpath -m "results/bench/${name}_warm$WARMUP")
FROZEN=$(realpath -m "results/bench/${name}_warm${WARMUP}_rigid$FREEZE")
make_work rigid
bench_header
echo "# $SCENE: $STEPS steps per run from ${FROM:-$WARMUP dynamic + $FREEZE rigid steps}," \
     "$ROUNDS rounds, $NP rank(s)${SET:+, $SET}${OTHER:+; OTHER = $OTHER ($("$OTHER" --version))}"
launch() {
  if [ "$NP" -gt 1 ]; then ${MPIRUN:-mpirun} --bind-to none -n "$NP" "$@"; else taskset -c 0 "$@"; fi
}
if [ -n "${FROM:-}" ]; then
  FROZEN_CKPT=$(realpath "$FROM")
else
  FROZEN_CKPT="$FROZEN/checkpoint.h5"
fi
if [ -z "${FROM:-}" ] && [ ! -f "$WARM/checkpoint.h5" ]; then
  echo "# making the warm state ($WARMUP dynamic steps, once)"
  taskset -c 0 "$BIN" run "$SCENE" "${extra[@]}" --max-steps "$WARMUP" --set scene.output_dir="$WARM" \
    > "$WORK/warm.log" 2>&1
fi
if [ -z "${FROM:-}" ] && [ ! -f "$FROZEN/checkpoint.h5" ]; then
  echo "# freezing the bulk ($FREEZE rigid steps, once)"
  launch "$BIN" run "$SCENE" "${extra[@]}" --restart "$WARM/checkpoint.h5" --max-steps "$FREEZE" \
    --set fidelity.bulk=rigid --set scene.output_dir="$FROZEN" > "$WORK/freeze.log" 2>&1
fi
once() {  # variant binary bulk log
  launch "$2" run "$SCENE" "${extra[@]}" --restart "$FROZEN_CKPT" --max-steps "$STEPS" \
    --set fidelity.bulk="$3" --set output.progress_interval=0.5 \
    --set scene.output_dir="$WORK/run_$1" > "$4" 2>&1 || { echo "# $1 failed:" >&2; tail -n 20 "$4" >&2; exit 1; }
}
variants=(rigid dynamic)
[ -n "${OTHER:-}" ] && variants+=(other)
# The peer, dynamic only (no DEM code users pick for tumblers has a rigid bulk), on the shared bed
# (its deck is that bed's), in the same rotation; its warm state is made once and kept.
peer=""
if [ "$SCENE" = jobs/bench/bst_R35_bench.toml ] && command -v liggghts > /dev/null; then
  peer=liggghts variants+=(liggghts)
  export LIGGGHTS_RESTART_DIR=results/bench/liggghts_warm LIGGGHTS_WARMUP=$WARMUP
  bash jobs/bench/liggghts/run.sh "$NP" 0 > "$WORK/liggghts_warm.log" 2>&1 ||
    { echo "# the LIGGGHTS warm-up failed:" >&2; tail -n 20 "$WORK/liggghts_warm.log" >&2; exit 1; }
fi
printf '| round |'; for v in "${variants[@]}"; do printf ' %s particle-steps/s (frozen) |' "$v"; done
echo " dynamic / rigid |${OTHER:+ other / rigid |}"
printf '|---|'; for _ in "${variants[@]}"; do printf -- '---|'; done; echo "---|${OTHER:+---|}"
for r in $(seq 1 "$ROUNDS"); do
  n=${#variants[@]}
  for k in $(seq 0 $((n - 1))); do  # the order rotates: each variant goes first in turn
    v=${variants[$(((k + r - 1) % n))]}
    case $v in
      rigid) once rigid "$BIN" rigid "$WORK/rigid_$r.log" ;;
      dynamic) once dynamic "$BIN" dynamic "$WORK/dynamic_$r.log" ;;
      other) once other "$OTHER" rigid "$WORK/other_$r.log" ;;
      liggghts)  # its last line: LIGGGHTS nprocs=P ... psteps_per_s=X ...
        bash jobs/bench/liggghts/run.sh "$NP" "$STEPS" 2>> "$WORK/liggghts.err" | tail -n 1 |
          sed -n 's/.*psteps_per_s=\([0-9.e+-]*\).*/(\1 particle-steps\/s/p' > "$WORK/liggghts_$r.log" ;;
    esac
  done
  line="| $r |" rates=""
  for v in "${variants[@]}"; do
    rt=$(rate "$WORK/${v}_$r.log")
    [ -n "$rt" ] || { echo "# $v gave no rate in round $r:" >&2; tail -n 20 "$WORK/${v}_$r.log" "$WORK/liggghts.err" 2>/dev/null >&2; exit 1; }
    fz=$(grep -o 'frozen [0-9.]*' "$WORK/${v}_$r.log" | tail -1 | cut -d' ' -f2 || true)
    line+=" $rt (${fz:--}) |" rates+="$rt "
  done
  echo "$rates" >> "$WORK/rates"
  read -r -a x <<< "$rates"
  line+=$(awk -v a="${x[0]}" -v b="${x[1]}" 'BEGIN { printf " %.3f |", a / b }')
  [ -n "${OTHER:-}" ] && line+=$(awk -v a="${x[0]}" -v c="${x[2]}" 'BEGIN { printf " %.3f |", a / c }')
  echo "$line"
done
/usr/bin/python3 - "$WORK/rates" "${variants[@]}" <<'PY'
import statistics, sys
names = sys.argv[2:]
rows = [list(map(float, line.split())) for line in open(sys.argv[1])]
def spread(v, f=".4g"):
    return f"{statistics.median(v):{f}} ({min(v):{f}}-{max(v):{f}})"
for k, name in enumerate(names):
    print(f"{name}: {spread([r[k] for r in rows])} particle-steps/s")
print(f"dynamic / rigid wall time per round (the rigid bulk's speed-up): "
      f"{spread([r[0] / r[1] for r in rows], '.3f')}")
if "other" in names:
    k = names.index("other")
    q = [r[0] / r[k] for r in rows]
    print(f"other / rigid wall time per round: {spread(q, '.3f')}, rigid faster in "
          f"{sum(x > 1 for x in q)} of {len(q)} rounds")
if "liggghts" in names:
    k = names.index("liggghts")
    print(f"Tumble dynamic / LIGGGHTS rate per round: {spread([r[1] / r[k] for r in rows], '.3f')}; "
          f"Tumble rigid / LIGGGHTS: {spread([r[0] / r[k] for r in rows], '.3f')}")
PY
if [ -z "$peer" ]; then
  if [ "$SCENE" != jobs/bench/bst_R35_bench.toml ]; then
    echo "(no peer run: LIGGGHTS' deck is set up for the shared R35 bed only)"
  else
    echo "(no peer run: LIGGGHTS is not installed; apt-get install liggghts)"
  fi
fi
