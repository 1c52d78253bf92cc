#!/usr/bin/env bash
# Bad data on a peer link of the direct data plane (tests/corrupt_proxy.py
# rewrites the 20th data frame the soil node sends its peer): a non-finite
# value, then a point far in the future. Each run fails (exit 1) naming the
# soil participant as the sender, and history.csv keeps every step all
# participants completed before it.
# The same with the Python SDK's soil as the receiver of bad data.
# Usage: peer_data_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
export RAILCOSIM_SDK_CACHE=$work/cache
# The Python soil integrates with fixed micro steps: the soil scene with 10.
# One rate: the peer links of the direct plane's windows (the soil scene's
# default window for the soil is dropped).
sed -e '/^ss_macro_step/d' "$src/scenes/soil.toml" >"$work/soil.toml"
sed -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' "$work/soil.toml" >"$work/soil10.toml"

check() {  # NAME EXPECTED_MESSAGE SOIL DIRECTION BLAMED
  if [[ ${3:-built-in} == python ]]; then
    start "soil-$1" /usr/bin/python3 "$src/examples/python_soil/soil_participant.py" \
      --config "$work/soil10.toml"
  else
    start "soil-$1" "$bin/soil_node" --listen 127.0.0.1:0
  fi
  start "proxy-$1" /usr/bin/python3 "$src/tests/corrupt_proxy.py" "$address" \
    "$src/protocol/railcosim.proto" "${1%-sdk}" 20 "${4:-from}"
  local rc=0
  local scene=$work/soil.toml
  [[ $3 == python ]] && scene=$work/soil10.toml
  "$bin/master" run --scene "$scene" --case ss-xx-jacobi --node "soil=$address" \
    --out "$work/$1" >"$work/$1.log" 2>&1 || rc=$?
  [[ $rc == 1 ]] || { echo "$1: exit $rc, expected 1"; cat "$work/$1.log"; exit 1; }
  grep -q "$2" "$work/$1.log" || { echo "$1: the sender is not named"; cat "$work/$1.log"; exit 1; }
  # Points 0..18 reached the peer whole: t = 0 and 19 macro steps, plus the header.
  local rows
  rows=$(wc -l <"$work/$1/ss-xx-jacobi/history.csv")
  # The sender is blamed by the master (the error's sender field), not the receiver.
  grep -q "^master: ss-xx-jacobi failed: $5 node" "$work/$1.log" ||
    { echo "$1: the master does not blame the $5 node"; cat "$work/$1.log"; exit 1; }
  [[ $rows == 21 ]] || { echo "$1: history.csv has $rows lines, expected 21"; exit 1; }
}
check nan "the soil participant at [0-9.:]* sent a non-finite value for point 19" built-in from soil
check jump "the soil participant at [0-9.:]* sent data for point 1000000019 where point 19 was due" \
  built-in from soil
# The Python SDK checks what it receives the same way.
check nan-sdk "the vehicle participant.* sent a non-finite value for point 19" python to vehicle
check jump-sdk "the vehicle participant.* sent data for point 1000000019 where point 19 was due" \
  python to vehicle
echo "bad peer data: refused, the sender named, the history kept"
