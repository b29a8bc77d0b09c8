#!/usr/bin/env bash
# The command line's error contract (README "Errors and exit codes"), table-driven over every
# command: every numeric option refuses NaN, infinities, values outside its range (a negative one
# where it has none), overflowing values and words, at parse time, naming the option (exit 2);
# every path option refuses a missing path and a path of the wrong kind, naming the path (exit 1);
# every command refuses an unknown option (exit 2). The numeric options and the commands are read
# from --help, so an option added without a range check fails here.
#   usage: command_line_contract.sh HYDRA_MULTI TMP_DIR DATASET_DIR DATA_DIR
set -u
HM=$1
TMP=$2
DATASET=$3
G2O=$4/pgo/tinyGrid3D.g2o
mkdir -p "$TMP"
FILE=$TMP/contract_file.txt
echo "not what any command reads" > "$FILE"
DIR=$TMP/contract_dir
mkdir -p "$DIR"
MISSING=$TMP/no_such_path
checks=0
failures=0

# expect CODE REGEX ARGS...: the command exits with CODE and its stderr matches REGEX.
expect() {
  local code=$1 regex=$2
  shift 2
  local err
  err=$(timeout 60 "$HM" "$@" 2>&1 >/dev/null)
  local got=$?
  checks=$((checks + 1))
  if [ "$got" -ne "$code" ] || ! printf '%s' "$err" | grep -Eq -- "$regex"; then
    failures=$((failures + 1))
    echo "FAIL: hydra-multi $* -> exit $got (want $code), stderr: $err (want /$regex/)"
  fi
}

# Arguments that make each command's parse complete but for the option under test.
base_args() {
  case $1 in
    info) echo "$FILE" ;;
    convert) echo "$FILE $TMP/x.json" ;;
    pgo) echo "--input $FILE" ;;
    ate) echo "--est $FILE --gt $FILE" ;;
    simulate) echo "--out $TMP/x" ;;
    evaluate) echo "--dataset $DIR --result $FILE" ;;
    dataset-graph) echo "--dataset $DIR --robot a --out $TMP/x.json" ;;
    detect) echo "--dataset $DIR" ;;
    run) echo "--dataset $DIR --out $TMP/x" ;;
    trials) echo "--preset tiny --out $TMP/x" ;;
    station) echo "--out $TMP/x" ;;
    robot) echo "--dataset $DIR --robot a --connect tcp://127.0.0.1:1" ;;
    keygen) echo "--out $TMP/key" ;;
    watch) echo "--connect tcp://127.0.0.1:1" ;;
    *) echo "" ;;
  esac
}

# Values just outside a bound, and the words and non-finite values every number refuses.
outside() {  # type bound_char value side(min|max)
  local type=$1 bracket=$2 value=$3 side=$4
  [ "$value" = inf ] || [ "$value" = -inf ] && return
  if [ "$type" = FLOAT ]; then
    if { [ "$side" = min ] && [ "$bracket" = "(" ]; } || { [ "$side" = max ] && [ "$bracket" = ")" ]; }; then
      echo "$value"
    elif [ "$side" = min ]; then
      awk -v v="$value" 'BEGIN { printf "%.17g\n", v - 1e-6 * (v < 0 ? -v : v) - 1e-9 }'
    else
      awk -v v="$value" 'BEGIN { printf "%.17g\n", v + 1e-6 * (v < 0 ? -v : v) + 1e-9 }'
    fi
  elif [ "$side" = min ]; then
    if [ "$value" = 0 ]; then echo -1; else echo $((value - 1)); fi
  else
    echo "${value}0"  # ten times the largest value: above it, whatever its size
  fi
}

commands=$("$HM" --help | awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print $1 }')
[ -n "$commands" ] || { echo "FAIL: no commands in hydra-multi --help"; exit 1; }
numeric=0
for cmd in $commands; do
  # Unknown option: named, exit 2.
  expect 2 "^hydra-multi: error: $cmd: unknown option '--no-such-option'" $cmd --no-such-option
  # Every option whose value is a number.
  while read -r option type range; do
    numeric=$((numeric + 1))
    checks=$((checks + 1))
    if [[ ! $range =~ ^in\ ([\[\(])([^,]+),\ ([^]\)]+)([]\)])(=.*)?$ ]]; then
      failures=$((failures + 1))
      echo "FAIL: $cmd $option ($type) has no range in --help: '$range'"
      continue
    fi
    lo_bracket=${BASH_REMATCH[1]} lo=${BASH_REMATCH[2]} hi=${BASH_REMATCH[3]} hi_bracket=${BASH_REMATCH[4]}
    values="nan NaN inf -inf infinity abc 1x"
    if [ "$type" = FLOAT ]; then
      values="$values 1e999 -1e999"
    else
      values="$values 1.5 1e3 99999999999999999999999 -99999999999999999999999"
    fi
    [ "$lo" = 0 ] && values="$values -1"
    values="$values $(outside "$type" "$lo_bracket" "$lo" min) $(outside "$type" "$hi_bracket" "$hi" max)"
    for value in $values; do
      # shellcheck disable=SC2046
      expect 2 "^hydra-multi: error: $cmd: $option: " $cmd $(base_args "$cmd") "$option" "$value"
    done
  done < <("$HM" "$cmd" --help | sed -nE 's/^  (--[a-z-]+) (FLOAT|INT|UINT):?([^ ]* [^ ]* [^ ]*)?.*$/\1 \2 \3/p')
