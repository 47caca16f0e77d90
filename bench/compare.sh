#!/bin/bash
# rabbit against MuJoCo on the same workload, whole processes, alternating:
#   rabbit side: `rabbit run --jobs 1 --no-html -q` on the default suite (CSV report, one thread);
#   MuJoCo side: bench/mujoco_workload stepping the same robot for the same simulated time (the sum
#                of duration_s in the suite's summary.csv) at the 1 ms controller rate (Euler,
#                default soft contacts, pd_hold through qfrc_applied).
# Each round runs both, the order alternating from round to round (ABBA), and notes the machine's
# 1-minute load before each process. Prints every round, then the medians of CPU (user + sys) and
# wall time and the rabbit / MuJoCo ratios (of the medians, and the median of the rounds' ratios).
#
#   bash bench/compare.sh [BUILD_DIR] [ROUNDS] [-- extra rabbit run arguments]
#
# BUILD_DIR defaults to build, ROUNDS to 5. Needs python3 (to read summary.csv).
set -euo pipefail

build=${1:-build}
rounds=${2:-5}
shift $(($# > 2 ? 2 : $#))
[[ "${1:-}" == "--" ]] && shift
extra=("$@")
rabbit="$build/rabbit"
mujoco="$build/bench/mujoco_workload"
for exe in "$rabbit" "$mujoco"; do
  if [[ ! -x "$exe" ]]; then
    echo "compare.sh: $exe not found (build the rabbit and mujoco_workload targets)" >&2
    exit 2
  fi
done

work=$(mktemp -d "${TMPDIR:-/tmp}/rabbit-compare-XXXXXX")
trap 'rm -rf "$work"' EXIT

# rabbit run exits 1 when some run fails its criteria: that is a result here, not an error.
run_rabbit() {
  "$rabbit" run --jobs 1 --no-html -q --out "$1" "${extra[@]}" || [[ $? -eq 1 ]]
}

run_rabbit "$work/probe"
seconds=$(python3 - "$work/probe/summary.csv" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(f"{sum(float(r['duration_s']) for r in rows):.3f} {len(rows)}")
EOF
)
read -r simulated runs <<<"$seconds"
rm -rf "$work/probe"
echo "workload: $runs runs, $simulated simulated s; MuJoCo steps the same $simulated s"

load() { cut -d' ' -f1 /proc/loadavg; }
# Each prints "cpu_s wall_s" (CPU = user + system) of one whole process.
rabbit_once() {
  local rc=0
  /usr/bin/time -f "%U %S %e" -o "$work/time" \
    "$rabbit" run --jobs 1 --no-html -q --out "$work/r$1" "${extra[@]}" >/dev/null || rc=$?
  if ((rc > 1)); then
    echo "compare.sh: rabbit run failed (exit $rc)" >&2
    exit 1
  fi
  rm -rf "$work/r$1"
  awk '{printf "%.3f %.3f\n", $1 + $2, $3}' "$work/time"
}
mujoco_once() {
  /usr/bin/time -f "%U %S %e" -o "$work/time" "$mujoco" "$simulated" >/dev/null
  awk '{printf "%.3f %.3f\n", $1 + $2, $3}' "$work/time"
}

printf "%-5s %-8s %9s %9s %6s\n" round side cpu_s wall_s load
: >"$work/rounds"
for ((i = 1; i <= rounds; ++i)); do
  if ((i % 2 == 1)); then order=(rabbit mujoco); else order=(mujoco rabbit); fi
  declare -A cpu wall ld
  for side in "${order[@]}"; do
    ld[$side]=$(load)
    read -r c w <<<"$("${side}_once" "$i")"
    cpu[$side]=$c
    wall[$side]=$w
    printf "%-5s %-8s %9s %9s %6s\n" "$i" "$side" "$c" "$w" "${ld[$side]}"
  done
  echo "${cpu[rabbit]} ${wall[rabbit]} ${cpu[mujoco]} ${wall[mujoco]} ${ld[rabbit]} ${ld[mujoco]}" \
    >>"$work/rounds"
  unset cpu wall ld
done

python3 - "$work/rounds" <<'EOF'
import statistics as st, sys
rows = [list(map(float, line.split())) for line in open(sys.argv[1])]
col = lambda k: [r[k] for r in rows]
med = lambda k: st.median(col(k))
print(f"median CPU s:  rabbit {med(0):.3f}  MuJoCo {med(2):.3f}")
print(f"median wall s: rabbit {med(1):.3f}  MuJoCo {med(3):.3f}")
print(f"rabbit / MuJoCo CPU: {med(0) / med(2):.3f} (ratio of medians), "
      f"{st.median([r[0] / r[2] for r in rows]):.3f} (median of the rounds' ratios)")
print(f"rabbit / MuJoCo wall: {med(1) / med(3):.3f} (ratio of medians)")
loads = col(4) + col(5)
print(f"1-min load before each process: min {min(loads):.2f} median {st.median(loads):.2f} "
      f"max {max(loads):.2f} ({len(rows)} rounds)")
EOF
