#!/usr/bin/env bash
# Robustness benchmark: GNC on real data with labelled outliers, on sphere2500 with injected
# outliers, and the CSAIL two-robot split with unknown frames. Prints one line per case from the
# JSON of `hydra-multi pgo`. About a minute on 2 cores (the 80-90 % cases take longest).
set -euo pipefail
bin=${1:?usage: bench_robust.sh HYDRA_MULTI_BINARY DATA_DIR}
data=${2:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

row() {  # name, then pgo arguments
  local name=$1
  shift
  local json="$tmp/row.json"
  "$bin" pgo "$@" --json --quiet > "$json"
  python3 - "$name" "$json" <<'PY'
import json, sys
name, d = sys.argv[1], json.load(open(sys.argv[2]))
f = lambda v, fmt: "-" if v is None else format(v, fmt)
print(f"{name:<34} {d['loop_closures']:>6} {d['outliers_injected']:>6} "
      f"{d['robots_aligned']}/{d['robots']:<3} {f(d['inlier_precision'], '.4f'):>9} "
      f"{f(d['inlier_recall'], '.4f'):>7} {f(d['ate_m'], '.4f'):>8} {f(d['ate_vs_clean_m'], '.4f'):>10} "
      f"{d['time_s']:>8.1f}")
PY
}

printf '%-34s %6s %6s %-5s %9s %7s %8s %10s %8s\n' case closures inject robots precision recall \
  "ATE[m]" "vs clean" "time[s]"
for p in 10p 30p; do
  g=$data/pgo/grid1000_${p}_outliers
  row "grid1000 $p (labelled)" --input "$g/measurements.g2o" --inliers-xml "$g/gt_info.xml" \
    --robust gnc --init odometry
done
for f in 0.5 0.7 0.8 0.9; do
  row "sphere2500 + ${f} injected" --input "$data/pgo/sphere2500.g2o" --robust gnc --outliers "$f" \
    --seed 1 --groundtruth "$data/pgo/sphere2500_groundtruth.txt"
done
c=$data/multirobot/csail_2robots
"$bin" pgo --input "$c/CSAIL_robot1.g2o" --input "$c/CSAIL_robot2.g2o" \
  --input "$c/CSAIL_interrobot_loop_closures.g2o" --unknown-frames --output "$tmp/clean.g2o" --quiet >/dev/null
row "CSAIL unknown frames, 250 spurious" --input "$c/CSAIL_robot1.g2o" --input "$c/CSAIL_robot2.g2o" \
  --input "$c/CSAIL_interrobot_loop_closures_outliers.g2o" --unknown-frames --robust gnc \
  --inlier-edges "$c/CSAIL_interrobot_loop_closures.g2o" --groundtruth "$tmp/clean.g2o"
echo "(CSAIL's ATE column is against the solution of the 128 true closures alone.)"
