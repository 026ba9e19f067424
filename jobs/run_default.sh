#!/usr/bin/env bash
# The README's first command: install what is missing, build, and run the default job.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/install_deps.sh
bash jobs/build.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# One rank until domain decomposition lands (issue 3).
mpirun -n 1 ./build/tumble run scenes/bst_tiny.toml "$@"
echo "Results: results/bst_tiny/ (results.h5, snap_*.h5, snapshots.xdmf for ParaView, checkpoint.h5)"
