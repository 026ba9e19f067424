#!/usr/bin/env bash
# A whole campaign in one plain mpirun (docs/campaign.md):
#
#   jobs/mpirun_campaign.sh campaign/fig4_fraction.toml [NP [K]] [tumble campaign options]
#
# NP ranks (default: the number of cores) form groups of K consecutive ranks (default: the
# campaign file's campaign.ranks_per_case, usually 1), each running one case at a time
# decomposed over its K ranks; NP mod K ranks stay idle. Rank 0 also hands out the cases.
# Rerunning the same command resumes, with the same or another K: finished cases are skipped,
# interrupted ones continue from their checkpoints. The statistics land in OUTPUT_DIR/ensemble.h5.
# Environment: TUMBLE (default build/tumble), MPIRUN (default mpirun).
set -euo pipefail
cd "$(dirname "$0")/.."
campaign=${1:?usage: jobs/mpirun_campaign.sh CAMPAIGN.toml [NP] [options]}
shift
np=$(nproc)
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then np=$1; shift; fi
group=()
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then group=(--ranks-per-case "$1"); shift; fi
tumble=${TUMBLE:-build/tumble}
[ -x "$tumble" ] || { echo "mpirun_campaign.sh: $tumble not built (bash jobs/build.sh)" >&2; exit 2; }
if [ "$(id -u)" = 0 ]; then  # Open MPI refuses root unless told
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
# (${group[@]+...}: an empty array under set -u is an error on bash < 4.4, e.g. RHEL 7)
exec ${MPIRUN:-mpirun} -n "$np" "$tumble" campaign "$campaign" ${group[@]+"${group[@]}"} "$@"
