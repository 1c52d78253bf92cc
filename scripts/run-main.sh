#!/usr/bin/env bash
# Installs what is missing, builds the programs and the benchmarks (not the
# tests: scripts/run-tests.sh builds those), and runs the study of a scene (default:
# the paper scene): the monolithic reference, every co-simulation case over
# TCP (with nodes the master starts), the macro-step sweeps, figures and
# OUT/REPORT.md. A scene on the FE soil ([soil] model = "fe") gets the
# ground-vibration study instead (python3 -m fe_soil.study): the
# co-simulations with the FE soil, the two-step method, figures and
# OUT/REPORT.md. A scene on the soil from Green's functions ([soil] model =
# "green") gets the study of which soil it needs (python3 -m
# green_soil.study): its co-simulation, whose
# OUT/runs/green/ss-xt-jacobi/vibration.csv has the levels at every
# receiver, a lumped soil's two-step run beside it, with --fe KEYS the FE
# soil too, the differences and costs in OUT/REPORT.md and
# OUT/soil_choice.csv/.json.
# Arguments: [OUT_DIR] [SCENE] [options of the study after the scene]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DRAILCOSIM_BUILD_TESTS=OFF -DRAILCOSIM_BUILD_BENCH=ON
out="${1:-results}"
scene="${2:-scenes/paper.toml}"
shift $(( $# < 2 ? $# : 2 ))
soil_model=$(/usr/bin/python3 -c '
import sys, tomllib
try:
    with open(sys.argv[1], "rb") as f:
        print(tomllib.load(f).get("soil", {}).get("model", ""))
except (OSError, tomllib.TOMLDecodeError):
    print("")  # the study that follows names the problem' "$scene")
if [ "$soil_model" = "fe" ]; then
  OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" exec /usr/bin/python3 -m fe_soil.study \
    --scene "$scene" --out "$out" --master build/bin/master
fi
if [ "$soil_model" = "green" ]; then
  OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" exec /usr/bin/python3 -m green_soil.study \
    --scene "$scene" --out "$out" --master build/bin/master "$@"
fi
build/bin/master study --scene "$scene" --out "$out"
