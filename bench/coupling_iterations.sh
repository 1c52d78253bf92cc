#!/usr/bin/env bash
# Implicit coupling's cost: iterations per macro step (mean, max) for each
# accelerator, case and macro step, and the wall time per macro step against
# the explicit scheme over the same transport. Prints a Markdown table.
#   bench/coupling_iterations.sh [SCENE] [TRANSPORT]   (default scenes/paper.toml, inproc)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/paper.toml}
transport=${2:-inproc}
master=build/bin/master
[[ -x $master ]] || { echo "build first: scripts/build.sh" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); v=d
for k in sys.argv[2].split('.'): v=v[k] if v is not None else None
print(v if v is not None else '–')" "$1" "$2"; }
echo "scene $scene, transport $transport, inputs linear, convergence 1e-8"
echo
echo "| case | H (s) | accelerator | status | iterations mean | max | wall per step (ms) | explicit wall per step (ms) |"
echo "|---|---|---|---|---|---|---|---|"
for c in wr-xt-jacobi rs-xx-jacobi rs-xx-gauss-seidel rs-xt-jacobi; do
  for H in 1e-4 1e-3; do
    "$master" run --scene "$scene" --case "$c" --macro-step "$H" --transport "$transport" \
      --out "$out/explicit" >/dev/null 2>&1 || true
    ex="$out/explicit/$c/summary.json"
    ex_ms=$(/usr/bin/python3 -c "import json; d=json.load(open('$ex')); print('%.3f' % (1e3*d['wall_s']/max(1,d['macro_steps'])))")
    for acc in constant aitken iqn-ils; do
      "$master" run --scene "$scene" --case "$c" --macro-step "$H" --transport "$transport" \
        --coupling implicit --inputs linear --accelerator "$acc" --out "$out/$acc" >/dev/null 2>&1 || true
      s="$out/$acc/$c/summary.json"
      ms=$(/usr/bin/python3 -c "import json; d=json.load(open('$s')); print('%.3f' % (1e3*d['wall_s']/max(1,d['macro_steps'])))")
      mean=$(field "$s" iterations.mean)
      [[ $mean != – ]] && mean=$(printf '%.2f' "$mean")
      echo "| $c | $H | $acc | $(field "$s" status) | $mean | $(field "$s" iterations.max) | $ms | $ex_ms |"
    done
  done
done
