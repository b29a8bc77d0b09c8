#!/usr/bin/env bash
# The demo until the station exists: a simulated office team (the built-in default dataset), the
# real Hydra scene graph of the uHumans2 apartment in every format the project writes, and the
# robust back end on real multi-robot data.
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
echo "== hydra-multi demo: a simulated team of 3 robots mapping an office floor (office-3, seed 1) =="
"$bin" simulate --preset office-3 --seed 1 --out "$out/office-3"
"$bin" dataset-graph --dataset "$out/office-3" --robot a --out "$out/office-3-robot-a.json"
echo "Robot a's own map scored against the ground truth (in its own frame: the global frame):"
"$bin" evaluate --dataset "$out/office-3" --result "$out/office-3-robot-a.json"
echo
echo "== the station's frontend on the team's streams: where did two robots see the same place? =="
"$bin" detect --dataset "$out/office-3" --quiet
echo
echo "== the station: frontend and backend threads, one scene graph of the team (about a minute) =="
"$bin" run --dataset "$out/office-3" --out "$out/office-3-run" --quiet

echo
echo "== the real Hydra scene graph of the uHumans2 apartment =="
"$bin" info "$input"
echo
"$bin" convert "$input" "$out/apartment.dsgb"
"$bin" convert "$out/apartment.dsgb" "$out/apartment.json"
"$bin" convert "$out/apartment.json" "$out/apartment.spark.json"
"$bin" info "$out/apartment.dsgb" --json > "$out/summary.json"
echo "wrote $out/summary.json (the counts above as one JSON object)"

echo
echo "== the robust back end: two robots of unknown frames, 128 true and 250 spurious loop closures =="
csail="$data/multirobot/csail_2robots"
"$bin" pgo --input "$csail/CSAIL_robot1.g2o" --input "$csail/CSAIL_robot2.g2o" \
  --input "$csail/CSAIL_interrobot_loop_closures_outliers.g2o" --unknown-frames --robust gnc \
  --inlier-edges "$csail/CSAIL_interrobot_loop_closures.g2o" --output "$out/csail_optimized.g2o" --quiet
echo
echo "Results are in $out/:"
echo "  office-3/             the simulated dataset: dataset.json, robots/<r>/updates.dsgb, gt/"
echo "  office-3-robot-a.json robot a's final graph (its update stream replayed)"
echo "  office-3-run/         the station's output: graph.json, graph.spark.json, mesh.ply,"
echo "                        metrics.json, timing.csv"
echo "  apartment.json        our readable JSON (one node, edge or vertex per line)"
echo "  apartment.dsgb        our compact binary"
echo "  apartment.spark.json  Spark-DSG's JSON layout, read back by our importer"
echo "  summary.json          counts per layer and per robot"
echo "  csail_optimized.g2o   both CSAIL robots in robot 0's frame, outliers rejected"
echo "Not built yet: merging what several robots saw twice, baselines, ablations, trials (README.md)."
