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
    {"fallingBeamLagrangianCollision.scn", "RegularGridTopology"},
    {"liver.scn", NULL},
    {"raptor-cpu.scn", "IndexValueMapper"},
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

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    ck_assert_ptr_nonnull(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)n + 1);
    ck_assert_uint_eq(fread(b, 1, (size_t)n, f), (size_t)n);
    b[n] = '\0';
    fclose(f);
    return b;
}

/* Replaces the first `from` in *text by `to`. */
static void replace(char **text, const char *from, const char *to)
{
    char *p = strstr(*text, from);
    ck_assert_ptr_nonnull(p);
    size_t n = strlen(*text) - strlen(from) + strlen(to) + 1;
    char *r = malloc(n);
    snprintf(r, n, "%.*s%s%s", (int)(p - *text), *text, to, p + strlen(from));
    free(*text);
    *text = r;
}

START_TEST(shared_finger_pulled)
{
    if (!have_shared()) return;
    char meshes[2048], scene[2048];
    setenv("PLIANT_DATA_PATH", shared(meshes, sizeof meshes, "meshes"), 1);
    shared(scene, sizeof scene, "sofa_scenes/CableFinger_displacement.scn");
    char *xml = read_text(scene);
    replace(&xml, "2.5\" value=\"0\"", "2.5\" value=\"10\""); /* the cable, not the comment */
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

int main(void)
{
    if (!have_shared()) return 77; /* ctest's SKIP_RETURN_CODE: reported as skipped */
    Suite *s = suite_create("sofa_shared");
    TCase *tc = tcase_create("shared");
    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, shared_scene, 0, (int)(sizeof CASES / sizeof CASES[0]));
    tcase_add_test(tc, shared_finger_pulled);
    tcase_add_test(tc, shared_liver_against_sofa);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
