#!/usr/bin/env bash
# One task of a Slurm job array runs one slice of a campaign (docs/campaign.md):
#
#   sbatch --array=1-16 --ntasks=8 jobs/slurm_array.sh campaign/fig4_fraction.toml [options]
#   sbatch --dependency=afterany:JOBID --wrap "build/tumble merge results/fig4_fraction"
#
# Rank groups: one array task = one srun of k x m ranks running m cases at a time on groups of k
# (domain decomposition inside each case), e.g. 4 groups of 16 ranks per task:
#
#   sbatch --array=1-8 --ntasks=64 --export=ALL,TUMBLE_RANKS_PER_CASE=16 jobs/slurm_array.sh FILE
#
# Task i of an array 1-N (or 0-(N-1)) runs `tumble campaign FILE --slice i/N [options]` under
# srun. The slices are a deterministic, cost-balanced split of the cases, so a task resubmitted
# later runs the same cases; a slice with nothing left to run exits at once without starting
# MPI, and a slice cut off by the time limit resumes from its checkpoints when resubmitted. To
# resubmit only some tasks (e.g. --array=3,7), export TUMBLE_SLICES=N so that N is not guessed
# (and TUMBLE_FIRST_INDEX=0 if the array was numbered from 0); an array that is not a whole range
# 1-N or 0-(N-1) is refused without it.
#
# Environment: TUMBLE (the binary; default SUBMIT_DIR/build/tumble, then tumble on PATH),
# TUMBLE_LAUNCH (default "srun"), TUMBLE_SLICES (default: the array's size), TUMBLE_FIRST_INDEX
# (0 or 1: the number of the array's first task; default: the lowest task now), TUMBLE_RANKS_PER_CASE
# (ranks per case, default: the campaign file's campaign.ranks_per_case), TUMBLE_JOBS (this jobs/
# folder, for a spooled copy submitted from outside the repository).
#
# Five minutes before the time limit Slurm sends SIGUSR1 to the tasks (--signal below): every
# running case writes a checkpoint at its next neighbour rebuild, no case starts any more, and the
# task exits 10 (work left); the resubmitted task continues the cases bit for bit. Raise the 300 s
# if one neighbour rebuild plus a checkpoint of your largest case can take longer.
#SBATCH --job-name=tumble-campaign
#SBATCH --output=tumble-campaign-%A_%a.out
#SBATCH --signal=USR1@300
set -euo pipefail
campaign=${1:?usage: sbatch --array=1-N jobs/slurm_array.sh CAMPAIGN.toml [tumble campaign options]}
shift
: "${SLURM_ARRAY_TASK_ID:?not a Slurm array task (SLURM_ARRAY_TASK_ID is unset)}"

min=${SLURM_ARRAY_TASK_MIN:-1}
max=${SLURM_ARRAY_TASK_MAX:-${SLURM_ARRAY_TASK_ID}}
count=${SLURM_ARRAY_TASK_COUNT:-$((max - min + 1))}
# The slicing is guessed from the array only when the array is the whole range 1-N or 0-(N-1): a
# resubmitted subset (--array=5, --array=3,7) or a stepped one (0-30:2) would give another N, and
# another slicing deals the cases anew.
if [ -z "${TUMBLE_SLICES:-}" ] && { [ "$min" -gt 1 ] || [ "$count" -ne $((max - min + 1)) ]; }; then
  echo "slurm_array.sh: the array (tasks $min-$max, $count of them) is not a whole range 1-N or" \
    "0-(N-1), so N cannot be read from it: export TUMBLE_SLICES=N (and TUMBLE_FIRST_INDEX=0 if" \
    "the array was numbered from 0)" >&2
  exit 2
fi
case ${TUMBLE_FIRST_INDEX:-} in
  "") offset=$((min == 0 ? 1 : 0)) ;;  # --array=0-15 numbers slices 1..16
  0) offset=1 ;;
  1) offset=0 ;;
  *) echo "slurm_array.sh: TUMBLE_FIRST_INDEX='${TUMBLE_FIRST_INDEX}' must be 0 or 1" >&2; exit 2 ;;
esac
i=$((SLURM_ARRAY_TASK_ID + offset))
n=${TUMBLE_SLICES:-$((max + offset))}

echo "slurm_array.sh: array task ${SLURM_ARRAY_TASK_ID} -> slice $i/$n of $campaign"
# The scheduler may run a spooled copy of this script: then find the helper in TUMBLE_JOBS, or in
# the submit directory's jobs/.
here=$(dirname "${BASH_SOURCE[0]}")
[ -f "$here/run_slice.sh" ] || here=${TUMBLE_JOBS:-${SLURM_SUBMIT_DIR:-$PWD}/jobs}
[ -f "$here/run_slice.sh" ] || {
  echo "slurm_array.sh: cannot find run_slice.sh beside this script or in $here: submit from the" \
    "repository's root, or export TUMBLE_JOBS=/path/to/tumble/jobs" >&2
  exit 2
}
# shellcheck source=jobs/run_slice.sh
source "$here/run_slice.sh"
export TUMBLE_TASK_RANKS=${SLURM_NTASKS:-}
run_slice slurm_array.sh "${SLURM_SUBMIT_DIR:-$PWD}" "${TUMBLE_LAUNCH:-srun}" "$campaign" "$i" "$n" "$@"
