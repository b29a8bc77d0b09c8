#!/usr/bin/env bash
# The station and the robots in network namespaces of their own, made and removed here, joined by
# a veth pair, with faults on the robots' link: 5 % of the packets crossing it dropped both ways
# (iptables' statistic match in the robots' namespace), and every robot connection going through
# a proxy of the test's own (tests/support/fault_proxy.cpp) that delays all traffic by 50 ms and
# cuts each connection at a random moment (mean 1.5 s). Nothing is lost: every update applied
# once, none behind a gap or rejected, none late in the time order, and the map is run's on the
# same dataset. The order's hold is 60 s: a robot whose connections are cut before the station
# welcomes them backs off 0.5, 1, 2, 4, 8 and 16 s (robot_client.h), silent 31.5 s after six such
# cuts; under a loaded fresh-clone `.ci/run` robot a (8 connections) once sent 8 updates after a
# hold of 30 s had let later ones go (the map still run's). Needs root (for the namespaces) and
# iptables: without them it says so and is skipped (exit 77). Bounded: it ends itself after 100 s,
# saying where it was; every process started here is stopped and both namespaces deleted when it
# ends, also on failure, and namespaces of an earlier run that was killed are deleted at its start.
#   usage: faulty_links.sh HYDRA_MULTI FAULT_PROXY DATASET OUT_DIR SPEED
set -u
HM=$1
PROXY=$2
DATASET=$3
OUT=$4
SPEED=$5
rm -rf "$OUT"
mkdir -p "$OUT"
[ "$(id -u)" -eq 0 ] || { echo "SKIP: network namespaces need root"; exit 77; }
for tool in ip iptables; do
  command -v "$tool" > /dev/null || { echo "SKIP: no $tool (scripts/install_deps.sh installs it)"; exit 77; }
done
. "$(dirname "$0")/processes.sh"

ns_station=hm$$s
ns_robots=hm$$r
subnet=10.231.$(($$ % 250))
# Namespaces an earlier run of this test left behind when it was killed (hmPIDs, hmPIDr, with
# PID no longer running): ours by their names, removed.
for ns in $(ip netns list | awk '{ print $1 }' | grep -E '^hm[0-9]+[sr]$'); do
  pid=${ns#hm}
  pid=${pid%?}
  kill -0 "$pid" 2> /dev/null || ip netns del "$ns"
done
step="setting up"
namespaces_cleanup() {
  [ -n "${watchdog:-}" ] && pkill -P "$watchdog" 2> /dev/null  # its sleep
  spawn_cleanup
  ip netns del "$ns_station" 2> /dev/null
  ip netns del "$ns_robots" 2> /dev/null
  return 0
}
trap namespaces_cleanup EXIT
# The test ends by itself within 100 s, before ctest's timeout could kill it without its cleanup.
trap 'echo "FAIL: still $step after 100 s"; cat "$OUT"/*.txt; exit 1' USR1
(sleep 100 && kill -USR1 $$) > /dev/null 2>&1 &
watchdog=$!
pids+=("$watchdog")
ip netns add "$ns_station" || { echo "SKIP: cannot make a network namespace"; exit 77; }
ip netns add "$ns_robots" || exit 1
ip link add hm$$a netns "$ns_station" type veth peer name hm$$b netns "$ns_robots" || exit 1
ip -n "$ns_station" addr add "$subnet.1/30" dev hm$$a
ip -n "$ns_robots" addr add "$subnet.2/30" dev hm$$b
for ns in "$ns_station" "$ns_robots"; do ip -n "$ns" link set lo up; done
ip -n "$ns_station" link set hm$$a up
ip -n "$ns_robots" link set hm$$b up
in_robots() { ip netns exec "$ns_robots" "$@"; }
in_robots iptables -A INPUT -i hm$$b -m statistic --mode random --probability 0.05 -j DROP || exit 1
in_robots iptables -A OUTPUT -o hm$$b -m statistic --mode random --probability 0.05 -j DROP || exit 1

spawn "$OUT/station.txt" timeout 80 ip netns exec "$ns_station" "$HM" station \
  --listen "tcp://$subnet.1:7800" --out "$OUT/station" --expect-robots 2 --order time \
  --order-hold 60 --quiet
station=$spawned
spawn "$OUT/proxy.txt" timeout 80 ip netns exec "$ns_robots" "$PROXY" --listen 127.0.0.1:0 \
  --upstream "$subnet.1:7800" --port-file "$OUT/proxy.port" --delay-ms 50 --cut-mean-s 1.5 \
  --seed 7
proxy=$spawned
for _ in $(seq 100); do [ -s "$OUT/station/endpoint" ] && [ -s "$OUT/proxy.port" ] && break; sleep 0.1; done
[ -s "$OUT/proxy.port" ] || { echo "FAIL: the proxy did not start"; cat "$OUT"/*.txt; exit 1; }
robots=()
for robot in a b; do
  spawn "$OUT/robot_$robot.txt" timeout 70 ip netns exec "$ns_robots" "$HM" robot \
    --dataset "$DATASET" --robot "$robot" --connect "tcp://127.0.0.1:$(cat "$OUT/proxy.port")" \
    --speed "$SPEED" --quiet
  robots+=("$spawned")
done
step="waiting for the robots"
status=0
for p in "${robots[@]}"; do wait "$p" || status=1; done
[ "$status" -eq 0 ] || { echo "FAIL: a robot failed"; cat "$OUT"/*.txt; exit 1; }
step="waiting for the station"
wait "$station" || { echo "FAIL: the station failed"; cat "$OUT"/*.txt; exit 1; }
step="stopping the proxy"
kill -TERM "$proxy"
wait "$proxy"
step="comparing the map with run's"
dropped=$(in_robots iptables -L -v -n -x | awk '$3 == "DROP" { n += $1 } END { print n + 0 }')
echo "dropped $dropped packets on the robots' link"
cat "$OUT/proxy.txt" "$OUT"/robot_*.txt
tr -d ' \n' < "$OUT/station/station.json" |
  grep -o '"updates_applied":[0-9]*,"updates_duplicate":[0-9]*,"updates_refused":{[^}]*},"updates_rejected":[0-9]*,"updates_behind_gap":[0-9]*\|"updates_late":[0-9]*'
"$HM" evaluate --dataset "$DATASET" --result "$OUT/station/graph.json" --json \
  > "$OUT/evaluated.json" || exit 1
"$HM" run --dataset "$DATASET" --out "$OUT/run" --quiet > /dev/null || exit 1
compare_with_run "$HM" "$DATASET" "$OUT/evaluated.json" "$OUT/run/metrics.json" station || exit 1
