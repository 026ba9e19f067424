#!/usr/bin/env bash
# One whole (57°, 57°) iteration of SCENE rigid and dynamic, interleaved chunk by chunk, for the
# rigid bulk's speed-up per iteration (issue 20, docs/accuracy.md "Rigid bulk"). On a shared
# machine two runs hours apart cannot be compared (its load moves their rates by tens of per
# cent), so the two runs advance in turns, CHUNK steps at a time, each from its own last
# checkpoint (a restart continues bitwise): every chunk of one has a partner of the other over the
# same steps of the protocol, run minutes apart. The first chunk of each round alternates.
#
# Resumable: each variant's state is its checkpoint in OUT/<variant>, and every finished chunk is
# a line of OUT/chunks.tsv (variant, first step, steps, wall s of the stepping, the frozen share of
# the chunk's last progress line). A chunk cut short (the job killed) left no line and no
# checkpoint, and runs again whole.
# Rerun the same command to go on; REPORT=1 prints the table of what is done without running.
# To lend the cores to other work without spoiling a chunk's time: `touch OUT/pause`; the job
# waits after the chunk it is in until the file is removed.
# Each chunk's wall time is the run's own "[run] done" figure: its steps and its final checkpoint
# (one per chunk for every variant), not the start-up.
# OTHER=path/to/tumble adds a third run, "rigid_before": that binary's rigid bulk (a change to the
# rigid path measured over the same iteration; the order of the three rotates from round to round).
# usage: jobs/accuracy/rigid_iteration_ab.sh [SCENE=scenes/bst_paper.toml] [TIER=standard]
#                                            [CHUNK=20000] [NP=2] [ROUNDS=1000000]
# ROUNDS bounds the rounds run by this call (the job stops when every run reaches the iteration's
# end).
# START=N (default 0) measures from protocol step N on: one rigid run to step N first (not timed;
# ~18 min for bst_paper's z half, N = 600000, on 2 ranks here), whose checkpoint every variant
# then continues from (a rigid checkpoint restarts dynamic). The x half alone is so ~half the job;
# jobs/accuracy/rigid_iteration_table.py takes the segments not run from their twins.
# RIGID_SET="--set fidelity.bulk_calm_distance=0.02 ..." passes more keys to the rigid run (and
# the START run), not to rigid_before: OTHER=build/tumble with RIGID_SET times a setting against
# the defaults of the same binary. Split on blanks, not globbed. Give each setting its own OUT.
# BEFORE_SET="..." passes keys to rigid_before: one key against a setting that already has others
# (RIGID_SET="A B C" against BEFORE_SET="A B" times C alone, both runs otherwise the same).
# SEED=k runs bed k (fill.seed = k, its settled bed and β turn cached in beds/ as any run's)
# instead of the scene's own: a key measured per bed (fidelity.bulk_still_slope = "measured")
# gains what its bed's onset allows, so one bed's time is not every bed's.
# BETA=27 (default) pins the tilt by beta (protocol.repose) of every run; "measured" turns the bed
# once first (cached in beds/ as any run's: bst_paper ~34 min on 2 ranks here, not timed) and tilts
# by its own beta (bst_paper's 24.8 instead of 27: a shorter tilt, as the scene's own campaigns run).
# VARIANTS="rigid rigid_before" (with OTHER) leaves the dynamic run out: a setting against the
# defaults in a third of the time (the dynamic run is ~60% of a three-way job's wall time); its
# ratio to dynamic is then the defaults' one times this job's rigid_before / rigid, an estimate.
{  # read to the closing brace before running: an edit or a `git pull` while it runs (hours)
   # cannot change what it does next
set -euo pipefail
cd "$(dirname "$0")/../.."
SCENE=${1:-scenes/bst_paper.toml}
TIER=${2:-standard}
CHUNK=${3:-20000}
NP=${4:-2}
ROUNDS=${5:-1000000}
if [ -n "${SEED:-}" ] && ! [[ $SEED =~ ^[1-9][0-9]*$ ]]; then
  echo "SEED must be a whole number >= 1, not '$SEED'" >&2; exit 2
fi
source jobs/lib/bench_common.sh
OUT=$(realpath -m "${OUT:-results/rigid_iteration_ab/$(basename "$SCENE" .toml)_$TIER}")
mkdir -p "$OUT"
TSV="$OUT/chunks.tsv"
[ -f "$TSV" ] || printf 'variant\tfirst_step\tsteps\twall_s\tfrozen\tutc\n' > "$TSV"

report() {
  /usr/bin/python3 - "$TSV" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
by = {}
for r in rows:
    by.setdefault(r["variant"], {})[int(r["first_step"])] = r
done = {v: sum(int(r["steps"]) for r in c.values()) for v, c in by.items()}
wall = {v: sum(float(r["wall_s"]) for r in c.values()) for v, c in by.items()}
for v in sorted(by):
    print(f"# {v}: {len(by[v])} chunks, {done[v]} steps, {wall[v]:.0f} s of stepping")
for a, b in (("dynamic", "rigid"), ("dynamic", "rigid_before"), ("rigid_before", "rigid")):
    if a not in by or b not in by:
        continue
    common = sorted(set(by[a]) & set(by[b]))
    pairs = [(by[a][k], by[b][k]) for k in common if by[a][k]["steps"] == by[b][k]["steps"]]
    if not pairs:
        continue
    d = sum(float(x["wall_s"]) for x, _ in pairs)
    r = sum(float(y["wall_s"]) for _, y in pairs)
    ratios = sorted(float(x["wall_s"]) / float(y["wall_s"]) for x, y in pairs)
    q = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else ratios * 3
    steps = sum(int(x["steps"]) for x, _ in pairs)
    print(f"# {a} / {b}, {len(pairs)} paired chunks ({steps} steps): {d:.0f} s / {r:.0f} s"
          f" = {d / r:.2f} over their sum; per chunk median {statistics.median(ratios):.2f}"
          f" (quartiles {q[0]:.2f}-{q[2]:.2f}, range {ratios[0]:.2f}-{ratios[-1]:.2f})")
EOF
}
if [ -n "${REPORT:-}" ]; then report; exit 0; fi

bench_header | tee -a "$OUT/job.log"
echo "# $SCENE at $TIER, (57, 57), beta = ${BETA:-27} deg, one iteration," \
     "${VARIANTS:-rigid dynamic ${OTHER:+rigid_before}} in turns of" \
     "$CHUNK steps, $NP ranks${SEED:+, bed $SEED}${RIGID_SET:+; the rigid run with $RIGID_SET}" \
     "${BEFORE_SET:+; rigid_before with $BEFORE_SET}" |
  tee -a "$OUT/job.log"
read -ra rigid_set <<< "${RIGID_SET:-}"
read -ra before_set <<< "${BEFORE_SET:-}"
common=("$SCENE" --set fidelity.tier="$TIER" --set fill.bed_cache=beds --set protocol.repose="${BETA:-27}"
        --set protocol.iterations=1 --set output.analysis_interval=0.05
        --set output.snapshot_interval=1e6 --set output.checkpoint_interval=1e6
        --set output.checkpoint_wall=0 --set output.progress_interval=15)
[ -n "${SEED:-}" ] && common+=(--set fill.seed="$SEED")

# run_chunk VARIANT: CHUNK more steps of VARIANT; returns 1 when it has reached the end.
run_chunk() {
  local v=$1 dir="$OUT/$1" log first steps wall frozen bin=$BIN bulk=$1 extra=()
  [ "$v" = rigid_before ] && bin=$OTHER bulk=rigid extra=("${before_set[@]}")
  [ "$v" = rigid ] && extra=("${rigid_set[@]}")
  [ -f "$dir/finished" ] && return 1
  while [ -f "$OUT/pause" ]; do sleep 5; done
  log="$OUT/$v.last.log"
  ${MPIRUN:-mpirun} --bind-to none -n "$NP" "$bin" run "${common[@]}" --set fidelity.bulk="$bulk" \
    "${extra[@]}" --set scene.output_dir="$dir" --resume --max-steps "$CHUNK" > "$log" 2>&1 ||
    { echo "# $v: run failed, see $log" | tee -a "$OUT/job.log"; exit 1; }
  cat "$log" >> "$OUT/$v.log"
  # "[run] done: N steps in W s" and the first step from the restart line (0 on a fresh start).
  steps=$(sed -n 's/.*done: \([0-9]*\) steps in.*/\1/p' "$log" | tail -1)
  wall=$(sed -n 's/.*done: [0-9]* steps in \([0-9.e+]*\) s.*/\1/p' "$log" | tail -1)
  first=$(sed -n 's/.*restarting from .* (step \([0-9]*\).*/\1/p' "$log" | tail -1)
  frozen=$(grep -o 'frozen [0-9.]*' "$log" | tail -1 | cut -d' ' -f2 || true)
  [ -n "$steps" ] && [ -n "$wall" ] || { echo "# $v: no done line in $log" >&2; exit 1; }
  if [ "$steps" -gt 0 ]; then
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$v" "${first:-0}" "$steps" "$wall" "${frozen:--}" \
      "$(date -u +%H:%MZ)" >> "$TSV"
  fi
  if [ "$steps" -lt "$CHUNK" ]; then touch "$dir/finished"; return 1; fi
  return 0
}

read -ra variants <<< "${VARIANTS:-rigid dynamic ${OTHER:+rigid_before}}"
for v in "${variants[@]}"; do
  case $v in
    rigid | dynamic) ;;
    rigid_before) [ -n "${OTHER:-}" ] || { echo "VARIANTS: rigid_before needs OTHER=path/to/tumble" >&2; exit 2; } ;;
    *) echo "VARIANTS: unknown run '$v' (allowed: rigid, dynamic, rigid_before)" >&2; exit 2 ;;
  esac
