#!/usr/bin/env bash
# A study of a scene whose soil is an FMU its [soil] table maps
# (model = "external", file = the FMU): the study plans the methods the
# FMU's description and mapping allow, leaves the others out saying why,
# hosts the FMU itself (an fmu_node it starts, no --node), and judges every
# run against a co-simulation reference of the same participants:
# - the lumped soil FMU with input derivatives and state save
#   (lumped_soil2_ramps.fmu), mapped for the ss-xx cut: every ss-xx method
#   but substep waveforms runs (extrapolated and implicit ones among them),
#   the ss-xt methods are left out (no ss_in_force in the mapping), no run
#   fails, no monolithic run is planned, and every run is judged against
#   a co-simulation reference with linear inputs (second order);
# - the same soil without state save or input derivatives
#   (lumped_soil3_nostate.fmu): only explicit held-input methods run, each
#   `not judged` because the FMU cannot save its state.
# - the built-in vehicle exported as an FMU (railcosim_vehicle.fmu, which
#   cannot vary its communication step) mapped by [vehicle.fmu] on the
#   paper scene: the sweep keeps to its default experiment's step, saying
#   so; only held-input wr-xx methods run, none fails, each not judged
#   (no reference at a finer step can be made).
# Usage: fmu_study_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
source "$(dirname "$0")/fmu_scenes.bash"

each_run() {  # STUDY COUNT WHAT PATTERN...: COUNT runs, each summary.json matching every PATTERN
  local study=$1 count=$2 what=$3 runs=0 summary pattern
  shift 3
  while IFS= read -r summary; do
    runs=$((runs + 1))
    for pattern in "$@"; do
      grep -q "$pattern" "$summary" || fail "a run is not $what" "$summary"
    done
  done < <(find "$study" -name summary.json -not -path '*/references/*')
  [[ $runs -eq $count ]] || fail "$runs runs in $study, expected $count"
}
study() {  # SCENE OUT
  "$bin/master" study --scene "$1" --out "$2" --macro-steps 1e-4,2e-4 >"$work/study.log" 2>&1 ||
    fail "the study of $1 failed" "$work/study.log"
  grep -q '(0 failed, 0 missing' "$work/study.log" || fail "runs failed or are missing" "$work/study.log"
  grep -q 'monolithic' "$2/plan.txt" && fail "a monolithic run was planned" "$2/plan.txt"
  return 0
}

mapped_soil_scene lumped_soil2_ramps.fmu "$work/ramps.toml"
study "$work/ramps.toml" "$work/ramps"
for method in ss-xx-jacobi ss-xx-gauss-seidel ss-xx-jacobi+explicit-extrapolate1 \
  ss-xx-jacobi+implicit-linear-iqn-ils; do
  cut -d, -f3 "$work/ramps/summary.csv" | grep -qx "$method" || fail "$method did not run" "$work/ramps/summary.csv"
done
cut -d, -f3 "$work/ramps/summary.csv" | grep -q 'ss-xt' && fail "an ss-xt method ran" "$work/ramps/summary.csv"
cut -d, -f3 "$work/ramps/summary.csv" | grep -q 'waveform' && fail "a waveform method ran" "$work/ramps/summary.csv"
grep -q 'ss-xt-jacobi is left out: its mapping does not serve this case (the soil FMU' "$work/study.log" ||
  fail "the study does not say why the ss-xt methods are left out" "$work/study.log"
grep -q 'implicit-waveform3-iqn-ils is left out: the soil FMU takes no substep waveforms' "$work/study.log" ||
  fail "the study does not say why the waveform method is left out" "$work/study.log"
each_run "$work/ramps" 8 "judged against a co-simulation reference with linear inputs" \
  '"kind": "co-simulation"' '"estimate_order": 2,'
echo "soil FMU with ramps and state: 8 runs, each judged against a co-simulation reference"

mapped_soil_scene lumped_soil3_nostate.fmu "$work/nostate.toml"
study "$work/nostate.toml" "$work/nostate"
cut -d, -f3 "$work/nostate/summary.csv" | grep -q 'implicit\|extrapolate' &&
  fail "an implicit or ramped method ran with an FMU that cannot take them" "$work/nostate/summary.csv"
grep -q 'implicit-linear-iqn-ils is left out: the soil FMU does not interpolate its inputs' "$work/study.log" ||
  fail "the study does not say why the ramped methods are left out" "$work/study.log"
each_run "$work/nostate" 4 "not judged because the FMU cannot save its state" \
  '"status": "not_judged"' 'not judged: the soil FMU cannot save its state'
echo "soil FMU without state save: 4 explicit runs, each not judged for that reason"

sed -e 's/^end_time = .*/end_time = 0.05/' "$src/scenes/paper.toml" >"$work/vfmu.toml"
cat >>"$work/vfmu.toml" <<TOML
[vehicle.fmu]
file = "$bin/fmus/railcosim_vehicle.fmu"
wr_in_displacement = "wr_in_displacement"
wr_out_displacement = "wr_out_displacement"
history_wheel_m = "wheel_m"
history_contact_force_N = "contact_force_N"
TOML
study "$work/vfmu.toml" "$work/vfmu"
grep -q "the vehicle FMU cannot vary its communication step: the sweep keeps to its default experiment's 0.0001 s" \
  "$work/study.log" || fail "the study does not say why it sweeps one macro step" "$work/study.log"
methods=$(cut -d, -f3 "$work/vfmu/summary.csv" | tail -n +2 | sort | tr '\n' ' ')
[[ $methods == "wr-xx-gauss-seidel wr-xx-jacobi " ]] || fail "methods run: $methods" "$work/vfmu/summary.csv"
cut -d, -f17 "$work/vfmu/summary.csv" | tail -n +2 | grep -vqx not_judged &&
  fail "a run of the vehicle FMU is judged without a reference" "$work/vfmu/summary.csv"
echo "vehicle FMU with one communication step: $methods at H = 1e-4 s, not judged"
