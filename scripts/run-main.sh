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
# It installs only what the study needs: the base packages
# (scripts/install-deps.sh), and the FE soil's stack (FEniCSx, PETSc, MPI:
# --fe) or scipy (--green) only when the scene's soil is that soil.
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
  echo "run-main: $scene asks for the FE soil ([soil] model = \"fe\"): installing its stack" \
    "(FEniCSx, PETSc, MPI) if it is missing: scripts/install-deps.sh --fe" >&2
  scripts/install-deps.sh --fe
  OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" exec /usr/bin/python3 -m fe_soil.study \
    --scene "$scene" --out "$out" --master build/bin/master
fi
if [ "$soil_model" = "green" ]; then
  echo "run-main: $scene asks for the soil from Green's functions ([soil] model = \"green\"):" \
    "installing scipy if it is missing: scripts/install-deps.sh --green" >&2
  profiles=(--green)
  for arg in "$@"; do  # the study's --fe KEYS adds the FE soil beside it
    if [ "$arg" = "--fe" ]; then
      echo "run-main: --fe: the FE soil too: scripts/install-deps.sh --fe" >&2
      profiles+=(--fe)
    fi
  done
  scripts/install-deps.sh "${profiles[@]}"
  OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" exec /usr/bin/python3 -m green_soil.study \
    --scene "$scene" --out "$out" --master build/bin/master "$@"
fi
build/bin/master study --scene "$scene" --out "$out"
