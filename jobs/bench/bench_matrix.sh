#!/usr/bin/env bash
# Several tumble binaries (e.g. before and after, generic and native builds) on the Yu scene (the
# shared R35 bed) and the Rapaport cylinder (run #E), on 1 rank and on NP ranks, all in one job:
# each round runs every (scene, ranks, binary) once, the binaries of one scene and rank count
# one after the other, so that each comparison is made within minutes on the same machine.
# Prints every run's particle-steps/s, then per scene and rank count each binary's median
# (min-max), its ratio to the first binary per round, and its parallel efficiency per round
# (rate at NP / (NP x rate at 1 in the same round)).
# usage: [ROUNDS=5] [NP=2] [YU_STEPS=10000] [CYL_STEPS=3000] jobs/bench/bench_matrix.sh \
#            LABEL=BIN LABEL=BIN ...
# Each binary starts from a warm state of its own build (its checkpoints are the ones it reads),
# made once pinned to core 0 and kept in results/bench/warm_<version>_<scene>_<steps>: the R35
# bed after 200,000 steps (flowing), #E after one revolution (6,283 steps).
set -euo pipefail
cd "$(dirname "$0")/../.."
[ $# -ge 1 ] || { echo "usage: bench_matrix.sh LABEL=BIN [LABEL=BIN ...]" >&2; exit 1; }
TUMBLE=${1#*=} source jobs/lib/bench_common.sh
ROUNDS=${ROUNDS:-5}
NP=${NP:-2}
YU_STEPS=${YU_STEPS:-10000}
CYL_STEPS=${CYL_STEPS:-3000}
labels=() bins=()
for arg in "$@"; do
  labels+=("${arg%%=*}")
  bins+=("${arg#*=}")
  [ -x "${arg#*=}" ] || { echo "no executable at ${arg#*=}" >&2; exit 1; }
done
scenes=(jobs/bench/bst_R35_bench.toml scenes/rapaport/E.toml)
names=(yu cylinder)
warmups=(200000 6283)
steps=("$YU_STEPS" "$CYL_STEPS")
make_work matrix
bench_header
for k in "${!bins[@]}"; do echo "# ${labels[$k]} = ${bins[$k]} ($("${bins[$k]}" --version))"; done
echo "# Yu: R35 bed, $YU_STEPS steps a run; cylinder: Rapaport #E, $CYL_STEPS steps a run;" \
     "1 rank on core 0, $NP ranks with mpiexec --bind-to core; $ROUNDS rounds"

warm_dir() {  # binary scene-index
  local v
  v=$("$1" --version | sed 's/.*(\(.*\))/\1/')
  # (a build outside a git checkout has no commit: its checksum tells it apart)
  [ "$v" = unknown ] && v="unknown_$(md5sum "$1" | cut -c1-8)"
  echo "results/bench/warm_${v}_${names[$2]}_${warmups[$2]}"
}
for k in "${!bins[@]}"; do
  for s in 0 1; do
    w=$(warm_dir "${bins[$k]}" "$s")
    [ -f "$w/checkpoint.h5" ] && continue
    echo "# warming ${labels[$k]} on ${names[$s]} ($w)"
    taskset -c 0 "${bins[$k]}" run "${scenes[$s]}" --max-steps "${warmups[$s]}" \
      --set scene.output_dir="$w" > "$WORK/warm.log" 2>&1 ||
      { echo "warm-up failed: $(tail -3 "$WORK/warm.log")" >&2; exit 1; }
  done
done

echo "| round | scene | ranks | binary | particle-steps/s |"
echo "|---|---|---|---|---|"
for r in $(seq 1 "$ROUNDS"); do
  for s in 0 1; do
    for n in 1 "$NP"; do
      for k in "${!bins[@]}"; do
        launch=(taskset -c 0)
        [ "$n" -gt 1 ] && launch=(mpiexec --bind-to core -n "$n")
        log="$WORK/run.log"
        "${launch[@]}" "${bins[$k]}" run "${scenes[$s]}" \
          --restart "$(warm_dir "${bins[$k]}" "$s")/checkpoint.h5" --max-steps "${steps[$s]}" \
          --set scene.output_dir="$WORK/run" --set output.snapshot_interval=1e6 > "$log" 2>&1 ||
          { echo "run failed: $(tail -3 "$log")" >&2; exit 1; }
        x=$(rate "$log")
        echo "| $r | ${names[$s]} | $n | ${labels[$k]} | $x |"
        echo "$r ${names[$s]} $n ${labels[$k]} $x" >> "$WORK/rates"
      done
    done
  done
done

/usr/bin/python3 - "$WORK/rates" "$NP" "${labels[@]}" <<'PY'
import collections, statistics, sys
rates, np_, labels = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
rate = {}
for line in open(rates):
    r, scene, n, label, x = line.split()
    rate[(int(r), scene, int(n), label)] = float(x)
rounds = sorted({k[0] for k in rate})
def spread(v, f=".3g"):
    return f"{statistics.median(v):{f}} ({min(v):{f}}-{max(v):{f}})"
print(f"\n| scene | ranks | binary | particle-steps/s, median (min-max) | / {labels[0]} per round "
      f"| efficiency per round |")
print("|---|---|---|---|---|---|")
for scene in ("yu", "cylinder"):
    for n in (1, np_):
        for label in labels:
            v = [rate[(r, scene, n, label)] for r in rounds]
            q = [rate[(r, scene, n, label)] / rate[(r, scene, n, labels[0])] for r in rounds]
            e = ([100 * rate[(r, scene, n, label)] / (n * rate[(r, scene, 1, label)]) for r in rounds]
                 if n > 1 else [])
            faster = sum(x > 1 for x in q)
            ratio = "" if label == labels[0] else f"{spread(q, '.3f')}, {faster} of {len(q)} faster"
            eff = f"{spread(e, '.1f')}%" if e else ""
            print(f"| {scene} | {n} | {label} | {spread(v)} | {ratio} | {eff} |")
PY
