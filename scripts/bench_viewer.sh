#!/usr/bin/env bash
# The viewer on the final graph of a 10-robot run (office-3 --robots 10 --scale 2, seed 7): makes
# the run first when RUN_DIR has none (about 11 minutes on 2 cores), then scripts/bench_viewer.mjs.
set -euo pipefail
bin=${1:?usage: bench_viewer.sh HYDRA_MULTI_BINARY RUN_DIR}
run=${2:?}
here=$(cd "$(dirname "$0")" && pwd)
if [ ! -s "$run/viewer/mesh.bin" ]; then
  dataset="${run%-run}"
  [ "$dataset" = "$run" ] && dataset="$run-dataset"
  echo "bench-viewer: no viewer history in $run: simulating office-3 --robots 10 --scale 2 (seed 7) into $dataset"
  "$bin" simulate --preset office-3 --robots 10 --scale 2 --seed 7 --out "$dataset" --quiet > /dev/null
  echo "bench-viewer: running the station over it into $run (about 11 minutes)"
  "$bin" run --dataset "$dataset" --out "$run" --quiet > /dev/null
fi
node "$here/bench_viewer.mjs" --bin "$bin" --web "$here/../web" --run "$run"
