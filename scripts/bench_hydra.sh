#!/usr/bin/env bash
# What the station loses when robots send only what Hydra sends (issue 21): office-3 (SEED, 1 by
# default) mapped by
#   run            the file replay of our robots' streams (the reference)
#   run, no kp     the same robots without keypoints (no visual loop closures can be verified)
#   run, no own lc the same robots without their own loop closures
#   run, Hydra's   both: the content of a Hydra robot's graph, through our protocol
#   protocol       our robots as processes over our protocol on loopback at SPEED times real time
#   Hydra          the same robots speaking as Hydra robots (robot --spark: their whole graph in
#                  Spark-DSG's wire form after every update) into station --spark-robot
# and, per method: ATE, objects found and correct, places error, rooms, robots aligned,
# inter-robot loop closures detected and kept, and the bytes the robots sent. Loopback only.
# About 6 minutes on 2 cores at SPEED 10.
#   usage: bench_hydra.sh HYDRA_MULTI OUT_DIR [SEED] [SPEED]
set -euo pipefail
bin=${1:?usage: bench_hydra.sh HYDRA_MULTI OUT_DIR [SEED] [SPEED]}
out=${2:?}
seed=${3:-1}
speed=${4:-10}
mkdir -p "$out"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done; }
trap cleanup EXIT

# field FILE EXPRESSION: a value of a JSON file (j is the file's object).
field() { node -p "const j = JSON.parse(require('fs').readFileSync('$1', 'utf8')); $2"; }

# BENCH_HYDRA_TABLE_ONLY=1: only the table, from the outputs of an earlier run in OUT_DIR.
if [ -z "${BENCH_HYDRA_TABLE_ONLY:-}" ]; then
declare -A datasets=([full]="" [nokp]="--no-keypoints" [nolc]="--no-own-loop-closures"
                     [hydra]="--no-keypoints --no-own-loop-closures")
for name in full nokp nolc hydra; do
  rm -rf "$out/office-3-$name"
  # shellcheck disable=SC2086
  "$bin" simulate --preset office-3 --seed "$seed" --out "$out/office-3-$name" ${datasets[$name]} \
    --quiet > /dev/null
  echo "run on office-3 seed $seed (${datasets[$name]:-as our robots send it})" >&2
  rm -rf "$out/run-$name"
  "$bin" run --dataset "$out/office-3-$name" --out "$out/run-$name" --quiet > /dev/null
done
dataset=$out/office-3-full

echo "our protocol: 3 robots at --speed $speed into a station on loopback" >&2
rm -rf "$out/protocol"
"$bin" station --listen 'tcp://127.0.0.1:*' --out "$out/protocol" --expect-robots 3 --quiet \
  > "$out/protocol.txt" 2>&1 &
station=$!
pids+=("$station")
for _ in $(seq 100); do [ -s "$out/protocol/endpoint" ] && break; sleep 0.1; done
for robot in a b c; do
  "$bin" robot --dataset "$dataset" --robot "$robot" --connect "$(cat "$out/protocol/endpoint")" \
    --speed "$speed" --timeout 3600 --quiet > "$out/protocol-$robot.txt" 2>&1 &
  pids+=("$!")
done
wait "$station"

echo "Hydra robots: 3 robots at --speed $speed publishing their whole graphs, station --spark-robot" >&2
rm -rf "$out/hydra"
args=()
for robot in a b c; do
  "$bin" robot --dataset "$dataset" --robot "$robot" --spark --bind 'tcp://127.0.0.1:*' \
    --speed "$speed" > "$out/hydra-$robot.txt" 2>&1 &
  pids+=("$!")
  for _ in $(seq 50); do grep -q "tcp://" "$out/hydra-$robot.txt" && break; sleep 0.1; done
  args+=(--spark-robot "$robot=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$out/hydra-$robot.txt" | head -1)")
done
"$bin" station --listen 'tcp://127.0.0.1:*' --out "$out/hydra" "${args[@]}" --expect-robots 3 \
  --spark-done-after 5 > "$out/hydra.txt" 2>&1

for name in protocol hydra; do
  "$bin" evaluate --dataset "$dataset" --result "$out/$name/graph.json" --json > "$out/$name/metrics.json"
