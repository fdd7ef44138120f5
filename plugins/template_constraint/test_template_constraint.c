/* test_template_constraint.c - the template plugin end to end, on
 * scenes/template_constraint.xml (a cube hanging from its top face, which
 * slides on the plane y = 0):
 *  - the plugin is the one just built (loaded from TEMPLATE_PLUGIN_DIR);
 *  - the top face stays on the plane at every step (|y| < 1e-8 m);
 *  - nothing acts along x: the mean x velocity (uniform masses) stays the
 *    initial 0.1 m/s to round-off, so the cube slides freely;
 *  - once settled (with damping) the plane carries the weight: the sum of
 *    the multipliers is m g within 1e-3. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/pliant.h"

static pl_registry *reg;

/* The scene with the plugin searched first in the folder it was built in. */
static pl_sim *load(const char *override)
{
    reg = pl_registry_create();
    ck_assert_ptr_nonnull(reg);
    pl_error err;
    ck_assert_int_eq(pl_register_builtin_components(reg, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add_plugin_dir(reg, TEMPLATE_PLUGIN_DIR), PL_OK);
    pl_sim_options opt = {0};
    opt.registry = reg;
    opt.overrides = &override;
    opt.noverrides = override ? 1 : 0;
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_file(TEMPLATE_SCENE, &opt, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    return s;
}

static void unload(pl_sim *s)
{
    pl_sim_free(s);
    pl_registry_free(reg);
}

static void step(pl_sim *s)
{
    pl_error err;
    int rc = pl_sim_step(s, 1, &err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
}

START_TEST(loads_the_plugin_just_built)
{
    pl_sim *s = load(NULL);
    int found = 0;
    for (int i = 0; i < pl_registry_plugin_count(reg); ++i)
        if (!strcmp(pl_registry_plugin_name(reg, i), "template_constraint")) {
            found = 1;
            const char *path = pl_registry_plugin_path(reg, i);
            ck_assert_msg(!strncmp(path, TEMPLATE_PLUGIN_DIR, strlen(TEMPLATE_PLUGIN_DIR)),
                          "loaded %s, expected it from %s", path, TEMPLATE_PLUGIN_DIR);
        }
    ck_assert_int_eq(found, 1);
    unload(s);
}
END_TEST

START_TEST(slides_on_the_plane)
{
    pl_sim *s = load(NULL);
    pl_component *dofs = pl_sim_component(s, "dofs");
    const pl_state_ops *ops = pl_component_role(dofs, PL_ROLE_STATE);
    pl_buffer rb = ops->rest_positions(dofs);
    const double *x0 = pl_buffer_f64(&rb);
    int n = (int)rb.rows, ntop = 0;
    for (int k = 0; k < 100; ++k) {
        step(s);
        pl_buffer xb = ops->positions(dofs, pl_sim_data(s));
        pl_buffer vb = ops->velocities(dofs, pl_sim_data(s));
        const double *x = pl_buffer_f64(&xb), *v = pl_buffer_f64(&vb);
        double vx = 0;
        ntop = 0;
        for (int i = 0; i < n; ++i) {
            vx += v[3 * i] / n;
            if (fabs(x0[3 * i + 1]) < 1e-12) {
                ck_assert_double_lt(fabs(x[3 * i + 1]), 1e-8);
                ntop++;
            }
        }
        ck_assert_double_eq_tol(vx, 0.1, 1e-10);
    }
    ck_assert_int_eq(ntop, 16); /* the 4 x 4 top face */
    unload(s);
}
END_TEST

START_TEST(plane_carries_the_weight)
{
    pl_sim *s = load("solver.damping=20");
    for (int k = 0; k < 200; ++k) step(s);
    char buf[64];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "slider.force", buf, sizeof buf, &err), PL_OK);
    double W = 0.125 * 9.81;
    ck_assert_double_lt(fabs(strtod(buf, NULL) - W), 1e-3 * W);
    unload(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("template_constraint");
    TCase *tc = tcase_create("scene");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, loads_the_plugin_just_built);
    tcase_add_test(tc, slides_on_the_plane);
    tcase_add_test(tc, plane_carries_the_weight);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
