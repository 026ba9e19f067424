#!/usr/bin/env bash
# Rank groups in `tumble campaign` (campaign.ranks_per_case = k): the same 4 bst_small cases on 2
# ranks, run as 2 groups of 1 rank (k = 1: two cases at a time, each serial) and as 1 group of
# 2 ranks (k = 2: one case at a time, domain-decomposed over both ranks; rank 0 dispatches between
# its own case's time steps). Measures the campaign's wall time, cases per hour, aggregate
# particle-steps/s (sum of the cases' costs from --list / wall), the "ranks idle" and "rank 0
# dispatched" figures of the campaign's finished line and every case's own wall time (manifest).
#
#   jobs/bench/bench_campaign_groups.sh                           # REPEATS=2, ITER=0.018
#   TUMBLE=build/tumble REPEATS=3 jobs/bench/bench_campaign_groups.sh
#
# Cases: theta_z [57, 90] x theta_x 57 x 2 replicas, ITER iterations each (0.018: 2.5-2.9e8
# particle-steps, ~25-30 s on one core), one field sample every 0.002 iterations (10 in the run),
# checkpoints only at the end. The two replica beds are settled once before anything is timed
# (a 2-case warm-up campaign of 0.002 iterations into the shared bed cache WORK/beds; beds depend
# on the seed, replica and bed keys only) and every timed case's log is checked to have reused
# its bed. Runs alternate k = 1, k = 2 (A B A B ...), each into a fresh output directory; the
# summary is a markdown table of medians with min-max. NP (default 2) sets the ranks for both.
# Each run also records the CPU seconds of its ranks (GNU time around mpirun) and the machine's
# busy CPU seconds (/proc/stat) over the run: "others" = the cores, on average, that something
# else used meanwhile (a shared VM), which the wall times cannot show by themselves.
set -euo pipefail
cd "$(dirname "$0")/../.."
source jobs/lib/bench_common.sh   # BIN (= $TUMBLE or build/tumble), bench_header, root MPI env
repeats=${REPEATS:-2}
iter=${ITER:-0.018}
np=${NP:-2}
mpirun_cmd=${MPIRUN:-mpirun}
work=${WORK:-$(mktemp -d /tmp/tumble_bench_groups.XXXXXX)}
mkdir -p "$work"
echo "# work directory: $work (kept)"

# sample spacing 0.002 iterations: samples_per_iteration = 1/0.002; Δψ over 3 spacings.
campaign_file() {  # ITERATIONS THETA_Z_LIST DISPLACEMENT_PERIODS
  cat <<TOML
[campaign]
name = "groups"
scene = "$PWD/scenes/bst_small.toml"
seed = 1
replicas = 2
bed_cache = "$work/beds"
progress_interval = 30

[overrides]
"protocol.iterations" = $1
"output.checkpoint_interval" = 1e6
"protocol.repose" = 27   # pinned: the measured tilt's 80 degrees would enter the timings

[[sweep]]
theta_z = $2
theta_x = 57

[collect]
iterations = [0, $1]
samples_per_iteration = 500
displacement_periods = $3
grid = 8
TOML
}
campaign_file "$iter" "[57, 90]" 0.006 > "$work/groups.toml"
# Warm-up: the same beds (same seed and replicas), a trivially short protocol.
campaign_file 0.002 57 0.002 > "$work/warm.toml"

"$BIN" campaign "$work/groups.toml" --list > "$work/list.txt"
cost=$(awk '!/^#/ {s += $5} END {printf "%.6e", s}' "$work/list.txt")
ncases=$(grep -vc '^#' "$work/list.txt")

bench_header
echo "# command: TUMBLE=$BIN REPEATS=$repeats ITER=$iter NP=$np $0"
echo "# $ncases cases, $iter iterations each, sum of costs $cost particle-steps; $np ranks"
sed 's/^/#   /' "$work/list.txt"

echo "# warm-up: settling the replica beds into $work/beds (not timed)"
$mpirun_cmd -n "$np" "$BIN" campaign "$work/warm.toml" --output "$work/warm" --ranks-per-case 1 \
  --quiet > "$work/warm.log" 2>&1
ls "$work/beds"

