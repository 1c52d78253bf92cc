#!/usr/bin/env bash
# Installs what is missing, then configures and builds into build/ (Release,
# warnings as errors, each library's sources compiled in batches). Extra
# arguments go to the CMake configure step: scripts/run-main.sh builds the
# programs and the benchmarks (-DRAILCOSIM_BUILD_TESTS=OFF), and
# scripts/run-tests.sh the programs and the tests
# (-DRAILCOSIM_BUILD_BENCH=OFF). Both keep every other option alike, so
# that one after the other in build/ compiles only what the first did not.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRAILCOSIM_WERROR=ON -DRAILCOSIM_UNITY=ON "$@" >/dev/null
cmake --build build -j "$(nproc)"