done
START=${START:-0}
if [ "$START" -gt 0 ] && [ ! -f "$OUT/rigid/checkpoint.h5" ]; then
  echo "# START=$START: one rigid run to that step first (not timed)" | tee -a "$OUT/job.log"
  ${MPIRUN:-mpirun} --bind-to none -n "$NP" "$BIN" run "${common[@]}" --set fidelity.bulk=rigid \
    "${rigid_set[@]}" --set scene.output_dir="$OUT/rigid" --max-steps "$START" > "$OUT/start.log" 2>&1 ||
    { echo "# the run to step $START failed, see $OUT/start.log"; exit 1; }
  cp "$OUT/start.log" "$OUT/rigid.log"  # its first line gives the table script the iteration's steps
  for v in "${variants[@]}"; do
    [ "$v" = rigid ] && continue
    mkdir -p "$OUT/$v"
    cp "$OUT/rigid/checkpoint.h5" "$OUT/rigid/results.h5" "$OUT/$v/"
  done
fi
# Steps done by a variant (a run added later, or one that lost a chunk, first catches up: its
# chunks then have partners run minutes, not rounds, apart).
done_steps() { awk -F'\t' -v v="$1" '$1 == v { s += $3 } END { print s + 0 }' "$TSV"; }
for ((r = 1; r <= ROUNDS; r++)); do
  most=0
  for v in "${variants[@]}"; do most=$(( $(done_steps "$v") > most ? $(done_steps "$v") : most )); done
  for v in "${variants[@]}"; do
    while [ "$(done_steps "$v")" -lt "$most" ] && run_chunk "$v"; do :; done
  done
  more=0
  for ((k = 0; k < ${#variants[@]}; k++)); do  # the order rotates from round to round
    v=${variants[$(((k + r) % ${#variants[@]}))]}
    if run_chunk "$v"; then more=1; fi
  done
  report | grep '^# .* / ' | tee -a "$OUT/job.log"
  [ "$more" -eq 1 ] || break
done
report
exit
}
