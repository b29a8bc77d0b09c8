#!/usr/bin/env bash
# The fused graph in Spark-DSG's wire form (loopback only): a station with --spark-publish, the
# tiny team's two robots, and `watch --spark` as a plain SUB (as Spark-DSG's ZmqReceiver). The
# watcher takes whole graphs in Spark-DSG's binary layout, decodes them with our codec, and its
# last one is the graph the station wrote: the same counts per layer, robot and mesh, and byte
# for byte the station's graph.json in Spark-DSG's form (convert). Bounded: 60 s; every process
# started here is stopped when it ends.
#   usage: station_spark_publish.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

spawn "$OUT/station.txt" timeout 50 "$HM" station --listen 'tcp://127.0.0.1:*' \
  --spark-publish 'tcp://127.0.0.1:*' --out "$OUT/station" --expect-robots 2
station=$spawned
await_endpoint "$OUT/station"
for _ in $(seq 50); do [ -s "$OUT/station/spark_publish" ] && break; sleep 0.1; done
spawn "$OUT/watch.txt" timeout 55 "$HM" watch --spark --connect "$(cat "$OUT/station/spark_publish")" \
  --out "$OUT/spark.sparkdsg" --idle 4
watcher=$spawned
sleep 0.5
for robot in a b; do
  spawn "$OUT/robot_$robot.txt" timeout 50 "$HM" robot --dataset "$DATASET" --robot "$robot" \
    --connect "$endpoint" --speed 10 --quiet
done
wait "$station" || { echo "FAIL: the station failed"; cat "$OUT"/*.txt; exit 1; }
wait "$watcher" || { echo "FAIL: the watcher failed"; cat "$OUT"/*.txt; exit 1; }
grep -E "^station: publishing the fused graph in Spark-DSG's wire form" "$OUT/station.txt" | sed 's/:[0-9]*$/:PORT/'
echo "watch: $(grep -c '^spark graph ' "$OUT/watch.txt") graphs"
if diff <("$HM" info "$OUT/station/graph.json" | tail -n +2) <("$HM" info "$OUT/spark.sparkdsg" | tail -n +2); then
  echo "the last Spark-DSG graph is the station's graph"
fi
"$HM" convert "$OUT/station/graph.json" "$OUT/station.sparkdsg" > /dev/null
cmp "$OUT/station.sparkdsg" "$OUT/spark.sparkdsg" && echo "byte for byte"
