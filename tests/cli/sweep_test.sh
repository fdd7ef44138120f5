#!/bin/sh
# sweep_test.sh PLIANT SOURCE_DIR FAULT_PLUGIN - `pliant sweep` in one
# process after the other: the grid (a:b:n and lists, last --set fastest),
# the recorded outputs against implicit Euler's free fall, the tables,
# resuming, a run that fails on purpose (NaN, SIGSEGV, abort, hang) reported
# while the others complete, and bad requests refused before anything runs.
set -u
PLIANT=$1
SRC=$2
# a scene names plugins, found on the plugin path (a path would be refused)
PLIANT_PLUGIN_PATH=$(dirname "$3")${PLIANT_PLUGIN_PATH:+:$PLIANT_PLUGIN_PATH}
export PLIANT_PLUGIN_PATH
FAULT=$(basename "$3" .so)
FAULT=${FAULT#libpliant_}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/pliant_sweep_test.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

# A 10 cm cube in free fall (ARAP: no elastic force in a rigid motion), and a
# FaultInjector that does nothing unless told to.
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
    <ARAP name="arap" youngModulus="1e5" poissonRatio="0.3"/>
    <FaultInjector name="fault" kind="none" step="3"/>
    <VTKExporter name="vtk" filename="body" every="1000"/>
  </Node>
</Node>
XML
sweep() { "$PLIANT" sweep "$TMP/fall.xml" -q "$@"; }

# 1. a 2 x 2 grid of gravity (a list of vectors) and dt (a:b:n)
sweep --set "root.gravity=0 -1 0,0 -3 0" --set root.dt=0.01:0.02:2 -n 10 \
  --record body/dofs.position -o "$TMP/g" > "$TMP/out" 2> "$TMP/err"
check "a sweep of 4 runs exits 0" "[ $? -eq 0 ] && grep -q '^4 runs: 4 ok, 0 failed' '$TMP/out'"
check "the CSV and Markdown tables have a row per run" \
  "[ \$(wc -l < '$TMP/g/sweep.csv') -eq 5 ] && [ \$(wc -l < '$TMP/g/sweep.md') -eq 6 ]"
check "runs follow the grid, the last --set fastest" \
  "awk -F'|' 'NR > 2 { printf \"%s/%s/%s;\", \$2, \$3, \$4 }' '$TMP/g/sweep.md' | grep -q '^ 0000 / 0 -1 0 / 0.01 ; 0001 / 0 -1 0 / 0.02 ; 0002 / 0 -3 0 / 0.01 ; 0003 / 0 -3 0 / 0.02 ;\$'"
# implicit Euler from rest: y_n = g dt^2 n (n + 1) / 2
check "each run's recorded position is implicit Euler's free fall (rel. 1e-9)" \
  "awk -F'|' 'NR > 2 { split(\$5, p, \" \"); split(\$3, g, \" \"); n = \$6; e = g[2] * \$4 * \$4 * n * (n + 1) / 2;
     if (\$8 != \" ok \" || (p[2] - e) * (p[2] - e) > 1e-18 * e * e) bad = 1; rows++ }
     END { exit bad || rows != 4 }' '$TMP/g/sweep.md'"
check "each run has its outputs, log and result in OUT/run_NNNN/" \
  "[ -s '$TMP/g/run_0003/body.pvd' ] && [ -f '$TMP/g/run_0003/log.txt' ] && grep -q '^status ok' '$TMP/g/run_0003/result.txt'"

# 2. resume: the same command runs nothing again, a run without result.txt runs again
cp "$TMP/g/sweep.csv" "$TMP/first.csv"
sweep --set "root.gravity=0 -1 0,0 -3 0" --set root.dt=0.01:0.02:2 -n 10 \
  --record body/dofs.position -o "$TMP/g" > "$TMP/out" 2> "$TMP/err"
check "a complete sweep run again runs nothing and writes the same table" \
  "[ $? -eq 0 ] && grep -q '4 of 4 runs completed before; running the other 0' '$TMP/err' && cmp -s '$TMP/first.csv' '$TMP/g/sweep.csv'"
rm "$TMP/g/run_0002/result.txt"
sweep --set "root.gravity=0 -1 0,0 -3 0" --set root.dt=0.01:0.02:2 -n 10 \
  --record body/dofs.position -o "$TMP/g" > "$TMP/out" 2> "$TMP/err"
check "a sweep cut short runs only the runs that did not complete" \
  "[ $? -eq 0 ] && grep -q '3 of 4 runs completed before; running the other 1' '$TMP/err' && grep -q '^status ok' '$TMP/g/run_0002/result.txt'"
sweep --set root.dt=0.01,0.02 -n 10 -o "$TMP/g" > /dev/null 2> "$TMP/err"
check "another sweep into the same folder is refused" "[ $? -eq 2 ] && grep -q 'holds another sweep' '$TMP/err'"

# 3. runs that go wrong on purpose are reported; the others complete
sweep --set fault.kind=none,nan,segv,abort,hang --set root.dt=0.01 -n 6 --timeout 8 \
  --record body/dofs.position -o "$TMP/f" > "$TMP/out" 2> "$TMP/err"
code=$?
st() { awk -F'|' -v r="$1" 'NR > 2 && $2 == " " r " " { print $8 }' "$TMP/f/sweep.md"; }
check "a sweep with failed runs exits 1 and counts them" "[ $code -eq 1 ] && grep -q '^5 runs: 1 ok, 4 failed' '$TMP/out'"
check "the run without a fault completes" "[ \"\$(st 0000)\" = ' ok ' ]"
check "a NaN injected: failed, with the solver's message" \
  "[ \"\$(st 0001)\" = ' failed (exit 1) ' ] && grep '^| 0001 ' '$TMP/f/sweep.md' | grep -Eq 'non-finite|NaN'"
check "a segfault: crashed (SIGSEGV)" "[ \"\$(st 0002)\" = ' crashed (SIGSEGV) ' ]"
check "an abort: crashed (SIGABRT)" "[ \"\$(st 0003)\" = ' crashed (SIGABRT) ' ]"
check "a hang: timed out" "[ \"\$(st 0004)\" = ' timed out after 8 s ' ]"
check "a crash is reported with host, scene and values" \
  "grep -q 'run_0002 crashed (SIGSEGV) on host .*fall.xml --set fault.kind=segv --set root.dt=0.01 (log: ' '$TMP/err'"
check "runs that did not complete have no result.txt" \
  "[ ! -e '$TMP/f/run_0001/result.txt' ] && [ ! -e '$TMP/f/run_0002/result.txt' ] && [ -e '$TMP/f/run_0000/result.txt' ]"

# 4. bad requests: refused before any run, exit 2
sweep --set body/arp.youngModulus=1e5,1e6 -n 2 -o "$TMP/b1" > /dev/null 2> "$TMP/err"
check "a misspelled --set path is refused with a suggestion, nothing run" \
  "[ $? -eq 2 ] && grep -q 'did you mean body/arap' '$TMP/err' && [ ! -e '$TMP/b1/run_0000' ]"
sweep --set root.dt=0.01,0.02 --record body/dofs.positon -n 2 -o "$TMP/b2" > /dev/null 2> "$TMP/err"
check "a misspelled --record path is refused, nothing run" "[ $? -eq 2 ] && [ ! -e '$TMP/b2/run_0000' ]"
sweep --set root.dt=0.01:0.02 -n 2 -o "$TMP/b3" > /dev/null 2> "$TMP/err"
check "a malformed a:b:n is refused" "[ $? -eq 2 ] && grep -q 'expected a:b:n' '$TMP/err'"
sweep --set root.dt=0.01 --set root.dt=0.02 -n 2 -o "$TMP/b4" > /dev/null 2> "$TMP/err"
check "a path given twice is refused" "[ $? -eq 2 ] && grep -q 'given twice' '$TMP/err'"
"$PLIANT" sweep --help > "$TMP/out" 2>&1
check "sweep --help" "[ $? -eq 0 ] && grep -q '^usage: pliant sweep' '$TMP/out'"

# 5. regress: a scene that crashes or hangs is an ERROR row, the others pass
sed 's/kind="none"/kind="segv"/' "$TMP/fall.xml" > "$TMP/fall_segv.xml"
sed 's/kind="none"/kind="hang"/' "$TMP/fall.xml" > "$TMP/fall_hang.xml"
cp "$TMP/fall.xml" "$TMP/fall2.xml"
printf 'fall.xml 6 1e-12\nfall2.xml 8 1e-12 0 1\n' > "$TMP/ok.txt"
printf 'fall.xml 6 1e-12\nfall_segv.xml 6 1e-12\nfall_hang.xml 6 1e-12\nfall2.xml 8 1e-12 0 1\n' > "$TMP/list.txt"
"$PLIANT" regress "$TMP/ok.txt" --update -q > /dev/null 2>&1
"$PLIANT" regress "$TMP/list.txt" -q --timeout 5 > "$TMP/out" 2> "$TMP/err"
code=$?
check "regress with a crashing and a hanging scene exits 2, the others pass" \
  "[ $code -eq 2 ] && grep -q '^4 scenes: 2 passed, 0 failed, 2 errors' '$TMP/out' && grep -q '^fall.xml .* pass\$' '$TMP/out' && grep -q '^fall2.xml .* pass\$' '$TMP/out'"
check "the crash is its row's ERROR and reported with the host" \
  "grep -q '^fall_segv.xml .*ERROR: the run crashed: SIGSEGV' '$TMP/out' && grep -q 'fall_segv.xml: the run crashed: SIGSEGV (Segmentation fault) (host ' '$TMP/err'"
check "the hang is stopped by --timeout" "grep -q '^fall_hang.xml .*ERROR: the run timed out after 5 s' '$TMP/out'"

# 6. a build without MPI started by mpirun says so (what mpirun sets: Open MPI's variables)
if "$PLIANT" --version | grep -q 'without MPI'; then
  OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=1 "$PLIANT" sweep "$TMP/fall.xml" --set root.dt=0.01 \
    -n 2 -o "$TMP/m" > /dev/null 2> "$TMP/err"
  check "a build without MPI under mpirun refuses, saying why" \
    "[ $? -eq 2 ] && grep -q 'built without MPI' '$TMP/err' && [ ! -e '$TMP/m' ]"
  OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 "$PLIANT" regress "$SRC/tests/regression/list.txt" > /dev/null 2> "$TMP/err"
  check "regress too" "[ $? -eq 2 ] && grep -q 'built without MPI' '$TMP/err'"
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
