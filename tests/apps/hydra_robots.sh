#!/usr/bin/env bash
# The tiny team's two robots speaking as Hydra robots (robot --spark: their whole graph after
# every update, no station protocol) into a station that takes them with --spark-robot
# (loopback only). The station is killed with SIGKILL after 4 s and started again on the same
# --out: it replays its journal and takes each robot's next graph whole, numbered after what the
# journal holds. It ends with nothing refused, rejected or behind a gap, an intact journal, and
# robot a's keyframes (the global frame's) once each. Robot b stays unaligned: the tiny team is
# aligned by visual loop closures alone, and Hydra robots send no keypoints to verify them.
# Bounded: 60 s; every process started here is stopped when it ends.
#   usage: hydra_robots.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"

args=()
robots=()
for robot in a b; do
  spawn "$OUT/robot_$robot.txt" timeout 40 "$HM" robot --dataset "$DATASET" --robot "$robot" \
    --spark --bind 'tcp://127.0.0.1:*' --speed 10
  robots+=("$spawned")
  for _ in $(seq 50); do grep -q "tcp://" "$OUT/robot_$robot.txt" && break; sleep 0.1; done
  args+=(--spark-robot "$robot=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$OUT/robot_$robot.txt" | head -1)")
done
# Not under timeout: the station itself must get the SIGKILL (the cleanup stops it in any case).
spawn "$OUT/first.txt" "$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station" \
  "${args[@]}" --expect-robots 2 --spark-done-after 2
first=$spawned
sleep 4
kill -9 "$first"
wait "$first" 2> /dev/null
echo "killed the station after 4 s"
spawn "$OUT/second.txt" timeout 50 "$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station" \
  "${args[@]}" --expect-robots 2 --spark-done-after 2
second=$spawned
status=0
for p in "${robots[@]}"; do wait "$p" || status=1; done
wait "$second" || status=1
[ "$status" -eq 0 ] || { echo "FAIL: a process failed"; cat "$OUT"/*.txt; exit 1; }
grep -E "^station: resumed from" "$OUT/second.txt" | sed -E 's/: [0-9]+ updates replayed/: N updates replayed/;s/from .*journal.sqlite/from JOURNAL/'
summary=$(tr -d ' \n' < "$OUT/station/station.json")
for robot in a b; do
  entry=$(printf '%s' "$summary" | grep -o "\"$robot\":{\"input\":\"hydra\",[^}]*")
  whole=$(printf '%s' "$entry" | grep -o '"snapshots":[0-9]*')
  refused=$(printf '%s' "$entry" | grep -o '"refused":[0-9]*')
  echo "robot $robot: ${whole#*:} whole graphs in the second station, ${refused#*:} refused"
done
printf '%s\n' "$summary" | grep -o '"updates_rejected":[0-9]*,"updates_behind_gap":[0-9]*'
printf '%s\n' "$summary" | grep -o '"journal_integrity":"[a-z]*"'
grep -E "^  robots aligned" "$OUT/second.txt"
for robot in a; do
  "$HM" dataset-graph --dataset "$DATASET" --robot "$robot" --out "$OUT/own_$robot.json" > /dev/null
  own=$("$HM" info "$OUT/own_$robot.json" | grep -o "robot $robot: [0-9]* agent poses")
  fused=$("$HM" info "$OUT/station/graph.json" | grep -o "robot $robot: [0-9]* agent poses")
  [ "$own" = "$fused" ] && echo "$fused, as its own map" || echo "FAIL: $fused, its own map $own"
done
