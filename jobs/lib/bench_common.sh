# Shared by the benchmark and accuracy scripts (source it after cd to the repository root).
#   BIN            the tumble executable ($TUMBLE, default build/tumble); checked to exist
#   bench_header   prints the machine, date and commit line every recorded result starts with
#   make_work N    a scratch directory removed on exit, in $WORK
#   rate LOG       the particle-steps/s of a run's final "[run] done" line
#   run_tier_campaign DIR TIER NP   DIR/campaign.toml on NP ranks ($MPIRUN, default mpirun), then
#                  `tumble analyze campaign DIR`; logs in DIR, a line with the wall time; returns 10
#                  (no analysis) when the campaign was stopped by a signal with cases left
BIN=${TUMBLE:-build/tumble}
[ -x "$BIN" ] || { echo "no executable at $BIN (build first, or set TUMBLE)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

bench_header() {
  echo "# $(lscpu | awk -F: '/Model name/ {gsub(/^ +/, "", $2); print $2}'), $(nproc) cores;" \
       "$(date -u +%Y-%m-%dT%H:%MZ); git $(git rev-parse --short HEAD 2>/dev/null || echo unknown);" \
       "tumble $("$BIN" --version)"
}

make_work() {
  WORK=$(mktemp -d "${TMPDIR:-/tmp}/tumble_$1.XXXXXX")
  trap 'rm -rf "$WORK"' EXIT
}

rate() { sed -n 's/.*(\([0-9.e+]*\) particle-steps\/s.*/\1/p' "$1" | tail -1; }

run_tier_campaign() {
  local dir=$1 tier=$2 np=$3 start
  start=$(date +%s)
  local rc=0
  ${MPIRUN:-mpirun} -n "$np" --oversubscribe "$BIN" campaign "$dir/campaign.toml" --quiet \
    > "$dir/campaign.log" 2>&1 || rc=$?
  if [ "$rc" = 10 ]; then  # stopped by a signal after its checkpoints (README, "Exit codes")
    echo "# $tier: campaign stopped with cases left (exit 10) after $(( $(date +%s) - start )) s;" \
      "rerun the same command to go on"
    return 10  # (the callers' set -e ends them here: no analysis of a campaign part-way)
  else
    [ "$rc" = 0 ] || echo "# $tier: campaign exited with $rc, see $dir/campaign.log"
    "$BIN" analyze campaign "$dir" > "$dir/analyze.log" 2>&1 ||
      echo "# $tier: analyze failed, see $dir/analyze.log"
  fi
  echo "# $tier: $(( $(date +%s) - start )) s wall"
}
