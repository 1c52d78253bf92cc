#!/usr/bin/env bash
# The conformance kit (master conform) passes on every built-in node, with
# and without a shared secret, and fails on purpose-broken participants
# (tests/broken_node.cpp, tests/broken_peer_soil.py) naming the item that
# catches each; the example soil on the Python SDK passes too.
# Usage: conform_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
sed -e 's/^end_time = .*/end_time = 0.02/' -e '/^ss_macro_step/d' "$src/scenes/soil.toml" >"$work/soil.toml"
# The Python soil integrates with fixed micro steps.
sed -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' "$work/soil.toml" >"$work/soil10.toml"
export RAILCOSIM_SDK_CACHE=$work/cache
(umask 077; head -c 32 /dev/urandom | base64 >"$work/token")

serve() {  # NAME PROGRAM [ARGS]: starts a node, sets $address
  local name=$1
  shift
  start "$name" "$@" --listen 127.0.0.1:0
}

conform() {  # EXPECTED_STATUS LOG ARGS...: runs master conform, checks its status
  local want=$1 log=$2
  shift 2
  local rc=0
  "$bin/master" conform --scene "${scene:-$work/soil.toml}" "$@" >"$work/$log" 2>&1 || rc=$?
  if [[ $rc != "$want" ]]; then
    echo "master conform $* exited $rc, expected $want:"; cat "$work/$log"; exit 1
  fi
}

for role in vehicle track soil; do
  serve "$role" "$bin/${role}_node"
  conform 0 "$role.log" --node "$role=$address"
  grep -q '^16 passed, 0 failed, 1 skipped$' "$work/$role.log" || { cat "$work/$role.log"; exit 1; }
done
serve secret "$bin/soil_node" --token-file "$work/token"
conform 0 secret.log --node "soil=$address" --token-file "$work/token"
grep -q '^18 passed, 0 failed, 0 skipped$' "$work/secret.log" || { cat "$work/secret.log"; exit 1; }

# The example soil on the Python SDK.
scene=$work/soil10.toml
serve sdk /usr/bin/python3 "$src/examples/python_soil/soil_participant.py" --config "$work/soil10.toml"
conform 0 sdk.log --node "soil=$address"
grep -q '^16 passed, 0 failed, 1 skipped$' "$work/sdk.log" || { cat "$work/sdk.log"; exit 1; }
# A soil that replays the replies it recorded from the example soil: it
# passes the items whose requests it has seen, and fails the two that send
# inputs never sent before (another seed than the recording's; once they
# fail, its replies fall out of step with the requests and later items may
# fail too).
serve record /usr/bin/python3 "$src/tests/replay_soil.py" "$src" --record "$work/replies.jsonl" \
  --config "$work/soil10.toml"
conform 0 record.log --node "soil=$address" --seed 1
serve replay /usr/bin/python3 "$src/tests/replay_soil.py" "$src" --replay "$work/replies.jsonl" \
  --config "$work/soil10.toml"
conform 1 replay.log --node "soil=$address" --seed 2
for item in "statics under loads never sent before" "a restore followed by new inputs"; do
  grep -q "^  FAIL  .*$item" "$work/replay.log" ||
    { echo "replay: '$item' did not fail:"; cat "$work/replay.log"; exit 1; }
done
serve broken-peer /usr/bin/python3 "$src/tests/broken_peer_soil.py" "$src" --config "$work/soil10.toml"
conform 1 broken-peer.log --node "soil=$address"
grep -q '^  FAIL  .*a wrong session key and an unexpected peer are refused' "$work/broken-peer.log" ||
  { echo "broken-peer: the peer item did not fail:"; cat "$work/broken-peer.log"; exit 1; }
scene=

expect_failure() {  # MODE ITEM_TEXT: the broken node fails exactly that item (and maybe others)
  local mode=$1 item=$2
  serve "$mode" "$bin/broken_node" "$mode"
  conform 1 "$mode.log" --node "soil=$address"
  grep -q "^  FAIL  .*$item" "$work/$mode.log" || { echo "$mode: '$item' did not fail:"; cat "$work/$mode.log"; exit 1; }
}
expect_failure ignores-restore "save and restore: the steps after a restore repeat bit for bit"
expect_failure late "every step answered within the reply deadline"
expect_failure wrong-count "macro steps, relayed"
expect_failure accepts-nan "a non-finite input is refused"
echo "conformance kit: built-in nodes and the Python SDK soil pass, a replaying soil and five broken participants fail their items"
