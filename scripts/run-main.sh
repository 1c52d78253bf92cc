#!/usr/bin/env bash
# Installs what is missing, builds, and runs the study of the paper scene:
# the monolithic reference, every co-simulation case over TCP (with nodes the
# master starts), the macro-step sweeps, figures and results/REPORT.md.
# Arguments: [OUT_DIR] [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
build/bin/master study --scene "${2:-scenes/paper.toml}" --out "${1:-results}"
