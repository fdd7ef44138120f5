/* test_sofa_shared.c - the SOFA and SoftRobots scenes of the reference data
 * ($PLIANT_REFERENCE_DIR/data/sofa_scenes: upstream files, never copied into the project), run when
 * that folder exists; without it the test says so and exits 77, which ctest
 * reports as skipped (SKIP_RETURN_CODE), not as a pass.
 *  - every scene either loads and runs, or is refused before running with
 *    the reason this table expects (what Pliant does not do yet: each line
 *    names the missing piece of issue 17), never run silently wrong;
 *  - liver.scn runs (LinearizedEulerSolver, SOFA's 'large' rotation) and
 *    ends within 1e-5 of the rest diagonal of SOFA's stored state at
 *    T = 1.98 (measured 1.13e-6);
 *  - the cable finger as written (firstOrder: LocalGlobalSolver's) with the
 *    cable pulled by 10 mm bends its tip by about as much as SoftRobots'
 *    finger (23.7 mm; 23.80 mm here after 80 steps);
 *  - SurfacePressureConstraint.scn's bunny grows its cavity by the commanded
 *    volume under an inflating pressure (check_bunny). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cable/cable_test_util.h"

/* The reference data (SOFA's and SoftRobots' scenes, meshes, SOFA's stored
 * states) are not part of the project: PLIANT_REFERENCE_DIR names the folder
 * holding them (data/sofa_scenes, data/meshes); .ci/run sets it where CI has
 * that folder.  Without it the test is skipped (exit 77). */
static char SHARED_DIR[1024];

/* PLIANT_REFERENCE_DIR/data/<rel> into buf. */
static const char *shared(char *buf, size_t size, const char *rel)
{
    snprintf(buf, size, "%s/%s", SHARED_DIR, rel);
    return buf;
}

typedef struct {
    const char *scene;
    const char *refused; /* the expected error, or NULL: runs */
} shared_case;

/* SoftRobots' bunny: valueType="1" is volumeGrowth (SOFA's option index),
 * value 40 [mm^3]: the cavity grows by 40 mm^3 under a positive (inflating)
 * pressure, which the constraint row solves. */
static void check_bunny(pl_sim *s)
{
    const char *sp = "bunny/SurfacePressureConstraint";
    char path[256];
    double v[4];
    const char *out[4] = {"initialCavityVolume", "cavityVolume", "volumeGrowth", "pressure"};
    for (int k = 0; k < 4; ++k) {
        snprintf(path, sizeof path, "%s.%s", sp, out[k]);
        v[k] = ct_get(s, path);
    }
    printf("SurfacePressureConstraint.scn after 200 steps: cavity volume %.6g (initial %.6g, "
           "growth %.6g), pressure %.6g\n",
           v[1], v[0], v[2], v[3]);
    fflush(stdout);
    ck_assert_double_gt(v[0], 0);
    ck_assert_double_eq_tol(v[1] - v[0], v[2], 1e-9 * v[0]);
    ck_assert_double_eq_tol(v[2], 40, 0.4); /* the commanded growth, within 1% */
    ck_assert_double_gt(v[3], 0);           /* an inflating pressure */
}

/* The physical check of a scene that runs, after its 200 steps (or NULL). */
static void (*check_of(const char *scene))(pl_sim *)
{
    if (!strcmp(scene, "SurfacePressureConstraint.scn")) return check_bunny;
    return NULL;
}

static const shared_case CASES[] = {
    {"CableFinger_displacement.scn", NULL},              /* firstOrder: LocalGlobalSolver's */
    {"FreeMotionAnimationLoop.scn", "\"Rigid3\""},      /* rigid bodies: refused by design */
    {"SurfacePressureConstraint.scn", NULL}, /* item 3; check_bunny */
    /* fallingBeamLagrangianCollision.scn runs in shared_falling_beam */
    {"liver.scn", NULL},
    /* raptor-cpu.scn runs in shared_raptor (200 steps, its moduli checked) */
};

static int have_shared(void)
{
    const char *root = getenv("PLIANT_REFERENCE_DIR");
    char liver[2048];
    if (root && *root) {
        snprintf(SHARED_DIR, sizeof SHARED_DIR, "%s/data", root);
        if (access(shared(liver, sizeof liver, "sofa_scenes/liver.scn"), R_OK) == 0) return 1;
    }
    printf("SKIPPED: no SOFA reference scenes (set PLIANT_REFERENCE_DIR to the folder holding "
           "data/sofa_scenes; they are not part of the project)\n");
    return 0;
}

