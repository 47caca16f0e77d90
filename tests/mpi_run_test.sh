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
[ ! -e "$work/two/.rabbit-rank-probe" ] || fail "the ranks' probe was left behind"
# The same with rank 1 made to send its files to rank 0 (as a rank that does not see the report
# folder does) instead of writing them into it.
TMPDIR="$work/tmp" RABBIT_RANK_FILES=transfer mpirun_2 -x RABBIT_RANK_FILES "$rabbit" run "$suite" \
  --filter "$filter" --jobs 1 --no-html -q --out "$work/sent"
without_wall "$work/sent/summary.csv" >"$work/sent.csv"
cmp "$work/one.csv" "$work/sent.csv" || fail "summary.csv differs when rank 1 sends its files"
diff -r -x summary.csv "$work/one" "$work/sent" || fail "run files differ when rank 1 sends its files"
ls "$work/tmp" | grep -q "^rabbit-rank" && fail "a rank left its scratch folder"
code=0
RABBIT_RANK_FILES=sideways mpirun_2 -x RABBIT_RANK_FILES "$rabbit" run "$suite" --filter "$filter" \
  -q --out "$work/sideways" >/dev/null 2>"$work/sideways.err" || code=$?
[ "$code" -eq 2 ] || fail "RABBIT_RANK_FILES=sideways exited $code, not 2"
grep -q "RABBIT_RANK_FILES" "$work/sideways.err" || fail "the error does not name RABBIT_RANK_FILES"

# Shard 1 of 2 under mpirun, shard 2 in one process, then the merge.
mpirun_2 "$rabbit" run "$suite" --filter "$filter" --jobs 1 -q --shard 1/2 --out "$work/sharded"
"$rabbit" run "$suite" --filter "$filter" -q --shard 2/2 --out "$work/sharded"
"$rabbit" report "$work/sharded" -q --gnuplot /bin/false 2>/dev/null
without_wall "$work/sharded/summary.csv" >"$work/sharded.csv"
cmp "$work/one.csv" "$work/sharded.csv" || fail "merged shards differ from one process"
# (The merge writes the page, whose file the inventory lists; the rest must agree.)
diff -r -x summary.csv -x index.html -x .rabbit-inventory "$work/one" "$work/sharded" ||
  fail "merged run files differ"
grep -vx index.html "$work/sharded/.rabbit-inventory" | cmp - "$work/one/.rabbit-inventory" ||
  fail "the merged report's inventory differs"

# Killed midway (rank 0 kills itself after N of its runs; mpirun ends the job), then resumed
# under mpirun: the finished runs are kept, every rank skips them, the report is the same. With
# rank 1 sending its files (they die with it): exactly rank 0's 2 runs are kept. Writing into the
# report folder: rank 0's run and whatever runs rank 1 had finished when the job ended.
killed_and_resumed() {  # NAME MODE KILL_AFTER PATTERN
  code=0
  TMPDIR="$work/tmp" RABBIT_RANK_FILES=$2 RABBIT_RUN_KILL_AFTER=$3 mpirun_2 -x RABBIT_RANK_FILES \
    -x RABBIT_RUN_KILL_AFTER "$rabbit" run "$suite" --filter "$filter" --jobs 1 --no-html -q \
    --out "$work/$1" >/dev/null 2>&1 || code=$?
  [ "$code" -ne 0 ] || fail "$1: RABBIT_RUN_KILL_AFTER=$3 did not kill the run"
  [ -d "$work/$1.partial" ] || fail "$1: the killed run left no staging folder"
  TMPDIR="$work/tmp" RABBIT_RANK_FILES=$2 mpirun_2 -x RABBIT_RANK_FILES "$rabbit" run "$suite" \
    --filter "$filter" --jobs 1 --no-html --out "$work/$1" --resume >"$work/$1.log"
  grep -Eq "$4 of 6 runs already finished" "$work/$1.log" || fail "$1: the resume ran finished runs"
  without_wall "$work/$1/summary.csv" >"$work/$1.csv"
  cmp "$work/one.csv" "$work/$1.csv" || fail "$1: the resumed summary.csv differs"
  diff -r -x summary.csv "$work/one" "$work/$1" || fail "$1: the resumed run files differ"
  [ ! -e "$work/$1.partial" ] || fail "$1: the resume left its staging folder"
}
killed_and_resumed resumed_sent transfer 2 2
killed_and_resumed resumed auto 1 "[1-6]"

# Bad input: every rank exits 2, nothing is written.
code=0
mpirun_2 "$rabbit" run "$work/missing.toml" -q --out "$work/bad" >/dev/null 2>&1 || code=$?
[ "$code" -eq 2 ] || fail "bad input under mpirun exited $code, not 2"
[ ! -e "$work/bad" ] || fail "bad input under mpirun wrote $work/bad"
rm -rf "$work"
echo "mpi_run_test: passed"
