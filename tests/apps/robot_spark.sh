#!/usr/bin/env bash
# A robot that speaks as a Hydra robot (loopback only): `robot --spark` publishes its whole graph
# in Spark-DSG's wire form after every update on a PUB it binds; `watch --spark`, a plain SUB,
# takes every graph and its last is the robot's own final graph (`dataset-graph`: the same counts
# per layer, robot and mesh). Bounded: 40 s; every process started here is stopped when it ends.
#   usage: robot_spark.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

spawn "$OUT/robot.txt" timeout 35 "$HM" robot --dataset "$DATASET" --robot a --spark \
  --bind 'tcp://127.0.0.1:*' --speed 10
robot=$spawned
for _ in $(seq 50); do grep -q "tcp://" "$OUT/robot.txt" && break; sleep 0.1; done
ep=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$OUT/robot.txt" | head -1)
timeout 35 "$HM" watch --spark --connect "$ep" --out "$OUT/hydra.dsgb" --idle 3 > "$OUT/watch.txt" 2>&1 \
  || { echo "FAIL: the watcher failed"; cat "$OUT"/*.txt; exit 1; }
wait "$robot" || { echo "FAIL: the robot failed"; cat "$OUT"/*.txt; exit 1; }
grep -E "^robot a: published" "$OUT/robot.txt" | sed 's/(the last [0-9]* bytes)/(the last N bytes)/'
echo "watch: $(grep -c '^spark graph ' "$OUT/watch.txt") graphs"
"$HM" dataset-graph --dataset "$DATASET" --robot a --out "$OUT/own.dsgb" > /dev/null
if diff <("$HM" info "$OUT/own.dsgb" | tail -n +2) <("$HM" info "$OUT/hydra.dsgb" | tail -n +2); then
  echo "the last graph is the robot's own"
fi
