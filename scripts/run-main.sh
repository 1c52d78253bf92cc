#!/usr/bin/env bash
# Installs what is missing, builds the programs and the benchmarks (not the
# tests: scripts/run-tests.sh builds those), and runs the study of a scene (default:
# the paper scene): the monolithic reference, every co-simulation case over
# TCP (with nodes the master starts), the macro-step sweeps, figures and
# OUT/REPORT.md. A scene on the FE soil ([soil] model = "fe") gets the
# ground-vibration study instead (python3 -m fe_soil.study): the
# co-simulations with the FE soil, the two-step method, figures and
# OUT/REPORT.md. A scene on the soil from Green's functions ([soil] model =
# "green") gets its co-simulation (master run --case ss-xt-jacobi), whose
# OUT/ss-xt-jacobi/vibration.csv has the levels at every receiver.
# Arguments: [OUT_DIR] [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DRAILCOSIM_BUILD_TESTS=OFF -DRAILCOSIM_BUILD_BENCH=ON
out="${1:-results}"
scene="${2:-scenes/paper.toml}"
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
  OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" exec build/bin/master run --scene "$scene" \
    --case ss-xt-jacobi --out "$out"
fi
build/bin/master study --scene "$scene" --out "$out"
