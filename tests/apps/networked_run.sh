#!/usr/bin/env bash
# The station and the robots of a dataset as separate processes on loopback (127.0.0.1 only):
# every robot's updates arrive once and are applied, every robot is aligned, and the station's
# graph scores as `run`'s on the same dataset. Bounded: 60 s for the whole; every process this
# script starts is killed when it ends, also on failure.
#   usage: networked_run.sh HYDRA_MULTI DATASET OUT_DIR SPEED
set -u
HM=$1
DATASET=$2
OUT=$3
SPEED=$4
rm -rf "$OUT"
mkdir -p "$OUT"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done; }
trap cleanup EXIT

timeout 60 "$HM" station --listen 'tcp://127.0.0.1:*' --out "$OUT/station" --expect-robots 2 \
  --quiet > "$OUT/station.txt" 2>&1 &
station=$!
pids+=("$station")
for _ in $(seq 100); do [ -s "$OUT/station/endpoint" ] && break; sleep 0.1; done
[ -s "$OUT/station/endpoint" ] || { echo "FAIL: the station wrote no endpoint"; cat "$OUT/station.txt"; exit 1; }
endpoint=$(cat "$OUT/station/endpoint")
case $endpoint in tcp://127.0.0.1:*) ;; *) echo "FAIL: endpoint $endpoint is not loopback"; exit 1 ;; esac

for robot in a b; do
  timeout 50 "$HM" robot --dataset "$DATASET" --robot "$robot" --connect "$endpoint" \
    --speed "$SPEED" --quiet > "$OUT/robot_$robot.txt" 2>&1 &
  pids+=("$!")
done
status=0
for p in "${pids[@]:1}"; do wait "$p" || status=1; done
wait "$station" || status=1
cat "$OUT"/robot_*.txt "$OUT/station.txt"
[ "$status" -eq 0 ] || { echo "FAIL: a process failed"; exit 1; }

"$HM" evaluate --dataset "$DATASET" --result "$OUT/station/graph.json" --json > "$OUT/networked.json" || exit 1
"$HM" run --dataset "$DATASET" --out "$OUT/run" --quiet > /dev/null || exit 1
tr -d ' \n' < "$OUT/station/station.json"
echo
# The two maps' objects and ATE, side by side: the same within 1 mm and 0.1 points.
figures() {
  tr -d ' \n' < "$1" | sed -E 's/.*"ate_rmse_m":([0-9.e-]+),"objects_found_pct":([0-9.]+),"objects_correct_pct":([0-9.]+).*/\1 \2 \3/'
}
read -r ate_net found_net correct_net < <(figures "$OUT/networked.json")
read -r ate_run found_run correct_run < <(figures "$OUT/run/metrics.json")
echo "networked: ATE $ate_net m, objects found $found_net %, correct $correct_net %"
echo "run:       ATE $ate_run m, objects found $found_run %, correct $correct_run %"
awk -v a="$ate_net" -v b="$ate_run" -v f="$found_net" -v g="$found_run" -v c="$correct_net" -v d="$correct_run" \
  'BEGIN { d1 = a - b; d2 = f - g; d3 = c - d;
           if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2; if (d3 < 0) d3 = -d3;
           if (d1 <= 0.001 && d2 <= 0.1 && d3 <= 0.1) print "same map"; else { print "FAIL: the maps differ"; exit 1 } }'
