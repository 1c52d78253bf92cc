#!/usr/bin/env bash
# An outside participant for real: the Python soil participant of
# examples/python_soil serves the soil of three-participant (and two-
# participant X-T) cases over TCP; each run must agree with the same run on
# the built-in soil node to 1e-6 relative (both with fixed micro steps).
# Usage: python_soil_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
bin=$1
src=$2
work=$(mktemp -d)
participant=""
cleanup() {
  [[ -n $participant ]] && kill "$participant" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# The soil scene, shortened, with 10 fixed micro steps per macro step.
sed -e 's/^end_time = .*/end_time = 0.05/' -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' \
  "$src/scenes/soil.toml" >"$work/soil.toml"
grep -q '^micro_steps = 10' "$work/soil.toml"

/usr/bin/python3 "$src/examples/python_soil/soil_participant.py" --scene "$work/soil.toml" \
  --proto "$src/protocol/railcosim.proto" >"$work/participant.out" 2>"$work/participant.err" &
participant=$!
for _ in $(seq 100); do
  grep -q '^listening on ' "$work/participant.out" && break
  sleep 0.1
done
address=$(sed -n 's/^listening on //p' "$work/participant.out")
if [[ -z $address ]]; then
  echo "the Python participant did not start:"
  cat "$work/participant.err"
  exit 1
fi

run_both() {  # CASE [master options]: the same run on the outside and the built-in soil
  local case=$1
  shift
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --node "soil=$address" \
    --out "$work/outside" "$@" >"$work/master.log" 2>&1 || { cat "$work/master.log"; exit 1; }
  "$bin/master" run --scene "$work/soil.toml" --case "$case" --out "$work/builtin" "$@" \
    >"$work/master.log" 2>&1 || { cat "$work/master.log"; exit 1; }
  grep -q '"transport": "tcp"' "$work/outside/$case/summary.json"
}
for case in wr-xx+ss-xx-jacobi wr-xt+ss-xt-gauss-seidel ss-xt-jacobi; do
  run_both "$case"
done
# Implicit coupling with ramped inputs: checkpoints (Save/Restore) and
# inputs_end through the outside participant.
run_both ss-xx-jacobi --coupling implicit --inputs linear
grep -q '"method": "implicit"' "$work/outside/ss-xx-jacobi/summary.json"

/usr/bin/python3 - "$work/builtin" "$work/outside" <<'PY'
import csv, os, sys
builtin, outside = sys.argv[1], sys.argv[2]
worst = 0.0
for case in sorted(os.listdir(builtin)):
    for name in ("deflection.csv", "history.csv", "soil.csv"):
        a = list(csv.reader(open(os.path.join(builtin, case, name))))
        b = list(csv.reader(open(os.path.join(outside, case, name))))
        assert a[0] == b[0], (case, name, a[0], b[0])
        assert len(a) == len(b), (case, name, len(a), len(b))
        for col in range(len(a[0])):
            x = [float(r[col]) for r in a[1:]]
            y = [float(r[col]) for r in b[1:]]
            scale = max(abs(v) for v in x) or 1.0
            diff = max(abs(p - q) for p, q in zip(x, y)) / scale
            worst = max(worst, diff)
            if diff > 1e-6:
                sys.exit("%s/%s column %s differs by %.3g relative" % (case, name, a[0][col], diff))
print("outside soil participant agrees with the built-in one: worst relative difference %.3g"
      % worst)
PY
