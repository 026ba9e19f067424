#!/usr/bin/env bash
# A view of a finished campaign whose cases' snapshots run on past its end: the cases continued
# from their checkpoints into CONT_DIR/<case id>/ (jobs/drift_from_campaign.sh does this; their
# snapshots go on numbering where the case's stopped) are joined to the case's own, by symbolic
# links, in VIEW_DIR, which `tumble analyze campaign` then reads like the campaign itself:
#
#   jobs/campaign_view_with_continuation.sh results/bst_small_fates_24 \
#       results/bst_small_fates_24/drift results/bst_small_fates_39
#   build/tumble analyze campaign results/bst_small_fates_39 --from 6 --to 36 --dpsi-lags 3 6 18
#
# Nothing is copied or changed in either source; the view's analysis.h5 and report are its own.
# The fields (fields.h5: maps collected during the campaign's run) stay the campaign's.
set -euo pipefail
cd "$(dirname "$0")/.."
src=${1:?usage: jobs/campaign_view_with_continuation.sh CAMPAIGN_DIR CONT_DIR VIEW_DIR}
cont=${2:?usage: jobs/campaign_view_with_continuation.sh CAMPAIGN_DIR CONT_DIR VIEW_DIR}
view=${3:?usage: jobs/campaign_view_with_continuation.sh CAMPAIGN_DIR CONT_DIR VIEW_DIR}
[ -d "$src/cases" ] || { echo "campaign_view_with_continuation.sh: $src has no cases/" >&2; exit 2; }
[ -d "$cont" ] || { echo "campaign_view_with_continuation.sh: $cont is not a directory" >&2; exit 2; }
[ -e "$view" ] && { echo "campaign_view_with_continuation.sh: $view exists; remove it first" >&2; exit 2; }
abs() { readlink -f "$1"; }
mkdir -p "$view/cases"
for f in campaign.toml cases.tsv ensemble.h5 manifest beds; do
  [ -e "$src/$f" ] && ln -s "$(abs "$src/$f")" "$view/$f"
done
# The cached CM islands are copied: the analysis may add to its cache.
[ -d "$src/analysis" ] && cp -r "$src/analysis" "$view/analysis"
joined=0
for case in "$src"/cases/*/; do
  id=$(basename "$case")
  [ -f "$case/fields.h5" ] || continue
  mkdir "$view/cases/$id"
  for f in "$case"/fields.h5 "$case"/results.h5 "$case"/snap_*.h5; do
    [ -e "$f" ] && ln -s "$(abs "$f")" "$view/cases/$id/"
  done
  n=0
  for f in "$cont/$id"/snap_*.h5; do
    [ -e "$f" ] || continue
    [ -e "$view/cases/$id/$(basename "$f")" ] && {
      echo "campaign_view_with_continuation.sh: $f has the name of one of the case's own snapshots" >&2
      exit 2
    }
    ln -s "$(abs "$f")" "$view/cases/$id/"
    n=$((n + 1))
  done
  echo "[view] $id: $(ls "$view/cases/$id" | grep -c '^snap_') snapshots ($n from the continuation)"
  joined=$((joined + 1))
done
echo "[view] $joined cases in $view"
