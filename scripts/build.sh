#!/usr/bin/env bash
# Installs what is missing, then configures and builds into build/ (Release,
# warnings as errors). Extra arguments go to the CMake configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRAILCOSIM_WERROR=ON -DRAILCOSIM_BUILD_BENCH=ON "$@" >/dev/null
cmake --build build -j "$(nproc)"
