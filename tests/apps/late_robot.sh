#!/usr/bin/env bash
# The time order with a robot silent for longer than the hold, on loopback (127.0.0.1 only):
# robot b streams its whole mission to a station holding updates at most 0.5 s, and robot a
# starts only 2 s after b has finished. b's updates go on at the hold; a's earlier ones come after
# them: the station says so at a's first, counts them late in station.json and its summary, and
# still applies every update. Bounded: 40 s for the whole; every process started here is stopped
# when it ends.
#   usage: late_robot.sh HYDRA_MULTI DATASET OUT_DIR
. "$(dirname "$0")/processes.sh" with_dataset "$@"

spawn "$OUT/station.txt" timeout 40 "$HM" station --listen 'tcp://127.0.0.1:*' \
  --out "$OUT/station" --expect-robots 2 --order time --order-hold 0.5
station=$spawned
await_endpoint "$OUT/station"
timeout 30 "$HM" robot --dataset "$DATASET" --robot b --connect "$endpoint" --speed 0 --quiet ||
  { echo "FAIL: robot b failed"; cat "$OUT/station.txt"; exit 1; }
sleep 2
timeout 30 "$HM" robot --dataset "$DATASET" --robot a --connect "$endpoint" --speed 0 --quiet ||
  { echo "FAIL: robot a failed"; cat "$OUT/station.txt"; exit 1; }
wait "$station" || { echo "FAIL: the station failed"; cat "$OUT/station.txt"; exit 1; }
grep -E "came after updates of later robot time|^  (updates|time order) " "$OUT/station.txt"
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"updates_applied":[0-9]*\|"updates_late":[0-9]*'
