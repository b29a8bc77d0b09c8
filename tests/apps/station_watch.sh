#!/usr/bin/env bash
# The fused graph for others (loopback only): a station with --publish, one `watch` subscribed
# before the robots start and one that joins 2 s later. Each prints a line per fused update, the
# late one starting from a snapshot, and both end at the station's final graph with the graph the
# station wrote (the same counts per layer, robot and mesh). The station serves the viewer too
# (--http on a free port): its event stream carries a view and both robots' links, and the station
# leaves the history `view` reads. Bounded: 60 s; every process started here is stopped when it
# ends.
#   usage: station_watch.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

spawn "$OUT/station.txt" timeout 50 "$HM" station --listen 'tcp://127.0.0.1:*' \
  --publish 'tcp://127.0.0.1:*' --out "$OUT/station" --expect-robots 2 --http 127.0.0.1:0
station=$spawned
await_endpoint "$OUT/station"
for _ in $(seq 50); do [ -s "$OUT/station/publish" ] && break; sleep 0.1; done
publish=$(cat "$OUT/station/publish")
spawn "$OUT/early.txt" timeout 50 "$HM" watch --connect "$publish" --out "$OUT/early.dsgb"
early=$spawned
for robot in a b; do
  spawn "$OUT/robot_$robot.txt" timeout 50 "$HM" robot --dataset "$DATASET" --robot "$robot" \
    --connect "$endpoint" --speed 10 --quiet
done
for _ in $(seq 50); do [ -s "$OUT/station/http" ] && break; sleep 0.1; done
timeout 20 node "$(dirname "$0")/../web/read_events.mjs" "$(cat "$OUT/station/http")" 15 a b > "$OUT/events.txt"
sleep 1
spawn "$OUT/late.txt" timeout 50 "$HM" watch --connect "$publish" --out "$OUT/late.json"
late=$spawned
wait "$station" || { echo "FAIL: the station failed"; cat "$OUT"/*.txt; exit 1; }
for w in "$early" "$late"; do wait "$w" || { echo "FAIL: a watcher failed"; cat "$OUT"/*.txt; exit 1; }; done
grep -E "^station: publishing the fused graph" "$OUT/station.txt"
for name in early late; do
  echo "$name: $(grep -c '^sequence ' "$OUT/$name.txt") lines, first: $(grep -m1 '^sequence ' "$OUT/$name.txt" | cut -d' ' -f1-2)"
  grep -E "^watch: " "$OUT/$name.txt"
done
cat "$OUT/events.txt"
echo "viewer history: $(($(wc -l < "$OUT/station/viewer/history.jsonl") - 1)) views, mesh.bin $([ -s "$OUT/station/viewer/mesh.bin" ] && echo written)"
for name in early.dsgb late.json; do
  if diff <("$HM" info "$OUT/station/graph.json" | tail -n +2) <("$HM" info "$OUT/$name" | tail -n +2); then
    echo "$name is the station's graph"
  fi
done
