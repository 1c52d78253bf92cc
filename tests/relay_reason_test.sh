#!/usr/bin/env bash
# Why a run on the direct data plane stays relayed, said truly: a soil on the
# Python SDK that offers the direct plane's windows but not the lock step
# (its hello reply declares "direct" only) takes explicit coupling with held
# inputs on the direct plane; an implicit run with it is relayed, and the
# master's log names the lock step and the soil node at its address.
# Usage: relay_reason_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
bin=$1
src=$2
work=$(mktemp -d)
pid=
cleanup() {
  [[ -n $pid ]] && kill "$pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
export RAILCOSIM_SDK_CACHE=$work/cache
sed -e 's/^end_time = .*/end_time = 0.002/' -e '/^ss_macro_step/d' -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' \
  "$src/scenes/soil.toml" >"$work/soil.toml"
grep -q '^micro_steps = 10' "$work/soil.toml"

cat >"$work/direct_only.py" <<PY
import runpy, sys
sys.path.insert(0, "$src/sdk/python")
from railcosim_sdk import lockstep
plain = lockstep.LockstepSession.hello_reply
def direct_only(self, out):
    out = plain(self, out)
    kept = [c for c in out.hello_reply.capabilities if c == "direct"]
    del out.hello_reply.capabilities[:]
    out.hello_reply.capabilities.extend(kept)
    return out
lockstep.LockstepSession.hello_reply = direct_only
ns = runpy.run_path("$src/examples/python_soil/soil_participant.py")
ns["rc"].serve(ns["LumpedSoil"]())
PY
/usr/bin/python3 "$work/direct_only.py" --config "$work/soil.toml" >"$work/soil.out" 2>"$work/soil.err" &
pid=$!
for _ in $(seq 400); do
  grep -q '^listening on ' "$work/soil.out" 2>/dev/null && break
  sleep 0.1
done
address=$(sed -n 's/^listening on //p' "$work/soil.out")
[[ -n $address ]] || { echo "the soil did not start:"; cat "$work/soil.err"; exit 1; }

run() {  # NAME [master options]
  local name=$1
  shift
  "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --node "soil=$address" \
    --data-plane direct --out "$work/$name" "$@" >"$work/$name.log" 2>&1 ||
    { cat "$work/$name.log"; exit 1; }
}
expect() {  # FILE TEXT
  grep -qF -- "$2" "$1" || { echo "$1 does not say: $2"; cat "$1"; exit 1; }
}
run windows
expect "$work/windows/ss-xx-jacobi/summary.json" '"data_plane_mode": "windows"'
run implicit --coupling implicit
expect "$work/implicit/ss-xx-jacobi/summary.json" '"data_plane": "relay"'
expect "$work/implicit.log" "ss-xx-jacobi: relayed data plane (the lock step, which implicit \
coupling and ramped inputs need on the direct plane, is not offered by soil node at $address)"
echo "relayed for want of the lock step, and the log says so"
