# Sourced by the kill tests (sweep_resume_test.sh, curve_units_test.sh).
# kill_mid_run JOURNAL MAX_SECONDS CMD [ARG ...]: starts CMD in the background, waits until it has
# written JOURNAL, and kills it with SIGKILL at a random moment within MAX_SECONDS after that.
# Returns 0 if the kill interrupted the run, 1 if the run had ended before it (a fast machine: the
# caller retries with a shorter delay; resuming a finished run is an error, not a test of resume).
kill_mid_run() {
  local journal="$1" max="$2" pid status
  shift 2
  "$@" > /dev/null 2>&1 &
  pid=$!
  for _ in $(seq 500); do
    [ -f "$journal" ] && break
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.02
  done
  sleep "$(/usr/bin/python3 -c 'import random, sys; print(round(random.uniform(0.0, float(sys.argv[1])), 3))' "$max")"
  kill -9 "$pid" 2> /dev/null || true
  status=0
  wait "$pid" 2> /dev/null || status=$?
  [ "$status" = 137 ]  # 128 + SIGKILL: it was still running
}

# seconds_since T0: wall seconds since T0 (from `date +%s.%N`).
seconds_since() { /usr/bin/python3 -c 'import sys, time; print(time.time() - float(sys.argv[1]))' "$1"; }
