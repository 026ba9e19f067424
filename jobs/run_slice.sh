# shellcheck shell=bash
# Shared by jobs/slurm_array.sh and jobs/pbs_array.sh (sourced, not run): find the tumble binary,
# skip a slice that has nothing left to run, otherwise launch it.
#   run_slice SCRIPT_NAME SEARCH_DIR LAUNCHER CAMPAIGN I N [tumble campaign options...]
# TUMBLE_RANKS_PER_CASE=K (optional) runs every case on a group of K ranks (--ranks-per-case K);
# the task's ranks (TUMBLE_TASK_RANKS, set by the caller from the scheduler) then form
# floor(ranks / K) groups, and a remainder stays idle (said here and in the campaign's start line).
# TUMBLE_STOP_AFTER=S (optional, whole seconds) sends SIGUSR1 to the launcher S seconds after the
# launch, TUMBLE_STOP_AT=T (seconds since 1970, to the millisecond: 1764900000.250; pbs_array.sh
# sets it from the walltime) at time T: the campaign's stop request (its cases checkpoint, exit
# 10), for a scheduler that gives no warning before its time limit (PBS sends SIGTERM, then
# SIGKILL: the cases lost what they had done since their last checkpoint, and the task exited 1).

# Milliseconds since 1970 (GNU date's %N; whole seconds where date has no %N).
epoch_ms() {
  local t
  t=$(date +%s%3N)
  [[ $t =~ ^[0-9]+$ ]] || t=$(($(date +%s) * 1000))
  echo "$t"
}

# A duration in ms as seconds for sleep and the log: 2000 -> 2.000
ms_as_seconds() {
  printf '%d.%03d' $(($1 / 1000)) $(($1 % 1000))
}

# Its inverse, for a time in seconds with or without a fraction: 2.25 -> 2250, 2 -> 2000
seconds_as_ms() {
  local frac=
  [[ $1 != *.* ]] || frac=${1#*.}
  frac=${frac}000
  echo $((10#${1%%.*} * 1000 + 10#${frac:0:3}))
}

# Pass a signal the slice's shell caught on to the launcher, or keep it for the launcher that is
# about to start (run_slice sets run_slice_launcher once it has its pid).
run_slice_forward() {
  if [ -n "$run_slice_launcher" ]; then
    kill -"$1" "$run_slice_launcher" 2> /dev/null || true
  else
    run_slice_pending=$1
  fi
}

run_slice() {
  local name=$1 dir=$2 launcher=$3 campaign=$4 i=$5 n=$6
  shift 6
  local stop=${TUMBLE_STOP_AFTER:-} stop_at=${TUMBLE_STOP_AT:-}
  [ -z "$stop" ] || [[ $stop =~ ^[1-9][0-9]*$ ]] || { echo "$name: TUMBLE_STOP_AFTER='$stop' must be a whole number of seconds >= 1" >&2; exit 2; }
  [ -z "$stop_at" ] || [[ $stop_at =~ ^[1-9][0-9]*(\.[0-9]+)?$ ]] || { echo "$name: TUMBLE_STOP_AT='$stop_at' must be a time in seconds since 1970 (a fraction allowed: 1764900000.25)" >&2; exit 2; }
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
  if [ -z "$stop" ] && [ -n "$stop_at" ]; then
    # (the time left now, after the status check, to the millisecond: whole seconds on both
    # sides, the stop time and now, let the request come up to a second late, inside the margin)
    local left=$(($(seconds_as_ms "$stop_at") - $(epoch_ms)))
    [ "$left" -ge 1000 ] || left=1000
    stop=$(ms_as_seconds "$left")
  fi
  # (set -f: the launcher's words are split, not globbed: "--host node[1-4]")
  set -f
  if [ -z "$stop" ]; then
    # shellcheck disable=SC2086  # the launcher is a command line, split on purpose
    exec $launcher "$tumble" campaign "$campaign" --slice "$i/$n" "$@"
  fi
  echo "$name: SIGUSR1 (stop at the next checkpoints) after $stop s"
  # This shell is the job's top process now (without the timer, exec made the launcher it): a
  # stop request or a kill sent to it (qsig, Ctrl-C) is passed on to the launcher, not lost with
  # this shell while the campaign runs on. The traps are set before the launcher starts: set
  # after it, a request sent in between killed this shell alone and left the campaign running.
  # One that comes before the launcher's pid is known waits in run_slice_pending.
  run_slice_launcher=
  run_slice_pending=
  trap 'run_slice_forward USR1' USR1
  trap 'run_slice_forward TERM' TERM
  trap 'run_slice_forward INT' INT
  # shellcheck disable=SC2086
  $launcher "$tumble" campaign "$campaign" --slice "$i/$n" "$@" &
  run_slice_launcher=$!
  set +f
  [ -z "$run_slice_pending" ] || run_slice_forward "$run_slice_pending"
  local timer
  # (the sleep killed with its subshell when the campaign ends first)
  (
    s=
    trap '[ -z "$s" ] || kill "$s" 2> /dev/null; exit 0' TERM
    sleep "$stop" &
    s=$!
    wait "$s"
    echo "$name: $stop s passed: SIGUSR1 to the campaign"
    kill -USR1 "$run_slice_launcher" 2> /dev/null || true
  ) &
  timer=$!
  local rc
  while :; do
    rc=0
    wait "$run_slice_launcher" || rc=$?
    # (wait also returns when a trapped signal comes in: the launcher still runs, wait again)
    kill -0 "$run_slice_launcher" 2> /dev/null && continue
    # (gone: a wait cut short by a trapped signal (> 128) has not reaped it; this one gives its
    # status, and 127 if the first had reaped it after all)
    if [ "$rc" -gt 128 ]; then
      local again=0
      wait "$run_slice_launcher" 2> /dev/null || again=$?
      [ "$again" -eq 127 ] || rc=$again
    fi
    break
  done
  kill "$timer" 2> /dev/null || true
  wait "$timer" 2> /dev/null || true
  exit "$rc"
}