START_TEST(shared_scene)
{
    if (!have_shared()) return;
    const shared_case *c = &CASES[_i];
    char path[2048], rel[256], meshes[2048];
    snprintf(rel, sizeof rel, "sofa_scenes/%s", c->scene);
    shared(path, sizeof path, rel);
    setenv("PLIANT_DATA_PATH", shared(meshes, sizeof meshes, "meshes"), 1);
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_file(path, NULL, &d);
    if (c->refused) {
        const pl_error *e = ct_find_error(&d, c->refused);
        if (s || !e) pl_diag_print(&d, stderr);
        ck_assert_ptr_null(s);
        ck_assert_ptr_nonnull(e);
        ck_assert_int_gt(e->line, 0);
        printf("%s: refused as expected: %s\n", c->scene, e->msg);
        if (!strcmp(c->scene, "FreeMotionAnimationLoop.scn")) {
            /* the rigid torus is the reason: its refusal comes first, naming the state */
            const pl_error *first = NULL;
            for (int k = 0; k < d.count && !first; ++k)
                if (d.items[k].code != PL_OK) first = &d.items[k];
            ck_assert_ptr_nonnull(first);
            ck_assert_ptr_nonnull(strstr(first->msg, "\"Rigid3\""));
            ck_assert_ptr_nonnull(strstr(first->where, "MechanicalObject"));
        }
    } else {
        if (!s) pl_diag_print(&d, stderr);
        ck_assert_ptr_nonnull(s);
        ct_step(s, 200);
        if (check_of(c->scene)) check_of(c->scene)(s);
        pl_sim_free(s);
    }
    pl_diag_free(&d);
}
END_TEST

