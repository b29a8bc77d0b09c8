#!/usr/bin/env bash
# The station's frontend alone (scene-graph processor and loop-closure detection) over simulated
# datasets: loop closures found and correct per robot pair and per layer, and the time to process
# one update (median, 95th percentile, max). Issue 5's bars: on office-3 every overlapping pair
# has 20 or more inter-robot loop closures, most correct; median under 10 ms, max under 100 ms.
set -euo pipefail
bin=${1:?usage: bench_frontend.sh HYDRA_MULTI_BINARY OUT_DIR [SEED]}
out=${2:?}
seed=${3:-1}
mkdir -p "$out"
for preset in office-3 dorm-2 dorm-2-meet residence-3f hetero-2; do
  dir="$out/$preset-$seed"
  rm -rf "$dir"
  "$bin" simulate --preset "$preset" --seed "$seed" --out "$dir" --quiet > /dev/null
  echo "== $preset seed $seed"
  "$bin" detect --dataset "$dir" --quiet
done
