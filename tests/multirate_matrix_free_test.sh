#!/usr/bin/env bash
# The multirate ρ through the participants (matrix-free, a soil served by
# soil_node given by --node) against the product's own dense map of the same
# physics (the built-in soil in process), on scenes/soil.toml with the soil's
# cut at its window of 5 H (10 micro steps, so that both describe the same
# map): for the two unstable multirate cases the growth rates per second
# agree within 2 %, both say ρ is per slow window of 0.0005 s, and both
# label the run unstable.
# Usage: multirate_matrix_free_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
fail() { echo "$1"; [[ -z ${2:-} ]] || cat "$2"; exit 1; }

sed -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' "$src/scenes/soil.toml" >"$work/soil.toml"
grep -q '^ss_macro_step = 5e-4' "$work/soil.toml" || fail "the scene has no ss window of 5 H"
start soil "$bin/soil_node" --listen 127.0.0.1:0
rate() {  # SUMMARY: the stability's rho_rate_per_s
  /usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["stability"]["rho_rate_per_s"])' "$1"
}
for case in wr-xt+ss-xx-gauss-seidel wr-xt+ss-xx-jacobi; do
  for how in dense node; do
    extra=()
    [[ $how == node ]] && extra=(--node "soil=$address")
    "$bin/master" run --scene "$work/soil.toml" --case "$case" --judge stability "${extra[@]}" \
      --out "$work/$how" >"$work/$how.log" 2>&1 || fail "$case ($how) failed" "$work/$how.log"
    grep -q "^$case: amplified, " "$work/$how.log" &&
      grep -q "^  unstable: at rest: ρ = [0-9.]* per slow window (0.0005 s)" "$work/$how.log" ||
      fail "$case ($how): not unstable per slow window" "$work/$how.log"
  done
  grep -q '"basis": "matrix-free"' "$work/node/$case/summary.json" ||
    fail "$case: the node's run was not measured matrix-free" "$work/node/$case/summary.json"
  dense=$(rate "$work/dense/$case/summary.json")
  free=$(rate "$work/node/$case/summary.json")
  /usr/bin/python3 -c 'import sys; d, f = map(float, sys.argv[1:]); sys.exit(abs(f - d) > 0.02 * abs(d))' \
    "$dense" "$free" || fail "$case: matrix-free rate $free 1/s, dense $dense 1/s: more than 2 % apart"
  echo "$case: rate per second, dense map $dense, matrix-free $free"
done
