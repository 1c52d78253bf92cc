#!/usr/bin/env bash
# The lumped soil as an FMI 3.0 FMU (tests/fmus/lumped_soil.c), served by
# fmu_node over TCP as the soil of scenes/soil.toml, against the built-in
# lumped soil: ss-xx-jacobi explicit and implicit (the implicit run saves
# and restores the FMU's state in lock step), each within 1e-9 of the
# built-in run by `master compare` (the FMU solves its tridiagonal systems
# by Thomas' algorithm, the built-in soil otherwise: round-off apart).
# Usage: fmu_node_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
fail() { echo "$1"; [[ -z ${2:-} ]] || cat "$2"; exit 1; }

sed -e 's/^end_time = .*/end_time = 0.05/' -e '/^ss_macro_step/d' \
  -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' "$src/scenes/soil.toml" >"$work/soil.toml"
grep -q '^micro_steps = 10' "$work/soil.toml" || fail "the scene was not edited"
cat >"$work/fmu.toml" <<TOML
[soil]
file = "$bin/fmus/lumped_soil3.fmu"
ss_in_displacement = "w_{i}"
ss_in_velocity = "wd_{i}"
ss_out_displacement = "u_{i}"
ss_out_velocity = "ud_{i}"
# The scene's [soil], [ballast] and simulation.micro_steps.
set_mass = 699.6
set_stiffness = 121.08e6
set_damping = 341.9e3
set_coupling_stiffness = 43.72e6
set_coupling_damping = 0.0
set_ballast_stiffness = 25.5e6
set_ballast_damping = 40e3
set_micro_steps = 10
# What the built-in soil records: its peak and its masses at the end.
peak_history = "soil_peak_m"
result_soil_m = "u_{i}"
TOML
start fmu "$bin/fmu_node" --role soil --listen 127.0.0.1:0 --config "$work/fmu.toml"
soil=$address

for coupling in explicit implicit; do
  "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --coupling "$coupling" \
    --node "soil=$soil" --out "$work/fmu-$coupling" >"$work/run.log" 2>&1 ||
    fail "the run with the FMU soil failed ($coupling)" "$work/run.log"
  grep -m1 "^ss-xx-jacobi: " "$work/run.log" || fail "no summary line ($coupling)" "$work/run.log"
  "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --coupling "$coupling" \
    --out "$work/builtin-$coupling" >"$work/run.log" 2>&1 ||
    fail "the built-in run failed ($coupling)" "$work/run.log"
  "$bin/master" compare "$work/builtin-$coupling" "$work/fmu-$coupling" --tolerance 1e-9 \
    >"$work/compare.log" 2>&1 || fail "the FMU soil differs from the built-in one ($coupling)" "$work/compare.log"
  grep -q '^agree: ' "$work/compare.log" || fail "unexpected verdict" "$work/compare.log"
  cat "$work/compare.log"
done
echo "1 passed, 0 failed"
