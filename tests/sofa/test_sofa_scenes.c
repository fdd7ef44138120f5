/* test_sofa_scenes.c - the project's own SOFA-style scene files
 * (tests/sofa/scenes/, written for Pliant; SOFA's and SoftRobots' scenes
 * are not part of the project), so that the SOFA path is tested without them:
 *  - liver_falling.scn: a liver falling freely under SOFA's implicit Euler
 *    (no damping, nothing holding it): a uniform translation has no elastic
 *    force and K v = 0, so every vertex moves by g h^2 n (n + 1) / 2 after n
 *    steps (v_k = k g h, x_n = x_0 + h sum v_k), to the CG's precision;
 *  - liver_hanging.scn: a damped liver hanging from three vertices: those
 *    stay exactly where they are, the rest sags, every value finite; its
 *    method="large" FEM takes SOFA's rotation from the edges;
 *  - broken scenes: each refused with its file, its line and the component,
 *    what it changes and what to use instead; a drawing component is one
 *    warning, not an error; an unknown Pliant type names the plugin that
 *    provides it. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cable/cable_test_util.h"

#define SCENES PL_SOURCE_DIR "/tests/sofa/scenes/"

static pl_sim *load(const char *file, pl_diag *d)
{
    pl_diag_init(d);
    pl_sim *s = pl_sim_load_file(file, NULL, d);
    if (!s) pl_diag_print(d, stderr);
    ck_assert_ptr_nonnull(s);
    return s;
}

START_TEST(falling_liver_moves_as_free_fall)
{
    pl_diag d;
    pl_sim *s = load(SCENES "liver_falling.scn", &d);
    /* the SOFA names became SOFA's integrator and Pliant's corotational FEM */
    ck_assert_str_eq(pl_sim_component(s, "odesolver")->type->name, "LinearizedEulerSolver");
    ck_assert_str_eq(pl_sim_component(s, "Liver/FEM")->type->name, "Corotational");
    enum { N = 10 };
    const double h = 0.02, g = -9.81, fall = g * h * h * N * (N + 1) / 2.0;
    int n;
    ct_step(s, N);
    const double *x = ct_positions(s, "Liver/dofs", 0, &n);
    const double *r = ct_positions(s, "Liver/dofs", 1, &n);
    ck_assert_int_eq(n, 181);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
        worst = fmax(worst, fabs(x[3 * i + 1] - r[3 * i + 1] - fall));
        worst = fmax(worst, fabs(x[3 * i] - r[3 * i]) + fabs(x[3 * i + 2] - r[3 * i + 2]));
    }
    printf("liver_falling.scn: %d steps fell %.6f (g h^2 n (n+1)/2 = %.6f), largest vertex "
           "deviation %.2e\n", N, x[1] - r[1], fall, worst);
    ck_assert_double_lt(worst, 1e-9 * fabs(fall));
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

START_TEST(hanging_liver_keeps_its_fixed_vertices)
{
    pl_diag d;
    pl_sim *s = load(SCENES "liver_hanging.scn", &d);
    ck_assert_double_eq(ct_get(s, "odesolver.rayleighMass"), 0.1);
    ck_assert_double_eq(ct_get(s, "odesolver.rayleighStiffness"), 0.1);
    /* method="large" under SOFA's integrator: the rotation from the element's edges, as SOFA's */
    char rot[64];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "Liver/FEM.rotation", rot, sizeof rot, &err), PL_OK);
    ck_assert_str_eq(rot, "edges");
    ct_step(s, 20);
    int n;
    const double *x = ct_positions(s, "Liver/dofs", 0, &n);
    const double *r = ct_positions(s, "Liver/dofs", 1, &n);
    static const int fixed[] = {3, 39, 64};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) ck_assert_double_eq(x[3 * fixed[k] + j], r[3 * fixed[k] + j]);
    double sag = 0;
    for (int i = 0; i < 3 * n; ++i) ck_assert(isfinite(x[i]));
    for (int i = 0; i < n; ++i) sag = fmin(sag, x[3 * i + 1] - r[3 * i + 1]);
    ck_assert_double_lt(sag, -1e-2); /* it hangs: the free part went down */
    pl_sim_free(s);
    pl_diag_free(&d);
}
END_TEST

typedef struct {
    const char *file;
    int line;
    const char *where; /* the component named */
    const char *what;  /* the message contains it */
} broken_case;

static const broken_case BROKEN[] = {
    {"broken_rigid_state.scn", 9, "rigid", "\"Rigid3\""},
    {"broken_physics.scn", 16, "PlaneForceField", "closest: PlaneObstacle"},
    {"broken_plugin_type.scn", 13, "PositionEffector", "SoftRobots.Inverse"},
};

START_TEST(broken_scene_is_refused_with_file_line_component)
{
    const broken_case *c = &BROKEN[_i];
    char path[512];
    snprintf(path, sizeof path, SCENES "%s", c->file);
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = pl_sim_load_file(path, NULL, &d);
    const pl_error *e = ct_find_error(&d, c->what);
    if (s || !e) pl_diag_print(&d, stderr);
    ck_assert_ptr_null(s);
    ck_assert_ptr_nonnull(e);
    ck_assert_ptr_nonnull(strstr(e->file, c->file));
    ck_assert_int_eq(e->line, c->line);
    char text[1024];
    pl_error_format(e, text, sizeof text);
    ck_assert_msg(strstr(text, c->where), "'%s' does not name %s", text, c->where);
    /* a drawing component is a warning, once, not an error */
    int visual_warnings = 0;
    for (int k = 0; k < d.count; ++k) {
        const pl_error *w = &d.items[k];
        if (strstr(w->msg, "VisualStyle") || strstr(w->where, "VisualStyle")) {
            ck_assert_int_eq(w->code, PL_OK);
            ++visual_warnings;
        }
    }
    ck_assert_int_le(visual_warnings, 1);
    pl_diag_free(&d);
}
END_TEST

/* A Pliant scene using a plugin's type without requiring the plugin: the
 * error names the plugin to require. */
START_TEST(unknown_type_names_its_plugin)
{
    pl_diag d = ct_load_fail("<Node name=\"root\" dt=\"0.01\">\n"
                             "<Node name=\"b\">\n"
                             "<NeoHookean name=\"law\" youngModulus=\"1e4\"/>\n"
                             "</Node></Node>\n");
    const pl_error *e = ct_find_error(&d, "<RequiredPlugin name=\"hyperelastic\"/>");
    if (!e) pl_diag_print(&d, stderr);
    ck_assert_ptr_nonnull(e);
    ck_assert_int_eq(e->line, 3);
    pl_diag_free(&d);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sofa_scenes");
    TCase *tc = tcase_create("scenes");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, falling_liver_moves_as_free_fall);
    tcase_add_test(tc, hanging_liver_keeps_its_fixed_vertices);
    tcase_add_loop_test(tc, broken_scene_is_refused_with_file_line_component, 0,
                        (int)(sizeof BROKEN / sizeof BROKEN[0]));
    tcase_add_test(tc, unknown_type_names_its_plugin);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
