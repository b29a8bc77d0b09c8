#!/usr/bin/env bash
# A robot process killed with SIGKILL mid-mission and started again (a new epoch, an empty outbox)
# while the other robot streams on (loopback only). Both runs of robot b share the mission's clock
# (--mission-start): the second takes the updates due before it started as its map, which it
# made while down. The station asks it for a snapshot, which brings them; nothing is lost, nothing
# applied twice (robot b's every update held, none duplicate, behind a gap or rejected), and the
# map scores as the one `run` makes of the same dataset (ATE, objects, rooms). Bounded: 60 s;
# every process started here is killed when the script ends.
#   usage: robot_restart.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

spawn "$OUT/station.txt" timeout 50 "$HM" station --listen 'tcp://127.0.0.1:*' \
  --out "$OUT/station" --expect-robots 2 --order time
station=$spawned
await_endpoint "$OUT/station"
start=$(awk -v now="$(date +%s.%N)" 'BEGIN { printf "%.3f", now + 0.5 }')
spawn "$OUT/robot_a.txt" timeout 50 "$HM" robot --dataset "$DATASET" --robot a \
  --connect "$endpoint" --speed 10
a=$spawned
# Not under timeout: the robot itself must get the SIGKILL.
spawn "$OUT/robot_b1.txt" "$HM" robot --dataset "$DATASET" --robot b --connect "$endpoint" \
  --speed 10 --mission-start "$start"
b1=$spawned
sleep 2.5
kill -9 "$b1"
wait "$b1" 2> /dev/null
echo "killed robot b after 2.5 s"
sleep 1.5
spawn "$OUT/robot_b2.txt" timeout 50 "$HM" robot --dataset "$DATASET" --robot b \
  --connect "$endpoint" --speed 10 --mission-start "$start"
b2=$spawned
status=0
for p in "$a" "$b2"; do wait "$p" || status=1; done
[ "$status" -eq 0 ] || { echo "FAIL: a robot failed"; cat "$OUT"/*.txt; exit 1; }
wait "$station" || { echo "FAIL: the station failed"; cat "$OUT"/*.txt; exit 1; }
grep -h -E "^robot b to |asked for a snapshot" "$OUT/robot_b2.txt"
grep -h -E "asked robot b for a snapshot" "$OUT/station.txt"
tr -d ' \n' < "$OUT/station/station.json" |
  grep -o '"updates_rejected":[0-9]*,"updates_behind_gap":[0-9]*,"snapshots_requested":[0-9]*'
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"b":{[^}]*}'
"$HM" evaluate --dataset "$DATASET" --result "$OUT/station/graph.json" --json \
  > "$OUT/evaluated.json" || exit 1
"$HM" run --dataset "$DATASET" --out "$OUT/run" --quiet > /dev/null || exit 1
compare_with_run "$HM" "$DATASET" "$OUT/evaluated.json" "$OUT/run/metrics.json" station || exit 1
