#!/usr/bin/env bash
# The station killed with SIGKILL while two robots stream to it (loopback only), and started again
# on the same --out: it replays its journal, the robots say HELLO again, are welcomed past what it
# holds and send the rest. Nothing acknowledged is lost, nothing is applied twice: the station
# ends with every update of both robots, each once, its journal holds each once and is intact,
# and its map scores as `run`'s (the station takes updates in robot time: --order time).
# Bounded: 60 s; every process started here is killed when the script ends.
#   usage: station_restart.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

# Not under timeout: the station itself must get the SIGKILL (the cleanup stops it in any case).
spawn "$OUT/first.txt" "$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station" \
  --expect-robots 2 --order time
first=$spawned
await_endpoint "$OUT/station"
robots=()
for robot in a b; do
  spawn "$OUT/robot_$robot.txt" timeout 50 "$HM" robot --dataset "$DATASET" --robot "$robot" \
    --connect "$endpoint" --speed 10
  robots+=("$spawned")
done
sleep 4
kill -9 "$first"
wait "$first" 2> /dev/null
echo "killed the station after 4 s"
spawn "$OUT/second.txt" timeout 50 "$HM" station --listen "$endpoint" --out "$OUT/station" \
  --expect-robots 2 --order time
second=$spawned
status=0
for p in "${robots[@]}"; do wait "$p" || status=1; done
# A robot that failed leaves the station waiting for its BYE: stop here (the cleanup stops it).
[ "$status" -eq 0 ] || { echo "FAIL: a robot failed"; cat "$OUT"/*.txt; exit 1; }
wait "$second" || status=1
grep -h -E "^robot [ab] to |saying HELLO again|welcomed, the station holds every update before [1-9]" "$OUT"/robot_*.txt | sort
grep -E "^station: resumed from" "$OUT/second.txt"
[ "$status" -eq 0 ] || { echo "FAIL: a process failed"; cat "$OUT"/*.txt; exit 1; }
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"updates_applied":[0-9]*,"updates_duplicate":[0-9]*'
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"journal_entries":[0-9]*,"journal_integrity":"[a-z]*","updates_replayed":[0-9]*'
"$HM" evaluate --dataset "$DATASET" --result "$OUT/station/graph.json" --json \
  > "$OUT/evaluated.json" || exit 1
"$HM" run --dataset "$DATASET" --out "$OUT/run" --quiet > /dev/null || exit 1
compare_with_run "$HM" "$DATASET" "$OUT/evaluated.json" "$OUT/run/metrics.json" station || exit 1
