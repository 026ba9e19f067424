# shellcheck shell=bash
# Shared by jobs/slurm_array.sh and jobs/pbs_array.sh (sourced, not run): find the tumble binary,
# skip a slice that has nothing left to run, otherwise launch it.
#   run_slice SCRIPT_NAME SEARCH_DIR LAUNCHER CAMPAIGN I N [tumble campaign options...]
# TUMBLE_RANKS_PER_CASE=K (optional) runs every case on a group of K ranks (--ranks-per-case K);
# the task's ranks (TUMBLE_TASK_RANKS, set by the caller from the scheduler) then form
# floor(ranks / K) groups, and a remainder stays idle (said here and in the campaign's start line).
# TUMBLE_STOP_AFTER=S (optional, whole seconds) sends SIGUSR1 to the launcher S seconds after the
# launch: the campaign's stop request (its cases checkpoint, exit 10), for a scheduler that gives no
# warning before its time limit (PBS sends SIGTERM, then SIGKILL: the cases lost what they had
# done since their last checkpoint, and the task exited 1).
run_slice() {
  local name=$1 dir=$2 launcher=$3 campaign=$4 i=$5 n=$6
  shift 6
  local k=${TUMBLE_RANKS_PER_CASE:-}
  if [ -n "$k" ]; then
    [[ $k =~ ^[1-9][0-9]*$ ]] || { echo "$name: TUMBLE_RANKS_PER_CASE='$k' must be an integer >= 1" >&2; exit 2; }
    local ranks=${TUMBLE_TASK_RANKS:-}
    if [ -n "$ranks" ]; then
      if [ "$ranks" -lt "$k" ]; then
        echo "$name: $ranks ranks in this task, fewer than TUMBLE_RANKS_PER_CASE=$k: ask for at least $k (k x groups)" >&2
        exit 2
      fi
      echo "$name: $ranks ranks -> $((ranks / k)) group(s) of $k$([ $((ranks % k)) -gt 0 ] && echo ", $((ranks % k)) rank(s) idle")"
    fi
    set -- --ranks-per-case "$k" "$@"
  fi
  local tumble=${TUMBLE:-} c
  if [ -z "$tumble" ]; then
    # (the submit directory's build, this repository's build, then PATH)
    for c in "$dir/build/tumble" "$(dirname "${BASH_SOURCE[0]}")/../build/tumble" \
      "$(command -v tumble || true)"; do
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
  local stop=${TUMBLE_STOP_AFTER:-}
  if [ -z "$stop" ]; then
    # shellcheck disable=SC2086  # the launcher is a command line, split on purpose
    exec $launcher "$tumble" campaign "$campaign" --slice "$i/$n" "$@"
  fi
  [[ $stop =~ ^[1-9][0-9]*$ ]] || { echo "$name: TUMBLE_STOP_AFTER='$stop' must be a whole number of seconds >= 1" >&2; exit 2; }
  echo "$name: SIGUSR1 (stop at the next checkpoints) after $stop s"
  # shellcheck disable=SC2086
  $launcher "$tumble" campaign "$campaign" --slice "$i/$n" "$@" &
  local pid=$! timer
  # (the sleep killed with its subshell when the campaign ends first)
  (
    trap 'kill "$s" 2>/dev/null; exit 0' TERM
    sleep "$stop" &
    s=$!
    wait "$s"
    echo "$name: $stop s passed: SIGUSR1 to the campaign"
    kill -USR1 "$pid" 2>/dev/null || true
  ) &
  timer=$!
  local rc=0
  wait "$pid" || rc=$?
  kill "$timer" 2>/dev/null || true
  wait "$timer" 2>/dev/null || true
  exit "$rc"
}
