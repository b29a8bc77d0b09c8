#!/usr/bin/env bash
# CURVE on loopback: keys made with keygen; the station admits robot a's key only. Robot a streams
# its map; robot b, with a key the station does not know, is never welcomed and gives up at its
# timeout (exit 1); robot a's key used for robot b is refused (exit 1); the station logs each
# refusal. Bounded: 60 s; every process started here is stopped when the script ends.
#   usage: station_keys.sh HYDRA_MULTI DATASET OUT_DIR
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"
mkdir -p "$OUT/keys/robots"

for k in station a b; do "$HM" keygen --out "$OUT/keys/$k" > /dev/null || exit 1; done
cp "$OUT/keys/a.pub" "$OUT/keys/robots/"
spawn "$OUT/station.txt" timeout 60 "$HM" station --listen 'tcp://127.0.0.1:*' \
  --out "$OUT/station" --keys "$OUT/keys/robots" --key "$OUT/keys/station.key" --expect-robots 1
station=$spawned
await_endpoint "$OUT/station"
robot() {  # robot NAME KEY [OPTIONS...]
  local name=$1 key=$2
  shift 2
  timeout 50 "$HM" robot --dataset "$DATASET" --robot "$name" --connect "$endpoint" \
    --key "$OUT/keys/$key.key" --station-key "$OUT/keys/station.pub" --quiet "$@"
}
robot b b --timeout 4 2>&1
echo "stranger exit $?"
robot b a --timeout 4 2>&1
echo "impostor exit $?"
robot a a 2>&1 || exit 1
wait "$station" || { echo "FAIL: the station failed"; cat "$OUT/station.txt"; exit 1; }
grep -E 'CURVE|refused a ' "$OUT/station.txt"
