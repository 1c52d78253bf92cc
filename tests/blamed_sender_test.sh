#!/usr/bin/env bash
# A node that sends bad data is the one blamed, however many links the
# receiver has and on either data plane (tests/corrupt_proxy.py sits in
# front of the sender):
# - the soil of wr-xx+ss-xx-jacobi sends the track (which has two peer
#   links, to the vehicle and to the soil) one value too few, or a frame
#   that is no message: the run fails naming the soil node;
# - the vehicle of wr-xx-gauss-seidel with substep waveforms reports samples
#   1000 s after its step, relayed and in lock step on the direct plane: the
#   run fails naming the vehicle node, the sample's time and the macro step.
# Usage: blamed_sender_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"

expect() {  # NAME LOG PATTERN: the run failed (exit 1) and its log holds PATTERN
  grep -q -- "$3" "$2" || { echo "$1: expected '$3'"; cat "$2"; exit 1; }
}

two_links() {  # MODE EXPECTED_MESSAGE
  start "soil-$1" "$bin/soil_node" --listen 127.0.0.1:0
  start "proxy-$1" /usr/bin/python3 "$src/tests/corrupt_proxy.py" "$address" \
    "$src/protocol/railcosim.proto" "$1" 20 from
  local rc=0
  "$bin/master" run --scene "$src/scenes/soil.toml" --case wr-xx+ss-xx-jacobi --macro-step ss=1e-4 \
    --node "soil=$address" --out "$work/$1" >"$work/$1.log" 2>&1 || rc=$?
  [[ $rc == 1 ]] || { echo "$1: exit $rc, expected 1"; cat "$work/$1.log"; exit 1; }
  expect "$1" "$work/$1.log" "$2"
  expect "$1" "$work/$1.log" "^master: wr-xx+ss-xx-jacobi failed: soil node"
}
two_links short "the soil participant at [0-9.:]* sent [0-9]* [a-z]* values for point 19 on interface"
two_links garbage "the soil participant at [0-9.:]* sent a frame that is not a message at macro step"

shifted() {  # DATA_PLANE
  start "vehicle-$1" "$bin/vehicle_node" --listen 127.0.0.1:0
  start "proxy-$1" /usr/bin/python3 "$src/tests/corrupt_proxy.py" "$address" \
    "$src/protocol/railcosim.proto" shift 20
  local rc=0
  "$bin/master" run --scene "$src/scenes/paper.toml" --case wr-xx-gauss-seidel \
    --inputs waveform1 --data-plane "$1" --vehicle "$address" --out "$work/shift-$1" \
    >"$work/shift-$1.log" 2>&1 || rc=$?
  [[ $rc == 1 ]] || { echo "shift-$1: exit $rc, expected 1"; cat "$work/shift-$1.log"; exit 1; }
  expect "shift-$1" "$work/shift-$1.log" \
    "failed: vehicle node at $address: bad reply: sample 0 of the step report at t = 1000.0019 s lies outside the step's window \[0.0019, 0.002\] s (tolerance 1e-07 s) at macro step 19 "
}
shifted relay
shifted direct
echo "bad data and bad sample times: the sender named"
