/* test_sofa_pressure.c - SoftRobots' pneumatic cavity in a SOFA scene: the
 * project's own tests/sofa/scenes/bunny_cavity.scn (a hollow bunny, its
 * cavity surface in a child node mapped by BarycentricMapping, written as
 * SoftRobots' scripts write it) and variants of it:
 *  - triangles="@topo.triangles" (a MeshTopology filled by the node's
 *    loader) are the loader's triangles: the initial cavity volume is the
 *    volume the OBJ file encloses, computed here from the file, and the same
 *    as without the link;
 *  - pressure mode: the pressure is the value and the cavity grows;
 *  - volumeGrowth mode, written as SOFA's option index (valueType="1"): the
 *    cavity grows by the commanded value (1%) under an inflating pressure;
 *  - the drawing node (Tetra2TriangleTopologicalMapping, OglModel,
 *    IdentityMapping) is dropped with a warning;
 *  - refused with the line and the component: a topological mapping in the
 *    cavity's node (SoftRobots would inflate the mapping's surface), and
 *    triangles linked from a topology the loader does not fill. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define SCENE_FILE PL_SOURCE_DIR "/tests/sofa/scenes/bunny_cavity.scn"
#define CAVITY_OBJ PL_SOURCE_DIR "/scenes/meshes/Hollow_Bunny_Body_Cavity.obj"
#define SP "bunny/pressure"

/* The scene with its first `from` replaced by `to` (caller frees). */
static char *variant(const char *from, const char *to)
{
    char *text = ct_read_text(SCENE_FILE);
    if (from) ct_replace(&text, from, to);
    return text;
}

/* Loads text as the scene file (its relative mesh paths resolve); NULL and
 * the diagnostics in *d when refused. */
static pl_sim *load(const char *xml, pl_diag *d)
{
    pl_diag_init(d);
    return pl_sim_load_string(xml, SCENE_FILE, NULL, d);
}

static pl_sim *load_ok(const char *xml)
{
    pl_diag d;
    pl_sim *s = load(xml, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    pl_diag_free(&d);
    return s;
}

/* A warning (code PL_OK) whose message contains `what`. */
static int has_warning(const pl_diag *d, const char *what)
{
    for (int k = 0; k < d->count; ++k)
        if (d->items[k].code == PL_OK && strstr(d->items[k].msg, what)) return 1;
    return 0;
}

/* The volume the OBJ's triangles enclose (divergence theorem). */
static double obj_volume(const char *path)
{
    FILE *f = fopen(path, "r");
    ck_assert_ptr_nonnull(f);
    double (*v)[3] = malloc(4096 * sizeof *v), vol = 0;
    int nv = 0, a, b, c;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            ck_assert_int_lt(nv, 4096);
            ck_assert_int_eq(sscanf(line + 2, "%lf %lf %lf", &v[nv][0], &v[nv][1], &v[nv][2]), 3);
            ++nv;
        } else if (line[0] == 'f' && line[1] == ' ') {
            ck_assert_int_eq(sscanf(line + 2, "%d%*[^ ] %d%*[^ ] %d", &a, &b, &c), 3);
            const double *p = v[a - 1], *q = v[b - 1], *r = v[c - 1];
            vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                    p[2] * (q[0] * r[1] - q[1] * r[0])) / 6;
        }
    }
    fclose(f);
    free(v);
    return fabs(vol);
}

START_TEST(linked_triangles_are_the_loaders)
{
    double V = obj_volume(CAVITY_OBJ);
    char *xml = variant(NULL, NULL), *plain = variant(" triangles=\"@topo.triangles\"", "");
    pl_sim *s = load_ok(xml), *t = load_ok(plain);
    double v1 = ct_get(s, SP ".initialCavityVolume"), v2 = ct_get(t, SP ".initialCavityVolume");
    printf("bunny cavity: %.10g (OBJ file %.10g, without the link %.10g)\n", v1, V, v2);
    ck_assert_double_gt(V, 50); /* 60.8 mm^3 */
    ck_assert_double_eq_tol(v1, V, 1e-9 * V);
    ck_assert_double_eq_tol(v2, v1, 1e-12 * V);
    pl_sim_free(s);
    pl_sim_free(t);
    free(xml);
    free(plain);
}
END_TEST

