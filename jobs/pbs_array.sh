#!/usr/bin/env bash
# One subjob of a PBS job array runs one slice of a campaign (docs/campaign.md). PBS passes no
# arguments to a job script, so the campaign comes in the environment:
#
#   qsub -J 1-16 -l select=1:ncpus=8:mpiprocs=8 \
#        -v CAMPAIGN=campaign/fig4_fraction.toml,TUMBLE_SLICES=16 jobs/pbs_array.sh
#
# Rank groups: one subjob = one mpiexec of k x m ranks running m cases at a time on groups of k,
# e.g. -l select=4:ncpus=16:mpiprocs=16 -v ...,TUMBLE_RANKS_PER_CASE=16 (4 groups of 16).
#
# Subjob i (PBS_ARRAY_INDEX; PBS_ARRAYID under Torque) runs
# `tumble campaign $CAMPAIGN --slice i/$TUMBLE_SLICES $TUMBLE_ARGS` under mpiexec; a slice with
# nothing left to run exits at once. Fold the slices afterwards with `tumble merge DIR`.
# Run by hand, the campaign and options may also be given as arguments.
#
# Environment: CAMPAIGN, TUMBLE_SLICES (required: PBS does not export the array size),
# TUMBLE_ARGS (extra options), TUMBLE (default PBS_O_WORKDIR/build/tumble, then tumble on PATH),
# TUMBLE_LAUNCH (default "mpiexec"), TUMBLE_RANKS_PER_CASE (ranks per case, default: the
# campaign file's campaign.ranks_per_case), TUMBLE_JOBS (this jobs/ folder, for a spooled copy
# submitted from outside the repository), TUMBLE_STOP_AFTER (seconds after which the campaign is
# asked to stop at its checkpoints; default: the walltime qstat reports, less TUMBLE_STOP_MARGIN,
# 300 s by default).
#PBS -N tumble-campaign
#PBS -j oe
set -euo pipefail
if [ -n "${PBS_O_WORKDIR:-}" ]; then cd "$PBS_O_WORKDIR"; fi
campaign=${1:-${CAMPAIGN:-}}
[ -n "$campaign" ] || { echo "pbs_array.sh: set CAMPAIGN (qsub -v CAMPAIGN=FILE,TUMBLE_SLICES=N)" >&2; exit 2; }
if [ $# -gt 0 ]; then shift; fi
index=${PBS_ARRAY_INDEX:-${PBS_ARRAYID:-}}
[ -n "$index" ] || { echo "pbs_array.sh: not a PBS array subjob (PBS_ARRAY_INDEX is unset)" >&2; exit 2; }
n=${TUMBLE_SLICES:?pbs_array.sh: set TUMBLE_SLICES to the number of subjobs}
case ${TUMBLE_FIRST_INDEX:-1} in  # qsub -J 0-15: set TUMBLE_FIRST_INDEX=0
  0) offset=1 ;;
  1) offset=0 ;;
  # (it went into $((...)), which reads a word as a variable's name: "abc" counted as 0)
  *) echo "pbs_array.sh: TUMBLE_FIRST_INDEX='${TUMBLE_FIRST_INDEX}' must be 0 or 1" >&2; exit 2 ;;
esac
[[ $index =~ ^[0-9]+$ ]] || { echo "pbs_array.sh: array index '$index' is not a whole number" >&2; exit 2; }
i=$((index + offset))
# TUMBLE_ARGS holds several options, split at blanks but not globbed (set -f): `--set a=*`
# became the names of the files in the directory.
set -f
# shellcheck disable=SC2206
extra=(${TUMBLE_ARGS:-} "$@")
set +f

echo "pbs_array.sh: array index $index -> slice $i/$n of $campaign"
# The scheduler may run a spooled copy of this script: then find the helper in TUMBLE_JOBS, or in
# the submit directory's jobs/.
here=$(dirname "${BASH_SOURCE[0]}")
[ -f "$here/run_slice.sh" ] || here=${TUMBLE_JOBS:-${PBS_O_WORKDIR:-$PWD}/jobs}
[ -f "$here/run_slice.sh" ] || {
  echo "pbs_array.sh: cannot find run_slice.sh beside this script or in $here: submit from the" \
    "repository's root, or export TUMBLE_JOBS=/path/to/tumble/jobs" >&2
  exit 2
}
# shellcheck source=jobs/run_slice.sh
source "$here/run_slice.sh"
# PBS warns of nothing before its walltime (SIGTERM, then SIGKILL): unless TUMBLE_STOP_AFTER is
# set, the campaign gets its stop request (SIGUSR1) TUMBLE_STOP_MARGIN seconds (default 300)
# before the job's walltime, as slurm_array.sh's --signal=USR1@300 does, read from qstat where it
# says. Raise the margin if one neighbour rebuild plus a checkpoint of the largest case can take
# longer.
margin=${TUMBLE_STOP_MARGIN:-300}
[[ $margin =~ ^[1-9][0-9]*$ ]] || { echo "pbs_array.sh: TUMBLE_STOP_MARGIN='$margin' must be a whole number of seconds >= 1" >&2; exit 2; }
# (counted from here, milliseconds into the script, to the millisecond: SECONDS and date +%s
# were whole seconds, which let the request come up to a second late, inside the margin, or a
# second early: a test that wanted it 2 s into a 3 s walltime saw it after 1.0 s)
started_ms=$(epoch_ms)
if [ -z "${TUMBLE_STOP_AFTER:-}" ] && [ -n "${PBS_JOBID:-}" ] && command -v qstat > /dev/null; then
  # (a server that does not answer must not hold the job: 30 s at most)
  walltime=$(timeout 30 qstat -f "$PBS_JOBID" 2> /dev/null | awk -F' = ' '/Resource_List.walltime/ {print $2; exit}' || true)
  if [[ $walltime =~ ^([0-9]+):([0-9]{2}):([0-9]{2})$ ]]; then
    seconds=$((10#${BASH_REMATCH[1]} * 3600 + 10#${BASH_REMATCH[2]} * 60 + 10#${BASH_REMATCH[3]}))
    stop_at_ms=$((started_ms + (seconds - margin) * 1000))
    if [ "$stop_at_ms" -gt "$(epoch_ms)" ]; then
      # (a time, not a delay: run_slice.sh takes the time the status check took off it)
      TUMBLE_STOP_AT=$(ms_as_seconds "$stop_at_ms")
      export TUMBLE_STOP_AT
    else
      echo "pbs_array.sh: walltime $walltime leaves no $margin s margin: no stop request before it" >&2
    fi
  else
    echo "pbs_array.sh: qstat gave no walltime for $PBS_JOBID: no stop request before it (set TUMBLE_STOP_AFTER)" >&2
  fi
fi
if [ -n "${PBS_NODEFILE:-}" ] && [ -f "$PBS_NODEFILE" ]; then
  TUMBLE_TASK_RANKS=$(wc -l < "$PBS_NODEFILE")
  export TUMBLE_TASK_RANKS
fi
# (${a[@]+"${a[@]}"}: an empty array under set -u is an error on bash < 4.4, e.g. RHEL 7)
run_slice pbs_array.sh "$PWD" "${TUMBLE_LAUNCH:-mpiexec}" "$campaign" "$i" "$n" ${extra[@]+"${extra[@]}"}
