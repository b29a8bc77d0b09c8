#!/usr/bin/env bash
# The station killed with SIGKILL while two robots stream to it (loopback only), and started again
# on the same --out: it replays its journal, the robots say HELLO again, are welcomed past what it
# holds and send the rest. Nothing acknowledged is lost, nothing is applied twice: the station
# ends with every update of both robots, each once, and its journal holds each once and is
# intact. Bounded: 60 s; every process started here is killed when the script ends.
#   usage: station_restart.sh HYDRA_MULTI DATASET OUT_DIR
set -u
HM=$1
DATASET=$2
OUT=$3
rm -rf "$OUT"
mkdir -p "$OUT"
pids=()
cleanup() { for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null; done; }
trap cleanup EXIT

# Not under timeout: the station itself must get the SIGKILL (the trap kills it in any case).
"$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station" --expect-robots 2 \
  > "$OUT/first.txt" 2>&1 &
first=$!
pids+=("$first")
for _ in $(seq 100); do [ -s "$OUT/station/endpoint" ] && break; sleep 0.1; done
endpoint=$(cat "$OUT/station/endpoint")
case $endpoint in tcp://127.0.0.1:*) ;; *) echo "FAIL: endpoint '$endpoint' is not loopback"; exit 1 ;; esac
robots=()
for robot in a b; do
  timeout 50 "$HM" robot --dataset "$DATASET" --robot "$robot" --connect "$endpoint" --speed 10 \
    > "$OUT/robot_$robot.txt" 2>&1 &
  robots+=("$!")
  pids+=("$!")
done
sleep 4
kill -9 "$first"
wait "$first" 2> /dev/null
echo "killed the station after 4 s"
timeout 50 "$HM" station --listen "$endpoint" --out "$OUT/station" --expect-robots 2 \
  > "$OUT/second.txt" 2>&1 &
second=$!
pids+=("$second")
status=0
for p in "${robots[@]}"; do wait "$p" || status=1; done
wait "$second" || status=1
grep -h -E "^robot [ab] to |saying HELLO again|welcomed, the station holds every update before [1-9]" "$OUT"/robot_*.txt | sort
grep -E "^station: resumed from" "$OUT/second.txt"
[ "$status" -eq 0 ] || { echo "FAIL: a process failed"; cat "$OUT"/*.txt; exit 1; }
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"updates_applied":[0-9]*,"updates_duplicate":[0-9]*'
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"journal_entries":[0-9]*,"journal_integrity":"[a-z]*","updates_replayed":[0-9]*'
