#!/usr/bin/env bash
# A station that runs until it is told to stop: a robot streams its map and leaves, then SIGTERM
# ends the station cleanly (exit 0, its last round run, its outputs written). Before, the signal
# interrupted ZeroMQ's poll and the station aborted. Loopback only; bounded: 60 s.
#   usage: station_signal.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

spawn "$OUT/station.txt" "$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station"
station=$spawned
await_endpoint "$OUT/station"
timeout 50 "$HM" robot --dataset "$DATASET" --robot a --connect "$endpoint" --quiet || exit 1
kill -TERM "$station"
wait "$station"
echo "station exit $?"
grep -E "^station: input closed|^outputs in" "$OUT/station.txt"
tr -d ' \n' < "$OUT/station/station.json" | grep -o '"updates_applied":[0-9]*'
echo
