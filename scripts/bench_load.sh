#!/usr/bin/env bash
# The station under load (issue 23): office-3 teams (ROBOTSxSCALE@SPEED each; by default 10
# robots at scale 2 ten times faster than real time, and 20 robots at scale 2 in real time), one
# seed, each simulated, then a station on loopback and one robot process per robot streaming at
# that speed; bench_load prints per team the latency of each update through the frontend, the
# ingest queue over time, the backend's rounds, memory, CPU and whether the station kept up.
# Each team's station folder keeps load.csv (the queue, memory and CPU once a second), timing.csv,
# station.json and the robots' logs. Nothing but 127.0.0.1 is addressed.
#   usage: bench_load.sh HYDRA_MULTI BENCH_LOAD OUT_DIR [SEED] [TEAMS]
set -euo pipefail
bin=${1:?usage: bench_load.sh HYDRA_MULTI BENCH_LOAD OUT_DIR [SEED] [TEAMS]}
summary=${2:?}
out=${3:?}
seed=${4:-1}
teams=${5:-"10x2@10 20x2@1"}
# The robots run on this machine too, where on a team each has its own computer: at the lowest
# priority they take only the CPU the station leaves (ROBOT_NICE=0: as the station).
robot_nice=${ROBOT_NICE:-19}
mkdir -p "$out"
now() { date +%s.%N; }
args=()
for team in $teams; do
  speed=${team#*@}
  size=${team%@*}
  robots=${size%x*}
  scale=${size#*x}
  data="$out/office-3-r$robots-s$scale-$seed"
  if [ ! -s "$data/dataset.json" ]; then
    echo "simulating office-3 --robots $robots --scale $scale --seed $seed" >&2
    "$bin" simulate --preset office-3 --robots "$robots" --scale "$scale" --seed "$seed" \
      --out "$data" --quiet > /dev/null
  fi
  run="$out/r$robots-s$scale-speed$speed"
  rm -rf "$run"
  mkdir -p "$run"
  "$bin" station --listen 'tcp://127.0.0.1:*' --out "$run/station" --expect-robots "$robots" \
    > "$run/station.txt" 2> "$run/station.log" &
  station=$!
  for _ in $(seq 100); do [ -s "$run/station/endpoint" ] && break; sleep 0.1; done
  [ -s "$run/station/endpoint" ] || { echo "bench_load: the station did not start" >&2; exit 1; }
  listening=$(now)
  endpoint=$(cat "$run/station/endpoint")
  letters=$(grep -o '"robot": "[a-z]"' "$data/dataset.json" | cut -d'"' -f4 | awk '!seen[$0]++' |
    tr -d '\n')  # the dataset's robots, in order (p is the places' prefix: a robot never has it)
  [ "${#letters}" -eq "$robots" ] || { echo "bench_load: $data has not $robots robots" >&2; exit 1; }
  echo "$robots robots (scale $scale) at $speed times real time into $endpoint" >&2
  pids=()
  for ((k = 0; k < robots; k++)); do
    r=${letters:$k:1}
    nice -n "$robot_nice" "$bin" robot --dataset "$data" --robot "$r" --connect "$endpoint" --speed "$speed" \
      --quiet --timeout 120 > "$run/robot-$r.log" 2>&1 &
    pids+=($!)
  done
  failed=0
  for pid in "${pids[@]}"; do wait "$pid" || failed=$((failed + 1)); done
  ended=$(now)
  wait "$station" || { echo "bench_load: the station failed (see $run/station.log)" >&2; exit 1; }
  [ "$failed" -eq 0 ] || { echo "bench_load: $failed robots failed (see $run/robot-*.log)" >&2; exit 1; }
  awk -v r="$robots" -v s="$scale" -v v="$speed" -v a="$listening" -v b="$ended" 'BEGIN {
    printf "{\"robots\": %d, \"scale\": %d, \"speed\": %s, \"robots_end_s\": %.3f}\n", r, s, v, b - a }' \
    > "$run/station/bench.json"
  args+=("$robots robots, scale $scale, ${speed}x=$run/station")
done
"$summary" "${args[@]}"
