#!/bin/bash
# How evenly `rabbit run` deals its runs over MPI ranks, measured in CPU time so that the figure
# does not depend on what else the machine runs: one process (--jobs 1), then `mpirun -np 2`
# (--jobs 1 per rank) with every rank timed by /usr/bin/time. With the ranks on two idle cores,
# the job's wall time is about its busiest rank's CPU time, so the speed-up over one process is
# about (one process's CPU) / (busiest rank's CPU); on an otherwise idle machine the wall-clock
# speed-up (one process's wall time / the two ranks' job's) is printed too. Also checks that
# summary.csv (but for the wall-time columns) and every run file are the same in both.
#
#   bash bench/rank_balance.sh [BUILD_DIR] [SUITE] [FILTER]
#
# Defaults: build, scenarios/robustness_train.toml, '^obstacle-' (200 runs).
set -euo pipefail

build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
suite=${2:-$root/scenarios/robustness_train.toml}
filter=${3-^obstacle-}
rabbit=$(realpath "$build/rabbit")
work=$(mktemp -d "${TMPDIR:-/tmp}/rabbit-ranks-XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/tmp"

rc=0
/usr/bin/time -f "%U %S %e" -o "$work/cpu_one" \
  "$rabbit" run "$suite" --filter "$filter" --jobs 1 --no-html -q --out "$work/one" || rc=$?
((rc <= 1)) || { echo "rank_balance.sh: rabbit run failed (exit $rc)" >&2; exit 1; }
rc=0
start=$(date +%s.%N)
TMPDIR="$work/tmp" mpirun --oversubscribe --allow-run-as-root --mca btl self,vader \
  --mca btl_vader_single_copy_mechanism none -np 2 \
  sh -c "/usr/bin/time -f '%U %S' -o '$work/cpu_rank'\$OMPI_COMM_WORLD_RANK '$rabbit' run \
         '$suite' --filter '$filter' --jobs 1 --no-html -q --out '$work/two'" || rc=$?
((rc <= 1)) || { echo "rank_balance.sh: mpirun failed (exit $rc)" >&2; exit 1; }
wall_two=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')

without_wall() { sed -E 's/,[^,]*,[^,]*$//' "$1"; }
runs=$(($(wc -l <"$work/one/summary.csv") - 1))
if cmp -s <(without_wall "$work/one/summary.csv") <(without_wall "$work/two/summary.csv") &&
  diff -r -q -x summary.csv "$work/one" "$work/two" >/dev/null; then
  same="identical"
else
  same="DIFFERENT"
fi
cpu() { awk '{printf "%.2f", $1 + $2}' "$1"; }
one=$(cpu "$work/cpu_one")
wall_one=$(awk '{printf "%.2f", $3}' "$work/cpu_one")
r0=$(cpu "$work/cpu_rank0")
r1=$(cpu "$work/cpu_rank1")
awk -v one="$one" -v r0="$r0" -v r1="$r1" -v runs="$runs" -v same="$same" \
  -v w1="$wall_one" -v w2="$wall_two" 'BEGIN {
  busiest = r0 > r1 ? r0 : r1
  printf "%d runs; one process %.2f s CPU; 2 ranks: rank 0 %.2f s, rank 1 %.2f s " \
         "(rank 0 share %.0f %%)\n", runs, one, r0, r1, 100 * r0 / (r0 + r1)
  printf "speed-up on 2 idle cores (one process / busiest rank): %.2f; results %s\n",
         one / busiest, same
  printf "wall: one process %.2f s, 2 ranks %.2f s (mpirun included): speed-up %.2f\n", w1, w2, w1 / w2
}'
