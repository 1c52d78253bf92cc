#!/usr/bin/env bash
# System calls per macro step of the master and of each node over TCP, by
# strace -c: the same case at two macro steps (N and 2N steps), so that the
# set-up (start, hello, configure, statics, results) cancels out in the
# difference. Prints a Markdown table: program, system call, calls per step.
#   bench/syscalls_per_step.sh [CASE] [SCENE] [EXTRA MASTER OPTIONS...]
#   (default rs-xx-gauss-seidel, scenes/paper.toml; e.g. --data-plane direct)
set -euo pipefail
cd "$(dirname "$0")/.."
case_name=${1:-rs-xx-gauss-seidel}
scene=${2:-scenes/paper.toml}
shift $(($# > 2 ? 2 : $#))
bin=build/bin
command -v strace >/dev/null || { echo "needs strace" >&2; exit 2; }
[[ -x $bin/master ]] || { echo "build first: scripts/build.sh" >&2; exit 2; }
out=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$(pgrep -P "$p")" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT

# The participants of the case, in load order: the vehicle, the rail alone
# between a wr and an rs cut, the track below the upper cut, the soil.
cuts=" $(sed -E 's/-(jacobi|gauss-seidel)$//; s/\+/ /g; s/-x[xt]//g' <<<"$case_name") "
roles=(vehicle)
[[ $cuts == *" wr "* && $cuts == *" rs "* ]] && roles+=(rail)
[[ $cuts == *" wr "* || $cuts == *" rs "* ]] && roles+=(track)
[[ $cuts == *" ss "* ]] && roles+=(soil)
program() { case $1 in vehicle) echo vehicle_node ;; soil) echo soil_node ;; *) echo track_node ;; esac; }

# One run at macro step $2 into $out/$1/: every node and the master under strace.
run() {
  local tag=$1 h=$2 node_args=() r
  shift 2
  mkdir -p "$out/$tag"
  pids=()
  for r in "${roles[@]}"; do
    strace -f -c -o "$out/$tag/$r.txt" "$bin/$(program "$r")" --role "$r" \
      --listen 127.0.0.1:0 >"$out/$tag/$r.out" 2>/dev/null &
    pids+=($!)
  done
  for r in "${roles[@]}"; do
    until grep -q 'listening on' "$out/$tag/$r.out" 2>/dev/null; do sleep 0.05; done
    node_args+=(--node "$r=$(awk '/listening on/ {print $3}' "$out/$tag/$r.out")")
  done
  strace -f -c -o "$out/$tag/master.txt" "$bin/master" run --scene "$scene" --case "$case_name" \
    --macro-step "$h" --out "$out/$tag/run" "${node_args[@]}" "$@" >/dev/null 2>&1
  # Stop each node (the child of its strace), then its strace writes the counts.
  for p in "${pids[@]}"; do kill -TERM "$(pgrep -P "$p")"; done
  wait "${pids[@]}" 2>/dev/null || true
  pids=()
}

# Macro steps of the scene at its own H, and at H/2.
read -r h steps < <(/usr/bin/python3 -c "import tomllib, sys
s = tomllib.load(open(sys.argv[1], 'rb'))['simulation']
print(s['macro_step'], round(s['end_time'] / s['macro_step']))" "$scene")
run one "$h" "$@"
run two "$(/usr/bin/python3 -c "print($h / 2)")" "$@"

echo "case $case_name, scene $scene, $steps extra macro steps between the two runs"
echo
echo "| program | system calls per macro step | of which |"
echo "|---|---|---|"
for p in master "${roles[@]}"; do
  /usr/bin/python3 - "$out/one/$p.txt" "$out/two/$p.txt" "$steps" "$p" <<'EOF'
import sys
def counts(path):
    c = {}
    for line in open(path):
        f = line.split()
        if len(f) >= 5 and f[0][0].isdigit() and f[-1] != "total":
            c[f[-1]] = int(f[3])
    return c
a, b, n, name = counts(sys.argv[1]), counts(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
d = {k: (b.get(k, 0) - a.get(k, 0)) / n for k in set(a) | set(b)}
d = {k: v for k, v in d.items() if v >= 0.05}
parts = ", ".join(f"{v:.2f} {k}" for k, v in sorted(d.items(), key=lambda kv: -kv[1]))
print(f"| {name} | {sum(d.values()):.2f} | {parts} |")
EOF
done
