#!/usr/bin/env bash
# Scheduling overhead of `tumble campaign` (docs/campaign.md, "Performance"): 1000 trivial cases
# (a 150-particle bed, 123 time steps, 3 field samples each) over NP ranks. Trivial cases make
# everything that is not a case visible: messages, manifest lines, the cases' start-up and the
# final ensemble.
#
#   jobs/bench/bench_campaign_overhead.sh            # NP=2 CASES=1000
#   NP=4 CASES=200 jobs/bench/bench_campaign_overhead.sh
#
# Reports the overhead as 1 - (sum of the cases' own wall times) / (workers x wall time), both
# for the scheduling loop (what the campaign prints) and end to end (start-up, expansion and the
# ensemble included), and the scheduling cost per case in milliseconds.
set -euo pipefail
cd "$(dirname "$0")/../.."
tumble=${TUMBLE:-build/tumble}
np=${NP:-2}
cases=${CASES:-1000}
work=${WORK:-$(mktemp -d /tmp/tumble_bench_overhead.XXXXXX)}
mkdir -p "$work"
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi

# One point per case: cases differ only in theta_z, so they share one bed (settled once).
thetas=$(/usr/bin/python3 -c "print(', '.join('%.1f' % (0.1 * k) for k in range(1, $cases + 1)))")
cat > "$work/trivial.toml" <<TOML
[campaign]
name = "trivial"
scene = "$PWD/scenes/bst_tiny.toml"
seed = 1
replicas = 1
progress_interval = 30

[overrides]
"tumbler.radius" = 0.008
"particles.d_large" = 0.002
"protocol.iterations" = 0.0002
"fill.settle_rms_speed" = 0.005

[[sweep]]
theta_z = [$thetas]

[collect]
iterations = [0, 0.0002]
samples_per_iteration = 10000
displacement_periods = 0.0001
grid = 4
TOML

out=$work/out
rm -rf "$out"
# Settle the shared bed first (it is case work, not scheduling): a 1-case slice of the same file.
"$tumble" campaign "$work/trivial.toml" --output "$work/warm" --slice "$cases/$cases" --quiet \
  > /dev/null
mkdir -p "$out" && cp -r "$work/warm/beds" "$out/beds"
start=$(date +%s.%N)
mpirun -n "$np" "$tumble" campaign "$work/trivial.toml" --output "$out" --quiet | tee "$work/log" \
  | grep -E "finished slice|statistics"
end=$(date +%s.%N)
/usr/bin/python3 - "$out" "$start" "$end" "$np" <<'PY'
import glob, json, sys
out, t0, t1, np_ = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
walls = [json.loads(l)["wall"] for f in glob.glob(out + "/manifest/*.jsonl") for l in open(f)
         if '"status":"done"' in l]
total = t1 - t0
busy = sum(walls)
print("cases %d on %d ranks: end-to-end wall %.2f s, mean case %.1f ms" % (len(walls), np_, total,
      1e3 * busy / len(walls)))
print("end-to-end overhead (start-up, scheduling, ensemble): %.2f%%; %.2f ms per case"
      % (100 * (1 - busy / (np_ * total)), 1e3 * (np_ * total - busy) / len(walls)))
PY
