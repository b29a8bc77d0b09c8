#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/README.md) for SECONDS each, JOBS at a time, from its
# committed seed corpus (fuzz/corpus/NAME) and, where the shared data has real files of its kind,
# from those too (read-only: ../shared/data/spark for the Spark-DSG targets, ../shared/data/pgo
# for g2o); inputs that found new coverage go to OUT/NAME/corpus, crashes to OUT/NAME/. Prints per
# target the executions, their rate, the corpus and what was found, and writes that table to
# OUT/summary.md. Exit status 1 if any target found something. With RUNS set, a target stops
# after that many executions (or SECONDS, whichever comes first).
#   usage: [RUNS=N] [TARGETS="NAME ..."] fuzz.sh FUZZ_BUILD_DIR OUT_DIR SECONDS [JOBS] [DATA_DIR]
set -uo pipefail
build=${1:?usage: fuzz.sh FUZZ_BUILD_DIR OUT_DIR SECONDS [JOBS] [DATA_DIR]}
out=${2:?}
seconds=${3:?}
jobs=${4:-2}
data=${5:-../shared/data}
here=$(cd "$(dirname "$0")/.." && pwd)
targets=${TARGETS:-"dsgb_records binary_payloads json spark_json spark_binary g2o protocol connection"}

run_target() {
  local name=$1 extra=()
  case $name in
    spark_json) extra=("$data/spark/apartment.json") ;;
    spark_binary) extra=("$data/spark/apartment.sparkdsg" "$data/spark/apartment_mesh.sparkdsg") ;;
    g2o) extra=("$data/pgo/tinyGrid3D.g2o" "$data/pgo/smallGrid3D.g2o") ;;
  esac
  local seeds=("$here/fuzz/corpus/$name")
  for f in "${extra[@]}"; do
    if [ -f "$f" ]; then
      mkdir -p "$out/$name/real"
      cp "$f" "$out/$name/real/"
    fi
  done
  [ -d "$out/$name/real" ] && seeds+=("$out/$name/real")
  mkdir -p "$out/$name/corpus"
  "$build/fuzz/fuzz_$name" -max_total_time="$seconds" -runs="${RUNS:--1}" -print_final_stats=1 -timeout=10 \
    -rss_limit_mb=2048 -max_len=20000 -artifact_prefix="$out/$name/" \
    "$out/$name/corpus" "${seeds[@]}" > "$out/$name/log.txt" 2>&1
  echo $? > "$out/$name/status"
}

mkdir -p "$out"
echo "fuzzing $targets: $seconds s each, $jobs at a time (logs in $out/NAME/log.txt)"
running=0
for name in $targets; do
  rm -rf "${out:?}/$name"
  mkdir -p "$out/$name"
  run_target "$name" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait

status=0
{
  echo "| target | seconds | executions | per second | corpus | found |"
  echo "|---|---|---|---|---|---|"
  for name in $targets; do
    log="$out/$name/log.txt"
    execs=$(grep -o "stat::number_of_executed_units: *[0-9]*" "$log" | tail -1 | grep -o "[0-9]*$")
    rate=$(grep -o "stat::average_exec_per_sec: *[0-9]*" "$log" | tail -1 | grep -o "[0-9]*$")
    took=$(grep -o "Done [0-9]* runs in [0-9]* second" "$log" | tail -1 | awk '{ print $5 }')
    corpus=$(find "$out/$name/corpus" -type f | wc -l)
    found=$(find "$out/$name" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' \
      -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
    if [ "$found" != 0 ] || [ "$(cat "$out/$name/status")" != 0 ]; then
      status=1
      found="$found (see $out/$name)"
    fi
    echo "| $name | ${took:-$seconds} | ${execs:-?} | ${rate:-?} | $corpus | $found |"
  done
} | tee "$out/summary.md"
exit $status
