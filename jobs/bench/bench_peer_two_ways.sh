#!/usr/bin/env bash
# Tumble against LIGGGHTS, set up two ways, in one job on one core: particle-steps per second and
# peak memory on the reference bed (jobs/bench/bst_R35_bench.toml: the settled 10,522-particle bed of
# jobs/bench/data in a 35 mm sphere turning at 3 rpm), with repeated, interleaved timed runs.
#
# usage: jobs/bench/bench_peer_two_ways.sh [STEPS=20000] [WARMUP=200000] [ROUNDS=3]
#
# Variants:
#   tumble_generic  $TUMBLE_BUILD/tumble (default build/; built with jobs/build.sh if missing)
#   tumble_plain    the generic binary with TUMBLE_PLAIN_KERNELS=1 (the plain pair loop and neighbour
#                   filter, the reference the lane kernels are checked against), if BENCH_PLAIN=1;
#                   it starts from tumble_generic's warmed state (the two loops agree bitwise)
#   tumble_native   $TUMBLE_NATIVE_BUILD/tumble, only if TUMBLE_NATIVE_BUILD is set
#   liggghts_a      LIGGGHTS, static STL sphere (facets within 0.05 mm) carrying the wall velocity
#                   (surface_ang_vel): LIGGGHTS_MESH_TOL=5e-5 LIGGGHTS_MOVEMESH=0
#   liggghts_b      LIGGGHTS, coarser STL sphere (facets within 0.085 mm) turned by fix move/mesh:
#                   LIGGGHTS_MESH_TOL=8.5e-5 LIGGGHTS_MOVEMESH=1
# LIGGGHTS is optional: without it (apt-get install liggghts) only Tumble is timed.
#
# Each variant first rotates the bed for WARMUP untimed steps, once: Tumble into an output
# directory whose checkpoint is copied afresh before every timed run (--resume), LIGGGHTS into a
# restart file (jobs/bench/liggghts/run.sh with LIGGGHTS_RESTART_DIR). Then ROUNDS rounds time STEPS
# steps of every variant in a fixed interleaved order (A B C D A B C D ...), every run a fresh
# process started from the same warmed state and pinned to one core (taskset). The summary gives
# per variant the median, min and max particle-steps/s and the peak RSS, and the ratios
# Tumble generic / LIGGGHTS (a) and (b) as the median (min-max) of the per-round ratios.
#
# environment (all optional):
#   TUMBLE_BUILD          build directory of the generic binary (default build)
#   TUMBLE_NATIVE_BUILD   build directory of a -DTUMBLE_NATIVE=ON binary (default: not timed)
#   BENCH_PLAIN           1: also time the plain loops (tumble_plain)
#   BENCH_CORE            the core every run is pinned to (default 0)
#   BENCH_WORKDIR         scratch directory, kept (default: a mktemp directory removed at exit)
#   LIGGGHTS_RESTART_DIR  where LIGGGHTS' warmed states are kept (default: in the scratch directory);
#                         a state made earlier with the same warm-up length, mesh and motion (and
#                         an unchanged deck, bed, STL and LIGGGHTS) is used without warming again
#   LIGGGHTS_BIN          LIGGGHTS executable (default: liggghts in PATH)
set -euo pipefail

usage() {
  echo "usage: $0 [STEPS=20000] [WARMUP=200000] [ROUNDS=3]" >&2
  echo "  times Tumble (generic, and native if TUMBLE_NATIVE_BUILD is set) and LIGGGHTS two ways;" >&2
  echo "  other settings by environment variables: see the header of this script" >&2
  exit 2
}
[ $# -le 3 ] || usage
case "${1:-}${2:-}${3:-}" in *[!0-9]*) usage ;; esac
STEPS=${1:-20000}
WARMUP=${2:-200000}
ROUNDS=${3:-3}
if [ "$STEPS" -lt 1 ] || [ "$ROUNDS" -lt 1 ]; then usage; fi
COMMAND="$0 $*"

cd "$(dirname "$0")/../.."
CORE=${BENCH_CORE:-0}
BUILD=${TUMBLE_BUILD:-build}
[ -x "$BUILD/tumble" ] || TUMBLE_BUILD=$BUILD bash jobs/build.sh > /dev/null
if [ -n "${TUMBLE_NATIVE_BUILD:-}" ] && [ ! -x "$TUMBLE_NATIVE_BUILD/tumble" ]; then
  echo "TUMBLE_NATIVE_BUILD=$TUMBLE_NATIVE_BUILD has no tumble binary" >&2
  exit 1
fi
command -v taskset > /dev/null || { echo "needs taskset (util-linux)" >&2; exit 1; }
HAVE_TIME=0
[ -x /usr/bin/time ] && HAVE_TIME=1
LIGGGHTS=${LIGGGHTS_BIN:-$(command -v liggghts || true)}
if [ -n "${LIGGGHTS_BIN:-}" ] && [ ! -x "$LIGGGHTS_BIN" ]; then
  echo "LIGGGHTS_BIN=$LIGGGHTS_BIN is not an executable" >&2
  exit 1
