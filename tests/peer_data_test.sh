#!/usr/bin/env bash
# Bad data on a peer link of the direct data plane (tests/corrupt_proxy.py
# rewrites the 20th data frame the soil node sends its peer): a non-finite
# value, then a point far in the future. Each run fails (exit 1) naming the
# soil participant as the sender, and history.csv keeps every step all
# participants completed before it.
# Usage: peer_data_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
bin=$1
src=$2
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

start() {  # NAME COMMAND...: sets $address from its "listening on" line
  local name=$1
  shift
  "$@" >"$work/$name.out" 2>"$work/$name.err" &
  pids+=($!)
  for _ in $(seq 200); do
    grep -q '^listening on ' "$work/$name.out" && break
    sleep 0.05
  done
  address=$(sed -n 's/^listening on //p' "$work/$name.out")
  [[ -n $address ]] || { echo "$name did not start"; cat "$work/$name.err"; exit 1; }
}

check() {  # MODE EXPECTED_MESSAGE
  start "soil-$1" "$bin/soil_node" --listen 127.0.0.1:0
  start "proxy-$1" /usr/bin/python3 "$src/tests/corrupt_proxy.py" "$address" \
    "$src/protocol/railcosim.proto" "$1" 20
  local rc=0
  "$bin/master" run --scene "$src/scenes/soil.toml" --case ss-xx-jacobi --node "soil=$address" \
    --out "$work/$1" >"$work/$1.log" 2>&1 || rc=$?
  [[ $rc == 1 ]] || { echo "$1: exit $rc, expected 1"; cat "$work/$1.log"; exit 1; }
  grep -q "$2" "$work/$1.log" || { echo "$1: the sender is not named"; cat "$work/$1.log"; exit 1; }
  # Points 0..18 reached the peer whole: t = 0 and 19 macro steps, plus the header.
  local rows
  rows=$(wc -l <"$work/$1/ss-xx-jacobi/history.csv")
  [[ $rows == 21 ]] || { echo "$1: history.csv has $rows lines, expected 21"; exit 1; }
}
check nan "the soil participant at [0-9.:]* sent a non-finite value for point 19"
check jump "the soil participant at [0-9.:]* sent data for point 1000000019 where point 19 was due"
echo "bad peer data: refused, the sender named, the history kept"
