#!/usr/bin/env bash
# Multi-host check: the nodes on hosts of their own (network namespaces
# joined to this one by veth pairs, with addresses this test makes), the
# master here. Two hosts: a paper-scene case across the vehicle and track
# nodes; three hosts: a soil-scene case across vehicle, track and soil nodes.
# The results of each must equal the in-process run bit for bit. Exits 77
# (skipped) where namespaces cannot be made.
# Usage: netns_test.sh BIN_DIR PAPER_SCENE SOIL_SCENE
set -u
bin=$1
scene=$2
soil_scene=$3
id=$$
ns_v=rcs_v_$id
ns_t=rcs_t_$id
ns_s=rcs_s_$id
out=$(mktemp -d)
pids=()

forward_before=$(cat /proc/sys/net/ipv4/ip_forward 2>/dev/null || echo 0)
cleanup() {
  echo "$forward_before" >/proc/sys/net/ipv4/ip_forward 2>/dev/null
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  wait 2>/dev/null
  ip netns del "$ns_v" 2>/dev/null
  ip netns del "$ns_t" 2>/dev/null
  ip netns del "$ns_s" 2>/dev/null
  ip link del "rv${id}a" 2>/dev/null
  ip link del "rt${id}a" 2>/dev/null
  ip link del "rs${id}a" 2>/dev/null
  rm -rf "$out"
}
trap cleanup EXIT

if ! command -v ip >/dev/null || ! ip netns add "$ns_v" 2>/dev/null; then
  echo "SKIP: cannot create network namespaces here (needs root and iproute2)"
  exit 77
fi
ip netns add "$ns_t" || exit 1
ip netns add "$ns_s" || exit 1

# host   namespace  address          link to this host
# vehicle $ns_v     10.231.1.2/24    rv<id>a (10.231.1.1) <-> rv<id>b
# track   $ns_t     10.231.2.2/24    rt<id>a (10.231.2.1) <-> rt<id>b
# soil    $ns_s     10.231.3.2/24    rs<id>a (10.231.3.1) <-> rs<id>b
link() {  # ns side subnet
  local ns=$1 a=$2 b=$3 net=$4
  ip link add "$a" type veth peer name "$b" || return 1
  ip link set "$b" netns "$ns" || return 1
  ip addr add "$net.1/24" dev "$a" && ip link set "$a" up || return 1
  ip netns exec "$ns" ip addr add "$net.2/24" dev "$b" || return 1
  ip netns exec "$ns" ip link set "$b" up && ip netns exec "$ns" ip link set lo up || return 1
  # The nodes talk to each other directly (the direct data plane): through
  # this host, which routes between the hosts' links.
  ip netns exec "$ns" ip route add default via "$net.1"
}
if ! link "$ns_v" "rv${id}a" "rv${id}b" 10.231.1 || ! link "$ns_t" "rt${id}a" "rt${id}b" 10.231.2 ||
  ! link "$ns_s" "rs${id}a" "rs${id}b" 10.231.3; then
  echo "SKIP: cannot create veth links here"
  exit 77
fi

echo 1 >/proc/sys/net/ipv4/ip_forward || { echo "SKIP: cannot route between the hosts"; exit 77; }

# Nodes off loopback require a shared secret.
(umask 077; head -c 32 /dev/urandom | base64 >"$out/token")
start_node() {  # ns program address logfile
  ip netns exec "$1" "$bin/$2" --listen "$3" --token-file "$out/token" >"$4" 2>"$4.err" &
  pids+=($!)
  for _ in $(seq 100); do
    grep -q "^listening on" "$4" 2>/dev/null && return 0
    sleep 0.05
  done
  echo "FAIL: $2 did not start in $1"; cat "$4" "$4.err"
  return 1
}
start_node "$ns_v" vehicle_node 10.231.1.2:7001 "$out/vehicle.log" || exit 1
start_node "$ns_t" track_node 10.231.2.2:7002 "$out/track.log" || exit 1
start_node "$ns_s" soil_node 10.231.3.2:7003 "$out/soil.log" || exit 1

case=rs-xx-gauss-seidel
"$bin/master" run --scene "$scene" --case $case --vehicle 10.231.1.2:7001 --track 10.231.2.2:7002 \
  --token-file "$out/token" --out "$out/tcp" || { echo "FAIL: the run across hosts failed"; exit 1; }
# Without the secret, the master gets a refusal and nothing else.
if "$bin/master" run --scene "$scene" --case $case --vehicle 10.231.1.2:7001 --track 10.231.2.2:7002 \
  --out "$out/intruder" 2>"$out/intruder.err"; then
  echo "FAIL: a master without the token was served"; exit 1
fi
grep -q -- "--token-file" "$out/intruder.err" || { echo "FAIL: no word of the token"; cat "$out/intruder.err"; exit 1; }
"$bin/master" run --scene "$scene" --case $case --transport inproc --out "$out/inproc" >/dev/null || exit 1
for f in deflection.csv history.csv; do
  if ! cmp -s "$out/tcp/$case/$f" "$out/inproc/$case/$f"; then
    echo "FAIL: $f across hosts differs from the in-process run"
    exit 1
  fi
done
grep -q '"transport": "tcp"' "$out/tcp/$case/summary.json" || { echo "FAIL: transport"; exit 1; }
grep -q '"data_plane": "direct"' "$out/tcp/$case/summary.json" || { echo "FAIL: not direct"; exit 1; }
echo "PASS: $case across two network hosts (nodes exchanging directly) equals the in-process run bit for bit"
# The same over the relayed data plane.
"$bin/master" run --scene "$scene" --case $case --vehicle 10.231.1.2:7001 --track 10.231.2.2:7002 \
  --token-file "$out/token" --data-plane relay --out "$out/relay" >/dev/null ||
  { echo "FAIL: the relayed run across hosts failed"; exit 1; }
cmp -s "$out/relay/$case/history.csv" "$out/inproc/$case/history.csv" ||
  { echo "FAIL: the relayed history differs"; exit 1; }
grep -q '"data_plane": "relay"' "$out/relay/$case/summary.json" || { echo "FAIL: not relayed"; exit 1; }

# Three hosts: vehicle, track and soil each on its own (the same vehicle and
# track nodes serve this session after the first).
case=wr-xx+ss-xt-gauss-seidel
"$bin/master" run --scene "$soil_scene" --case $case --node vehicle=10.231.1.2:7001 \
  --node track=10.231.2.2:7002 --node soil=10.231.3.2:7003 --token-file "$out/token" \
  --out "$out/tcp3" || { echo "FAIL: the run across three hosts failed"; exit 1; }
"$bin/master" run --scene "$soil_scene" --case $case --transport inproc --out "$out/inproc3" \
  >/dev/null || exit 1
for f in deflection.csv history.csv soil.csv; do
  if ! cmp -s "$out/tcp3/$case/$f" "$out/inproc3/$case/$f"; then
    echo "FAIL: $f across three hosts differs from the in-process run"
    exit 1
  fi
done
grep -q '"s3"' "$out/tcp3/$case/summary.json" || { echo "FAIL: three participants"; exit 1; }
grep -q '"data_plane": "direct"' "$out/tcp3/$case/summary.json" || { echo "FAIL: not direct"; exit 1; }
echo "PASS: $case across three network hosts equals the in-process run bit for bit"
