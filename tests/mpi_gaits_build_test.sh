#!/bin/sh
# rabbit gaits build under mpirun -np 2 against one process on one thread: the same bytes in every
# file (the two cheapest shipped gaits, the targets of tests/gait_build_test.cc).
# Usage: mpi_gaits_build_test.sh MPIEXEC RABBIT WORKDIR
set -eu
mpiexec=$1
rabbit=$2
work=$3
rm -rf "$work"
mkdir -p "$work/tmp"
cat > "$work/two.toml" <<'TOML'
[[gait]]
v_m = 0.3
[gait.bounds]
qr1_dsw_deg = [10, 60]
q0_d_deg = [-5, 25]
pulse_torque_nm = [0, 100]
start_speed_m_s = [0.1, 1.5]
[gait.walker]
rule_share = 1

[[gait]]
v_m = 0.4
l_step = 0.24
TOML
"$rabbit" gaits build "$work/two.toml" --out "$work/one" --jobs 1 -q
TMPDIR="$work/tmp" "$mpiexec" --oversubscribe --allow-run-as-root --mca btl self,vader \
  --mca btl_vader_single_copy_mechanism none -np 2 \
  "$rabbit" gaits build "$work/two.toml" --out "$work/two" --jobs 1 -q
diff -r "$work/one" "$work/two" || { echo "mpi_gaits_build_test: ranks changed the files" >&2; exit 1; }
echo "mpi_gaits_build_test: identical"
