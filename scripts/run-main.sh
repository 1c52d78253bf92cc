#!/usr/bin/env bash
# Installs what is missing, builds, and runs the paper scene: the monolithic
# reference and every co-simulation case (over TCP, with nodes the master
# starts), into results/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
out=${1:-results}
build/bin/master run --scene scenes/paper.toml --case monolithic --out "$out"
for split in wr rs; do
  for type in xx xt; do
    for scheme in jacobi gauss-seidel; do
      build/bin/master run --scene scenes/paper.toml --case "$split-$type-$scheme" --out "$out"
    done
  done
done
