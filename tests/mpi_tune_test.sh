#!/usr/bin/env bash
# rabbit tune under MPI: `mpirun -np 2 rabbit tune` (one thread per rank) gives the same log (but
# for the wall-time column) and the same best.toml as one process on two threads.
# Usage: mpi_tune_test.sh MPIRUN RABBIT SOURCE_DIR
set -euo pipefail
mpirun=$1 rabbit=$2 source=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/base.toml" <<'TOML'
[params]
"simulation.duration" = 12
"criteria.min_steps" = 5
TOML
cat > "$work/job.toml" <<TOML
[job]
suites = ["$source/scenarios/tune_ramp.toml"]
params = "base.toml"
algorithm = "crs2"
population = 4
max_evaluations = 8
starts = 2
seed = 7
[objective]
speed_error = 1.0
failure_rate = 0.2
[[parameter]]
path = "controller.k_p"
lower = 0.0
upper = 0.6
[[parameter]]
path = "controller.k_v"
lower = 0.0
upper = 0.4
TOML
"$rabbit" tune "$work/job.toml" --out "$work/one" --jobs 2 --quiet --no-html
# As root (CI), OpenMPI needs --allow-run-as-root; --oversubscribe lets 2 ranks share fewer cores.
"$mpirun" --allow-run-as-root --oversubscribe --mca btl self,vader \
  --mca btl_vader_single_copy_mechanism none -np 2 \
  "$rabbit" tune "$work/job.toml" --out "$work/two" --jobs 1 --quiet --no-html
strip() { sed 's/,[^,]*$//' "$1"; }  # the last column (wall_s) is not deterministic
diff <(strip "$work/one/evaluations.csv") <(strip "$work/two/evaluations.csv")
diff "$work/one/runs.csv" "$work/two/runs.csv"
diff "$work/one/best.toml" "$work/two/best.toml"
test "$(wc -l < "$work/one/evaluations.csv")" -eq 9
# A shard of another job (fingerprint differs) in the folder: every rank exits 2, none hangs.
"$rabbit" tune "$work/job.toml" --out "$work/sharded" --shard 1/2 --jobs 2 --quiet --no-html
sed 's/^seed = 7$/seed = 8/' "$work/job.toml" > "$work/other.toml"
status=0
timeout 120 "$mpirun" --allow-run-as-root --oversubscribe --mca btl self,vader \
  --mca btl_vader_single_copy_mechanism none -np 2 \
  "$rabbit" tune "$work/other.toml" --out "$work/sharded" --resume --jobs 1 --quiet --no-html \
  2> "$work/err" || status=$?
test "$status" -eq 2 || { echo "a shard of another job: exit $status (124: hung)"; exit 1; }
grep -q "a shard of another job" "$work/err"
echo "mpi_tune_test: 2 ranks = 1 process ($(($(wc -l < "$work/one/evaluations.csv") - 1)) evaluations)"