fi
if [ "$(id -u)" = 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi

if [ -n "${BENCH_WORKDIR:-}" ]; then
  WORK=$(mkdir -p "$BENCH_WORKDIR" && cd "$BENCH_WORKDIR" && pwd)
else
  WORK=$(mktemp -d "${TMPDIR:-/tmp}/tumble_peer.XXXXXX")
  trap 'rm -rf "$WORK"' EXIT
fi
RESTART_DIR=${LIGGGHTS_RESTART_DIR:-$WORK/liggghts_restart}
RUNS="$WORK/runs.tsv"
printf 'round\tvariant\tpsteps_per_s\twall_s\tpeak_rss_mb\n' > "$RUNS"

# ---- header: where, when, what --------------------------------------------------------------
echo "# machine: $(lscpu | awk -F: '/Model name/ {gsub(/^ +/, "", $2); print $2; exit}'), nproc $(nproc)," \
     "load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
echo "# git: $(git describe --always --dirty --abbrev=12 2>/dev/null || echo unknown)"
echo "# command: $COMMAND (TUMBLE_BUILD=$BUILD TUMBLE_NATIVE_BUILD=${TUMBLE_NATIVE_BUILD:-})"
echo "# $STEPS timed steps after $WARMUP warm-up steps, $ROUNDS rounds, every run pinned to core $CORE"
VARIANTS=(tumble_generic)
[ "${BENCH_PLAIN:-0}" = 1 ] && VARIANTS+=(tumble_plain)
[ -n "${TUMBLE_NATIVE_BUILD:-}" ] && VARIANTS+=(tumble_native)
if [ -n "$LIGGGHTS" ]; then
  VARIANTS+=(liggghts_a liggghts_b)
  echo "# LIGGGHTS: $("$LIGGGHTS" -log none -h < /dev/null 2>&1 | head -n 1) ($LIGGGHTS)"
  echo "#   liggghts_a: static mesh, facets within 0.05 mm, surface_ang_vel;" \
       "liggghts_b: mesh within 0.085 mm turned by move/mesh"
else
  echo "# LIGGGHTS not found (apt-get install liggghts, or set LIGGGHTS_BIN): timing Tumble only"
fi
echo "# variants in run order: ${VARIANTS[*]}"

tumble_bin() {  # $1 = variant
  case $1 in
    tumble_generic | tumble_plain) echo "$BUILD/tumble" ;;
    tumble_native) echo "$TUMBLE_NATIVE_BUILD/tumble" ;;
  esac
}
# run on the benchmark core; LIGGGHTS' mpirun must not re-bind its rank
pinned() { taskset -c "$CORE" "$@"; }
export LIGGGHTS_MPIRUN_ARGS="--bind-to none ${LIGGGHTS_MPIRUN_ARGS:-}"
liggghts_run() {  # $1 = variant, $2 = timed steps (0: warm up only), $3 = log
  local tol mm
  case $1 in
    liggghts_a) tol=5e-5 mm=0 ;;
    liggghts_b) tol=8.5e-5 mm=1 ;;
  esac
  LIGGGHTS_MESH_TOL=$tol LIGGGHTS_MOVEMESH=$mm LIGGGHTS_BIN=$LIGGGHTS LIGGGHTS_WARMUP=$WARMUP \
    LIGGGHTS_RESTART_DIR=$RESTART_DIR LIGGGHTS_WORKDIR="$WORK/work_$1" \
    pinned bash jobs/bench/liggghts/run.sh 1 "$2" > "$3" 2>&1
}

# ---- warm-up: once per variant -----------------------------------------------------------------
warm() {  # $1 = variant
  local v=$1 t0 t1
  t0=$(date +%s)
  case $v in
    tumble_plain)  # the plain loops give tumble_generic's warm state bitwise
      rm -rf "$WORK/warm_$v"
      cp -a "$WORK/warm_tumble_generic" "$WORK/warm_$v"
      echo "warm-up $v: tumble_generic's state"
      return
      ;;
    tumble_*)
      rm -rf "$WORK/warm_$v"
      pinned "$(tumble_bin "$v")" run jobs/bench/bst_R35_bench.toml --set scene.output_dir="$WORK/warm_$v" \
        --max-steps "$WARMUP" > "$WORK/warm_$v.log" 2>&1 \
        || { echo "warm-up of $v failed, see $WORK/warm_$v.log" >&2; tail -n 5 "$WORK/warm_$v.log" >&2; exit 1; }
      [ -s "$WORK/warm_$v/checkpoint.h5" ] || { echo "warm-up of $v left no checkpoint" >&2; exit 1; }
      ;;
    liggghts_*)
      liggghts_run "$v" 0 "$WORK/warm_$v.log" \
        || { echo "warm-up of $v failed, see $WORK/warm_$v.log" >&2; tail -n 5 "$WORK/warm_$v.log" >&2; exit 1; }
      ;;
  esac
  t1=$(date +%s)
  if grep -q 'warmed state found' "$WORK/warm_$v.log" 2>/dev/null; then
    echo "warm-up $v: reused $(awk '/^LIGGGHTS warm state:/ {print $4}' "$WORK/warm_$v.log")"
  else
    echo "warm-up $v: $WARMUP steps, $((t1 - t0)) s"
  fi
}