done

fi

row() {  # NAME METRICS_JSON LOOP_CLOSURES_CSV ROBOTS_ALIGNED BYTES
  local m=$2
  local detected kept
  detected=$(($(wc -l < "$3") - 1))
  kept=$(awk -F, 'NR > 1 && $NF == 1 { n++ } END { print n + 0 }' "$3")
  printf '| %s | %.3f | %.1f | %.1f | %.3f | %d (%.2f, %.2f) | %d of 3 | %d / %d | %s |\n' "$1" \
    "$(field "$m" j.ate_rmse_m)" "$(field "$m" j.objects_found_pct)" \
    "$(field "$m" j.objects_correct_pct)" "$(field "$m" j.places_position_error_m)" \
    "$(field "$m" j.num_rooms)" "$(field "$m" j.rooms_precision)" "$(field "$m" j.rooms_recall)" \
    "$4" "$detected" "$kept" "$5"
}
mb() { awk -v b="$1" 'BEGIN { printf "%.2f MB", b / 1e6 }'; }
echo
echo "office-3 seed $seed: what the station makes of what robots send"
echo
echo "| method | ATE (m) | objects found (%) | objects correct (%) | places error (m) | rooms (P, R) | aligned | inter-robot loop closures detected / kept | bytes sent |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
aligned() { field "$1" j.robots_aligned; }
row "run: our robots' streams" "$out/run-full/metrics.json" "$out/run-full/loop_closures.csv" \
  "$(aligned "$out/run-full/metrics.json")" "$(mb "$(awk -F, 'NR > 1 { s += $5 } END { print s }' "$out/run-full/bandwidth.csv")") as records"
row "run: no keypoints" "$out/run-nokp/metrics.json" "$out/run-nokp/loop_closures.csv" \
  "$(aligned "$out/run-nokp/metrics.json")" ""
row "run: no own loop closures" "$out/run-nolc/metrics.json" "$out/run-nolc/loop_closures.csv" \
  "$(aligned "$out/run-nolc/metrics.json")" ""
row "run: neither (what Hydra sends)" "$out/run-hydra/metrics.json" "$out/run-hydra/loop_closures.csv" \
  "$(aligned "$out/run-hydra/metrics.json")" ""
row "our protocol, --speed $speed" "$out/protocol/metrics.json" "$out/protocol/loop_closures.csv" \
  "$(aligned "$out/protocol/station.json")" "$(mb "$(field "$out/protocol/station.json" j.update_bytes)") on the wire (zstd)"
row "Hydra robots, --speed $speed" "$out/hydra/metrics.json" "$out/hydra/loop_closures.csv" \
  "$(aligned "$out/hydra/station.json")" "$(mb "$(field "$out/hydra/station.json" j.bytes_received)") on the wire (whole graphs)"
echo
graphs=$(field "$out/hydra/station.json" "Object.values(j.per_robot).reduce((s, r) => s + r.graphs, 0)")
overtaken=$(field "$out/hydra/station.json" "Object.values(j.per_robot).reduce((s, r) => s + r.overtaken, 0)")
echo "Hydra robots: $graphs graphs received, $overtaken overtaken by a newer one; the updates the" \
  "station made of them: $(mb "$(field "$out/hydra/station.json" j.update_record_bytes)") as records"
echo "our robots' full resends of their maps, as our records: $(mb "$(field "$out/protocol/station.json" j.full_resend_bytes)")"
echo "per robot, Hydra's whole graphs against our protocol's deltas on the wire:"
for robot in a b c; do
  echo "  $robot: $(mb "$(field "$out/hydra/station.json" "j.per_robot.$robot.bytes")") against" \
    "$(mb "$(field "$out/protocol/station.json" "j.per_robot.$robot.update_bytes")")"
done
ms() { awk -v x="$1" 'BEGIN { printf "%.1f", x }'; }
for name in protocol hydra; do
  j=$out/$name/station.json
  echo "$name: frontend per update median $(ms "$(field "$j" j.frontend_ms_p50)") ms; backend" \
    "round median $(ms "$(field "$j" j.backend_ms_p50)") ms, max $(ms "$(field "$j" j.backend_ms_max)") ms"
done
