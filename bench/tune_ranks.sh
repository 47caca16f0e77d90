#!/usr/bin/env bash
# Tuning throughput over MPI ranks: one process on 1 and 2 threads against 1 and 2 MPI
# ranks of one thread each, on the job of tune_benchmark.cc (8 evaluations of 2 ramps each),
# alternating the four set-ups for ROUNDS rounds (this machine's speed drifts), then the median
# wall time and evaluations per second of each.
# Usage: bench/tune_ranks.sh [BUILD_DIR] [ROUNDS]
set -euo pipefail
build=${1:-build} rounds=${2:-5}
rabbit=$(realpath "$build/rabbit") source=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '[params]\n"simulation.duration" = 12\n"criteria.min_steps" = 5\n' > "$work/base.toml"
cat > "$work/job.toml" <<TOML
[job]
suites = ["$source/scenarios/tune_ramp.toml"]
params = "base.toml"
algorithm = "crs2"
population = 4
max_evaluations = 8
starts = 2
[objective]
speed_error = 1.0
[[parameter]]
path = "controller.k_p"
lower = 0.0
upper = 0.6
[[parameter]]
path = "controller.k_v"
lower = 0.0
upper = 0.4
TOML
mpi=(mpirun --allow-run-as-root --oversubscribe --bind-to none)
declare -A setups=(
  ["1 process, 1 thread"]="$rabbit tune $work/job.toml --jobs 1"
  ["1 process, 2 threads"]="$rabbit tune $work/job.toml --jobs 2"
  ["1 rank, 1 thread"]="${mpi[*]} -np 1 $rabbit tune $work/job.toml --jobs 1"
  ["2 ranks, 1 thread each"]="${mpi[*]} -np 2 $rabbit tune $work/job.toml --jobs 1"
)
declare -A times
for ((r = 0; r < rounds; r++)); do
  for name in "${!setups[@]}"; do
    start=$(date +%s.%N)
    ${setups[$name]} --out "$work/out" --force --quiet --no-html
    end=$(date +%s.%N)
    times[$name]+="$(echo "$end - $start" | bc) "
  done
done
printf '%-26s %10s %12s   (%d rounds, alternating)\n' "set-up" "median s" "evals/s" "$rounds"
for name in "1 process, 1 thread" "1 process, 2 threads" "1 rank, 1 thread" "2 ranks, 1 thread each"; do
  median=$(echo "${times[$name]}" | tr ' ' '\n' | grep . | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  printf '%-26s %10.3f %12.2f\n' "$name" "$median" "$(echo "8 / $median" | bc -l)"
done
