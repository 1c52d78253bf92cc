#!/usr/bin/env bash
# An outside participant for real: the soil of examples/python_soil, written
# on the Python SDK (sdk/python/railcosim_sdk), serves the soil over TCP. Every
# run must agree with the same run on the built-in soil node to 1e-12
# relative: relayed and direct data planes, explicit and implicit coupling,
# two and three participants, resolved feedthrough, a shared secret. A soil
# that ignores Restore must be caught by the implicit comparison; a soil whose
# integrator gives up while nothing grows must end the run failed (a
# participant's word alone is not a divergence), with its message. Substep
# waveforms (degree 1 and 3) in lock step and relayed, bit for bit alike.
# Usage: python_soil_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
source "$(dirname "$0")/node_start.bash" "$@"
export RAILCOSIM_SDK_CACHE=$work/cache

# The soil scene, shortened, with 10 fixed micro steps per macro step.
sed -e 's/^end_time = .*/end_time = 0.005/' -e '/^ss_macro_step/d' -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' \
  "$src/scenes/soil.toml" >"$work/soil.toml"
grep -q '^micro_steps = 10' "$work/soil.toml"

participant() {  # NAME PROGRAM [options]: start(); a .py program with the scene as --config
  local name=$1 program=$2
  shift 2
  if [[ $program == *.py ]]; then
    start "$name" /usr/bin/python3 "$program" --config "$work/soil.toml" "$@"
  else
    start "$name" "$program" "$@"
  fi
}
participant sdk "$src/examples/python_soil/soil_participant.py"
good=$address
# A purpose-broken soil: it ignores Restore.
cat >"$work/broken.py" <<PY
import runpy, sys
ns = runpy.run_path("$src/examples/python_soil/soil_participant.py")
class Forgetful(ns["LumpedSoil"]):
    def restore(self, state):
        pass
ns["rc"].serve(Forgetful())
PY
participant broken "$work/broken.py"
broken=$address
# A soil whose integrator gives up at macro step 10 (StepFailed).
cat >"$work/gives_up.py" <<PY
import runpy
ns = runpy.run_path("$src/examples/python_soil/soil_participant.py")
class GivesUp(ns["LumpedSoil"]):
    def advance(self, t, H, inputs):
        if t >= 10 * H:
            raise ns["rc"].StepFailed("the soil gives up at t = %g s" % t)
        return super().advance(t, H, inputs)
ns["rc"].serve(GivesUp())
PY
participant gives-up "$work/gives_up.py"
gives_up=$address
# With a shared secret: the upper node and the SDK soil authenticate the
# master and each other (the vehicle node, holding the track down to the
# sleepers in ss-only cases, opens the peer link to the soil).
(umask 077; echo "a shared secret of the run" >"$work/token")
participant secret-soil "$src/examples/python_soil/soil_participant.py" --token-file "$work/token"
secret_soil=$address
participant secret-upper "$bin/vehicle_node" --listen 127.0.0.1:0 --token-file "$work/token"
secret_upper=$address

run() {  # OUT NAME CASE [master options]: one run; NAME the run's folder under OUT
  # (OUT "failed": the run must fail, exit status 1)
  local out=$1 name=$2 case=$3 rc=0 want=0
  shift 3
  [[ $out == failed ]] && want=1
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --out "$work/tmp" "$@" \
    >"$work/master.log" 2>&1 || rc=$?
  [[ $rc == "$want" ]] || { echo "master exited $rc, not $want:"; cat "$work/master.log"; exit 1; }
  mkdir -p "$work/$out"
  mv "$work/tmp/$case" "$work/$out/$name"
  rm -rf "$work/tmp"
}
both() {  # NAME CASE [master options]: the SDK soil and the built-in one
  local name=$1 case=$2
  shift 2
  run outside "$name" "$case" --node "soil=$good" "$@"
  run builtin "$name" "$case" "$@"
  grep -q '"transport": "tcp"' "$work/outside/$name/summary.json"
}
for plane in relay direct; do
  both "3-jacobi-$plane" wr-xx+ss-xx-jacobi --data-plane "$plane"
  both "3-gs-$plane" wr-xt+ss-xt-gauss-seidel --data-plane "$plane"
  both "2-xt-jacobi-$plane" ss-xt-jacobi --data-plane "$plane"
  # The force the soil holds is resolved with fresh displacements (SetInputs,
  # GetOutputs relayed; the track's second sending on the direct plane).
  both "2-xt-resolved-$plane" ss-xt-jacobi --feedthrough resolved --data-plane "$plane"
done
run outside 2-secret ss-xx-jacobi --node "soil=$secret_soil" --node "vehicle=$secret_upper" \
  --token-file "$work/token"
run builtin 2-secret ss-xx-jacobi
grep -q '"data_plane": "direct"' "$work/outside/2-secret/summary.json"
# StepFailed with nothing growing: the run failed at that step, with the
# soil's words and why it is not judged diverged, on both planes.
for plane in relay direct; do
  run failed "gives-up-$plane" wr-xx+ss-xx-jacobi --node "soil=$gives_up" --data-plane "$plane"
  summary=$work/failed/gives-up-$plane/summary.json
  grep -q '"status": "failed"' "$summary" && grep -q '"macro_steps": 10,' "$summary" &&
    grep -q 'the soil gives up at t = 0.001 s at macro step 10' "$summary" &&
    grep -q 'not judged diverged: the displacements reported until then show no growth' \
      "$summary" || {
    echo "a soil that gives up at macro step 10 ($plane plane):"
    cat "$summary"
    exit 1
  }
