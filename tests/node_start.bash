# Sourced by the shell tests that start nodes (blamed_sender_test.sh,
# peer_data_test.sh, trickle_test.sh, conform_test.sh, python_soil_test.sh):
# the arguments BIN_DIR SOURCE_DIR as $bin and $src, a scratch folder $work of the test's own
# (mktemp, so tests that run side by side never share it), removed on exit
# with every process start() began, and start() itself.
# Usage (at the top of a test): source "$(dirname "$0")/node_start.bash" "$@"
bin=$1
src=$2
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

start() {  # NAME COMMAND...: sets $address from its "listening on" line (40 s at most)
  local name=$1
  shift
  "$@" >"$work/$name.out" 2>"$work/$name.err" &
  pids+=($!)
  for _ in $(seq 800); do
    grep -q '^listening on ' "$work/$name.out" && break
    sleep 0.05
  done
  address=$(sed -n 's/^listening on //p' "$work/$name.out")
  [[ -n $address ]] || { echo "$name did not start"; cat "$work/$name.err"; exit 1; }
}