START_TEST(pressure_mode_inflates)
{
    char *xml = variant(NULL, NULL);
    pl_diag d;
    pl_sim *s = load(xml, &d);
    if (!s) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert(has_warning(&d, "'root/bunny/visu' only follows the body"));
    pl_diag_free(&d);
    ct_step(s, 5);
    double p = ct_get(s, SP ".pressure"), g = ct_get(s, SP ".volumeGrowth");
    double V = ct_get(s, SP ".cavityVolume"), V0 = ct_get(s, SP ".initialCavityVolume");
    printf("bunny at pressure 20 after 5 steps: cavity %.6g (growth %.4g)\n", V, g);
    ck_assert_double_eq_tol(p, 20, 1e-9);
    ck_assert_double_gt(g, 1e-3 * V0);
    ck_assert_double_eq_tol(V - V0, g, 1e-9 * V0);
    pl_sim_free(s);
    free(xml);
}
END_TEST

START_TEST(volume_mode_reaches_the_growth)
{
    char *xml = variant("value=\"20\" valueType=\"pressure\"", "value=\"10\" valueType=\"1\"");
    pl_sim *s = load_ok(xml);
    ct_step(s, 10);
    double p = ct_get(s, SP ".pressure"), g = ct_get(s, SP ".volumeGrowth");
    printf("bunny, volume growth 10 commanded: %.6g reached after 10 steps, pressure %.6g\n", g, p);
    ck_assert_double_eq_tol(g, 10, 0.1);
    ck_assert_double_gt(p, 0);
    pl_sim_free(s);
    free(xml);
}
END_TEST

/* The scene with `from` replaced by `to` is refused at the line of `at`
 * with an error containing `what` and naming `who`. */
static void refused(const char *from, const char *to, const char *at, const char *what,
                    const char *who)
{
    char *text = ct_read_text(SCENE_FILE);
    int line = 1;
    ck_assert_ptr_nonnull(strstr(text, at));
    for (const char *p = text; p < strstr(text, at); ++p) line += *p == '\n';
    free(text);
    char *xml = variant(from, to);
    pl_diag d;
    pl_sim *s = load(xml, &d);
    const pl_error *e = ct_find_error(&d, what);
    if (s || !e) pl_diag_print(&d, stderr);
    ck_assert_ptr_null(s);
    ck_assert_ptr_nonnull(e);
    ck_assert_int_eq(e->line, line);
    ck_assert(strstr(e->msg, who) || strstr(e->where, who));
    pl_diag_free(&d);
    free(xml);
}

START_TEST(cavity_from_a_mapping_refused)
{
    refused("<MechanicalObject name=\"cavity\"/>",
            "<Tetra2TriangleTopologicalMapping name=\"t2t\" input=\"@../container\" "
            "output=\"@topo\"/><MechanicalObject name=\"cavity\"/>",
            "<MechanicalObject name=\"cavity\"/>", "not from a topological mapping",
            "Tetra2TriangleTopologicalMapping");
    refused("<MeshTopology name=\"topo\" src=\"@loader\"/>",
            "<MeshTopology name=\"topo\" triangles=\"0 1 2\"/>", "<SurfacePressureConstraint",
            "triangles of points that the node's loader gives", "pressure");
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_pressure");
    TCase *tc = tcase_create("pressure");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, linked_triangles_are_the_loaders);
    tcase_add_test(tc, pressure_mode_inflates);
    tcase_add_test(tc, volume_mode_reaches_the_growth);
    tcase_add_test(tc, cavity_from_a_mapping_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
