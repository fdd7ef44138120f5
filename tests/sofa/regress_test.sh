#!/bin/sh
# regress_test.sh PLIANT SOURCE_DIR own|shared - `pliant regress` with
# SOFA's semantics.
#   own:    the project's liver_hanging.scn (tests/sofa/scenes) listed by
#           its absolute path: --sofa-steps records t = 0 ... (N-1) h (the
#           reference written ends at (N-1) h, not N h); the run passes on
#           its own references; a perturbed reference fails with the reason
#           (state, vertex, distance, tolerance); a reference recorded with
#           SOFA's counting and compared with Pliant's says which step is
#           missing; broken SOFA inputs (a mapper's index past the
#           mesh, a plane without normal) exit 2 with file:line: error.
#   shared: SOFA's liver.scn against SOFA's stored references
#           ($PLIANT_REFERENCE_DIR/data/sofa_scenes/regression_refs): the error at the
#           last stored time over the rest diagonal (printed; below 1e-5,
#           the goal is 1e-3) and SOFA's measure within SOFA's
#           tolerance 1e-4; mapped 1 compares the mapped state too (the
#           sphere centres, MappedPoints; the beam's collision dofs);
#           fallingBeamLagrangianCollision.scn within
#           2e-3 of the rest diagonal at SOFA's last stored time, as written
#           and with rayleighStiffness 0.  Exits 77 (ctest: skipped) without PLIANT_REFERENCE_DIR
#           (the reference data are not part of the project; .ci/run sets it).
set -u
PLIANT=$1
SRC=$2
MODE=$3
SHARED="${PLIANT_REFERENCE_DIR:-/nonexistent}/data/sofa_scenes"
MESHES="${PLIANT_REFERENCE_DIR:-/nonexistent}/data/meshes"
if [ "$MODE" = shared ] && [ ! -r "$SHARED/liver.scn" ]; then
    echo "SKIPPED: no SOFA reference scenes at $SHARED (set PLIANT_REFERENCE_DIR; they are not part of the project)"
    exit 77
