#!/usr/bin/env bash
# Two Hydra robots that saw the same apartment (loopback only): both publish the real Hydra graph
# of the uHumans2 apartment as Spark-DSG wrote it (robot --spark --graph), the second moved by a
# rigid transform the station is not told (a 70 degree turn and an offset of metres), both with
# agents of Hydra's robot 0 ('a'). The station takes them as robots a and b (--spark-robot),
# aligns b with a and merges the copies: 7 objects and 185 places, not 14 and 370. Bounded:
# 60 s; every process started here is stopped when it ends.
#   usage: hydra_apartment.sh HYDRA_MULTI SPARKDSG OUT_DIR
set -u
. "$(dirname "$0")/processes.sh"
HM=$1
GRAPH=$2
OUT=$3
rm -rf "$OUT"
mkdir -p "$OUT"

# A robot's endpoint, once it has bound and said so: in $robot_endpoint.
await_robot() {
  for _ in $(seq 50); do grep -q "tcp://" "$1" && break; sleep 0.1; done
  robot_endpoint=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$1" | head -1)
  [ -n "$robot_endpoint" ] || { echo "FAIL: no endpoint in $1"; cat "$1"; exit 1; }
}
spawn "$OUT/robot_a.txt" timeout 40 "$HM" robot --spark --bind 'tcp://127.0.0.1:*' --graph "$GRAPH" \
  --count 8
await_robot "$OUT/robot_a.txt"
a=$robot_endpoint
spawn "$OUT/robot_b.txt" timeout 40 "$HM" robot --spark --bind 'tcp://127.0.0.1:*' --graph "$GRAPH" \
  --count 8 --move 4,-3,0.5,70
await_robot "$OUT/robot_b.txt"
b=$robot_endpoint
timeout 50 "$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station" \
  --spark-robot "a=$a" --spark-robot "b=$b" --expect-robots 2 --spark-done-after 2 \
  > "$OUT/station.txt" 2>&1 || { echo "FAIL: the station failed"; cat "$OUT"/*.txt; exit 1; }
grep -o "robot b (Hydra, [^)]*): its agents carry the prefix 'a', not 'b'; taken as robot b's keyframes" \
  "$OUT/station.txt" | sed 's/tcp:[^)]*/ENDPOINT/'
grep -E "^  robots aligned" "$OUT/station.txt"
"$HM" info "$OUT/station/graph.json" | grep -E "^  (agents|robot)"
