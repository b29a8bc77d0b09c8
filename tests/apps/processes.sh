# Sourced by the tests that run the station and robots as processes on loopback: every process
# started with `spawn` is stopped when the script ends, also when it fails (SIGTERM, which
# `timeout` passes on to its command; the station ends cleanly on it), `await_endpoint` waits
# for a station's bound endpoint and refuses one that is not 127.0.0.1, and `compare_with_run`
# says whether a station's map scores as run's.
# Sourced as `. processes.sh with_dataset HYDRA_MULTI DATASET OUT_DIR`: those three arguments in
# HM, DATASET and OUT, and OUT made anew, empty.
if [ "${1:-}" = with_dataset ]; then
  HM=$2
  DATASET=$3
  OUT=$4
  rm -rf "$OUT"
  mkdir -p "$OUT"
fi

pids=()
spawn_cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2> /dev/null; done
  sleep 0.2
  for p in "${pids[@]}"; do kill -KILL "$p" 2> /dev/null; done
  return 0
}
trap spawn_cleanup EXIT

# spawn OUTPUT_FILE COMMAND...: runs COMMAND in the background, its output to OUTPUT_FILE; its pid
# in $spawned.
spawn() {
  local output=$1
  shift
  "$@" > "$output" 2>&1 &
  spawned=$!
  pids+=("$spawned")
}

# await_endpoint OUT_DIR: the endpoint the station writes to OUT_DIR/endpoint, in $endpoint.
await_endpoint() {
  for _ in $(seq 100); do [ -s "$1/endpoint" ] && break; sleep 0.1; done
  endpoint=$(cat "$1/endpoint" 2> /dev/null)
  case $endpoint in
    tcp://127.0.0.1:*) ;;
    *) echo "FAIL: the station's endpoint '$endpoint' is not loopback"; exit 1 ;;
  esac
}

# compare_with_run HYDRA_MULTI DATASET EVALUATE_JSON RUN_METRICS_JSON NAME: the two maps' ATE,
# objects and rooms side by side; "same map" when they agree within 1 mm, 0.1 points and the
# same number of rooms, else FAIL and a non-zero status.
compare_with_run() {
  local figures='s/.*"ate_rmse_m":([0-9.e-]+),"objects_found_pct":([0-9.]+),"objects_correct_pct":([0-9.]+).*"num_rooms":([0-9]+).*/\1 \2 \3 \4/'
  local ate_net found_net correct_net rooms_net ate_run found_run correct_run rooms_run
  read -r ate_net found_net correct_net rooms_net < <(tr -d ' \n' < "$3" | sed -E "$figures")
  read -r ate_run found_run correct_run rooms_run < <(tr -d ' \n' < "$4" | sed -E "$figures")
  printf '%-10s ATE %s m, objects found %s %%, correct %s %%, %s rooms\n' "$5:" "$ate_net" \
    "$found_net" "$correct_net" "$rooms_net"
  printf '%-10s ATE %s m, objects found %s %%, correct %s %%, %s rooms\n' "run:" "$ate_run" \
    "$found_run" "$correct_run" "$rooms_run"
  awk -v a="$ate_net" -v b="$ate_run" -v f="$found_net" -v g="$found_run" -v c="$correct_net" \
    -v d="$correct_run" -v r="$rooms_net" -v s="$rooms_run" \
    'BEGIN { d1 = a - b; d2 = f - g; d3 = c - d;
             if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2; if (d3 < 0) d3 = -d3;
             if (d1 <= 0.001 && d2 <= 0.1 && d3 <= 0.1 && r == s) print "same map";
             else { print "FAIL: the maps differ"; exit 1 } }'
}
