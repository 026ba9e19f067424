#!/usr/bin/env bash
# LIGGGHTS 3.8 peer benchmark: settled bed (bst_R35) in a spherical tumbler
# rotating at 3 rpm about x. See README.md in this folder.
#
# usage: run.sh NPROCS STEPS
#   runs an untimed warm-up, then STEPS timed steps on NPROCS MPI ranks
#   (processor grid NPROCS x 1 x 1, i.e. slabs along the rotation axis) and
#   prints as its last line:
#   LIGGGHTS nprocs=P particles=N steps=S wall_s=T psteps_per_s=X peak_rss_mb=M
#   With LIGGGHTS_RESTART_DIR set, STEPS = 0 only makes sure the warmed state
#   is in the cache (runs the warm-up if it is not there) and prints
#   LIGGGHTS warm state: FILE
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
#   LIGGGHTS_RESTART_DIR cache of warmed states (made if missing). Unset: the
#                       warm-up and the timed run share one process. Set: the
#                       warm-up runs once, in a process of its own, and ends
#                       with write_restart into
#                       DIR/warm_w<WARMUP>_tol<MESH_TOL>_mm<MOVEMESH>.restart;
#                       every call with the same three values then starts from
#                       that file (read_restart) and runs only the STEPS timed
#                       steps. DIR/<same name>.meta holds a fingerprint of the
#                       deck, data file, STL and LIGGGHTS version; a state whose
#                       fingerprint does not match is made again.
set -euo pipefail

usage() {
  echo "usage: $0 NPROCS STEPS    (STEPS = 0: only warm up into \$LIGGGHTS_RESTART_DIR)" >&2
  echo "  environment variables: see the header of this script and README.md beside it" >&2
  exit 2
}
[ $# -eq 2 ] || usage
NP=$1
STEPS=$2
case "$NP$STEPS" in *[!0-9]*) usage ;; esac
[ "$NP" -ge 1 ] || usage
RESTART_DIR=${LIGGGHTS_RESTART_DIR:-}
if [ "$STEPS" -eq 0 ] && [ -z "$RESTART_DIR" ]; then
  echo "$0: STEPS = 0 needs LIGGGHTS_RESTART_DIR (nothing to time and nothing to save)" >&2
  exit 2
fi
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

# launch PHASE LOG RESTARTFILE: one LIGGGHTS job; phases (in.tumbler):
#   0 = warm-up + timed run, 1 = warm-up + write_restart, 2 = read_restart + timed run
# (no "-screen none": the 3.8 STL reader prints to the screen and crashes without one)
launch() {
  local phase=$1 log=$2 rfile=$3
  rm -f "$W"/time.*
  if ! (cd "$W" && mpirun "${MPIARGS[@]}" "${WRAP[@]}" "$BIN" -in "$HERE/in.tumbler" -log "$log" \
        -var phase "$phase" -var restartfile "$rfile" \
        -var datafile "$DATA" -var stlfile "$STL" -var px "$NP" \
        -var warmup "$WARMUP" -var steps "$STEPS" -var omega "$OMEGA" -var movemesh "$MOVEMESH" \
        -var dumpevery "$DUMP_EVERY" -var dumpfile "$W/dump.tumbler" -var thermoevery "$THERMO" \
        > "$W/mpirun.out" 2>&1); then
    echo "LIGGGHTS run failed; tail of $log and mpirun output:" >&2
    tail -n 20 "$log" "$W/mpirun.out" >&2 || true
    exit 1
  fi
}

LOG="$W/log.liggghts"
if [ -z "$RESTART_DIR" ]; then
  launch 0 "$LOG" none
  FROM="after $WARMUP warm-up steps in the same process"
else
  # the warmed state, keyed by warm-up length, mesh tolerance and mesh motion
  RDIR=$(mkdir -p "$RESTART_DIR" && cd "$RESTART_DIR" && pwd)
  KEY="warm_w${WARMUP}_tol${MESH_TOL}_mm${MOVEMESH}"
  RFILE="$RDIR/$KEY.restart"
  META="$RDIR/$KEY.meta"
  VERSION=$("$BIN" -log none -h < /dev/null 2>&1 || true)   # (-h exits with status 1; -log none: no log.liggghts here)
  VERSION=${VERSION%%$'\n'*}
  FPRINT="fingerprint $( { sha256sum < "$HERE/in.tumbler"; sha256sum < "$DATA"; sha256sum < "$STL"
                           echo "$VERSION"; } | sha256sum | cut -c1-16)"
  if [ -s "$RFILE" ] && [ -s "$META" ] && grep -qx "$FPRINT" "$META"; then
    echo "LIGGGHTS: warmed state found: $RFILE" >&2
  else
    echo "LIGGGHTS: warming up ($WARMUP steps, mesh tol $MESH_TOL, movemesh $MOVEMESH) into $RFILE" >&2
    TMPR="$RDIR/.$KEY.$$.restart"
    launch 1 "$W/log.warmup" "$TMPR"
    WT=$(awk '/^Loop time of/ {t=$4} END {print t}' "$W/log.warmup")
    mv -f "$TMPR" "$RFILE"
    { echo "$FPRINT"
      echo "warmup=$WARMUP mesh_tol=$MESH_TOL movemesh=$MOVEMESH nprocs=$NP loop_time_s=$WT"
      echo "$VERSION"
      echo "written $(date -u +%Y-%m-%dT%H:%M:%SZ)"; } > "$META"
    echo "LIGGGHTS: warm-up done, loop time $WT s" >&2
  fi
  if [ "$STEPS" -eq 0 ]; then
    echo "LIGGGHTS warm state: $RFILE"
    exit 0
  fi
  launch 2 "$LOG" "$RFILE"
  FROM="from the saved state after $WARMUP warm-up steps ($RFILE)"
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
echo "LIGGGHTS timed run: $S steps $FROM, loop time $T s; workdir $W" >&2
awk -v p="$P" -v n="$N" -v s="$S" -v t="$T" -v m="$RSS_SUM" 'BEGIN {
  printf "LIGGGHTS nprocs=%d particles=%d steps=%d wall_s=%.3f psteps_per_s=%.4g peak_rss_mb=%s\n",
         p, n, s, t, n * s / t, m }'
