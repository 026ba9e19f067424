# shellcheck shell=bash
# Shared by jobs/slurm_array.sh and jobs/pbs_array.sh (sourced, not run): find the tumble binary,
# skip a slice that has nothing left to run, otherwise launch it.
#   run_slice SCRIPT_NAME SEARCH_DIR LAUNCHER CAMPAIGN I N [tumble campaign options...]
run_slice() {
  local name=$1 dir=$2 launcher=$3 campaign=$4 i=$5 n=$6
  shift 6
  local tumble=${TUMBLE:-} c
  if [ -z "$tumble" ]; then
    for c in "$dir/build/tumble" "$(command -v tumble || true)"; do
      if [ -n "$c" ] && [ -x "$c" ]; then tumble=$c; break; fi
    done
  fi
  [ -n "$tumble" ] || { echo "$name: cannot find tumble; set TUMBLE=/path/to/tumble" >&2; exit 2; }
  local rc=0
  "$tumble" campaign "$campaign" --slice "$i/$n" --status "$@" || rc=$?
  if [ "$rc" -eq 0 ]; then
    echo "$name: slice $i/$n has nothing to run; skipping"
    exit 0
  elif [ "$rc" -ne 10 ]; then
    exit "$rc"  # the campaign file or the options are wrong: the message is above
  fi
  # shellcheck disable=SC2086  # the launcher is a command line, split on purpose
  exec $launcher "$tumble" campaign "$campaign" --slice "$i/$n" "$@"
}
