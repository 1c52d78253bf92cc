#!/usr/bin/env bash
# FMUs served by fmu_node over TCP against the built-in participants,
# explicit and implicit (the implicit run saves and restores the FMU's
# state in lock step):
# - the lumped soil as an FMI 3.0 FMU (tests/fmus/lumped_soil.c; and as FMI
#   2.0, the same runs bit for bit, over TCP and in process) as the soil
#   of scenes/soil.toml, ss-xx-jacobi, within 1e-9 by `master compare` (the
#   FMU solves its tridiagonal systems by Thomas' algorithm, the built-in
#   soil otherwise: round-off apart); the explicit run judged `ok` against a
#   co-simulation reference with held inputs (the FMU takes no ramps);
# - on both data planes (direct and relayed), each run the same;
# - the built-in vehicle exported as an FMU (fmu_export/) as the vehicle of
#   scenes/paper.toml, wr-xx-jacobi, equal bit for bit (tolerance 0);
# - the same soil mapped by the scene's own [soil] table (model = "external"),
#   sent to a node started without --config: equal bit for bit; and hosted
#   in the master's process (--transport inproc): equal bit for bit;
# - the vehicle FMU mapped by the scene ([vehicle.fmu]), in process and
#   over TCP with a node the master starts, at wr-xx-jacobi and (its xt
#   export) wr-xt-jacobi: equal bit for bit;
# - the lumped soil that cannot save its state: explicit runs, not judged
#   for that reason; implicit refused, saying so.
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
  if [[ $coupling == explicit ]]; then
    # Judged through the FMU's state save against a reference with held
    # inputs (the FMU takes no ramps), first order in its error estimate.
    grep -q '^ss-xx-jacobi: ok, ' "$work/run.log" || fail "the FMU soil's run is not ok" "$work/run.log"
    summary="$work/fmu-$coupling/ss-xx-jacobi/summary.json"
    grep -q '"coupling": "implicit-hold-iqn-ils"' "$summary" &&
      grep -q '"estimate_order": 1,' "$summary" &&
      grep -q 'the reference takes held inputs instead (first order)' "$summary" ||
      fail "not judged against a held-input reference" "$summary"
  fi
  "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --coupling "$coupling" \
    --out "$work/builtin-$coupling" >"$work/run.log" 2>&1 ||
    fail "the built-in run failed ($coupling)" "$work/run.log"
  "$bin/master" compare "$work/builtin-$coupling" "$work/fmu-$coupling" --tolerance 1e-9 \
    >"$work/compare.log" 2>&1 || fail "the FMU soil differs from the built-in one ($coupling)" "$work/compare.log"
  grep -q '^agree: ' "$work/compare.log" || fail "unexpected verdict" "$work/compare.log"
  cat "$work/compare.log"
  # The master's relay: the same run as the nodes' own exchange, bit for bit.
  "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --coupling "$coupling" \
    --data-plane relay --node "soil=$soil" --out "$work/fmu-$coupling-relay" >"$work/run.log" 2>&1 ||
    fail "the relayed run with the FMU soil failed ($coupling)" "$work/run.log"
  "$bin/master" compare "$work/fmu-$coupling" "$work/fmu-$coupling-relay" --tolerance 0 \
    >"$work/compare.log" 2>&1 || fail "the relayed FMU soil run differs ($coupling)" "$work/compare.log"
  echo "soil FMU, $coupling, relay against direct: $(tail -1 "$work/compare.log")"
done

# The same soil as an FMI 2.0 FMU (the same C source): the same runs bit
# for bit, over TCP and in process.
sed 's/lumped_soil3.fmu/lumped_soil2.fmu/' "$work/fmu.toml" >"$work/fmu2.toml"
start fmi2 "$bin/fmu_node" --role soil --listen 127.0.0.1:0 --config "$work/fmu2.toml"
for coupling in explicit implicit; do
  "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --coupling "$coupling" \
    --node "soil=$address" --out "$work/fmu2-$coupling" >"$work/run.log" 2>&1 ||
    fail "the run with the FMI 2.0 soil failed ($coupling)" "$work/run.log"
  "$bin/master" compare "$work/fmu-$coupling" "$work/fmu2-$coupling" --tolerance 0 \
    >"$work/compare.log" 2>&1 || fail "the FMI 2.0 soil differs from the FMI 3.0 one ($coupling)" \
    "$work/compare.log"
  echo "the FMI 2.0 soil, $coupling: $(tail -1 "$work/compare.log")"
