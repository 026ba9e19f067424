#!/usr/bin/env bash
# LIGGGHTS 3.8 peer benchmark: settled bed (bst_R35) in a spherical tumbler
# rotating at 3 rpm about x. See README.md in this folder.
#
# usage: run.sh NPROCS STEPS
#   runs an untimed warm-up, then STEPS timed steps on NPROCS MPI ranks
#   (processor grid NPROCS x 1 x 1, i.e. slabs along the rotation axis) and
#   prints as its last line:
#   LIGGGHTS nprocs=P particles=N steps=S wall_s=T psteps_per_s=X peak_rss_mb=M
#
# environment (all optional):
#   LIGGGHTS_WORKDIR    scratch dir (kept); default: a mktemp dir, removed at exit
#   LIGGGHTS_BIN        LIGGGHTS executable (default: liggghts in PATH)
#   LIGGGHTS_BED        settled bed (default jobs/bench/data/bst_R35_settled.txt, in the repository)
#   LIGGGHTS_WARMUP     untimed warm-up steps (default 1000)
#   LIGGGHTS_MESH_TOL   max facet deviation from the sphere [m] (default 5e-5)
#   LIGGGHTS_MOVEMESH   0 = static mesh + surface_ang_vel (default), 1 = move/mesh rotate
#   LIGGGHTS_DUMP_EVERY dump particles every N steps into WORKDIR/dump.tumbler (default 0 = off)
#   LIGGGHTS_THERMO     thermo interval (default 1000)
#   LIGGGHTS_MPIRUN_ARGS extra mpirun arguments
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: $0 NPROCS STEPS" >&2
  exit 2
fi
NP=$1
STEPS=$2
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

BIN=${LIGGGHTS_BIN:-$(command -v liggghts || echo /usr/bin/liggghts)}
BED=${LIGGGHTS_BED:-$HERE/../data/bst_R35_settled.txt}
WARMUP=${LIGGGHTS_WARMUP:-1000}
MESH_TOL=${LIGGGHTS_MESH_TOL:-5e-5}
MOVEMESH=${LIGGGHTS_MOVEMESH:-0}
DUMP_EVERY=${LIGGGHTS_DUMP_EVERY:-0}
THERMO=${LIGGGHTS_THERMO:-1000}
OMEGA=0.3141592653589793   # 3 rpm = 2*pi/20 rad/s

# scratch directory
if [ -n "${LIGGGHTS_WORKDIR:-}" ]; then
  W=$(mkdir -p "$LIGGGHTS_WORKDIR" && cd "$LIGGGHTS_WORKDIR" && pwd)
else
  W=$(mktemp -d "${TMPDIR:-/tmp}/liggghts_bench.XXXXXX")
  trap 'rm -rf "$W"' EXIT
fi

# inputs: data file and sphere mesh (regenerated only when missing or stale)
DATA="$W/bed.data"
STL="$W/sphere_tol${MESH_TOL}.stl"
if [ ! -s "$DATA" ] || [ "$BED" -nt "$DATA" ] || [ "$HERE/make_data.py" -nt "$DATA" ]; then
  python3 "$HERE/make_data.py" "$BED" "$DATA" >&2
fi
if [ ! -s "$STL" ] || [ "$HERE/make_sphere_stl.py" -nt "$STL" ]; then
  python3 "$HERE/make_sphere_stl.py" "$STL" --radius 0.035 --tol "$MESH_TOL" >&2
fi

# MPI launch options
if [ "$(id -u)" = 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
MPIARGS=(-n "$NP")
if [ "$NP" -gt "$(nproc)" ]; then
  MPIARGS+=(--oversubscribe --bind-to none)
fi
# shellcheck disable=SC2206
MPIARGS+=(${LIGGGHTS_MPIRUN_ARGS:-})

# per-rank peak RSS via GNU time (each rank writes WORKDIR/time.RANK)
rm -f "$W"/time.*
WRAP=()
if [ -x /usr/bin/time ]; then
  cat > "$W/rank_wrap.sh" <<'EOF'
#!/bin/sh
# run one MPI rank under GNU time; rank id from Open MPI (or MPICH/PMI)
r=${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}}
exec /usr/bin/time -v -o "$BENCH_TIMEDIR/time.$r" "$@"
EOF
  chmod +x "$W/rank_wrap.sh"
  export BENCH_TIMEDIR="$W"
  WRAP=("$W/rank_wrap.sh")
fi

# (no "-screen none": the 3.8 STL reader prints to the screen and crashes without one)
LOG="$W/log.liggghts"
cd "$W"
if ! mpirun "${MPIARGS[@]}" "${WRAP[@]}" "$BIN" -in "$HERE/in.tumbler" -log "$LOG" \
      -var datafile "$DATA" -var stlfile "$STL" -var px "$NP" \
      -var warmup "$WARMUP" -var steps "$STEPS" -var omega "$OMEGA" -var movemesh "$MOVEMESH" \
      -var dumpevery "$DUMP_EVERY" -var dumpfile "$W/dump.tumbler" -var thermoevery "$THERMO" \
      > "$W/mpirun.out" 2>&1; then
  echo "LIGGGHTS run failed; tail of $LOG and mpirun output:" >&2
  tail -n 20 "$LOG" "$W/mpirun.out" >&2 || true
  exit 1
fi

# timed run = last "Loop time of T on P procs for S steps with N atoms" line
read -r T P S N < <(awk '/^Loop time of/ {t=$4; p=$6; s=$9; n=$12} END {print t, p, s, n}' "$LOG")
# LIGGGHTS' own estimate of its allocations (last report, per rank)
MEMREP=$(awk '/^Memory usage per processor/ {m=$(NF-1)} END {print m}' "$LOG")
# GNU time: max RSS per rank in kB -> sum over ranks (and max) in MB
RSS_SUM=NA
if ls "$W"/time.* > /dev/null 2>&1; then
  read -r RSS_SUM RSS_MAX NR < <(awk -F': ' '/Maximum resident set size/ {s+=$2; if ($2>m) m=$2; n++}
      END {printf "%.1f %.1f %d\n", s/1024, m/1024, n}' "$W"/time.*)
  echo "LIGGGHTS memory: peak RSS summed over $NR ranks = $RSS_SUM MB (largest rank $RSS_MAX MB);" \
       "LIGGGHTS own estimate = $MEMREP MB per rank" >&2
fi
echo "LIGGGHTS timed run: $S steps after $WARMUP warm-up steps, loop time $T s; workdir $W" >&2
awk -v p="$P" -v n="$N" -v s="$S" -v t="$T" -v m="$RSS_SUM" 'BEGIN {
  printf "LIGGGHTS nprocs=%d particles=%d steps=%d wall_s=%.3f psteps_per_s=%.4g peak_rss_mb=%s\n",
         p, n, s, t, n * s / t, m }'
