#!/usr/bin/env bash
# The C++ participant SDK as an outside team uses it, from the installed
# package alone: `cmake --install` the build into a fresh prefix, build the
# installed copy of examples/cpp_soil (its own lumped soil) against the
# package with find_package, serve the soil with it (--config: its own
# model from a TOML table; its interface from the master's Configure, not
# from the scene), and compare each run with the same run on the built-in
# soil node with the installed `master compare` (fixed micro steps on both):
# explicit Jacobi and Gauss–Seidel, X-X and X-T, two and three participants,
# the direct and the relayed data plane, implicit coupling with ramped
# inputs (save/restore) and with substep waveforms (degree 3 and 1; the
# waveform run bit for bit alike relayed and in lock step). Then `master
# conform`, the refusals (BAD_REQUEST naming the file and the key; a
# --config the program cannot read) and `master compare`'s exit status on
# runs that differ. And the Python SDK installed with the package: its
# example soil, served from the prefix alone, in an implicit run in lock step.
# Usage: cpp_sdk_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "$1"; [[ -z ${2:-} ]] || cat "$2"; exit 1; }

prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null
bin=$prefix/bin
share=$prefix/share/railcosim
# The installed headers are a closed set: each one's own includes are installed.
include_dir="$prefix/include/railcosim"
for header in "$include_dir"/*.h*; do
  for wanted in $(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$header"); do
    [[ -f $include_dir/$wanted ]] || fail "$(basename "$header") includes $wanted, which is not installed"
  done
done
[[ ! -e $include_dir/server_conn.hpp ]] || fail "an internal header is installed: server_conn.hpp"
# The example reads its interface from the API, never from the product's scene.
! grep -n 'scene\.hpp\|Scene\b\|SubsystemConfig' "$share"/examples/cpp_soil/*.?pp ||
  fail "the installed example still reads the product's scene"
cmake -S "$share/examples/cpp_soil" -B "$work/soil-build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" 2>&1 || fail "configure failed" "$work/configure.log"
cmake --build "$work/soil-build" >"$work/compile.log" 2>&1 || fail "build failed" "$work/compile.log"
soil=$work/soil-build/cpp_soil

# One rate: this test holds the lock step and the waveforms (multirate runs are
# relayed when implicit), so the soil scene's default window is dropped.
sed -e 's/^end_time = .*/end_time = 0.05/' -e '/^ss_macro_step/d' -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' \
  "$share/scenes/soil.toml" >"$work/soil.toml"
grep -q '^micro_steps = 10' "$work/soil.toml"

serve() {  # NAME ARGS...: starts cpp_soil, sets $address
  local name=$1
  shift
  "$soil" --listen 127.0.0.1:0 "$@" >"$work/$name.out" 2>"$work/$name.err" &
  pids+=($!)
  for _ in $(seq 400); do
    grep -q '^listening on ' "$work/$name.out" && break
    sleep 0.1
  done
  address=$(sed -n 's/^listening on //p' "$work/$name.out")
  [[ -n $address ]] || fail "cpp_soil did not start:" "$work/$name.err"
}

"$soil" --help >"$work/help.txt"
grep -q -- '--config' "$work/help.txt" || fail "--help does not list --config" "$work/help.txt"
# Its own model: the [soil] table of the scene file, given with --config.
serve soil --config "$work/soil.toml"
good=$address

run_both() {  # CASE [master options]
  local case=$1
  shift
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --node "soil=$good" \
    --out "$work/outside" "$@" >"$work/master.log" 2>&1 || fail "outside run failed" "$work/master.log"
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --out "$work/builtin" "$@" \
    >"$work/master.log" 2>&1 || fail "built-in run failed" "$work/master.log"
}
run_both wr-xx+ss-xx-jacobi
run_both wr-xt+ss-xt-gauss-seidel
run_both ss-xt-jacobi --data-plane relay
run_both ss-xx-gauss-seidel
grep -q '"data_plane": "direct"' "$work/outside/wr-xx+ss-xx-jacobi/summary.json"
run_both rs-xx+ss-xx-jacobi --coupling implicit --inputs linear
grep -q '"method": "implicit"' "$work/outside/rs-xx+ss-xx-jacobi/summary.json"
# Substep waveforms: the soil takes each micro step's load from Waveform::at
# and records its outputs (in lock step on the direct plane, as relayed).
run_both ss-xx-jacobi --coupling implicit --inputs waveform3
run_both ss-xt-gauss-seidel --coupling implicit --inputs waveform1
grep -q '"data_plane_mode": "lock step"' "$work/outside/ss-xx-jacobi/summary.json" ||
  fail "the waveform run did not go in lock step" "$work/outside/ss-xx-jacobi/summary.json"
"$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --node "soil=$good" \
  --out "$work/relayed" --coupling implicit --inputs waveform3 --data-plane relay \
  >"$work/master.log" 2>&1 || fail "relayed waveform run failed" "$work/master.log"
for f in "$work/relayed/ss-xx-jacobi"/*.csv; do
  cmp "$f" "$work/outside/ss-xx-jacobi/${f##*/}" ||
    fail "${f##*/} of the waveform run differs between the relayed plane and the lock step"
done
"$bin/master" compare "$work/builtin" "$work/outside" --tolerance 1e-9 >"$work/compare.log" ||
  fail "the outside soil does not match the built-in one" "$work/compare.log"
grep -q '^agree: 7 run(s), 21 file(s), 0 over the tolerance 1e-09' "$work/compare.log" ||
  fail "unexpected verdict" "$work/compare.log"
cat "$work/compare.log"

# And it passes the protocol's checklist.
"$bin/master" conform --scene "$work/soil.toml" --node "soil=$good" >"$work/conform.log" 2>&1 ||
  fail "master conform failed" "$work/conform.log"