# ---- one timed run: prints "round variant psteps wall rss" into RUNS and a line on stdout ------
timed() {  # $1 = round, $2 = variant
  local r=$1 v=$2 out log rate wall rss
  case $v in
    tumble_*)
      out="$WORK/run_$v"
      log="$WORK/run_$v.log"
      rm -rf "$out"
      cp -a "$WORK/warm_$v" "$out"
      local TIMER=()
      [ "$HAVE_TIME" = 1 ] && TIMER=(/usr/bin/time -v -o "$WORK/time_$v")
      rm -f "$WORK/time_$v"
      local plain=0
      [ "$v" = tumble_plain ] && plain=1
      TUMBLE_PLAIN_KERNELS=$plain pinned "${TIMER[@]}" "$(tumble_bin "$v")" run jobs/bench/bst_R35_bench.toml \
        --set scene.output_dir="$out" --resume --max-steps "$STEPS" > "$log" 2>&1 \
        || { echo "timed run of $v failed, see $log" >&2; tail -n 5 "$log" >&2; exit 1; }
      grep -q '^\[run\] restarting from' "$log" || { echo "$v did not resume from the warm state" >&2; exit 1; }
      # "[run] done: S steps in T s (R particle-steps/s); results in ..."
      read -r wall rate < <(awk '/\[run\] done:/ {for (i = 1; i <= NF; ++i) {
          if ($i == "in" && w == "") w = $(i+1); if ($i ~ /particle-steps/) p = substr($(i-1), 2)}}
          END {print w, p}' "$log")
      rss=NA
      [ -s "$WORK/time_$v" ] && rss=$(awk -F': ' '/Maximum resident/ {printf "%.1f", $2 / 1024}' "$WORK/time_$v")
      ;;
    liggghts_*)
      log="$WORK/run_$v.log"
      liggghts_run "$v" "$STEPS" "$log" \
        || { echo "timed run of $v failed, see $log" >&2; tail -n 5 "$log" >&2; exit 1; }
      grep -q 'from the saved state' "$log" || { echo "$v did not start from the warm state" >&2; exit 1; }
      read -r wall rate rss < <(awk '/^LIGGGHTS nprocs=/ {for (i = 1; i <= NF; ++i) {split($i, a, "=");
          if (a[1] == "wall_s") w = a[2]; if (a[1] == "psteps_per_s") p = a[2]; if (a[1] == "peak_rss_mb") m = a[2]}}
          END {print w, p, m}' "$log")
      ;;
  esac
  [ -n "$rate" ] || { echo "no rate found in $log" >&2; exit 1; }
  printf '%s\t%s\t%s\t%s\t%s\n' "$r" "$v" "$rate" "$wall" "$rss" >> "$RUNS"
  printf 'round %d  %-15s %10.4g particle-steps/s  %8.2f s  peak RSS %s MB\n' "$r" "$v" "$rate" "$wall" "$rss"
}

T_START=$(date +%s)
for v in "${VARIANTS[@]}"; do warm "$v"; done
for ((r = 1; r <= ROUNDS; ++r)); do
  for v in "${VARIANTS[@]}"; do timed "$r" "$v"; done
done
echo "# load average at the end $(cut -d' ' -f1-3 /proc/loadavg); job took $(( $(date +%s) - T_START )) s"

# ---- summary ---------------------------------------------------------------------------------
python3 - "$RUNS" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
variants = list(dict.fromkeys(r["variant"] for r in rows))
rate = {(r["round"], r["variant"]): float(r["psteps_per_s"]) for r in rows}
print("\nsummary: particle-steps/s over rounds (median, min, max); peak RSS (MB, largest over runs)")
for v in variants:
    x = [float(r["psteps_per_s"]) for r in rows if r["variant"] == v]
    m = [float(r["peak_rss_mb"]) for r in rows if r["variant"] == v and r["peak_rss_mb"] != "NA"]
    rss = f"{max(m):.1f}" if m else "NA"
    print(f"  {v:15s} n={len(x)}  median {statistics.median(x):.4g}  min {min(x):.4g}  max {max(x):.4g}"
          f"  peak RSS {rss}")
rounds = list(dict.fromkeys(r["round"] for r in rows))
pairs = [(num, den) for num in ("tumble_generic", "tumble_native")
         for den in ("liggghts_a", "liggghts_b")]
pairs += [("tumble_generic", "tumble_plain"), ("tumble_native", "tumble_generic")]
for num, den in pairs:
    q = [rate[k, num] / rate[k, den] for k in rounds if (k, num) in rate and (k, den) in rate]
    if q:
        print(f"ratio {num} / {den}: median {statistics.median(q):.3f}  (min {min(q):.3f}, max {max(q):.3f},"
              f" {len(q)} rounds)")
PY
