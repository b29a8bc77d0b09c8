#!/usr/bin/env bash
# The demo: a simulated team of three robots mapping an office floor (office-3, seed 1, the
# built-in default dataset) through the whole station, scored against its ground truth, run again
# with the station and the robots as separate processes on loopback, and set against the paper's
# baselines; then the real Hydra scene graph of the uHumans2 apartment in every
# format the project writes and sent by two robots speaking Hydra's ZmqSink into one station, and
# the robust back end on real multi-robot data. About 2 minutes on
# 2 cores.
set -euo pipefail
bin=${1:?usage: demo.sh HYDRA_MULTI_BINARY DATA_DIR OUT_DIR}
data=${2:?}
out=${3:?}
input="$data/dsg/apartment_dsg.json"
if [ ! -f "$input" ]; then
  echo "demo: $input not found (the shared data must sit at ../shared/data)" >&2
  exit 1
fi
mkdir -p "$out"
start=$(date +%s)
echo "== hydra-multi demo: a simulated team of 3 robots mapping an office floor (office-3, seed 1) =="
"$bin" simulate --preset office-3 --seed 1 --out "$out/office-3"
echo
echo "== the station: frontend and backend threads over the team's streams (about 20 s) =="
"$bin" run --dataset "$out/office-3" --out "$out/office-3-run" --quiet
echo
echo "== the station's graph scored against the ground truth =="
"$bin" evaluate --dataset "$out/office-3" --result "$out/office-3-run/graph.json"
echo
echo "== the station as a service: the station and the three robots as separate processes on loopback =="
echo "   (robots as fast as acknowledged, taken in robot time; a watcher subscribed to the fused graph)"
rm -rf "$out/office-3-station"
"$bin" station --listen 'tcp://127.0.0.1:*' --out "$out/office-3-station" --expect-robots 3 \
  --order time --publish 'tcp://127.0.0.1:*' --quiet &
station=$!
trap 'kill "$station" 2> /dev/null || true' EXIT  # never left behind, also when a step fails
for _ in $(seq 100); do
  [ -s "$out/office-3-station/endpoint" ] && [ -s "$out/office-3-station/publish" ] && break
  sleep 0.1
done
endpoint=$(cat "$out/office-3-station/endpoint")
"$bin" watch --connect "$(cat "$out/office-3-station/publish")" --out "$out/office-3-watched.dsgb" \
  --quiet > "$out/office-3-watch.txt" &
watcher=$!
robots=()
for robot in a b c; do
  "$bin" robot --dataset "$out/office-3" --robot "$robot" --connect "$endpoint" --speed 0 --quiet &
  robots+=("$!")
done
for p in "${robots[@]}"; do wait "$p"; done
wait "$station"
wait "$watcher"
echo "the watcher saw $(grep -c '^sequence ' "$out/office-3-watch.txt") fused updates; its last:"
tail -n 1 "$out/office-3-watch.txt"
"$bin" evaluate --dataset "$out/office-3" --result "$out/office-3-station/graph.json"
echo
echo "== the same seed against the paper's baselines and ablation (about 1.5 minutes) =="
# --redo: a rerun of the demo shows what this build does, not runs an older one left behind.
"$bin" trials --preset office-3 --seeds 1-1 --methods full,gt-align,hm-align,no-rec \
  --out "$out/trials" --redo

echo
echo "== the real Hydra scene graph of the uHumans2 apartment =="
"$bin" info "$input"
"$bin" convert "$input" "$out/apartment.dsgb"
"$bin" convert "$out/apartment.dsgb" "$out/apartment.json"
"$bin" convert "$out/apartment.json" "$out/apartment.spark.json"
"$bin" info "$out/apartment.dsgb" --json > "$out/summary.json"

echo
echo "== Hydra robots joining unchanged: the apartment as Spark-DSG wrote it, from two robots speaking"
echo "   Hydra's ZmqSink, the second moved by 70 degrees and (4, -3, 0.5) m (about 10 s) =="
sparkdsg="$data/spark/apartment.sparkdsg"
rm -rf "$out/hydra-apartment"
mkdir -p "$out/hydra-apartment"
hydra=()
for robot in a b; do
  move=()
  [ "$robot" = b ] && move=(--move 4,-3,0.5,70)
  "$bin" robot --spark --bind 'tcp://127.0.0.1:*' --graph "$sparkdsg" --count 8 "${move[@]}" \
    > "$out/hydra-apartment/robot_$robot.txt" 2>&1 &
  hydra+=("$!")
  for _ in $(seq 50); do grep -q "tcp://" "$out/hydra-apartment/robot_$robot.txt" && break; sleep 0.1; done
done
"$bin" station --listen 'tcp://127.0.0.1:*' --out "$out/hydra-apartment/station" --expect-robots 2 \
  --spark-done-after 2 --quiet \
  --spark-robot "a=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$out/hydra-apartment/robot_a.txt" | head -1)" \
  --spark-robot "b=$(grep -o 'tcp://127.0.0.1:[0-9]*' "$out/hydra-apartment/robot_b.txt" | head -1)" \
  | grep -E "robots aligned|Hydra robots"
for p in "${hydra[@]}"; do wait "$p"; done
"$bin" info "$out/hydra-apartment/station/graph.json" | grep -E "^  (agents|robot)"
echo "(each copy has 7 objects and 185 places: the station merged them)"

echo
echo "== the robust back end: two robots of unknown frames, 128 true and 250 spurious loop closures =="
csail="$data/multirobot/csail_2robots"
"$bin" pgo --input "$csail/CSAIL_robot1.g2o" --input "$csail/CSAIL_robot2.g2o" \
  --input "$csail/CSAIL_interrobot_loop_closures_outliers.g2o" --unknown-frames --robust gnc \
  --inlier-edges "$csail/CSAIL_interrobot_loop_closures.g2o" --output "$out/csail_optimized.g2o" --quiet
echo
echo "Demo done in $(( $(date +%s) - start )) s. Results are in $out/:"
echo "  office-3/             the simulated dataset: dataset.json, robots/<r>/updates.dsgb, gt/"
echo "  office-3-run/         the station's output: graph.json, graph.spark.json, mesh.ply,"
echo "                        metrics.json, config.json, inputs.json, timing.csv, loop_closures.csv,"
echo "                        viewer/ (every backend round for the web viewer)"
echo "  office-3-station/     the networked station's output: graph.json, station.json,"
echo "                        bandwidth.csv, bandwidth.svg, journal.sqlite, ..."
echo "  office-3-watched.dsgb the fused graph as the watcher received it (office-3-watch.txt)"
echo "  trials/               table.md, objects.svg, places.svg, rooms.svg, backend_time.svg,"
echo "                        trials.json, runs/<method>/seed-1/ (each run's outputs)"
echo "  apartment.json        our readable JSON (one node, edge or vertex per line)"
echo "  apartment.dsgb        our compact binary"
echo "  apartment.spark.json  Spark-DSG's JSON layout, read back by our importer"
echo "  summary.json          counts per layer and per robot"
echo "  hydra-apartment/      the station's output for the two Hydra-speaking robots"
echo "  csail_optimized.g2o   both CSAIL robots in robot 0's frame, outliers rejected"
echo
echo "To look at the team's map in the web viewer, with every backend round of the run:"
echo "  $bin view $out/office-3-run --http 127.0.0.1:7880"
echo "then open http://127.0.0.1:7880/ in a browser (Ctrl-C stops the viewer)."