done
grep -q '"data_plane": "direct"' "$work/outside/3-jacobi-direct/summary.json" || {
  echo "the direct runs did not use the direct plane:"
  cat "$work/outside/3-jacobi-direct/summary.json"
  exit 1
}
# Implicit coupling with ramped inputs: Save/Restore and inputs_end.
both 2-implicit ss-xx-jacobi --coupling implicit --inputs linear
both 3-implicit wr-xx+ss-xx-jacobi --coupling implicit
grep -q '"method": "implicit"' "$work/outside/2-implicit/summary.json"
run forgetful 2-implicit ss-xx-jacobi --node "soil=$broken" --coupling implicit --inputs linear
rm -rf "$work/tmp"

compare() {  # A B [expect-differ]; TOLERANCE (default 1e-12) the relative bound
  /usr/bin/python3 - "$@" <<'PY'
import csv, os, sys
a_dir, b_dir = sys.argv[1], sys.argv[2]
differ = len(sys.argv) > 3
worst, where = 0.0, ""
for case in sorted(os.listdir(b_dir)):
    for name in ("deflection.csv", "history.csv", "soil.csv"):
        a = list(csv.reader(open(os.path.join(a_dir, case, name))))
        b = list(csv.reader(open(os.path.join(b_dir, case, name))))
        assert a[0] == b[0], (case, name, a[0], b[0])
        assert len(a) == len(b), (case, name, len(a), len(b))
        for col in range(len(a[0])):
            x = [float(r[col]) for r in a[1:]]
            y = [float(r[col]) for r in b[1:]]
            scale = max(abs(v) for v in x) or 1.0
            diff = max(abs(p - q) for p, q in zip(x, y)) / scale
            if diff > worst:
                worst, where = diff, "%s/%s column %s" % (case, name, a[0][col])
            if os.environ.get("VERBOSE") and diff > 1e-13:
                print(case, name, a[0][col], diff)
if differ:
    if worst <= 1e-6:
        sys.exit("a soil that ignores restore went unnoticed (worst %.3g)" % worst)
    print("the soil that ignores restore differs by %.3g relative (%s)" % (worst, where))
elif worst > float(os.environ.get("TOLERANCE", "1e-12")):
    sys.exit("%s differs by %.3g relative" % (where, worst))
else:
    print("the SDK soil agrees with the built-in one: worst relative difference %.3g (%s)"
          % (worst, where))
PY
}
compare "$work/builtin" "$work/outside"
compare "$work/builtin" "$work/forgetful" differ

# The lock step: the couplings the master decides at every macro step
# (implicit coupling with each accelerator, ramped and extrapolated inputs)
# run on the direct plane with the SDK soil as with the built-in one. Each
# run's summary names the plane it took; the SDK soil's lock-step run is bit
# for bit its relayed one, and agrees with the built-in soil's lock-step run
# as every run above does.
lockstep() {  # NAME CASE [master options]; the runs go to $group, $group-relay, $group-builtin
  local name=$1 case=$2 set=${group:-lockstep}
  shift 2
  run "$set" "$name" "$case" --node "soil=$good" --data-plane direct "$@"
  run "$set-relay" "$name" "$case" --node "soil=$good" --data-plane relay "$@"
  run "$set-builtin" "$name" "$case" --data-plane direct "$@"
  for dir in "$set" "$set-builtin"; do
    grep -q '"data_plane": "direct"' "$work/$dir/$name/summary.json" &&
      grep -q '"data_plane_mode": "lock step"' "$work/$dir/$name/summary.json" || {
      echo "$name ($dir) did not run in lock step on the direct plane:"
      cat "$work/$dir/$name/summary.json"
      exit 1
    }
  done
  grep -q '"data_plane": "relay"' "$work/$set-relay/$name/summary.json"
  for f in "$work/$set-relay/$name"/*.csv; do
    cmp "$f" "$work/$set/$name/${f##*/}" || {
      echo "$name: ${f##*/} differs between the relayed plane and the lock step"
      exit 1
    }
  done
}
for acc in constant aitken iqn-ils; do
  lockstep "2-implicit-$acc" ss-xx-jacobi --coupling implicit --inputs linear --accelerator "$acc"
done
lockstep 2-xt-implicit-iqn ss-xt-jacobi --coupling implicit --accelerator iqn-ils
lockstep 3-implicit-gs wr-xt+ss-xt-gauss-seidel --coupling implicit --inputs linear
lockstep 2-linear ss-xx-jacobi --inputs linear
lockstep 2-extrapolate1 ss-xt-jacobi --inputs extrapolate1
lockstep 3-extrapolate2 wr-xx+ss-xx-jacobi --inputs extrapolate2
grep -q '"method": "implicit"' "$work/lockstep/2-implicit-iqn-ils/summary.json"
compare "$work/lockstep-builtin" "$work/lockstep"

# Substep waveforms: the SDK soil evaluates its inputs at its own micro
# steps (Sampled.at) and records its outputs after each of them, explicit
# and implicit, X-X and X-T (a force received), degree 1 and 3: relayed and
# in lock step bit for bit alike, and the built-in soil's results to 1e-11
# relative (the interpolation's rounding, Python's against C++'s, is
# iterated on: 1.1e-12 seen).
for degree in 1 3; do
  group=wave lockstep "2-waveform$degree-implicit" ss-xx-jacobi --coupling implicit \
    --inputs "waveform$degree"
  group=wave lockstep "2-xt-waveform$degree-iqn" ss-xt-jacobi --coupling implicit \
    --accelerator iqn-ils --inputs "waveform$degree"
  group=wave lockstep "3-waveform$degree-gs" wr-xt+ss-xt-gauss-seidel --inputs "waveform$degree"
done
TOLERANCE=1e-11 compare "$work/wave-builtin" "$work/wave"
