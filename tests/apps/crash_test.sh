#!/usr/bin/env bash
# The crash test (issue 23): KILLS times, two robot processes stream the dataset's robots a and b
# to a station (loopback, --order time, the journal on), and SIGKILL hits, at a random moment of
# the mission, the station, one robot, or both; what was killed starts again (the station on the
# same --out, a robot with the same mission clock) and everyone finishes. After each kill point:
#   - every process ended well, and no robot was welcomed with less than the station had
#     acknowledged to it (the robot counts "acknowledged and then lost");
#   - SQLite's integrity_check of the journal says ok, and the journal holds each update the
#     station took once (journal entries = updates applied + those a snapshot superseded before
#     they could be applied, none behind a gap);
#   - the station's frontend holds what an uninterrupted station holds (station.json's
#     frontend_digest), and, where no robot restarted, its detector found the same inter-robot
#     loop closures (a restarted robot sends what it made while down as one snapshot: the detector
#     then meets keyframes in another order, and its online decisions may differ).
# The kill points come from SEED (printed; the same seed replays the same moments and victims).
# Each kill point is bounded (60 s) and every process started here is stopped when it ends.
#   usage: crash_test.sh HYDRA_MULTI DATASET OUT_DIR [KILLS] [SEED] [SPEED]
set -u
. "$(dirname "$0")/processes.sh" with_dataset "$@"
KILLS=${4:-200}
SEED=${5:-$(date +%s)}
SPEED=${6:-40}
RANDOM=$SEED
echo "crash test: $KILLS kill points, seed $SEED, robots at $SPEED times real time"

# run_team DIR KILL VICTIMS DELAY_MS: one mission into DIR; with KILL=1 the VICTIMS (station, a,
# b) get SIGKILL DELAY_MS after the mission's start and start again.
run_team() {
  local dir=$1 kill=$2 victims=$3 delay_ms=$4
  mkdir -p "$dir"
  spawn "$dir/station1.txt" "$HM" station --listen 'tcp://127.0.0.1:*' --out "$dir/station" \
    --expect-robots 2 --order time --quiet
  local station=$spawned
  await_endpoint "$dir/station"
  local start
  start=$(awk -v now="$(date +%s.%N)" 'BEGIN { printf "%.3f", now + 0.3 }')
  declare -A robot
  for r in a b; do
    spawn "$dir/robot_${r}1.txt" "$HM" robot --dataset "$DATASET" --robot "$r" \
      --connect "$endpoint" --speed "$SPEED" --mission-start "$start" --timeout 50 --quiet
    robot[$r]=$spawned
  done
  if [ "$kill" = 1 ]; then
    sleep "$(awk -v ms="$delay_ms" -v s="$start" -v now="$(date +%s.%N)" \
      'BEGIN { t = s + ms / 1000 - now; printf "%.3f", (t > 0 ? t : 0) }')"
    for v in $victims; do
      # A robot may have finished already: its restart then has nothing new to send.
      if [ "$v" = station ]; then kill -9 "$station"; else kill -9 "${robot[$v]}" 2> /dev/null; fi
    done
    for v in $victims; do
      if [ "$v" = station ]; then
        wait "$station" 2> /dev/null
        spawn "$dir/station2.txt" timeout 60 "$HM" station --listen "$endpoint" \
          --out "$dir/station" --expect-robots 2 --order time --quiet
        station=$spawned
      else
        wait "${robot[$v]}" 2> /dev/null
        spawn "$dir/robot_${v}2.txt" timeout 60 "$HM" robot --dataset "$DATASET" --robot "$v" \
          --connect "$endpoint" --speed "$SPEED" --mission-start "$start" --timeout 50 --quiet
        robot[$v]=$spawned
      fi
    done
  fi
  local status=0
  for r in a b; do wait "${robot[$r]}" || status=1; done
  # The station ends once both robots said BYE; one that does not within 60 s (or whose robots
  # failed) is stopped, and the kill point fails.
  [ "$status" = 0 ] || kill -TERM "$station" 2> /dev/null
  for _ in $(seq 600); do kill -0 "$station" 2> /dev/null || break; sleep 0.1; done
  if kill -0 "$station" 2> /dev/null; then
    echo "the station did not end within 60 s of its robots" >> "$dir/station_stopped.txt"
    kill -TERM "$station" 2> /dev/null
    status=1
  fi
  wait "$station" || status=1
  return $status
}