done
[ "$numeric" -ge 19 ] || { echo "FAIL: only $numeric numeric options found in --help"; failures=$((failures + 1)); }

# trials --seeds: a range of unsigned 64-bit seeds.
for seeds in -1 5-3 1-1001 x 1-x 18446744073709551616 18446744073709551615-18446744073709551616; do
  expect 2 "^hydra-multi: error: trials: --seeds: " trials --preset tiny --out "$TMP/x" --seeds "$seeds"
done

# Paths. Input files: missing, or a folder; input folders: missing, or a file (exit 1, the path
# named). FILE stands for the option under test; the other inputs are real.
while IFS='|' read -r kind args; do
  [ -z "$kind" ] && continue
  case $kind in
    file)
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $MISSING: no such file \(" ${args//@/$MISSING}
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $DIR: is a folder, not a file \(" ${args//@/$DIR} ;;
    folder)
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $MISSING: no such folder \(" ${args//@/$MISSING}
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $FILE: not a folder \(" ${args//@/$FILE} ;;
    outfile)
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $DIR: is a folder; give a file name \(" ${args//@/$DIR}
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $MISSING/x: no folder $MISSING to write it in \(" ${args//@/$MISSING/x} ;;
    outdir)
      # shellcheck disable=SC2086
      expect 1 "^hydra-multi: error: $FILE: is a file, not a folder \(" ${args//@/$FILE} ;;
  esac
done <<EOF
file|info @
file|convert @ $TMP/x.json
file|pgo --input @
file|pgo --input $G2O --input @
file|pgo --input $G2O --inliers-xml @
file|pgo --input $G2O --inlier-edges @
file|pgo --input $G2O --groundtruth @
file|ate --est @ --gt $FILE
file|ate --est $FILE --gt @
file|evaluate --dataset $DATASET --result @
folder|evaluate --dataset @ --result $FILE
folder|dataset-graph --dataset @ --robot a --out $TMP/x.json
folder|detect --dataset @
folder|run --dataset @ --out $TMP/x
file|run --dataset $DATASET --out $TMP/x --config @
file|trials --preset tiny --out $TMP/x --config @
outfile|convert $FILE @
outfile|pgo --input $G2O --output @
outfile|evaluate --dataset $DATASET --result $FILE --objects @
outfile|evaluate --dataset $DATASET --result $FILE --keyframes @
outfile|dataset-graph --dataset $DATASET --robot a --out @
outfile|detect --dataset $DATASET --loop-closures @
outdir|simulate --out @
outdir|run --dataset $DATASET --out @
outdir|trials --preset tiny --out @
outdir|station --out @
file|station --out $TMP/x --config @
folder|robot --dataset @ --robot a --connect tcp://127.0.0.1:1
folder|station --out $TMP/x --keys @ --key $FILE
file|station --out $TMP/x --keys $DIR --key @
file|robot --dataset $DATASET --robot a --connect tcp://127.0.0.1:1 --key @ --station-key $FILE
file|robot --dataset $DATASET --robot a --connect tcp://127.0.0.1:1 --key $FILE --station-key @
outfile|keygen --out @
EOF

# Empty paths are a wrong command line.
expect 2 "^hydra-multi: error: simulate: --out: the path is empty" simulate --out ""
expect 2 "^hydra-multi: error: info: file: the path is empty" info ""
# No command, an unknown one; options that exclude each other.
expect 2 "^hydra-multi: error: give a command \(info, convert, " 
expect 2 "^hydra-multi: error: unknown command 'frobnicate' \(commands: info, " frobnicate
expect 2 "^hydra-multi: error: run: --ablation excludes --baseline" run --dataset "$DATASET" --out "$TMP/x" --ablation no-rec --baseline oracle-lc
expect 2 "^hydra-multi: error: pgo: --unknown-frames excludes --init" pgo --input "$G2O" --unknown-frames --init odometry
expect 2 "^hydra-multi: error: pgo: --inliers-xml excludes --inlier-edges" pgo --input "$G2O" --inliers-xml "$FILE" --inlier-edges "$FILE"
# Keys come in pairs: the station's secret with the robots' keys, a robot's with the station's.
expect 2 "^hydra-multi: error: station: --keys requires --key" station --out "$TMP/x" --keys "$DIR"
expect 2 "^hydra-multi: error: robot: --key requires --station-key" robot --dataset "$DATASET" --robot a --connect tcp://127.0.0.1:1 --key "$FILE"
# Options that would do nothing beside the others given.
expect 2 "^hydra-multi: error: pgo: --seed applies to --outliers only" pgo --input "$G2O" --seed 3
expect 2 "^hydra-multi: error: pgo: --linear-solver applies to --robust gnc only" pgo --input "$G2O" --linear-solver cg
expect 2 "^hydra-multi: error: pgo: --gnc-inner-iterations applies to --robust gnc only" pgo --input "$G2O" --robust none --gnc-inner-iterations 5
expect 2 "^hydra-multi: error: pgo: --keep-chains applies to --robust gnc only" pgo --input "$G2O" --keep-chains
expect 2 "^hydra-multi: error: ate: --max-time-difference applies to --format tum only" ate --est "$FILE" --gt "$FILE" --max-time-difference 0.1

echo "$checks checks, $numeric numeric options, $failures failures"
[ "$failures" -eq 0 ]
