# Sourced by the tests that run the station and robots as processes on loopback: every process
# started with `spawn` is stopped when the script ends, also when it fails (SIGTERM, which
# `timeout` passes on to its command; the station ends cleanly on it), and `await_endpoint`
# waits for a station's bound endpoint and refuses one that is not 127.0.0.1.
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
