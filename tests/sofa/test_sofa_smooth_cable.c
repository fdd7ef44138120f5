/* test_sofa_smooth_cable.c - SoftRobots' surface cable in a SOFA scene: the
 * project's own tests/sofa/scenes/bunny_smooth_cable.scn (a port of
 * CableSmoothActuation.py: a hollow bunny pulled by a CableConstraint with
 * centers, radii, method="geodesic" and surfaceTopology in a child node
 * mapped by BarycentricMapping, whose MechanicalObject takes its points from
 * the node's MeshTopology/loader) and variants of it:
 *  - it loads and runs; the cable acts in the bunny's node; the drawing node
 *    (Tetra2TriangleTopologicalMapping, OglModel, IdentityMapping) is
 *    dropped with a warning;
 *  - the cable pulls its area by the commanded displacement (1 mm) with a
 *    positive tension (minForce = 0);
 *  - method="sphere" (straight distance) loads as well; a larger radius
 *    holds the same displacement with another tension (more points pulled);
 *  - refused with the line and the component: surfaceTopology naming no
 *    loader of the node, and a center whose area holds no surface point. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define SCENE_FILE PL_SOURCE_DIR "/tests/sofa/scenes/bunny_smooth_cable.scn"
#define CABLE "bunny/cable"

/* The scene with its first `from` replaced by `to` (caller frees). */
static char *variant(const char *from, const char *to)
{
    char *text = ct_read_text(SCENE_FILE);
    if (from) ct_replace(&text, from, to);
    return text;
}

static int has(const pl_diag *d, int error, const char *what)
{
    for (int k = 0; k < d->count; ++k)
        if ((d->items[k].code != PL_OK) == error && strstr(d->items[k].msg, what)) return 1;
    return 0;
}

/* Loads the variant, runs n steps; returns the cable's tension. */
static double run(const char *from, const char *to, int n, double *disp, pl_diag *d)
{
    char *xml = variant(from, to);
    pl_diag_init(d);
    pl_sim *s = pl_sim_load_string(xml, SCENE_FILE, NULL, d);
    if (!s) pl_diag_print(d, stderr);
    ck_assert_ptr_nonnull(s);
    ct_step(s, n);
    *disp = ct_get(s, CABLE ".displacement");
    double f = ct_get(s, CABLE ".force");
    pl_sim_free(s);
    free(xml);
    return f;
}

START_TEST(the_port_runs_and_pulls_its_area)
{
    pl_diag d;
    double disp, f = run(NULL, NULL, 5, &disp, &d);
    printf("bunny smooth cable (geodesic, radius 1): displacement %.6f mm, tension %.4g after "
           "5 steps\n", disp, f);
    ck_assert(has(&d, 0, "only follows the body"));       /* the drawing node */
    ck_assert(has(&d, 0, "acts in 'root/bunny'"));        /* the mapped cable moved */
    ck_assert_double_eq_tol(disp, 1.0, 1e-3);
    ck_assert(f > 0.0);
    pl_diag_free(&d);
    double disp2, f2 = run("method=\"geodesic\"", "method=\"sphere\"", 5, &disp2, &d);
    pl_diag_free(&d); /* run() starts a new one */
    double disp3, f3 = run("radii=\"1\"", "radii=\"2\"", 5, &disp3, &d);
    printf("sphere: %.6f mm, tension %.4g; geodesic radius 2: %.6f mm, tension %.4g\n", disp2,
           f2, disp3, f3);
    ck_assert_double_eq_tol(disp2, 1.0, 1e-3);
    ck_assert_double_eq_tol(disp3, 1.0, 1e-3);
    ck_assert(f2 > 0.0 && f3 > 0.0 && fabs(f3 - f) > 1e-3 * f);
    pl_diag_free(&d);
}
END_TEST

/* Loads a variant that must be refused: the error names the cable's line. */
static void refused(const char *from, const char *to, const char *what)
{
    char *xml = variant(from, to);
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_string(xml, SCENE_FILE, NULL, &d);
    if (s) pl_sim_free(s);
    ck_assert_ptr_null(s);
    int found = 0;
    for (int k = 0; k < d.count; ++k)
        if (d.items[k].code != PL_OK && strstr(d.items[k].msg, what)) {
            ck_assert(d.items[k].line >= 33 && d.items[k].line <= 35); /* the tag */
            found = 1;
        }
    if (!found) pl_diag_print(&d, stderr);
    ck_assert(found);
    pl_diag_free(&d);
    free(xml);
}

START_TEST(bad_surface_and_empty_area_refused)
{
    refused("surfaceTopology=\"@topoSurfaceCable\"", "surfaceTopology=\"@../container\"",
            "surfaceTopology");
    refused("centers=\"-4.5 -2.54 0\"", "centers=\"-40 -2.54 0\"", "no point of the surface");
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_smooth_cable");
    TCase *tc = tcase_create("smooth_cable");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, the_port_runs_and_pulls_its_area);
    tcase_add_test(tc, bad_surface_and_empty_area_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
