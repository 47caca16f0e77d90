#!/bin/bash
# Work-precision of the integrator tolerances on the walking workload: the default suite
# (scenarios/paper.toml, 21 walks) run whole, one thread, CSV report, at several rtol / atol
# settings (added to the suite's [defaults.simulation] in a temporary copy), each compared with
# the suite at the defaults and with a tight reference (rtol 1e-9, atol 1e-11): CPU time,
# how many runs changed outcome or pass, and the largest change of a run's distance and mean
# L_step (m). A setting may name the ARKODE method's order too (RTOL:ATOL:ORDER; without one,
# the default order, 4). A setting fixed:STEP[:ORDER] takes fixed steps of STEP s instead
# ([simulation] fixed_step; at order 4 the classic Runge-Kutta method).
#
#   bash bench/walk_tolerance.sh [BUILD_DIR] ["RTOL:ATOL[:ORDER] fixed:STEP[:ORDER] ..."]
set -euo pipefail

build=${1:-build}
settings=${2:-"1e-6:1e-7 1e-6:1e-6 1e-5:1e-6 1e-5:1e-5"}
root=$(cd "$(dirname "$0")/.." && pwd)
rabbit="$build/rabbit"
work=$(mktemp -d "${TMPDIR:-/tmp}/rabbit-tolerance-XXXXXX")
trap 'rm -rf "$work"' EXIT

# A copy of the suite with absolute gait paths and, when given, the tolerances.
suite() {
  local file="$work/paper_$1.toml"
  sed "s#\"\.\./gaits#\"$root/gaits#" "$root/scenarios/paper.toml" >"$file"
  if [[ -n "$2" ]]; then
    python3 - "$file" "$2" "$3" "${4:-0}" <<'EOF'
import sys
path, rtol, atol, order = sys.argv[1:]
text = open(path).read()
key = "[defaults.simulation]\n"
extra = f"order = {order}\n" if order != "0" else ""
setting = f"fixed_step = {atol}\n" if rtol == "fixed" else f"rtol = {rtol}\natol = {atol}\n"
text = text.replace(key, key + setting + extra, 1)
open(path, "w").write(text)
EOF
  fi
  echo "$file"
}

run() {  # name rtol atol [order]
  local file rc=0
  file=$(suite "$1" "$2" "$3" "${4:-}")
  /usr/bin/time -f "%U %S" -o "$work/time_$1" \
    "$rabbit" run "$file" --jobs 1 --no-html -q --out "$work/out_$1" >/dev/null || rc=$?
  ((rc <= 1)) || { echo "rabbit run failed ($1, exit $rc)" >&2; exit 1; }
}

run default "" ""
run reference 1e-9 1e-11
names=(default reference)
for s in $settings; do
  IFS=: read -r rtol atol order <<<"$s"
  name=${s//:/_}
  run "$name" "$rtol" "$atol" "${order:-}"
  names+=("$name")
done

python3 - "$work" "${names[@]}" <<'EOF'
import csv, math, sys
work, names = sys.argv[1], sys.argv[2:]
def load(name):
    rows = {r["run"]: r for r in csv.DictReader(open(f"{work}/out_{name}/summary.csv"))}
    # The last line: on exit 1, time prints "Command exited with non-zero status 1" first.
    user, sys_ = map(float, open(f"{work}/time_{name}").read().splitlines()[-1].split())
    return rows, user + sys_
data = {n: load(n) for n in names}
def diff(a, b, key):
    worst = 0.0
    for run, r in a.items():
        x, y = float(r[key]), float(b[run][key])
        if math.isnan(x) and math.isnan(y):
            continue
        worst = max(worst, abs(x - y) if not (math.isnan(x) or math.isnan(y)) else math.inf)
    return worst
def changed(a, b):
    return sum(1 for run, r in a.items()
               if (r["outcome"], r["passed"]) != (b[run]["outcome"], b[run]["passed"]))
def mean_l(rows):
    v = [float(r["l_step_mean_m"]) for r in rows.values() if r["l_step_mean_m"] != "nan"]
    return sum(v) / len(v)
print(f"{'setting':<16} {'cpu_s':>6} {'vs default: changed':>20} {'max d dist m':>13} "
      f"{'max d L_step m':>15} {'d mean L_step m':>16} | vs reference: {'changed':>7} "
      f"{'max d dist m':>13} {'max d L_step m':>15}")
base, ref = data["default"][0], data["reference"][0]
for n in names:
    rows, cpu = data[n]
    print(f"{n:<16} {cpu:6.2f} {changed(rows, base):>20} {diff(rows, base, 'distance_m'):13.2e} "
          f"{diff(rows, base, 'l_step_mean_m'):15.2e} {mean_l(rows) - mean_l(base):16.2e} | "
          f"{'':>14}{changed(rows, ref):>7} {diff(rows, ref, 'distance_m'):13.2e} "
          f"{diff(rows, ref, 'l_step_mean_m'):15.2e}")
for n in names:
    rows = data[n][0]
    moved = [f"{run} ({base[run]['outcome']}/{base[run]['passed']} -> {r['outcome']}/{r['passed']})"
             for run, r in rows.items()
             if (r["outcome"], r["passed"]) != (base[run]["outcome"], base[run]["passed"])]
    if moved:
        print(f"{n}: outcome/passed changed against the default: {', '.join(moved)}")
EOF
