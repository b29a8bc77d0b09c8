#!/usr/bin/env bash
# The online maps of every team preset: each dataset simulated, then bench_backend with a round
# every EVERY updates, each round's map scored against the truth. Per preset and seed: rounds,
# those with an ATE over 1 m (a robot in the wrong room or wing) and the last of them, those
# keeping wrong inter-robot loop closures, the rounds' median and max ATE, and the ATE of a round
# on the final state. The README lists the wrong early maps of look-alike buildings as missing;
# this is their measure.
set -euo pipefail
bin=${1:?usage: bench_online.sh HYDRA_MULTI_BINARY BENCH_BACKEND_BINARY OUT_DIR [SEEDS] [EVERY]}
bench=${2:?}
out=${3:?}
seeds=${4:-1 2 3 4 5}
every=${5:-10}
mkdir -p "$out"
printf '| preset | seed | rounds | ATE over 1 m | the last | keeping wrong loop closures | median ATE m | max ATE m | final state ATE m |\n'
printf '|---|---|---|---|---|---|---|---|---|\n'
for preset in office-3 residence-3f dorm-2 dorm-2-meet hetero-2; do
  for seed in $seeds; do
    dir="$out/$preset-$seed"
    rm -rf "$dir"
    "$bin" simulate --preset "$preset" --seed "$seed" --out "$dir" --quiet > /dev/null
    "$bench" "$dir" --every "$every" --rounds 1 > "$dir/bench_backend.txt"
    awk -v p="$preset" -v s="$seed" '
      /^online maps:/ {
        rounds = $3; over = $6
        last = "-"; if (match($0, /the last [^)]*/)) last = substr($0, RSTART + 9, RLENGTH - 9)
        match($0, /[0-9]+ keeping/); kept = substr($0, RSTART, RLENGTH - 8)
        match($0, /median [0-9.]+/); median = substr($0, RSTART + 7, RLENGTH - 7)
        match($0, /max [0-9.]+/); max = substr($0, RSTART + 4, RLENGTH - 4)
      }
      /^ +0 / { final = $NF }
      END { printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", p, s, rounds, over, last, kept, median, max, final }
    ' "$dir/bench_backend.txt"
  done
done