done

# The mapping in the scene itself: the soil `external`, its [soil] table the
# FMU's configuration, which the master sends the node (no --config): the
# same run bit for bit.
awk -v fmu="$work/fmu.toml" '
  /^\[soil\]/ { print; print "model = \"external\""
                while ((getline line < fmu) > 0) if (line !~ /^\[soil\]/) print line
                skip = 1; next }
  /^\[/ { skip = 0 }
  !skip { print }' "$work/soil.toml" >"$work/external.toml"
grep -q '^model = "external"' "$work/external.toml" || fail "the external scene was not written"
start scene "$bin/fmu_node" --role soil --listen 127.0.0.1:0
"$bin/master" run --scene "$work/external.toml" --case ss-xx-jacobi --node "soil=$address" \
  --out "$work/fmu-scene" >"$work/run.log" 2>&1 || fail "the run with the scene's mapping failed" "$work/run.log"
"$bin/master" compare "$work/fmu-explicit" "$work/fmu-scene" --tolerance 0 >"$work/compare.log" 2>&1 ||
  fail "the scene's mapping differs from the node's configuration" "$work/compare.log"
echo "the mapping in the scene: $(tail -1 "$work/compare.log")"

# The same scene in the master's own process (--transport inproc): the FMU
# hosted there, no node, the same run bit for bit, explicit and implicit,
# and the explicit run judged as over TCP.
"$bin/master" run --scene "$work/external.toml" --case ss-xx-jacobi --transport inproc \
  --out "$work/fmu-inproc" >"$work/run.log" 2>&1 || fail "the run with the FMU in process failed" "$work/run.log"
grep -q '^ss-xx-jacobi: ok, ' "$work/run.log" || fail "the in-process FMU soil's run is not ok" "$work/run.log"
"$bin/master" compare "$work/fmu-explicit" "$work/fmu-inproc" --tolerance 0 >"$work/compare.log" 2>&1 ||
  fail "the FMU in process differs from the FMU over TCP" "$work/compare.log"
echo "the FMU in process, explicit: $(tail -1 "$work/compare.log")"
"$bin/master" run --scene "$work/external.toml" --case ss-xx-jacobi --transport inproc \
  --coupling implicit --out "$work/fmu-inproc-implicit" >"$work/run.log" 2>&1 ||
  fail "the implicit run with the FMU in process failed" "$work/run.log"
"$bin/master" compare "$work/fmu-implicit" "$work/fmu-inproc-implicit" --tolerance 0 \
  >"$work/compare.log" 2>&1 || fail "the implicit FMU in process differs from over TCP" "$work/compare.log"
echo "the FMU in process, implicit: $(tail -1 "$work/compare.log")"
sed 's/lumped_soil3.fmu/lumped_soil2.fmu/' "$work/external.toml" >"$work/external2.toml"
"$bin/master" run --scene "$work/external2.toml" --case ss-xx-jacobi --transport inproc \
  --out "$work/fmu2-inproc" >"$work/run.log" 2>&1 || fail "the FMI 2.0 soil in process failed" "$work/run.log"
"$bin/master" compare "$work/fmu-explicit" "$work/fmu2-inproc" --tolerance 0 >"$work/compare.log" 2>&1 ||
  fail "the FMI 2.0 soil in process differs" "$work/compare.log"
echo "the FMI 2.0 soil in process: $(tail -1 "$work/compare.log")"
# Over TCP without --node: the master starts an fmu_node for the soil itself.
"$bin/master" run --scene "$work/external.toml" --case ss-xx-jacobi --out "$work/fmu-started" \
  >"$work/run.log" 2>&1 || fail "the run with an fmu_node the master started failed" "$work/run.log"
"$bin/master" compare "$work/fmu-explicit" "$work/fmu-started" --tolerance 0 >"$work/compare.log" 2>&1 ||
  fail "the FMU served by a node the master started differs" "$work/compare.log"
echo "the FMU on a node the master started: $(tail -1 "$work/compare.log")"
# Without the FMU's file, an external soil in process is refused, saying why.
grep -v '^file = ' "$work/external.toml" >"$work/nofile.toml"
if "$bin/master" run --scene "$work/nofile.toml" --case ss-xx-jacobi --transport inproc \
  --out "$work/nofile" >"$work/run.log" 2>&1; then
  fail "an external soil without an FMU ran in process" "$work/run.log"
fi
grep -q 'give its address with --node soil=HOST:PORT (and --transport tcp)' "$work/run.log" ||
  fail "the refusal does not say what to do" "$work/run.log"

sed 's/lumped_soil3.fmu/lumped_soil3_nostate.fmu/' "$work/fmu.toml" >"$work/nostate.toml"
start nostate "$bin/fmu_node" --role soil --listen 127.0.0.1:0 --config "$work/nostate.toml"
"$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --node "soil=$address" \
  --out "$work/nostate" >"$work/run.log" 2>&1 || fail "the explicit run without state save failed" "$work/run.log"
grep -q '^ss-xx-jacobi: not_judged, ' "$work/run.log" || fail "not 'not_judged'" "$work/run.log"
grep -q 'lumped_soil3_nostate.fmu cannot save its state' "$work/run.log" ||
  fail "the judgement does not say the FMU cannot save its state" "$work/run.log"
if "$bin/master" run --scene "$work/soil.toml" --case ss-xx-jacobi --coupling implicit \
  --node "soil=$address" --out "$work/nostate" >"$work/run.log" 2>&1; then
  fail "an implicit run without state save was made" "$work/run.log"
fi
grep -q 'cannot save its state .*: explicit coupling only' "$work/run.log" ||
  fail "the implicit refusal does not say why" "$work/run.log"
echo "without state save: explicit not judged, implicit refused"

sed -e 's/^end_time = .*/end_time = 0.05/' "$src/scenes/paper.toml" >"$work/paper.toml"
cat >"$work/vehicle.toml" <<TOML
[vehicle]
file = "$bin/fmus/railcosim_vehicle.fmu"
wr_in_displacement = "wr_in_displacement"
wr_out_displacement = "wr_out_displacement"
history_wheel_m = "wheel_m"
history_contact_force_N = "contact_force_N"
TOML
start vehicle "$bin/fmu_node" --role vehicle --listen 127.0.0.1:0 --config "$work/vehicle.toml"
vehicle=$address
for coupling in explicit implicit; do
  "$bin/master" run --scene "$work/paper.toml" --case wr-xx-jacobi --coupling "$coupling" \
    --out "$work/vbuiltin-$coupling" >"$work/run.log" 2>&1 ||
    fail "the built-in run failed ($coupling)" "$work/run.log"
  # Both data planes: the nodes' own exchange and the master's relay.
  for plane in direct relay; do
    "$bin/master" run --scene "$work/paper.toml" --case wr-xx-jacobi --coupling "$coupling" \
      --data-plane "$plane" --node "vehicle=$vehicle" --out "$work/vfmu-$coupling-$plane" \
      >"$work/run.log" 2>&1 || fail "the run with the vehicle FMU failed ($coupling, $plane)" "$work/run.log"
    grep -m1 "^wr-xx-jacobi: " "$work/run.log" || fail "no summary line ($coupling, $plane)" "$work/run.log"
    "$bin/master" compare "$work/vbuiltin-$coupling" "$work/vfmu-$coupling-$plane" --tolerance 0 \
      >"$work/compare.log" 2>&1 ||
      fail "the vehicle FMU differs from the built-in one ($coupling, $plane)" "$work/compare.log"
    grep -q '^agree: 1 run(s), 2 file(s), 0 over the tolerance 0; worst relative difference 0 ' \
      "$work/compare.log" || fail "unexpected verdict ($coupling, $plane)" "$work/compare.log"
    echo "vehicle FMU, $coupling, $plane plane: $(tail -1 "$work/compare.log")"
  done
done

# The vehicle's mapping in the scene ([vehicle.fmu]): hosted in process, or
# served by an fmu_node the master starts itself (no --node), explicit and
# implicit, each equal to the built-in vehicle bit for bit; its judgement
# says why it is not judged (this FMU steps only at the scene's macro step,
# so no reference at H / 2 can be made); no monolithic case.
cp "$work/paper.toml" "$work/vfmu.toml"
{
  echo "[vehicle.fmu]"
  grep -v '^\[vehicle\]' "$work/vehicle.toml"
} >>"$work/vfmu.toml"
for coupling in explicit implicit; do
  for transport in inproc tcp; do
    "$bin/master" run --scene "$work/vfmu.toml" --case wr-xx-jacobi --coupling "$coupling" \
      --transport "$transport" --out "$work/vscene-$coupling-$transport" >"$work/run.log" 2>&1 ||
      fail "the scene's vehicle FMU failed ($coupling, $transport)" "$work/run.log"
    grep -q 'not judged: no co-simulation reference: .*the communication step must be the scene' \
      "$work/run.log" || fail "the judgement does not say why ($coupling, $transport)" "$work/run.log"
    "$bin/master" compare "$work/vbuiltin-$coupling" "$work/vscene-$coupling-$transport" \
      --tolerance 0 >"$work/compare.log" 2>&1 ||
      fail "the scene's vehicle FMU differs from the built-in one ($coupling, $transport)" \
        "$work/compare.log"
    echo "the scene's vehicle FMU, $coupling, $transport: $(tail -1 "$work/compare.log")"
  done
done
# The vehicle FMU cut for wr-xt-jacobi (it receives the rail's displacement
# and sends the contact force): equal to the built-in vehicle bit for bit,
# and the explicit run, unstable, found so through the FMU's state save as
# the built-in run is by its map.
cp "$work/paper.toml" "$work/vfmu_xt.toml"
cat >>"$work/vfmu_xt.toml" <<TOML
[vehicle.fmu]
file = "$bin/fmus/railcosim_vehicle_xt.fmu"
wr_in_displacement = "wr_in_displacement"
wr_out_force = "wr_out_force"
history_wheel_m = "wheel_m"
history_contact_force_N = "contact_force_N"
TOML
for coupling in explicit implicit; do
  "$bin/master" run --scene "$work/paper.toml" --case wr-xt-jacobi --coupling "$coupling" \
    --out "$work/xtbuiltin-$coupling" >"$work/builtin.log" 2>&1 ||
    fail "the built-in wr-xt-jacobi run failed ($coupling)" "$work/builtin.log"
  for transport in inproc tcp; do
    "$bin/master" run --scene "$work/vfmu_xt.toml" --case wr-xt-jacobi --coupling "$coupling" \
      --transport "$transport" --out "$work/xt-$coupling-$transport" >"$work/run.log" 2>&1 ||
      fail "the xt vehicle FMU failed ($coupling, $transport)" "$work/run.log"
    if [[ $coupling == explicit ]]; then
      grep -Eq '^wr-xt-jacobi: (amplified|diverged|unstable), ' "$work/builtin.log" &&
        grep -q 'unstable: at rest: ρ = 1.10[0-9]* per macro step' "$work/run.log" ||
        fail "the xt vehicle FMU's run is not found unstable as the built-in one" "$work/run.log"
    fi
    "$bin/master" compare "$work/xtbuiltin-$coupling" "$work/xt-$coupling-$transport" \
      --tolerance 0 >"$work/compare.log" 2>&1 ||
      fail "the xt vehicle FMU differs from the built-in one ($coupling, $transport)" \
        "$work/compare.log"
    echo "the xt vehicle FMU, $coupling, $transport: $(tail -1 "$work/compare.log")"
  done
done
if "$bin/master" run --scene "$work/vfmu.toml" --case monolithic --out "$work/vmono" \
  >"$work/run.log" 2>&1; then
  fail "a monolithic run of a scene whose vehicle is an FMU was made" "$work/run.log"
fi
grep -q 'vehicle is an FMU (\[vehicle.fmu\]): there is no monolithic reference' "$work/run.log" ||
  fail "the monolithic refusal does not say why" "$work/run.log"
echo "1 passed, 0 failed"
