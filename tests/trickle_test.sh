#!/usr/bin/env bash
# A node that trickles its report stream (one byte every 0.5 s, through
# tests/trickle_proxy.py) on the direct data plane: the master fails on its
# own within its step deadline, naming that node at the address it used, and
# leaves summary.json; and a SIGINT meanwhile stops it within a second.
# Usage: trickle_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
# A run long enough to be mid-window when the trickle starts (50,000 steps).
sed -e "s/^end_time = .*/end_time = 5.0/" -e "s/^speed_kmh = .*/speed_kmh = 10.0/" "$src/scenes/paper.toml" >"$work/long.toml"

run_master() {  # OUT: the run through a fresh trickling proxy; sets $master
  start track "$bin/track_node" --listen 127.0.0.1:0
  start proxy /usr/bin/python3 "$src/tests/trickle_proxy.py" "$address" 0.3
  proxy=$address
  "$bin/master" run --scene "$work/long.toml" --case rs-xx-jacobi --node "track=$proxy" \
    --out "$work/$1" >"$work/$1.log" 2>&1 &
  master=$!
}

# 1. On its own: the deadline (at least 2 s, 50 x the slowest step) acts.
run_master alone
t0=$(date +%s.%N)
rc=0
wait "$master" || rc=$?
t1=$(date +%s.%N)
[[ $rc != 0 ]] || { echo "the master did not fail"; cat "$work/alone.log"; exit 1; }
grep -q "track node at $proxy: no reply within" "$work/alone.log" || { cat "$work/alone.log"; exit 1; }
grep -q '"status": "failed"' "$work/alone/rs-xx-jacobi/summary.json"
awk -v a="$t0" -v b="$t1" 'BEGIN { if (b - a > 10) { print "took " b - a " s"; exit 1 } }'

# 2. A SIGINT while the node trickles acts within a second.
run_master interrupted
# Once it has done some steps (a loaded machine takes a while to get there).
for _ in $(seq 200); do
  [[ $(cat "$work/interrupted/rs-xx-jacobi/history.csv" 2>/dev/null | wc -l) -gt 2 ]] && break
  sleep 0.05
done
sleep 0.2
t0=$(date +%s.%N)
kill -INT "$master"
rc=0
wait "$master" || rc=$?
t1=$(date +%s.%N)
[[ $rc != 0 ]] || { echo "the master did not stop"; exit 1; }
grep -q "interrupted by signal 2" "$work/interrupted.log" || { cat "$work/interrupted.log"; exit 1; }
grep -q '"status": "failed"' "$work/interrupted/rs-xx-jacobi/summary.json"
# A failed run's summary counts the macro steps it completed (history rows
# after t = 0), not 0.
/usr/bin/python3 - "$work/interrupted/rs-xx-jacobi/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["history_rows"] > 1 and s["macro_steps"] == s["history_rows"] - 1, s
PY
awk -v a="$t0" -v b="$t1" 'BEGIN { if (b - a > 1.0) { print "SIGINT took " b - a " s"; exit 1 } }'
echo "a trickling node: named within the deadline, SIGINT within a second"