fi
TMP=$(mktemp -d "${TMPDIR:-/tmp}/pliant_sofa_regress.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

if [ "$MODE" = own ]; then
    # an absolute scene path; the list lives elsewhere
    echo "$SRC/tests/sofa/scenes/liver_hanging.scn 10 1e-12 0 1" > "$TMP/list"
    "$PLIANT" regress "$TMP/list" --sofa-steps --update --refs "$TMP/refs" -q > "$TMP/out" 2>&1
    check "an absolute path in a list runs (--update)" "[ $? -eq 0 ] && grep -q 'reference written' '$TMP/out'"
    REF="$TMP/refs/liver_hanging.scn.reference_0_dofs_mstate.txt.gz"
    check "SOFA's counting: 10 steps record T= 0 and T= 0.18 (9 h), lastonly" \
        "zcat '$REF' | awk '/^T=/ {t[n++] = \$2} END { exit !(n == 2 && t[0] == 0 && t[1] > 0.18 - 1e-9 && t[1] < 0.18 + 1e-9) }'"
    "$PLIANT" regress "$TMP/list" --sofa-steps --refs "$TMP/refs" -q > "$TMP/out" 2>&1
    check "the run passes on its own references" "[ $? -eq 0 ] && grep -q '1 passed, 0 failed' '$TMP/out'"
    # move vertex 0 of the last record by 0.5 in x
    last=$(zcat "$REF" | grep -n 'X=' | tail -1 | cut -d: -f1)
    zcat "$REF" | awk -v L="$last" 'NR == L {$2 = $2 + 0.5; $0 = "  " $0} {print}' \
        | gzip > "$TMP/p.gz" && mv "$TMP/p.gz" "$REF"
    "$PLIANT" regress "$TMP/list" --sofa-steps --refs "$TMP/refs" -q > "$TMP/out" 2>&1
    code=$?
    check "a perturbed reference fails (exit 1)" "[ $code -eq 1 ] && grep -q 'FAIL' '$TMP/out'"
    check "the failure says which state, vertex, distance and tolerance" \
        "grep -q \"state 0 'dofs': error/DoF .* > epsilon 1e-12 .*its vertex 0 is 0.5 from the reference at T= 0.18\" '$TMP/out'"
    "$PLIANT" regress "$TMP/list" --refs "$TMP/refs" -q > "$TMP/out" 2>&1
    check "without --sofa-steps the step SOFA recorded at 9 h is missing, said so" \
        "[ $? -eq 1 ] && grep -q 'not recorded by this run (the first at T= 0.18' '$TMP/out'"
    # broken SOFA inputs to the new lowerings: file:line: error, exit 2 (bad input)
    for b in broken_value_mapper broken_plane_normal; do
        (cd "$TMP" && "$PLIANT" run "$SRC/tests/sofa/scenes/$b.scn" -n 1) > "$TMP/out" 2>&1
        code=$?
        check "$b.scn: exit 2, file:line: error" \
            "[ $code -eq 2 ] && grep -q '$b.scn:[0-9]*: error' '$TMP/out'"
    done
else
    REFS="$SHARED/regression_refs"
    echo "$SHARED/liver.scn 100 1e-4 0 1" > "$TMP/list"
    PLIANT_DATA_PATH="$MESHES" "$PLIANT" regress "$TMP/list" --sofa-steps \
        --refs "$REFS" -q > "$TMP/out" 2>&1
    cat "$TMP/out"
    rel=$(awk '$1 ~ /liver.scn$/ {print $5}' "$TMP/out")
    echo "liver.scn against SOFA at T= 1.98: largest vertex distance / rest diagonal = $rel"
    check "liver.scn passes SOFA's own tolerance (1e-4 per DoF)" "grep -q '1 passed, 0 failed' '$TMP/out'"
    check "liver.scn within 1e-5 of the rest diagonal at SOFA's last stored time (goal 1e-3)" \
        "awk -v r='$rel' 'BEGIN { exit !(r + 0 > 0 && r + 0 < 1e-5) }'"
    echo "$SHARED/liver.scn 100 1e-4 1 1" > "$TMP/list1"
    PLIANT_DATA_PATH="$MESHES" "$PLIANT" regress "$TMP/list1" --sofa-steps \
        --refs "$REFS" -q > "$TMP/out" 2>&1
    code=$?
    cat "$TMP/out"
    rel=$(awk '$1 ~ /liver.scn$/ {print $5}' "$TMP/out")
    echo "liver.scn mapped 1 (dofs and the sphere centres) at T= 1.98: last/diag = $rel"
    check "mapped 1 compares the mapped state (the spheres, MappedPoints) and passes at 1e-4" \
        "[ $code -eq 0 ] && grep -q '1 passed, 0 failed' '$TMP/out'"
    # measured 1.15e-6 (the spheres; the dofs alone 1.13e-6)
    check "liver.scn mapped 1: every state within 1e-5 of its rest diagonal at T= 1.98" \
        "awk -v r='$rel' 'BEGIN { exit !(r + 0 > 0 && r + 0 < 1e-5) }'"
    echo "$SHARED/liver.scn 100 1e-12 1 1" > "$TMP/list1"
    PLIANT_DATA_PATH="$MESHES" "$PLIANT" regress "$TMP/list1" --sofa-steps \
        --refs "$REFS" -q > "$TMP/out" 2>&1
    check "mapped 1 at epsilon 1e-12: the failure names the mapped state 'spheres' (state 1)" \
        "grep -q \"state 1 'spheres': error/DoF\" '$TMP/out'"
    echo "$SHARED/fallingBeamLagrangianCollision.scn 46 1e-4 1 1" > "$TMP/list2"
    PLIANT_DATA_PATH="$MESHES" "$PLIANT" regress "$TMP/list2" --sofa-steps \
        --refs "$REFS" -q > "$TMP/out" 2> "$TMP/err"
    code=$?
    cat "$TMP/out"
    check "fallingBeamLagrangianCollision.scn mapped 1: the collision node's dofs compared, passes" \
        "[ $code -eq 0 ] && grep -q '1 passed, 0 failed' '$TMP/out'"
    # fallingBeam as written (rayleighStiffness 0.1) and without rayleighStiffness
    echo "$SHARED/fallingBeamLagrangianCollision.scn 46 1e-4 0 1" > "$TMP/list2"
    PLIANT_DATA_PATH="$MESHES" "$PLIANT" regress "$TMP/list2" --sofa-steps \
        --refs "$REFS" -q > "$TMP/out" 2> "$TMP/err"
    code=$?
    cat "$TMP/out"
    rel=$(awk '$1 ~ /fallingBeamLagrangianCollision.scn$/ {print $5}' "$TMP/out")
    echo "fallingBeamLagrangianCollision.scn against SOFA at T= 0.45: last/diag = $rel"
    check "fallingBeamLagrangianCollision.scn: runs and passes SOFA's measure at 1e-4 per DoF" \
        "[ $code -eq 0 ] && grep -q '1 passed, 0 failed' '$TMP/out'"
    # measured 1.19e-3 (2.34e-2 when the iterations started from sn, docs/sofa.md)
    check "fallingBeamLagrangianCollision.scn within 2e-3 of the rest diagonal at T= 0.45" \
        "awk -v r='$rel' 'BEGIN { exit !(r + 0 > 0 && r + 0 < 2e-3) }'"
    mkdir -p "$TMP/beam"
    sed 's/rayleighStiffness="0.1"/rayleighStiffness="0"/' \
        "$SHARED/fallingBeamLagrangianCollision.scn" > "$TMP/beam/fallingBeamLagrangianCollision.scn"
    echo "$TMP/beam/fallingBeamLagrangianCollision.scn 46 1e-4 0 1" > "$TMP/list2"
    PLIANT_DATA_PATH="$MESHES" "$PLIANT" regress "$TMP/list2" --sofa-steps \
        --refs "$REFS" -q > "$TMP/out" 2> "$TMP/err"
    cat "$TMP/out"
    rel=$(awk '$1 ~ /fallingBeamLagrangianCollision.scn$/ {print $5}' "$TMP/out")
    # measured 1.33e-3: rayleighMass applied after the step, the floor's look-ahead contact
    check "fallingBeamLagrangianCollision.scn, rayleighStiffness 0: within 2e-3 at T= 0.45" \
        "awk -v r='$rel' 'BEGIN { exit !(r + 0 > 0 && r + 0 < 2e-3) }'"
fi
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