# field NAME FILE: a JSON field's value (numbers and strings) from station.json.
field() { tr -d ' \n' < "$2" | grep -o "\"$1\":[^,}]*" | head -1 | cut -d: -f2 | tr -d '"'; }

run_team "$OUT/reference" 0 "" 0 || { echo "FAIL: the uninterrupted run failed"; cat "$OUT"/reference/*.txt; exit 1; }
ref_digest=$(field frontend_digest "$OUT/reference/station/station.json")
# The detector's loop closures as a set: the station's journal replay hands the frontend what it
# held in one burst, and a closure's distinctiveness (column 10: against the keyframes described
# at that moment) may differ.
closures() { cut -d, -f1-9,11- "$1" | sort | cksum; }
ref_closures=$(closures "$OUT/reference/station/loop_closures.csv")
ref_applied=$(field updates_applied "$OUT/reference/station/station.json")
# The mission's length in robot time over the speed: kill points fall within it.
window_ms=$(awk -F, -v speed="$SPEED" 'NR > 1 && $1 == "update" && $5 > max { max = $5 }
  END { printf "%d", max * 1000 / speed }' "$OUT/reference/station/timing.csv")
echo "uninterrupted: $ref_applied updates applied, frontend digest $ref_digest, kill points within ${window_ms} ms"

passed=0
declare -A by_victim
for k in $(seq "$KILLS"); do
  case $(( (k - 1) % 3 )) in
    0) victims=station ;;
    1) victims=$([ $((RANDOM % 2)) = 0 ] && echo a || echo b) ;;
    2) victims="station $([ $((RANDOM % 2)) = 0 ] && echo a || echo b)" ;;
  esac
  delay_ms=$(( (RANDOM * 32768 + RANDOM) % window_ms ))
  dir="$OUT/kill$k"
  failure=""
  run_team "$dir" 1 "$victims" "$delay_ms" || failure="a process failed"
  json="$dir/station/station.json"
  if [ -z "$failure" ]; then
    lost=$(cat "$dir"/robot_*.txt | grep -c "acknowledged and then lost")
    integrity=$(field journal_integrity "$json")
    entries=$(field journal_entries "$json")
    applied=$(field updates_applied "$json")
    superseded=$(field updates_superseded "$json")
    gap=$(field updates_behind_gap "$json")
    digest=$(field frontend_digest "$json")
    closures=$(closures "$dir/station/loop_closures.csv")
    if [ "$lost" != 0 ]; then failure="a robot found acknowledged updates lost"
    elif [ "$integrity" != ok ]; then failure="journal integrity: $integrity"
    elif [ "$entries" != $((applied + superseded)) ]; then
      failure="$entries journal entries, $applied applied and $superseded superseded"
    elif [ "$gap" != 0 ]; then failure="$gap updates behind a gap"
    elif [ "$digest" != "$ref_digest" ]; then failure="frontend digest $digest"
    elif [ "$victims" = station ] && [ "$closures" != "$ref_closures" ]; then
      failure="other inter-robot loop closures"
    fi
  fi
  if [ -n "$failure" ]; then
    echo "kill $k/$KILLS: ${victims// /+} at $delay_ms ms: FAIL: $failure (seed $SEED; $dir)"
    for f in "$dir"/*.txt; do echo "--- $f"; tail -5 "$f"; done
    exit 1
  fi
  echo "kill $k/$KILLS: ${victims// /+} at $delay_ms ms: ok ($entries journal entries, replayed $(field updates_replayed "$json"))"
  by_victim[${victims// /+}]=$(( ${by_victim[${victims// /+}]:-0} + 1 ))
  passed=$((passed + 1))
  rm -rf "$dir"
done
summary=""
for v in "${!by_victim[@]}"; do summary="$summary, $v ${by_victim[$v]}"; done
echo "crash test: $passed of $KILLS kill points passed (seed $SEED${summary})"
