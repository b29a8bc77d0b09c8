#!/usr/bin/env bash
# The station and the robots of a dataset as separate processes on loopback (127.0.0.1 only):
# every robot's updates arrive once and are applied, every robot is aligned, and the station's
# graph scores as `run`'s on the same dataset. Bounded: 60 s for the whole; every process this
# script starts is killed when it ends, also on failure.
# Prints the bandwidth the station counted: rows of bandwidth.csv, full resends against the
# updates. ROBOT_FLAGS go to every robot (--full-resend: the whole map every update); ORDER in the
# environment is the station's --order (arrival unless given).
#   usage: networked_run.sh HYDRA_MULTI DATASET OUT_DIR SPEED [ROBOT_FLAGS...]
set -u
HM=$1
DATASET=$2
OUT=$3
SPEED=$4
shift 4
rm -rf "$OUT"
mkdir -p "$OUT"
. "$(dirname "$0")/processes.sh"

spawn "$OUT/station.txt" timeout 60 "$HM" station --listen 'tcp://127.0.0.1:*' \
  --out "$OUT/station" --expect-robots 2 --order "${ORDER:-arrival}" --quiet
station=$spawned
await_endpoint "$OUT/station"
robots=()
for robot in a b; do
  spawn "$OUT/robot_$robot.txt" timeout 50 "$HM" robot --dataset "$DATASET" --robot "$robot" \
    --connect "$endpoint" --speed "$SPEED" --quiet "$@"
  robots+=("$spawned")
done
status=0
for p in "${robots[@]}"; do wait "$p" || status=1; done
# A robot that failed leaves the station waiting for its BYE: stop here (the cleanup stops it).
[ "$status" -eq 0 ] || { echo "FAIL: a robot failed"; cat "$OUT"/*.txt; exit 1; }
wait "$station" || status=1
cat "$OUT"/robot_*.txt "$OUT/station.txt"
[ "$status" -eq 0 ] || { echo "FAIL: a process failed"; exit 1; }

"$HM" evaluate --dataset "$DATASET" --result "$OUT/station/graph.json" --json > "$OUT/networked.json" || exit 1
"$HM" run --dataset "$DATASET" --out "$OUT/run" --quiet > /dev/null || exit 1
tr -d ' \n' < "$OUT/station/station.json"
echo
compare_with_run "$HM" "$DATASET" "$OUT/networked.json" "$OUT/run/metrics.json" networked || exit 1
rows=$(($(wc -l < "$OUT/station/bandwidth.csv") - 1))
ratio=$(tr -d ' \n' < "$OUT/station/station.json" | sed -E 's/.*"full_resend_ratio":([0-9.]+).*/\1/')
printf 'bandwidth: %d updates in bandwidth.csv, full resends %.1f times the updates\n' "$rows" "$ratio"
grep -q '<polyline class="full"' "$OUT/station/bandwidth.svg" && echo "bandwidth.svg drawn"
# The station's loop closures, without the truth's columns: its measurements and verdicts only.
head -n 1 "$OUT/station/loop_closures.csv"
echo "loop_closures.csv: $(($(wc -l < "$OUT/station/loop_closures.csv") - 1)) inter-robot loop closures"
