#!/usr/bin/env bash
# Ramped inputs through an FMU that follows input derivatives (FMI 2
# canInterpolateInputs: tests/fmus/lumped_soil.c built with
# INPUT_DERIVATIVES=1, lumped_soil2_ramps.fmu), served by fmu_node over TCP
# as the soil of scenes/soil.toml (ss-xx-jacobi, 0.05 s, 10 micro steps):
# - explicit Jacobi with extrapolate1, explicit Gauss-Seidel and implicit
#   Jacobi with linear inputs: within 1e-9 of the built-in soil's same runs (`master
#   compare`; the FMU solves its systems by Thomas' algorithm and ramps its
#   load by the derivatives, round-off apart), and different from the
#   held-input run by more than that (the ramp is not dropped);
# - on the relayed plane the same run bit for bit as on the direct one;
# - its held-input run is judged against a reference with linear inputs
#   (second order), where the FMU without input derivatives gets one with
#   held inputs;
# - the FMU without them (lumped_soil3.fmu) refuses ramped inputs, saying it
#   takes held inputs only (degree 0), and `master fmu check` says so.
# Usage: fmu_ramps_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
source "$(dirname "$0")/fmu_scenes.bash"

soil_scene "$work/soil.toml"
{ echo "[soil]"; soil_mapping lumped_soil2_ramps.fmu; } >"$work/ramps.toml"
{ echo "[soil]"; soil_mapping lumped_soil3.fmu; } >"$work/held.toml"
start ramps "$bin/fmu_node" --role soil --listen 127.0.0.1:0 --config "$work/ramps.toml"
ramps=$address
start held "$bin/fmu_node" --role soil --listen 127.0.0.1:0 --config "$work/held.toml"
held=$address

run() {  # OUT CASE ARGS...: a run that must succeed
  local out=$1 case=$2
  shift 2
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --out "$work/$out" "$@" \
    >"$work/run.log" 2>&1 || fail "the run $out failed" "$work/run.log"
}
agree() {  # A B TOLERANCE
  "$bin/master" compare "$work/$1" "$work/$2" --tolerance "$3" >"$work/compare.log" 2>&1 ||
    fail "$2 differs from $1 beyond $3" "$work/compare.log"
  grep -q '^agree: ' "$work/compare.log" || fail "unexpected verdict" "$work/compare.log"
}

# Explicit Jacobi ramps to an extrapolated value; Gauss-Seidel's later
# participant and an implicit iteration ramp to the value at the step's end.
for variant in "ss-xx-jacobi explicit extrapolate1" "ss-xx-gauss-seidel explicit linear" \
  "ss-xx-jacobi implicit linear"; do
  read -r case coupling inputs <<<"$variant"
  tag="$case-$coupling-$inputs"
  run "fmu-$tag" "$case" --coupling "$coupling" --inputs "$inputs" --node "soil=$ramps" --judge none
  run "builtin-$tag" "$case" --coupling "$coupling" --inputs "$inputs" --judge none
  agree "builtin-$tag" "fmu-$tag" 1e-9
  echo "$tag: $(grep '^agree: ' "$work/compare.log")"
  # The ramp reached the FMU: the run is not the held-input one.
  run "fmu-hold-$tag" "$case" --coupling "$coupling" --node "soil=$ramps" --judge none
  if "$bin/master" compare "$work/fmu-hold-$tag" "$work/fmu-$tag" --tolerance 1e-9 \
    >"$work/compare.log" 2>&1; then
    fail "$tag: the same run as with held inputs (the ramp was dropped)" "$work/compare.log"
  fi
  # The master's relay: the same run as the direct plane's, bit for bit.
  run "fmu-relay-$tag" "$case" --coupling "$coupling" --inputs "$inputs" --data-plane relay \
    --node "soil=$ramps" --judge none
  agree "fmu-$tag" "fmu-relay-$tag" 0
done

# The held-input run judged against a reference with linear inputs.
run fmu-judged ss-xx-jacobi --node "soil=$ramps"
summary="$work/fmu-judged/ss-xx-jacobi/summary.json"
grep -q '"estimate_order": 2,' "$summary" && grep -q 'the reference takes linear inputs instead' "$summary" ||
  fail "not judged against a reference with linear inputs" "$summary"
grep -q 'held inputs instead' "$summary" && fail "the reference fell back to held inputs" "$summary"

# The FMU that does not interpolate its inputs refuses ramps.
if "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --inputs extrapolate1 \
  --node "soil=$held" --judge none --out "$work/refused" >"$work/run.log" 2>&1; then
  fail "ramped inputs were taken by an FMU that does not interpolate them" "$work/run.log"
fi
grep -q 'does not interpolate its inputs' "$work/run.log" && grep -q 'held inputs only (degree 0)' "$work/run.log" ||
  fail "the refusal does not say why" "$work/run.log"
"$bin/master" fmu check "$bin/fmus/lumped_soil3.fmu" >"$work/check.log" 2>&1 || true
grep -q 'ramped or extrapolated inputs .*no: held inputs only (degree 0)' "$work/check.log" ||
  fail "fmu check does not say the FMU takes held inputs only" "$work/check.log"
"$bin/master" fmu check "$bin/fmus/lumped_soil2_ramps.fmu" >"$work/check.log" 2>&1 || true
grep -q 'ramped or extrapolated inputs .*yes: the FMU interpolates its inputs' "$work/check.log" ||
  fail "fmu check does not say the FMU interpolates its inputs" "$work/check.log"
echo "ramped inputs through an FMU: as the built-in soil, refused where the FMU cannot"
