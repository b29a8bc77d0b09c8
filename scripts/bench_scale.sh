#!/usr/bin/env bash
# The station at team scale (issue 22): office-3 with TEAMS (ROBOTSxSCALE each; by default 2, 5,
# 10, 15 and 20 robots at scales 1, 2 and 3, and 3 robots at scale 1: office-3 itself), one seed,
# each simulated and run (`run --speed SPEED`: the robots at SPEED times real time, 10 unless
# given; 0: as fast as the frontend takes them), then per team the final graph's size, the
# backend's time per round and per stage, the frontend's time per update, peak memory and
# accuracy, a plot of backend time against graph size, and issue 22's targets (bench_scale). A
# team whose run folder already holds a run at that speed is not run again unless REDO=1.
#   usage: bench_scale.sh HYDRA_MULTI BENCH_SCALE OUT_DIR [SEED] [TEAMS] [SPEED]
set -euo pipefail
bin=${1:?usage: bench_scale.sh HYDRA_MULTI BENCH_SCALE OUT_DIR [SEED] [TEAMS] [SPEED]}
summary=${2:?}
out=${3:?}
seed=${4:-1}
teams=${5:-"2x1 3x1 5x1 10x1 15x1 20x1 2x2 5x2 10x2 15x2 20x2 2x3 5x3 10x3 15x3 20x3"}
speed=${6:-10}
mkdir -p "$out"
# Whether RUN holds a finished run at this speed (metrics.json's "speed").
ran_at_speed() {
  [ -s "$1/metrics.json" ] &&
    grep -o '"speed": *[0-9.e+-]*' "$1/metrics.json" | awk -v want="$speed" -F: \
      '{ found = 1; if ($2 + 0 != want + 0) bad = 1 } END { exit !(found && !bad) }'
}
args=()
for team in $teams; do
  robots=${team%x*}
  scale=${team#*x}
  name="office-3-r$robots-s$scale-$seed"
  if [ "${REDO:-0}" = 1 ] || ! ran_at_speed "$out/$name-run"; then
    if [ ! -s "$out/$name/dataset.json" ]; then
      echo "simulating office-3 --robots $robots --scale $scale --seed $seed" >&2
      "$bin" simulate --preset office-3 --robots "$robots" --scale "$scale" --seed "$seed" \
        --out "$out/$name" --quiet > /dev/null
    fi
    echo "running $name at --speed $speed" >&2
    start=$(date +%s)
    rm -rf "$out/$name-run"
    "$bin" run --dataset "$out/$name" --out "$out/$name-run" --speed "$speed" --quiet \
      > "$out/$name-run.txt"
    echo "  $(( $(date +%s) - start )) s" >&2
  fi
  args+=("$robots robots, scale $scale=$out/$name-run")
done
"$summary" "$out/backend-scale.svg" "${args[@]}"
