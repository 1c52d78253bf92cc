#!/usr/bin/env bash
# Multirate on every plane: scenes/soil.toml, wr-xx+ss-xt-jacobi with the
# soil's cut at 10 times the wheel/rail window (--macro-step ss=1e-3). The
# soil steps a tenth of the windows (its micro steps, adaptive, fall at
# least four times), the rail deflection and the wheel stay within 1 % of the
# single-rate run at the fine window, and the run is bitwise the same in
# process, relayed and on the direct plane (in lock step); summary.json
# states every cut's window. Implicit: the same
# bitwise in process and relayed, on a shortened scene.
# Usage: multirate_planes_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
bin=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
case=wr-xx+ss-xt-jacobi
run() {
  local out=$1
  shift
  "$bin/master" run --scene "$src/scenes/soil.toml" --case $case --out "$work/$out" "$@" \
    >"$work/$out.log" 2>&1 || { cat "$work/$out.log"; exit 1; }
}
run single --macro-step ss=1e-4
run inproc --macro-step ss=1e-3
run relay --macro-step ss=1e-3 --transport tcp --data-plane relay
run direct --macro-step ss=1e-3 --transport tcp --data-plane direct
for f in history.csv deflection.csv soil.csv; do
  cmp "$work/inproc/$case/$f" "$work/relay/$case/$f"
  cmp "$work/inproc/$case/$f" "$work/direct/$case/$f"
done
grep -q '"data_plane_mode": "lock step"' "$work/direct/$case/summary.json"
/usr/bin/python3 - "$work" "$case" <<'PY'
import csv, json, sys
work, case = sys.argv[1], sys.argv[2]
def column(run, name, key):
    with open(f"{work}/{run}/{case}/{name}") as f:
        return [float(r[key]) for r in csv.DictReader(f)]
def summary(run):
    with open(f"{work}/{run}/{case}/summary.json") as f:
        return json.load(f)
one, multi = summary("single"), summary("inproc")
# Every cut's window, as the command line gave it (H where none was given).
assert one["windows"] == {"wr": 1e-4, "ss": 1e-4}, one.get("windows")
for run in ("inproc", "relay", "direct"):
    assert summary(run)["windows"] == {"wr": 1e-4, "ss": 1e-3}, (run, summary(run).get("windows"))
soil_one, soil_multi = one["micro_steps"]["s3"], multi["micro_steps"]["s3"]
assert soil_multi * 4 <= soil_one, f"soil micro steps {soil_multi} against {soil_one}"
for name, key in (("deflection.csv", "w_m"), ("history.csv", "wheel_m")):
    a, b = column("single", name, key), column("inproc", name, key)
    assert len(a) == len(b), f"{name}: {len(a)} rows against {len(b)}"
    peak = max(abs(x) for x in a)
    worst = max(abs(x - y) for x, y in zip(a, b)) / peak
    assert worst <= 0.01, f"{name} {key}: {worst:.4f} of the peak off the single-rate run"
    print(f"{name} {key}: within {worst:.2e} of the peak; soil micro steps {soil_multi} / {soil_one}")
PY
# Implicit, shortened: in process and relayed alike, bit for bit.
sed -e 's/^end_time = .*/end_time = 0.02/' "$src/scenes/soil.toml" >"$work/short.toml"
for plane in inproc relay; do
  extra=()
  [[ $plane == relay ]] && extra=(--transport tcp --data-plane direct)
  "$bin/master" run --scene "$work/short.toml" --case $case --macro-step ss=1e-3 \
    --coupling implicit --out "$work/i_$plane" --verbose "${extra[@]}" >"$work/i_$plane.log" 2>&1 ||
    { cat "$work/i_$plane.log"; exit 1; }
done
cmp "$work/i_inproc/$case/history.csv" "$work/i_relay/$case/history.csv"
grep -q 'relayed data plane (a node keeps one checkpoint in lock step' "$work/i_relay.log" ||
  { cat "$work/i_relay.log"; exit 1; }
echo "multirate planes: ok"
