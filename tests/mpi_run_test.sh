#!/bin/sh
# rabbit run under mpirun against one process: the same summary.csv but for the wall-time columns
# (wall_s, real_time_factor: the last two, never quoted), the same run files; a sharded run with
# one shard under mpirun merges to the same; a run killed midway resumes under mpirun to the same;
# bad input exits 2 on every rank and writes nothing.
# Usage: mpi_run_test.sh MPIEXEC RABBIT SUITE WORKDIR
set -eu
mpiexec=$1
rabbit=$2
suite=$3
work=$4
filter='^(flat|obstacle)$'
# As root in CI containers: allowed explicitly; shared memory only (no network interfaces to
# probe), without the single-copy mechanism that needs ptrace rights containers often lack.
mpirun_2() {
  "$mpiexec" --oversubscribe --allow-run-as-root --mca btl self,vader \
    --mca btl_vader_single_copy_mechanism none -np 2 "$@"
}
without_wall() { sed -E 's/,[^,]*,[^,]*$//' "$1"; }
fail() {
  echo "mpi_run_test: $*" >&2
  exit 1
}

rm -rf "$work"
mkdir -p "$work"
"$rabbit" run "$suite" --filter "$filter" --no-html -q --out "$work/one"
mkdir -p "$work/tmp"  # the ranks' scratch folders (and OpenMPI's session folder)
TMPDIR="$work/tmp" mpirun_2 "$rabbit" run "$suite" --filter "$filter" --jobs 1 --no-html -q \
  --out "$work/two"
without_wall "$work/one/summary.csv" >"$work/one.csv"
without_wall "$work/two/summary.csv" >"$work/two.csv"
cmp "$work/one.csv" "$work/two.csv" || fail "summary.csv differs under mpirun -np 2"
[ "$(wc -l <"$work/one.csv")" -eq 7 ] || fail "expected 6 runs in summary.csv"
diff -r -x summary.csv "$work/one" "$work/two" || fail "run files differ under mpirun -np 2"
ls "$work" | grep -q partial && fail "a staging folder was left behind"
ls "$work/tmp" | grep -q "^rabbit-rank" && fail "a rank left its scratch folder"

# Shard 1 of 2 under mpirun, shard 2 in one process, then the merge.
mpirun_2 "$rabbit" run "$suite" --filter "$filter" --jobs 1 -q --shard 1/2 --out "$work/sharded"
"$rabbit" run "$suite" --filter "$filter" -q --shard 2/2 --out "$work/sharded"
"$rabbit" report "$work/sharded" -q --gnuplot /nonexistent/gnuplot 2>/dev/null
without_wall "$work/sharded/summary.csv" >"$work/sharded.csv"
cmp "$work/one.csv" "$work/sharded.csv" || fail "merged shards differ from one process"
diff -r -x summary.csv -x index.html "$work/one" "$work/sharded" || fail "merged run files differ"

# Killed midway (rank 0 kills itself after 2 of its runs; mpirun ends the job), then resumed
# under mpirun: rank 0's finished runs are kept, every rank skips them, the report is the same.
code=0
TMPDIR="$work/tmp" RABBIT_RUN_KILL_AFTER=2 mpirun_2 -x RABBIT_RUN_KILL_AFTER "$rabbit" run "$suite" \
  --filter "$filter" --jobs 1 --no-html -q --out "$work/resumed" >/dev/null 2>&1 || code=$?
[ "$code" -ne 0 ] || fail "RABBIT_RUN_KILL_AFTER=2 did not kill the run"
[ -d "$work/resumed.partial" ] || fail "the killed run left no staging folder"
TMPDIR="$work/tmp" mpirun_2 "$rabbit" run "$suite" --filter "$filter" --jobs 1 --no-html \
  --out "$work/resumed" --resume >"$work/resume.log"
grep -q "2 of 6 runs already finished" "$work/resume.log" || fail "the resume ran finished runs"
without_wall "$work/resumed/summary.csv" >"$work/resumed.csv"
cmp "$work/one.csv" "$work/resumed.csv" || fail "the resumed summary.csv differs"
diff -r -x summary.csv "$work/one" "$work/resumed" || fail "the resumed run files differ"
[ ! -e "$work/resumed.partial" ] || fail "the resume left its staging folder"

# Bad input: every rank exits 2, nothing is written.
code=0
mpirun_2 "$rabbit" run "$work/missing.toml" -q --out "$work/bad" >/dev/null 2>&1 || code=$?
[ "$code" -eq 2 ] || fail "bad input under mpirun exited $code, not 2"
[ ! -e "$work/bad" ] || fail "bad input under mpirun wrote $work/bad"
rm -rf "$work"
echo "mpi_run_test: passed"
