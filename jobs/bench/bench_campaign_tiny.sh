#!/usr/bin/env bash
# Throughput of a 2-rank campaign of real bst_tiny cases (docs/campaign.md, "Performance"): the
# CI-size scene as it is (about 2,000 particles, one (θz, θx) iteration of 616,667 steps), two
# protocols x REPLICAS, each case settling its own bed, collecting c_L, Δψ and the series.
#
#   jobs/bench/bench_campaign_tiny.sh                 # NP=2 REPLICAS=2: 4 cases
#
# Prints cases per hour (wall clock, bed settling included) and the scheduling overhead.
set -euo pipefail
cd "$(dirname "$0")/../.."
tumble=${TUMBLE:-build/tumble}
np=${NP:-2}
replicas=${REPLICAS:-2}
work=${WORK:-$(mktemp -d /tmp/tumble_bench_tiny.XXXXXX)}
mkdir -p "$work"
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
cat > "$work/tiny.toml" <<TOML
[campaign]
name = "bench_tiny"
scene = "$PWD/scenes/bst_tiny.toml"
seed = 7
replicas = $replicas
progress_interval = 60

[[sweep]]
zip = true
theta_z = [57, 90]
theta_x = [57, 90]

[collect]
iterations = [0, 1]
samples_per_iteration = 4
displacement_periods = 0.25
grid = 12
TOML
out=$work/out
rm -rf "$out"
start=$(date +%s.%N)
mpirun -n "$np" "$tumble" campaign "$work/tiny.toml" --output "$out" | tee "$work/log" \
  | grep -E "^\[campaign\] (done:|finished|statistics)"
end=$(date +%s.%N)
/usr/bin/python3 - "$out" "$start" "$end" "$np" <<'PY'
import glob, json, sys
out, t0, t1, np_ = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
done = [json.loads(l) for f in glob.glob(out + "/manifest/*.jsonl") for l in open(f)
        if '"status":"done"' in l]
wall = t1 - t0
busy = sum(r["wall"] for r in done)
print("%d bst_tiny cases on %d ranks in %.1f s: %.1f cases per hour; mean case %.1f s; "
      "end-to-end overhead %.2f%%" % (len(done), np_, wall, 3600 * len(done) / wall,
                                      busy / len(done), 100 * (1 - busy / (np_ * wall))))
PY
