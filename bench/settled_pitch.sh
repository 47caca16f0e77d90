#!/bin/bash
# The trunk pitch the default walker settles at: one walk of 40 s at each constant V_d on flat
# ground, and the mean q0_d and stride V_M of its last 10 steps (steps.csv). The velocity
# control's feed-forward and start use a pitch map (controller.velocity_control.pitch_map_deg;
# the gaits' own by default); this is the map the walker itself would give. The second argument
# sets [controller.slope] touchdown_heights (docs/design/slope.md, "Slope adaptation"), the
# third the speeds (empty: the 16 below), the fourth the gait database (default: gaits/). The
# adaptive preset's settled map (velocity_control.settled_pitch_map_deg) is this table for gaits/.
#
#   bash bench/settled_pitch.sh [BUILD_DIR] [false|true] ["0.30 0.40 ..."] [DATABASE]
set -euo pipefail

build=${1:-build}
heights=${2:-false}
read -r -a speeds <<<"${3:-0.30 0.33 0.36 0.40 0.45 0.50 0.55 0.60 0.65 0.70 0.75 0.80 0.85 0.90 0.95 1.00}"
case "$heights" in true | false) ;; *) echo "touchdown_heights must be true or false" >&2; exit 2 ;; esac
for v in "${speeds[@]}"; do
  [[ "$v" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "a speed must be a number in m/s: '$v'" >&2; exit 2; }
done
if [[ $(printf '%s\n' "${speeds[@]}" | sort | uniq -d) ]]; then
  echo "a speed is given twice" >&2
  exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
database=${4:-$root/gaits}
[[ -f "$database/reference/index.csv" ]] || {
  echo "not a gait database (no reference/index.csv): '$database'" >&2
  exit 2
}
database=$(cd "$database" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/rabbit-settled-XXXXXX")
trap 'rm -rf "$work"' EXIT

{
  printf '[suite]\nname = "settled_pitch"\n[defaults]\nexpect_outcome = "completed"\n'
  printf 'required = false\n[defaults.simulation]\nduration = 40.0\nrecord_every = 50\n'
  printf '[defaults.controller]\ntype = "fuzzy_cmac"\ndatabase = "%s"\n' "$database"
  printf '[defaults.controller.slope]\ntouchdown_heights = %s\n' "$heights"
  for v in "${speeds[@]}"; do
    printf '\n[[scenario]]\nname = "v_%s"\n[scenario.velocity]\nvalue = %s\n' "$v" "$v"
  done
} >"$work/suite.toml"
# Exit 1 is a walk that failed (reported in the table); anything else stops here.
"$build/rabbit" run "$work/suite.toml" --no-html -q -j2 --out "$work/out" || [[ $? -eq 1 ]]

python3 - "$work/out" "${speeds[@]}" <<'PY'
import csv, sys
out, speeds = sys.argv[1], sys.argv[2:]
outcome = {r["scenario"]: r["outcome"] for r in csv.DictReader(open(f"{out}/summary.csv"))}
print("v_d_m_s,settled_q0_d_deg,settled_v_m_m_s,outcome")
for v in speeds:
    name = f"v_{v}"
    rows = list(csv.DictReader(open(f"{out}/{name}/steps.csv")))[-10:]
    if not rows:  # no step: a walk that fell at once
        print(f"{v},nan,nan,{outcome[name]}")
        continue
    q = sum(float(r["q0_d_deg"]) for r in rows) / len(rows)
    vm = sum(float(r["v_m_m_s"]) for r in rows) / len(rows)
    print(f"{v},{q:.1f},{vm:.3f},{outcome[name]}")
PY
