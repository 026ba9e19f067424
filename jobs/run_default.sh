#!/usr/bin/env bash
# The README's first command: install what is missing, build, run the default campaign and
# write its report.
#
# The default campaign (campaign/default.toml): scenes/bst_tiny.toml under (57°, 57°) and
# (68°, 68°), 2 replicas each, one protocol iteration; about 2.5 minutes on 2 cores. Then
# `tumble analyze campaign` (CM islands, island enrichment, Fig. 8 counts) and
# postproc/report.py (HTML + PNG + CSV, docs/report.md). Extra arguments go to `tumble campaign`.
# Rerunning resumes: finished cases are skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/install_deps.sh
bash jobs/build.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out=results/default
np=$(nproc)
if ((np > 4)); then np=4; fi  # 4 cases: more ranks would idle
# One rank per case (campaign.ranks_per_case = 1: 2,000-particle cases gain nothing from more);
# --bind-to none: Open MPI would otherwise pin every run on a shared machine to the same cores.
mpirun -n "$np" --bind-to none ./build/tumble campaign campaign/default.toml --output "$out" "$@"
./build/tumble analyze campaign "$out"
/usr/bin/python3 postproc/report.py "$out" -o "$out/report"
echo "Results: $out/ (ensemble.h5, analysis.h5, cases/*/ with snapshots)"
echo "Report:  $out/report/report.html (figures *.png and every number in *.csv beside it)"