/* Replaces the first `from` in *text by `to`. */
START_TEST(shared_finger_pulled)
{
    if (!have_shared()) return;
    char meshes[2048], scene[2048];
    setenv("PLIANT_DATA_PATH", shared(meshes, sizeof meshes, "meshes"), 1);
    shared(scene, sizeof scene, "sofa_scenes/CableFinger_displacement.scn");
    char *xml = ct_read_text(scene);
    ct_replace(&xml, "2.5\" value=\"0\"", "2.5\" value=\"10\""); /* the cable, not the comment */
    /* the scene's folder, so that its mesh/ paths resolve as in the file */
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_string(xml, scene, NULL, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    int n, tip = 0;
    const double *r = ct_positions(s, "finger/tetras", 1, &n);
    for (int i = 1; i < n; ++i)
        if (r[3 * i] < r[3 * tip]) tip = i;
    ct_step(s, 80);
    const double *x = ct_positions(s, "finger/tetras", 0, &n);
    double d2 = 0;
    for (int j = 0; j < 3; ++j) d2 += (x[3 * tip + j] - r[3 * tip + j]) * (x[3 * tip + j] - r[3 * tip + j]);
    printf("shared CableFinger_displacement.scn, 10 mm pull: tip displacement %.2f mm, cable "
           "displacement %.3f mm\n",
           sqrt(d2), ct_get(s, "finger/aCable.displacement"));
    ck_assert_double_gt(sqrt(d2), 20.0);
    ck_assert_double_lt(sqrt(d2), 28.0);
    pl_sim_free(s);
    pl_diag_free(&d);
    free(xml);
}
END_TEST

/* SOFA's liver against SOFA's own regression reference (Regression repo):
 * SOFA's WriteState records before each step, so its record T = 1.98 is the
 * state after 99 steps.  The error: the largest vertex distance over the
 * diagonal of the rest bounding box. */
START_TEST(shared_liver_against_sofa)
{
    if (!have_shared()) return;
    char meshes[2048], scene[2048], refs[2048];
    setenv("PLIANT_DATA_PATH", shared(meshes, sizeof meshes, "meshes"), 1);
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_file(shared(scene, sizeof scene, "sofa_scenes/liver.scn"), NULL, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    pl_state_records ref;
    pl_state_records_init(&ref);
    pl_error e;
    shared(refs, sizeof refs, "sofa_scenes/regression_refs/liver.scn.reference_0_dofs_mstate.txt.gz");
    ck_assert_int_eq(pl_state_file_read(refs, &ref, &e),
                     PL_OK);
    ck_assert_int_ge(ref.count, 2);
    const pl_state_record *last = &ref.items[ref.count - 1];
    ck_assert_double_eq_tol(last->time, 1.98, 1e-9);
    int n;
    const double *r = ct_positions(s, "Liver/dofs", 1, &n);
    ck_assert_int_eq(3 * n, last->nx);
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 3; ++j) lo[j] = fmin(lo[j], r[3 * i + j]), hi[j] = fmax(hi[j], r[3 * i + j]);
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    ct_step(s, 99);
    const double *x = ct_positions(s, "Liver/dofs", 0, &n);
    double err = 0, moved = 0;
    for (int i = 0; i < n; ++i) {
        double e2 = 0, m2 = 0;
        for (int j = 0; j < 3; ++j) {
            e2 += (x[3 * i + j] - last->x[3 * i + j]) * (x[3 * i + j] - last->x[3 * i + j]);
            m2 += (last->x[3 * i + j] - r[3 * i + j]) * (last->x[3 * i + j] - r[3 * i + j]);
        }
        err = fmax(err, sqrt(e2)), moved = fmax(moved, sqrt(m2));
    }
    printf("liver.scn at T = 1.98 (99 steps) against SOFA's reference: largest vertex distance "
           "%.4g = %.3e of the rest diagonal %.4g (SOFA moved it up to %.4g)\n",
           err, err / diag, diag, moved);
    fflush(stdout);
    ck_assert_double_gt(moved, 1e-2 * diag); /* the reference did move */
    /* 1.13e-6 measured (the reference has 6 digits): method="large" takes
     * SOFA's rotation from the edges (Corotational rotation="edges"); with
     * the polar rotation it was 1.44e-3.  The goal is 1e-3. */
    ck_assert_double_lt(err / diag, 1e-5);
    pl_state_records_free(&ref);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

/* Tetrahedra of m with all four vertices in the box (SOFA's strict BoxROI). */
static int tets_in_box(const pl_mesh *m, const double b[6], char *in)
{
    int count = 0;
    for (int t = 0; t < m->ntets; ++t) {
        int all = 1;
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 3; ++j) {
                double p = m->verts[3 * m->tets[4 * t + k] + j];
                all &= p >= b[j] && p <= b[j + 3];
            }
        in[t] = (char)all;
        count += all;
    }
    return count;
}

/* raptor-cpu.scn: IndexValueMapper over BoxROI tetrahedronIndices gives its
 * FEM 1e5 Pa in box0, 1e6 Pa in box1 and SOFA's defaultValue 1 elsewhere,
 * element by element as counted here from the mesh; with SOFA's penalty
 * plane (PlaneForceField d = -0.2) it runs 200 steps. */
START_TEST(shared_raptor)
{
    if (!have_shared()) return;
    char meshes[2048], scene[2048], mesh_path[2048];
    setenv("PLIANT_DATA_PATH", shared(meshes, sizeof meshes, "meshes"), 1);
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_file(shared(scene, sizeof scene, "sofa_scenes/raptor-cpu.scn"), NULL, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_str_eq(pl_sim_component(s, "M1/planeForceField")->type->name, "PlaneForceField");
    char rot[32];
    pl_error rerr;
    /* no method given: SOFA's default, large, which is the edges' rotation */
    ck_assert_int_eq(pl_sim_get(s, "M1/FEM.rotation", rot, sizeof rot, &rerr), PL_OK);
    ck_assert_str_eq(rot, "edges");
    pl_mesh m;
    pl_mesh_init(&m);
    pl_diag md;
    pl_diag_init(&md);
    ck_assert_int_eq(pl_mesh_load(shared(mesh_path, sizeof mesh_path, "meshes/raptorTetra_19409.vtu"),
                                  NULL, &m, &md),
                     PL_OK);
    pl_diag_free(&md);
    static const double box0[6] = {-2.2, -1, -10, 2.2, 10, 10}, box1[6] = {-2.2, -1, -1, 2.2, 2.5, 1.5};
    char *in0 = malloc((size_t)m.ntets), *in1 = malloc((size_t)m.ntets);
    int n0 = tets_in_box(&m, box0, in0), n1 = tets_in_box(&m, box1, in1);
    size_t cap = (size_t)m.ntets * 26 + 1;
    char *text = malloc(cap);
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "M1/FEM.youngModulus", text, cap, &err), PL_OK);
    int t = 0, wrong = 0, stiff = 0;
    for (char *p = text, *end;; p = end, ++t) {
        double v = strtod(p, &end);
        if (end == p) break;
        double want = in1[t] ? 1e6 : in0[t] ? 1e5 : 1.0;
        wrong += v != want;
        stiff += v == 1e6;
    }
    printf("raptor-cpu.scn: %d tetrahedra, %d in box0 (1e5 Pa), %d in box1 (1e6 Pa); the FEM has "
           "%d values, %d at 1e6 Pa, %d differ from SOFA's rule\n",
           m.ntets, n0, n1, t, stiff, wrong);
    ck_assert_int_eq(t, m.ntets);
    ck_assert_int_eq(wrong, 0);
    ck_assert_int_gt(n1, 0);
#ifdef __SANITIZE_ADDRESS__
    /* the sanitiser pass (Debug -O0 with ASan, 6-9 times slower: 200 steps
     * would take 10 minutes of CI) checks the memory in 20 steps; the plain
     * pass runs SOFA's 200 */
    const int steps = 20;
#else
    const int steps = 200;
#endif
    ct_step(s, steps);
    int n;
    const double *x = ct_positions(s, "M1/mechanicalObject", 0, &n);
    const double *r = ct_positions(s, "M1/mechanicalObject", 1, &n);
    double low = 1e300, moved = 0;
    for (int i = 0; i < n; ++i) {
        double d2 = 0;
        for (int j = 0; j < 3; ++j) {
            ck_assert(isfinite(x[3 * i + j]));
            d2 += (x[3 * i + j] - r[3 * i + j]) * (x[3 * i + j] - r[3 * i + j]);
        }
        low = fmin(low, x[3 * i + 1]), moved = fmax(moved, sqrt(d2));
    }
    printf("raptor-cpu.scn after %d steps: largest displacement %.4g, lowest y %.4g (plane at "
           "y = -0.2)\n", steps, moved, low);
    fflush(stdout);
    ck_assert_double_gt(moved, 1e-3);
    free(text), free(in0), free(in1);
    pl_mesh_free(&m);
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

/* The largest vertex distance of x from the record over the rest diagonal. */
static double last_over_diag(const double *x, const double *r, int n, const pl_state_record *rec)
{
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, err = 0;
    ck_assert_int_eq(3 * n, rec->nx);
    for (int i = 0; i < n; ++i) {
        double e2 = 0;
        for (int j = 0; j < 3; ++j) {
            lo[j] = fmin(lo[j], r[3 * i + j]), hi[j] = fmax(hi[j], r[3 * i + j]);
            e2 += (x[3 * i + j] - rec->x[3 * i + j]) * (x[3 * i + j] - rec->x[3 * i + j]);
        }
        err = fmax(err, sqrt(e2));
    }
    return err / sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* The beam of fallingBeamLagrangianCollision.scn (text xml) loaded and run
 * 45 steps: its largest distance from SOFA's state at T = 0.45 over the rest
 * diagonal. */
static pl_sim *beam_at_045(const char *xml, const char *scene, const pl_state_record *last,
                           double *rel, pl_diag *d)
{
    pl_diag_init(d);
    pl_sim *s = pl_sim_load_string(xml, scene, NULL, d);
    if (!s) pl_diag_print(d, stderr);
    ck_assert_ptr_nonnull(s);
    int n;
    const double *r = ct_positions(s, "FEM/mstate", 1, &n);
    ck_assert_int_eq(n, 625);
    ct_step(s, 45);
    *rel = last_over_diag(ct_positions(s, "FEM/mstate", 0, &n), r, n, last);
    return s;
}

/* fallingBeamLagrangianCollision.scn: a RegularGridTopology split by
 * Hexa2Tetra, its surface's collision models and a still floor of inline
 * triangles, under LocalGlobalSolver with SOFA's rayleighMass and
 * rayleighStiffness and friction contact.  SOFA's state at T = 0.45 (45
 * steps) is a rigid free fall (no contact detected yet).  As written the
 * scene ends 1.19e-3 of the rest diagonal from it; with
 * rayleighStiffness 0, 1.33e-3 (rayleighMass applied after the step, and
 * the floor's look-ahead contact).  After 200 steps it rests on the floor:
 * the vertices above it at contactDistance, none below. */
START_TEST(shared_falling_beam)
{
    if (!have_shared()) return;
    char meshes[2048], scene[2048], refs[2048];
    setenv("PLIANT_DATA_PATH", shared(meshes, sizeof meshes, "meshes"), 1);
    shared(scene, sizeof scene, "sofa_scenes/fallingBeamLagrangianCollision.scn");
    pl_state_records ref;
    pl_state_records_init(&ref);
    pl_error e;
    shared(refs, sizeof refs,
           "sofa_scenes/regression_refs/fallingBeamLagrangianCollision.scn.reference_0_mstate_mstate.txt.gz");
    ck_assert_int_eq(pl_state_file_read(refs, &ref, &e), PL_OK);
    const pl_state_record *last = &ref.items[ref.count - 1];
    ck_assert_double_eq_tol(last->time, 0.45, 1e-9);
    char *xml = ct_read_text(scene);
    pl_diag d;
    double rel, rel0;
    pl_sim *s = beam_at_045(xml, scene, last, &rel, &d);
    ck_assert_str_eq(pl_sim_component(s, "FEM/Container")->type->name, "RegularGridTetrahedra");
    ck_assert_str_eq(pl_sim_component(s, "Floor/FloorCM")->type->name, "MeshObstacle");
    ck_assert_double_eq(ct_get(s, "Pipeline.mu"), 0.5);
    ct_step(s, 155);
    int n;
    const double *x = ct_positions(s, "FEM/mstate", 0, &n);
    const double *r = ct_positions(s, "FEM/mstate", 1, &n);
    double low = 1e300, high = -1e300;
    for (int i = 0; i < n; ++i) {
        if (r[3 * i + 2] != 0 || r[3 * i] < 0.1 || r[3 * i] > 0.4) continue; /* above the floor */
        low = fmin(low, x[3 * i + 2]), high = fmax(high, x[3 * i + 2]);
    }
    pl_sim_free(s);
    pl_diag_free(&d);
    ct_replace(&xml, "rayleighStiffness=\"0.1\"", "rayleighStiffness=\"0\"");
    s = beam_at_045(xml, scene, last, &rel0, &d);
    printf("fallingBeamLagrangianCollision.scn at T = 0.45 (45 steps) against SOFA's reference: "
           "largest vertex distance %.3e of the rest diagonal (%.3e with rayleighStiffness 0); "
           "after 200 steps the bottom above the floor (z = -1) at z in [%.5f, %.5f]\n",
           rel, rel0, low, high);
    fflush(stdout);
    ck_assert_double_lt(rel, 2e-3);  /* 1.19e-3 measured */
    ck_assert_double_lt(rel0, 2e-3); /* 1.33e-3 measured */
    ck_assert_double_gt(low, -1.0005);
    ck_assert_double_lt(high, -0.995);
    pl_state_records_free(&ref);
    pl_sim_free(s);
    pl_diag_free(&d);
    free(xml);
}
END_TEST

int main(void)
{
    if (!have_shared()) return 77; /* ctest's SKIP_RETURN_CODE: reported as skipped */
    Suite *s = suite_create("sofa_shared");
    TCase *tc = tcase_create("shared");
    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, shared_scene, 0, (int)(sizeof CASES / sizeof CASES[0]));
    tcase_add_test(tc, shared_finger_pulled);
    tcase_add_test(tc, shared_liver_against_sofa);
    tcase_add_test(tc, shared_falling_beam);
    suite_add_tcase(s, tc);
    /* 200 steps of 19409 tetrahedra: about 0.5 s a step on 2 cores (mostly the
     * LinearizedEulerSolver's matrix assembly), minutes under load */
    TCase *raptor = tcase_create("raptor");
    tcase_set_timeout(raptor, 900);
    tcase_add_test(raptor, shared_raptor);
    suite_add_tcase(s, raptor);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