refused() {  # ADDRESS SCENE PATTERN: a run refused with PATTERN in its message
  if "$bin/master" run --scene "$2" --case ss-xx-jacobi --node "soil=$1" --out "$work/refused" \
    >"$work/refused.log" 2>&1; then
    fail "a run was not refused ($3)" "$work/refused.log"
  fi
  grep -q "$3" "$work/refused.log" || fail "the refusal does not say $3" "$work/refused.log"
}
# Settings the participant cannot run: adaptive micro steps.
refused "$good" "$share/scenes/soil.toml" 'BAD_REQUEST.*set simulation.micro_steps'
# A configuration without a key: BAD_REQUEST naming the file and the key.
sed '/^mass = /d' "$work/soil.toml" >"$work/no_mass.toml"
serve no_mass --config "$work/no_mass.toml"
refused "$address" "$work/soil.toml" "BAD_REQUEST.*no_mass.toml: key 'soil.mass': missing"
# No configuration at all (a built-in soil's scene sends none).
serve bare
refused "$address" "$work/soil.toml" "BAD_REQUEST.*no --config FILE.*key 'soil.mass': missing"
# A --config the program cannot use stops it at once, naming the file.
printf '[soil]\nmass = \n' >"$work/broken.toml"
printf '[ground]\nmass = 1.0\n' >"$work/other.toml"
for bad in broken other; do
  if "$soil" --config "$work/$bad.toml" --check >"$work/$bad.log" 2>&1; then
    fail "cpp_soil accepted --config $bad.toml" "$work/$bad.log"
  fi
  grep -q "$bad.toml" "$work/$bad.log" || fail "the error does not name $bad.toml" "$work/$bad.log"
done
grep -q 'line 2' "$work/broken.log" || fail "the syntax error has no line" "$work/broken.log"
grep -q 'no \[soil\] table' "$work/other.log" || fail "the missing table is not named" "$work/other.log"

# The Python SDK from the package alone: the installed example soil finds the
# SDK and the schema in the prefix (no checkout; a schema cache of its own);
# it runs implicit coupling in lock step and matches the built-in soil.
env -u RAILCOSIM_PROTO RAILCOSIM_SDK_CACHE="$work/sdk-cache" PYTHONDONTWRITEBYTECODE=1 \
  /usr/bin/python3 "$share/examples/python_soil/soil_participant.py" --listen 127.0.0.1:0 \
  --config "$work/soil.toml" >"$work/python.out" 2>"$work/python.err" &
pids+=($!)
for _ in $(seq 600); do
  grep -q '^listening on ' "$work/python.out" && break
  sleep 0.1
done
python=$(sed -n 's/^listening on //p' "$work/python.out")
[[ -n $python ]] || fail "the installed Python example did not start:" "$work/python.err"
"$bin/master" run --scene "$work/soil.toml" --case rs-xx+ss-xx-jacobi --coupling implicit \
  --inputs linear --node "soil=$python" --out "$work/python" >"$work/master.log" 2>&1 ||
  fail "the run on the installed Python soil failed" "$work/master.log"
grep -q '"data_plane_mode": "lock step"' "$work/python/rs-xx+ss-xx-jacobi/summary.json" ||
  fail "the installed Python soil's implicit run was not in lock step" \
    "$work/python/rs-xx+ss-xx-jacobi/summary.json"
"$bin/master" compare "$work/python" "$work/builtin" --tolerance 1e-9 >"$work/python.log" ||
  fail "the installed Python soil does not match the built-in one" "$work/python.log"
grep -q '^agree: 1 run(s), 3 file(s), 0 over the tolerance 1e-09' "$work/python.log" ||
  fail "unexpected verdict" "$work/python.log"

# master compare's exit status: 1 on runs that differ (a value, a file), 2 on
# a file it cannot read.
cp -r "$work/outside" "$work/changed"
history=$work/changed/ss-xt-jacobi/history.csv
awk -F, -v OFS=, 'NR == 20 { $2 = $2 * 1.001 } { print }' "$history" >"$work/h" && mv "$work/h" "$history"
rc=0
"$bin/master" compare "$work/builtin" "$work/changed" --tolerance 1e-9 >"$work/changed.log" || rc=$?
[[ $rc == 1 ]] || fail "compare exits $rc on a changed value" "$work/changed.log"
column=$(head -1 "$history" | cut -d, -f2)
grep -q "^differ: ss-xt-jacobi/history.csv: column $column by" "$work/changed.log" ||
  fail "compare does not name the changed column $column" "$work/changed.log"
rm "$work/changed/ss-xt-jacobi/history.csv" "$work/changed/ss-xx-gauss-seidel/soil.csv"
rc=0
"$bin/master" compare "$work/builtin" "$work/changed" >"$work/changed.log" || rc=$?
[[ $rc == 1 ]] || fail "compare exits $rc on a missing file" "$work/changed.log"
grep -q '^differ: ss-xx-gauss-seidel/soil.csv: missing' "$work/changed.log" || fail "no missing file" "$work/changed.log"
sed -i '3s/^[^,]*/x/' "$work/changed/wr-xx+ss-xx-jacobi/deflection.csv"
rc=0
"$bin/master" compare "$work/builtin" "$work/changed" >"$work/changed.log" 2>&1 || rc=$?
[[ $rc == 2 ]] || fail "compare exits $rc on a value that is not a number" "$work/changed.log"
grep -q "deflection.csv:3: column .*'x' is not a number" "$work/changed.log" || fail "no position" "$work/changed.log"
echo "cpp_soil: 7 cases agree with the built-in soil, conform passes, refusals and compare as expected;" \
  "the installed Python example runs implicit coupling in lock step and agrees too"
