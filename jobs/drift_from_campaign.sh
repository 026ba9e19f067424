#!/usr/bin/env bash
# The MCM's axial drift measured on a campaign's developed beds (Yu 2022 App. A, issue 17):
#
#   jobs/drift_from_campaign.sh results/bst_small_fates [EXTRA_ITERATIONS [NP]]
#
# Every finished case of the campaign is continued from its last checkpoint for EXTRA_ITERATIONS
# more protocol iterations (default 3: one period of (57°,57°)'s islands) with
# output.drift_grid = on, NP cases at a time (default: the number of cores), each with the exact
# scene it ran with (the resolved scene stored in its fields.h5). The cases' grids are merged
# (`tumble cm drift --merge`: per-cell statistics summed) and the MCM runs with the merged grid
# and, for comparison, with the synthetic one and without drift, all with c = 1 and the same
# seeds and islands. Output in DIR/drift/: one directory per case, drift_merged.h5,
# mcm_{measured,synthetic,none}_SEED.h5 and summary.txt (the MCM's lines).
# Rerunning skips the cases whose drift grid exists. Environment: TUMBLE (default build/tumble).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:?usage: jobs/drift_from_campaign.sh CAMPAIGN_DIR [EXTRA_ITERATIONS [NP]]}
extra=${2:-3}
np=${3:-$(nproc)}
tumble=${TUMBLE:-build/tumble}
py=/usr/bin/python3
[ -x "$tumble" ] || { echo "drift_from_campaign.sh: $tumble not built (bash jobs/build.sh)" >&2; exit 2; }
[[ $extra =~ ^[1-9][0-9]*$ ]] || { echo "drift_from_campaign.sh: EXTRA_ITERATIONS = '$extra' must be a whole number >= 1" >&2; exit 2; }
[[ $np =~ ^[1-9][0-9]*$ ]] || { echo "drift_from_campaign.sh: NP = '$np' must be a whole number >= 1" >&2; exit 2; }
out=$dir/drift
mkdir -p "$out"

# One line per finished case: case directory, its continued run's directory, total iterations,
# theta_z, theta_x (from the resolved scene of its fields file).
"$py" - "$dir" "$out" "$extra" > "$out/cases.txt" <<'EOF'
import glob, os, re, sys
import h5py
d, out, extra = sys.argv[1], sys.argv[2], int(sys.argv[3])
for f in sorted(glob.glob(os.path.join(d, "cases", "*", "fields.h5"))):
    case = os.path.dirname(f)
    if not os.path.exists(os.path.join(case, "checkpoint.h5")):
        print(f"# {case}: no checkpoint.h5, skipped", file=sys.stderr)
        continue
    with h5py.File(f, "r") as h:
        scene = h.attrs["scene"]
    scene = scene.decode() if isinstance(scene, bytes) else str(scene)
    key = lambda k: re.search(rf"^{re.escape(k)} = (.*)$", scene, re.M).group(1)
    iters = float(key("protocol.iterations"))
    run_dir = os.path.join(out, os.path.basename(case))
    os.makedirs(run_dir, exist_ok=True)
    with open(os.path.join(run_dir, "scene.toml"), "w") as fh:
        fh.write(scene + "\n")
    print(case, run_dir, f"{iters + extra:g}", key("protocol.theta_z"), key("protocol.theta_x"))
EOF
[ -s "$out/cases.txt" ] || { echo "drift_from_campaign.sh: no finished case with a checkpoint in $dir" >&2; exit 2; }

run_case() {  # case_dir run_dir iterations
  [ -f "$2/drift_grid.h5" ] && { echo "[drift] $2: done before"; return 0; }
  "$tumble" run "$2/scene.toml" --restart "$1/checkpoint.h5" --set "protocol.iterations=$3" \
    --set output.drift_grid=on --set "scene.output_dir=$2" > "$2/log.txt" 2>&1 \
    && echo "[drift] $2: $(grep 'drift grid' "$2/log.txt")" \
    || { echo "[drift] $2: failed, see $2/log.txt" >&2; return 1; }
}
export -f run_case
export tumble
awk '{print $1, $2, $3}' "$out/cases.txt" | xargs -P "$np" -n 3 bash -c 'run_case "$@"' _

read -r _ _ _ tz tx < "$out/cases.txt"
"$tumble" cm drift --merge "$out"/*/drift_grid.h5 -o "$out/drift_merged.h5" | tee "$out/summary.txt"
# The campaign's cached CM islands (tumble analyze names them orbits_TZ_TX_METHOD.h5, the KAM
# tubes in orbits_TZ_TX_kam_METHOD.h5); none cached: the MCM computes them with the same method.
islands=$(ls "$dir"/analysis/orbits_"${tz}"_"${tx}"_*.h5 2>/dev/null | grep -v '_kam_' | head -n 1 || true)
for seed in 1 2 3; do
  for drift in measured synthetic none; do
    case $drift in
      measured) opt=(--drift "$out/drift_merged.h5") ;;
      synthetic) opt=(--drift synthetic) ;;
      none) opt=(--no-drift) ;;
    esac
    echo "== MCM ($tz°,$tx°), drift $drift, c = 1, seed $seed" | tee -a "$out/summary.txt"
    "$tumble" cm mcm --theta-z "$tz" --theta-x "$tx" "${opt[@]}" --c 1 --seed "$seed" \
      ${islands:+--islands "$islands"} --progress-interval 0 \
      -o "$out/mcm_${drift}_${seed}.h5" | grep -E "drift grid|Pe|islands|tracers" \
      | tee -a "$out/summary.txt"
  done
done
