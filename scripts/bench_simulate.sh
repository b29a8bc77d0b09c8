#!/usr/bin/env bash
# Generation time, size and difficulty of every simulated preset (issue 4's done-when figures):
# wall time per preset, the dataset's size on disk, each robot's path and drift, the aliasing
# share and what odometry alone does to the objects.
set -euo pipefail
bin=${1:?usage: bench_simulate.sh HYDRA_MULTI_BINARY OUT_DIR [SEEDS]}
out=${2:?}
seeds=${3:-1}
mkdir -p "$out"
for preset in tiny office-3 residence-3f dorm-2 dorm-2-meet hetero-2; do
  for seed in $seeds; do
    dir="$out/$preset-$seed"
    rm -rf "$dir"
    start=$(date +%s%N)
    "$bin" simulate --preset "$preset" --seed "$seed" --out "$dir" --quiet > "$out/.summary"
    end=$(date +%s%N)
    kb=$(du -sk "$dir" | cut -f1)
    awk -v p="$preset" -v s="$seed" -v ns=$((end - start)) -v kb="$kb" \
      'BEGIN { printf "== %s seed %s: %.1f s, %.1f MB on disk\n", p, s, ns / 1e9, kb / 1024 }'
    sed -n '2,$p' "$out/.summary"
  done
done
rm -f "$out/.summary"