results=$work/runs.tsv
printf "run\tk\twall\tcases_per_hour\trate\tidle_pct\tdispatch_pct\tcase_walls\tcpu_s\tothers\n" \
  > "$results"
busy() { awk '/^cpu / {print $2 + $3 + $4 + $7 + $8 + $9}' /proc/stat; }  # jiffies, all cores
for r in $(seq 1 "$repeats"); do
  for k in 1 2; do
    out=$work/out_r${r}_k$k
    rm -rf "$out"
    busy0=$(busy)
    start=$(date +%s.%N)
    /usr/bin/time -f "%U %S" -o "$work/time_r${r}_k$k" $mpirun_cmd -n "$np" "$BIN" campaign \
      "$work/groups.toml" --ranks-per-case "$k" --output "$out" --quiet > "$work/log_r${r}_k$k" 2>&1
    end=$(date +%s.%N)
    busy1=$(busy)
    cpu=$(awk '{print $1 + $2}' "$work/time_r${r}_k$k")
    # Every case must have started from the cached bed: no settling inside a timed run.
    for f in "$out"/cases/*/log.txt; do
      grep -q "reusing settled bed" "$f" && ! grep -q "settled at t" "$f" ||
        { echo "bed not reused in $f" >&2; exit 1; }
    done
    finished=$(grep "finished slice" "$work/log_r${r}_k$k")
    /usr/bin/python3 - "$out" "$start" "$end" "$k" "$r" "$cost" "$finished" "$ncases" \
      "$cpu" "$(( busy1 - busy0 ))" "$(getconf CLK_TCK)" \
      >> "$results" <<'PY'
import glob, json, re, sys
out, t0, t1, k, r, cost, fin, ncases, cpu, jiffies, hz = sys.argv[1:]
wall = float(t1) - float(t0)
done = [json.loads(l) for f in glob.glob(out + "/manifest/*.jsonl") for l in open(f)
        if '"status":"done"' in l]
assert len(done) == int(ncases), "%d of %s cases done" % (len(done), ncases)
idle = re.search(r"ranks idle ([0-9.]+)%", fin).group(1)
disp = re.search(r"dispatched for ([0-9.]+)%", fin)
walls = ",".join("%s:%.2f@%s" % (d["params"].split(";")[0], d["wall"], d["ranks"].replace(",", "+"))
                 for d in sorted(done, key=lambda d: d["start"]))
others = (int(jiffies) / float(hz) - float(cpu)) / wall
print("%s\t%s\t%.2f\t%.1f\t%.4g\t%s\t%s\t%s\t%.1f\t%.2f" % (r, k, wall, 3600 * len(done) / wall,
      float(cost) / wall, idle, disp.group(1) if disp else "nan", walls, float(cpu), max(others, 0)))
PY
    tail -1 "$results" | sed 's/^/# run /'
    echo "#   $finished"
  done
done

/usr/bin/python3 - "$results" <<'PY'
import statistics as st, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])][1:]
def col(k, i):
    return [float(r[i]) for r in rows if r[1] == k]
def case_walls(k):
    return [float(w.split(":")[1].split("@")[0]) for r in rows if r[1] == k for w in r[7].split(",")]
names = [("campaign wall (s)", 2), ("cases per hour", 3), ("particle-steps/s (aggregate)", 4),
         ("ranks idle (%)", 5), ("rank 0 dispatched (%)", 6), ("CPU s of the ranks", 8),
         ("cores used by others meanwhile", 9)]
print("\n| quantity | k = 1 (2 groups of 1) | k = 2 (1 group of 2) | k=2 / k=1 (medians) |")
print("|---|---|---|---|")
def cell(v):
    return "%.4g (%.4g-%.4g)" % (st.median(v), min(v), max(v))
for name, i in names:
    a, b = col("1", i), col("2", i)
    ratio = st.median(b) / st.median(a) if st.median(a) else float("nan")
    print("| %s | %s | %s | %.3f |" % (name, cell(a), cell(b), ratio))
a, b = case_walls("1"), case_walls("2")
print("| case wall (s), all cases | %s | %s | %.3f |" % (cell(a), cell(b), st.median(b) / st.median(a)))
print("\nmedian (min-max) over %d runs per k" % len(col("1", 2)))
PY
