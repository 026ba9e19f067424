# Shared by the benchmark and accuracy scripts (source it after cd to the repository root).
#   BIN            the tumble executable ($TUMBLE, default build/tumble); checked to exist
#   bench_header   prints the machine, date and commit line every recorded result starts with
#   make_work N    a scratch directory removed on exit, in $WORK
#   rate LOG       the particle-steps/s of a run's final "[run] done" line
BIN=${TUMBLE:-build/tumble}
[ -x "$BIN" ] || { echo "no executable at $BIN (build first, or set TUMBLE)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

bench_header() {
  echo "# $(lscpu | awk -F: '/Model name/ {gsub(/^ +/, "", $2); print $2}'), $(nproc) cores;" \
       "$(date -u +%Y-%m-%dT%H:%MZ); git $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
}

make_work() {
  WORK=$(mktemp -d "${TMPDIR:-/tmp}/tumble_$1.XXXXXX")
  trap 'rm -rf "$WORK"' EXIT
}

rate() { sed -n 's/.*(\([0-9.e+]*\) particle-steps\/s.*/\1/p' "$1" | tail -1; }
