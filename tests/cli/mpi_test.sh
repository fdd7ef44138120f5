#!/bin/sh
# mpi_test.sh PLIANT SOURCE_DIR FAULT_PLUGIN MPIEXEC - `pliant sweep` and
# `pliant regress` over 2 MPI ranks give the serial run's tables bit for bit
# (timings aside), runs that crash or fail on purpose are reported with rank
# and host while the others complete, both ranks get runs, and each rank's
# runs see one GPU of the node's list (local rank modulo the GPU count).
set -u
PLIANT=$1
SRC=$2
# a scene names plugins, found on the plugin path (a path would be refused)
PLIANT_PLUGIN_PATH=$(dirname "$3")${PLIANT_PLUGIN_PATH:+:$PLIANT_PLUGIN_PATH}
export PLIANT_PLUGIN_PATH
FAULT=$(basename "$3" .so)
FAULT=${FAULT#libpliant_}
MPIEXEC=$4
TMP=$(mktemp -d "${TMPDIR:-/tmp}/pliant_mpi_test.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
# CI runs as root; Open MPI refuses that unless told (here, not in pliant).
# No single-copy (CMA) transfers: containers often forbid them.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none
unset OMP_NUM_THREADS
MPIRUN="$MPIEXEC --oversubscribe -n 2"
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

cat > "$TMP/fall.xml" <<XML
<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <RequiredPlugin name="hyperelastic"/>
  <RequiredPlugin name="sparse_inverse"/>
  <RequiredPlugin name="$FAULT"/>
  <LocalGlobalSolver name="solver" iterations="5"/>
  <SparseInverseSolver name="global"/>
  <Node name="body">
    <RegularGridTetrahedra name="grid" min="0 0 0" max="0.1 0.1 0.1" n="3 3 3"/>
    <MechanicalObject name="dofs" src="@grid"/>
    <DiagonalMass massDensity="1000"/>
    <ARAP name="arap" youngModulus="1e5" poissonRatio="0.45"/>
    <FixedConstraint indices="0"/>
    <FaultInjector name="fault" kind="none" step="3"/>
  </Node>
</Node>
XML
# the Markdown table without its ms/step column
untimed() {
  awk -F'|' -v OFS='|' 'NR == 1 { for (k = 1; k <= NF; ++k) if ($k == " ms/step ") c = k }
                        { $c = ""; print }' "$1"
}

# 1. runs that fail or crash on purpose, serial and over 2 ranks
args="--set fault.kind=none,nan,segv --set root.dt=0.01,0.02 -n 12 --record body/dofs.position --device cpu -q"
"$PLIANT" sweep "$TMP/fall.xml" $args -o "$TMP/s1" > "$TMP/s1.out" 2> "$TMP/s1.err"
c1=$?
$MPIRUN "$PLIANT" sweep "$TMP/fall.xml" $args -o "$TMP/m1" > "$TMP/m1.out" 2> "$TMP/m1.err"
c2=$?
check "serial and 2 ranks both exit 1 with 4 of 6 runs failed" \
  "[ $c1 -eq 1 ] && [ $c2 -eq 1 ] && grep -q '^6 runs: 2 ok, 4 failed' '$TMP/s1.out' && grep -q '^6 runs: 2 ok, 4 failed' '$TMP/m1.out'"
untimed "$TMP/s1/sweep.md" > "$TMP/s1.md"
untimed "$TMP/m1/sweep.md" > "$TMP/m1.md"
check "the tables are the same bit for bit (ms/step aside)" "cmp -s '$TMP/s1.md' '$TMP/m1.md'"
check "the crashes are reported with rank and host" \
  "[ \$(grep -c 'crashed (SIGSEGV) on rank [01] of 2, host ' '$TMP/m1.err') -eq 2 ]"
check "the runs without a fault completed beside the crashes" \
  "[ \$(grep -c '| ok |' '$TMP/m1/sweep.md') -eq 2 ]"

# 2. a grid that runs: both ranks get runs; each rank's runs see its GPU
args="--set root.dt=0.005:0.02:6 -n 15 --record body/dofs.position --device cpu -q"
"$PLIANT" sweep "$TMP/fall.xml" $args -o "$TMP/s2" > /dev/null 2>&1
CUDA_VISIBLE_DEVICES=7,9 $MPIRUN "$PLIANT" sweep "$TMP/fall.xml" $args -o "$TMP/m2" > "$TMP/m2.out" 2> "$TMP/m2.err"
check "a sweep over 2 ranks exits 0" "[ $? -eq 0 ] && grep -q '^6 runs: 6 ok, 0 failed' '$TMP/m2.out'"
untimed "$TMP/s2/sweep.md" > "$TMP/s2.md"
untimed "$TMP/m2/sweep.md" > "$TMP/m2.md"
check "its table is the serial one bit for bit (ms/step aside)" "cmp -s '$TMP/s2.md' '$TMP/m2.md'"
check "both ranks ran runs" \
  "grep -q '^rank 0' '$TMP'/m2/run_*/result.txt && grep -q '^rank 1' '$TMP'/m2/run_*/result.txt"
check "rank 0's runs saw GPU 7, rank 1's GPU 9 (of CUDA_VISIBLE_DEVICES=7,9)" \
  "! cat '$TMP'/m2/run_*/result.txt | awk '/^rank/ { r = \$2 } /^gpu/ { if (\$2 != (r == 0 ? 7 : 9)) bad = 1 } END { exit !bad }'"

# 3. regress over 2 ranks prints the serial table
"$PLIANT" regress "$SRC/tests/regression/list.txt" -q > "$TMP/r1.out" 2>/dev/null
c1=$?
$MPIRUN "$PLIANT" regress "$SRC/tests/regression/list.txt" -q > "$TMP/r2.out" 2> "$TMP/r2.err"
c2=$?
check "regress over 2 ranks passes and prints the serial table" \
  "[ $c1 -eq 0 ] && [ $c2 -eq 0 ] && cmp -s '$TMP/r1.out' '$TMP/r2.out' && grep -q '4 passed' '$TMP/r2.out'"

if [ "$fail" -ne 0 ]; then
  for f in "$TMP"/*.err; do echo "--- $f"; tail -n 20 "$f"; done
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
