#!/bin/sh
# hostile_test.sh PLIANT SOURCE_DIR BUILD_DIR - hostile inputs through the
# command line (issue 13): each is bad input (exit 2) named by file:line,
# none runs code, quotes a file or works for ever.
set -u
PLIANT=$1
BUILD=$3
TMP=$(mktemp -d "${TMPDIR:-/tmp}/pliant_hostile_test.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

BAR='  <Node name="bar">
    <RegularGridTetrahedra n="3 2 2"/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1000"/>
  </Node>'

# 1. a huge time step is bad input, not a NaN at the first step (exit 1)
printf '<Node name="root" dt="1e308">\n  <NewtonSolver/>\n%s\n</Node>\n' "$BAR" > "$TMP/dt.xml"
"$PLIANT" run "$TMP/dt.xml" -n 3 --out "$TMP/out" > /dev/null 2> "$TMP/err"
code=$?
check "dt=1e308 exits 2" "[ $code -eq 2 ]"
check "dt=1e308 names file:line" "grep -q 'dt.xml:1: error: root: dt = 1e+308 s' '$TMP/err'"

# 2. a scene cannot load a shared object by path unless the user allows it
LIB="$BUILD/tests/plugins/libpliant_pl_ctor_plugin.so"
printf '<Node name="root">\n  <RequiredPlugin name="%s"/>\n</Node>\n' "$LIB" > "$TMP/lib.xml"
"$PLIANT" run "$TMP/lib.xml" -n 1 --out "$TMP/out" > /dev/null 2> "$TMP/err"
code=$?
check "a plugin path exits 2" "[ $code -eq 2 ]"
check "a plugin path names file:line" "grep -q 'lib.xml:2: error: RequiredPlugin: .* is a path' '$TMP/err'"
"$PLIANT" run "$TMP/lib.xml" -n 1 --out "$TMP/out" --allow-plugin-path > /dev/null 2> "$TMP/err"
code=$?
check "--allow-plugin-path loads it" "[ $code -eq 0 ]"

# 3. a file that is not a mesh is not quoted
printf 'root:x:0:0:TOPSECRET-42:/root:/bin/sh\n' > "$TMP/passwd"
printf '<Node name="root">\n  <MeshLoader filename="%s"/>\n</Node>\n' "$TMP/passwd" > "$TMP/pw.xml"
"$PLIANT" run "$TMP/pw.xml" -n 1 --out "$TMP/out" > /dev/null 2> "$TMP/err"
code=$?
check "a non-mesh file exits 2" "[ $code -eq 2 ]"
check "a non-mesh file is named" "grep -q 'passwd:1: error' '$TMP/err'"
check "a non-mesh file is not quoted" "! grep -q 'TOPSECRET' '$TMP/err'"

# 4. unbounded work is refused before it starts
printf '# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n' > "$TMP/tet.vtk"
printf '<Node name="root">\n  <MeshLoader filename="tet.vtk" subdivide="30"/>\n</Node>\n' > "$TMP/sub.xml"
timeout 20 "$PLIANT" run "$TMP/sub.xml" -n 1 --out "$TMP/out" > /dev/null 2> "$TMP/err"
code=$?
check "subdivide=30 exits 2 at once" "[ $code -eq 2 ] && grep -q 'sub.xml:2: error' '$TMP/err'"
printf '<Node name="root">\n  <NewtonSolver maxIterations="2000000000"/>\n%s\n</Node>\n' "$BAR" > "$TMP/it.xml"
"$PLIANT" run "$TMP/it.xml" -n 1 --out "$TMP/out" > /dev/null 2> "$TMP/err"
code=$?
check "2e9 iterations exit 2" "[ $code -eq 2 ] && grep -q 'it.xml:2: error' '$TMP/err'"

# 5. regression lists: INT_MAX steps, a byte order mark, a NUL byte
printf '<Node name="root" dt="0.01">\n  <NewtonSolver/>\n%s\n</Node>\n' "$BAR" > "$TMP/ok.xml"
printf '# list\nok.xml 2147483647 1e-6\n' > "$TMP/steps.list"
timeout 60 "$PLIANT" regress "$TMP/steps.list" --update > "$TMP/out" 2>&1
code=$?
check "INT_MAX regress steps exit 2" "[ $code -eq 2 ]"
check "INT_MAX regress steps name list:line" "grep -q 'steps.list:2: .*above the cap' '$TMP/out'"
printf '# list\nok.xml 9000000 1e-6\n' > "$TMP/mem.list"
timeout 60 "$PLIANT" regress "$TMP/mem.list" --update > "$TMP/out" 2>&1
code=$?
check "a regress run too large to record exits 2" "[ $code -eq 2 ] && grep -q 'mem.list:2: .*MB' '$TMP/out'"
printf '\357\273\277refs\nok.xml 2 1e-6\n' > "$TMP/bom.list"
"$PLIANT" regress "$TMP/bom.list" > "$TMP/out" 2>&1
code=$?
check "a list with a BOM exits 2" "[ $code -eq 2 ] && grep -q 'bom.list:1: error' '$TMP/out'"
printf 'ok.xml 2 1e-6\nok.xml\0 2 1e-6\n' > "$TMP/nul.list"
"$PLIANT" regress "$TMP/nul.list" > "$TMP/out" 2>&1
code=$?
check "a list with a NUL byte exits 2" "[ $code -eq 2 ] && grep -q 'nul.list:2: error' '$TMP/out'"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
