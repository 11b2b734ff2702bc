#!/usr/bin/env bash
# The README's test command under load: four CPU-burning processes share the machine with it
# (on two cores, a load of about 6-8), as a busy CI runner or a shared workstation would.
#
#   bash scripts/stress_tests.sh [pytest arguments...]     # default: the whole suite
#
# The burners are stopped when the suite ends, on Ctrl-C and on error (they are this script's
# own children, stopped by their process ids), and each stops by itself after
# STRESS_LIMIT seconds (default 3600) in any case; the suite itself gets the same bound.
# Exit status: the suite's (124 if it hit the bound).
set -u
cd "$(dirname "$0")/.."
LIMIT=${STRESS_LIMIT:-3600}
BURNERS=${STRESS_BURNERS:-4}
pids=()
stop_burners() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
    for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null; done
    pids=()
}
trap stop_burners EXIT INT TERM
for _ in $(seq "$BURNERS"); do
    timeout "$LIMIT" sh -c 'while :; do :; done' &
    pids+=("$!")
done
echo "stress_tests: $BURNERS burners (pids ${pids[*]}), bound ${LIMIT} s; load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
source .venv/bin/activate
start=$(date +%s)
timeout "$LIMIT" python -m pytest -q -n 2 --dist loadfile "$@"
status=$?
echo "stress_tests: exit $status after $(( $(date +%s) - start )) s; load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
exit "$status"
