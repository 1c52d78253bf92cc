#!/usr/bin/env bash
# The C++ participant SDK as an outside team uses it: `cmake --install` the
# build into a fresh prefix, build examples/cpp_soil (its own lumped soil,
# outside the tree) against the installed package with find_package, serve
# the soil with it, and compare each run with the same run on the built-in
# soil node (fixed micro steps on both): explicit Jacobi and Gauss–Seidel,
# X-X and X-T, two and three participants, the direct and the relayed data
# plane, and implicit coupling with ramped inputs (save/restore).
# Usage: cpp_sdk_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
src=$2
bin=$build/bin
work=$(mktemp -d)
participant=""
cleanup() {
  [[ -n $participant ]] && kill "$participant" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

cmake --install "$build" --prefix "$work/prefix" >/dev/null
# The installed headers are a closed set: each one's own includes are installed.
include_dir="$work/prefix/include/railcosim"
for header in "$include_dir"/*.h*; do
  for wanted in $(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$header"); do
    [[ -f $include_dir/$wanted ]] || { echo "$(basename "$header") includes $wanted, which is not installed"; exit 1; }
  done
done
[[ ! -e $include_dir/server_conn.hpp ]] || { echo "an internal header is installed: server_conn.hpp"; exit 1; }
cmake -S "$src/examples/cpp_soil" -B "$work/soil-build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/soil-build" >"$work/compile.log" 2>&1 || { cat "$work/compile.log"; exit 1; }

sed -e 's/^end_time = .*/end_time = 0.05/' -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' \
  "$src/scenes/soil.toml" >"$work/soil.toml"
grep -q '^micro_steps = 10' "$work/soil.toml"

"$work/soil-build/cpp_soil" --listen 127.0.0.1:0 >"$work/participant.out" 2>"$work/participant.err" &
participant=$!
for _ in $(seq 400); do
  grep -q '^listening on ' "$work/participant.out" && break
  sleep 0.1
done
address=$(sed -n 's/^listening on //p' "$work/participant.out")
[[ -n $address ]] || { echo "cpp_soil did not start:"; cat "$work/participant.err"; exit 1; }

run_both() {  # CASE [master options]
  local case=$1
  shift
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --node "soil=$address" \
    --out "$work/outside" "$@" >"$work/master.log" 2>&1 || { cat "$work/master.log"; exit 1; }
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --out "$work/builtin" "$@" \
    >"$work/master.log" 2>&1 || { cat "$work/master.log"; exit 1; }
}
run_both wr-xx+ss-xx-jacobi
run_both wr-xt+ss-xt-gauss-seidel
run_both ss-xt-jacobi --data-plane relay
run_both ss-xx-gauss-seidel
grep -q '"data_plane": "direct"' "$work/outside/wr-xx+ss-xx-jacobi/summary.json"
run_both rs-xx+ss-xx-jacobi --coupling implicit --inputs linear
grep -q '"method": "implicit"' "$work/outside/rs-xx+ss-xx-jacobi/summary.json"
# A configuration the participant refuses reaches the user with its reason.
if "$bin/master" run --scene "$src/scenes/soil.toml" --case ss-xx-jacobi --node "soil=$address" \
  --out "$work/refused" >"$work/refused.log" 2>&1; then
  echo "a scene without fixed micro steps was not refused"; exit 1
fi
grep -q 'BAD_INTERFACE.*set simulation.micro_steps' "$work/refused.log" || { cat "$work/refused.log"; exit 1; }
# And it passes the protocol's checklist.
"$bin/master" conform --scene "$work/soil.toml" --node "soil=$address" >"$work/conform.log" 2>&1 ||
  { cat "$work/conform.log"; exit 1; }
/usr/bin/python3 "$src/tests/compare_runs.py" "$work/builtin" "$work/outside" 1e-9
