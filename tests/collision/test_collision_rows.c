/* test_collision_rows.c - the rows obstacles emit, called through their
 * constraint role on small scenes (a 5 x 3 x 3 grid body, numbered by a
 * NewtonSolver) with a hand-made pl_system:
 *  - a tilted plane: one contact per boundary vertex within alarmDistance
 *    (the interior vertex that is also within it is left out by
 *    SurfaceCollisionModel, kept by PointCollisionModel); kinds N, F, F;
 *    entries w n, w t1, w t2 on the right vertex; d = n . p + contactDistance
 *    so that H q - d = phi - contactDistance; tangents orthonormal and
 *    right-handed; pairs; mu;
 *  - a moving plane posed at t + h, its surface velocity in the friction d;
 *  - sphere, box, capsule and a spinning cylinder against the shape core;
 *  - prescribed vertices get no contact, groups opt out, a model's own mu
 *    wins, a cloth's every vertex collides;
 *  - multipliers handed back become the exported forces
 *    lambda_n n + lambda_t1 t1 + lambda_t2 t2, per obstacle;
 *  - a model whose box stays clear of a shape is skipped whole, and one
 *    whose nearest corner comes within alarm is not: an oblique plane 0.9
 *    alarm from the body's corner gives that corner's contact, at 1.1
 *    alarm none; a sphere likewise. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"
#include "coll_test_util.h"
#include "collision.h"

static const double H = 0.01;

static char *scene(const char *obstacles, const char *model)
{
    static const char *FMT =
        "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
        "<RequiredPlugin name=\"collision\"/>\n"
        "<NewtonSolver/>\n"
        "%s\n"
        "<Node name=\"body\">\n"
        "<RegularGridTetrahedra name=\"grid\" min=\"0 0.01 0\" max=\"0.2 0.1 0.1\" n=\"5 3 3\"/>\n"
        "<MechanicalObject name=\"dofs\"/>\n"
        "<DiagonalMass massDensity=\"1000\"/>\n"
        "%s\n"
        "</Node></Node>\n";
    size_t len = strlen(FMT) + strlen(obstacles) + strlen(model) + 1;
    char *s = malloc(len);
    ck_assert_ptr_nonnull(s);
    snprintf(s, len, FMT, obstacles, model);
    return s;
}

static pl_sim *load_scene(const char *obstacles, const char *model)
{
    char *xml = scene(obstacles, model);
    pl_sim *s = ct_load(xml, NULL, 0);
    free(xml);
    return s;
}

/* grid vertices strictly inside the box min (0, 0.01, 0), max (0.2, 0.1, 0.1) */
static int interior(const double *x)
{
    return x[0] > 1e-9 && x[0] < 0.2 - 1e-9 && x[1] > 0.01 + 1e-9 && x[1] < 0.1 - 1e-9 &&
           x[2] > 1e-9 && x[2] < 0.1 - 1e-9;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* One contact's three rows starting at rn. */
static void check_triple(const pl_rows *r, int rn, int vertex, const double n[3], double dn,
                         const double vs[3], double mu)
{
    ck_assert_int_eq(r->kind[rn], PL_ROW_NORMAL);
    ck_assert_int_eq(r->kind[rn + 1], PL_ROW_FRICTION);
    ck_assert_int_eq(r->kind[rn + 2], PL_ROW_FRICTION);
    const double *c[3];
    for (int k = 0; k < 3; ++k) {
        ck_assert_int_eq(r->start[rn + k + 1] - r->start[rn + k], 1);
        ck_assert_int_eq(r->vertex[r->start[rn + k]], vertex);
        c[k] = &r->coef[3 * r->start[rn + k]];
        ck_assert_ptr_eq(r->owner[rn + k], r->owner[rn]);
    }
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(c[0][i], n[i], 1e-12);
    ck_assert_double_eq_tol(dot3(c[1], c[1]), 1.0, 1e-13);
    ck_assert_double_eq_tol(dot3(c[2], c[2]), 1.0, 1e-13);
    ck_assert_double_eq_tol(dot3(c[1], c[2]), 0.0, 1e-13);
    ck_assert_double_eq_tol(dot3(c[0], c[1]), 0.0, 1e-13);
    ck_assert_double_eq_tol(dot3(c[0], c[2]), 0.0, 1e-13);
    double cross[3] = {c[1][1] * c[2][2] - c[1][2] * c[2][1], c[1][2] * c[2][0] - c[1][0] * c[2][2],
                       c[1][0] * c[2][1] - c[1][1] * c[2][0]};
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(cross[i], n[i], 1e-12);
    ck_assert_double_eq_tol(r->d[rn], dn, 1e-13);
    ck_assert_double_eq_tol(r->d[rn + 1], dot3(c[1], vs), 1e-12);
    ck_assert_double_eq_tol(r->d[rn + 2], dot3(c[2], vs), 1e-12);
    ck_assert_int_eq(r->pair[rn], rn + 1);
    ck_assert_int_eq(r->pair[rn + 1], rn);
    ck_assert_int_eq(r->pair[rn + 2], rn);
    ck_assert_double_eq(r->mu[rn], mu);
    ck_assert_double_eq(r->compliance[rn], 0.0);
}

/* Rows of obstacle `path` against the expectation of shape s (posed at
 * t + h by motion m, NULL = static): every boundary (or every, when
 * all_points) vertex with phi < alarm, in vertex order. */
static int check_obstacle(pl_sim *sim, const char *path, const pl_shape *s0, const pl_motion *m,
                          double alarm, double cd, double mu, int all_points)
{
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, H, NULL);
    pl_rows rows;
    pl_rows_init(&rows);
    pl_error err;
    ck_assert_int_eq(ct_build_rows(sim, path, &sys.sys, q, n, &rows, &err), PL_OK);
    double t1 = pl_sim_data(sim)->time + H, R[9], tr[3];
    pl_shape s = *s0;
    if (m) {
        motion_pose(m, t1, R, tr);
        shape_transform(s0, R, tr, &s);
    }
    int k = 0;
    for (int v = 0; v < n; ++v) {
        const double *x = &q[3 * v];
        double p[3], nn[3], vs[3] = {0, 0, 0};
        double phi = shape_query(&s, x, p, nn);
        if ((!all_points && interior(x)) || !(phi < alarm)) continue;
        ck_assert_int_lt(3 * k + 2, rows.n);
        if (m) motion_velocity(m, t1, p, vs);
        check_triple(&rows, 3 * k, v, nn, dot3(nn, p) + cd, vs, mu);
        /* delta = H q - d: the signed gap beyond contactDistance */
        ck_assert_double_eq_tol(pl_rows_dot(&rows, 3 * k, q) - rows.d[3 * k], phi - cd, 1e-13);
        k++;
    }
    ck_assert_int_eq(rows.n, 3 * k);
    pl_rows_free(&rows);
    ct_system_free(&sys);
    return k;
}

static const char *TILTED =
    "<PlaneObstacle name=\"floor\" normal=\"0 2 0\" rotation=\"0 0 10\" mu=\"0.3\" "
    "alarmDistance=\"0.03\" contactDistance=\"0.005\"/>";

static void tilted_plane(pl_shape *s)
{
    double deg = 10.0 * M_PI / 180.0, n[3] = {-sin(deg), cos(deg), 0}, o[3] = {0, 0, 0};
    pl_error err;
    ck_assert_int_eq(shape_plane(s, o, n, &err), PL_OK);
}

START_TEST(test_tilted_plane_rows)
{
    pl_shape s;
    tilted_plane(&s);
    pl_sim *sim = load_scene(TILTED, "<SurfaceCollisionModel name=\"surface\"/>");
    int ks = check_obstacle(sim, "floor", &s, NULL, 0.03, 0.005, 0.3, 0);
    pl_sim_free(sim);
    sim = load_scene(TILTED, "<PointCollisionModel name=\"points\"/>");
    int kp = check_obstacle(sim, "floor", &s, NULL, 0.03, 0.005, 0.3, 1);
    pl_sim_free(sim);
    /* only points within 3 cm: the two lower layers near x = 0.2 and the
     * bottom layer; one interior vertex (0.15, 0.055, 0.05) is within it */
    ck_assert_int_gt(ks, 0);
    ck_assert_int_lt(ks, 45);
    ck_assert_int_eq(kp, ks + 1);
}
END_TEST

START_TEST(test_moving_plane_posed_at_end_of_step)
{
    /* the floor rises at 0.1 m/s and slides along x at 0.5 m/s (a belt);
     * at t = 0.2 the step ends at 0.21: the floor is then at y = 0.021 */
    pl_sim *sim = load_scene("<PlaneObstacle name=\"floor\" velocity=\"0.5 0.1 0\" mu=\"0.4\" "
                             "alarmDistance=\"0.03\" contactDistance=\"0.002\"/>",
                             "<SurfaceCollisionModel/>");
    pl_sim_data(sim)->time = 0.2;
    pl_shape s0;
    pl_error err;
    const double o[3] = {0, 0, 0}, ny[3] = {0, 1, 0};
    ck_assert_int_eq(shape_plane(&s0, o, ny, &err), PL_OK);
    pl_motion m;
    memset(&m, 0, sizeof m);
    m.velocity[0] = 0.5, m.velocity[1] = 0.1;
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_OK);
    /* the bottom layer (y = 0.01, 15 vertices) is 1.1 cm inside the risen floor */
    ck_assert_int_eq(check_obstacle(sim, "floor", &s0, &m, 0.03, 0.002, 0.4, 0), 15);
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, H, NULL);
    pl_rows rows;
    pl_rows_init(&rows);
    ck_assert_int_eq(ct_build_rows(sim, "floor", &sys.sys, q, n, &rows, &err), PL_OK);
    ck_assert_double_eq_tol(rows.d[0], 0.021 + 0.002, 1e-15);
    ck_assert_double_eq_tol(pl_rows_dot(&rows, 0, q) - rows.d[0], 0.01 - 0.023, 1e-15);
    /* the belt speed enters d of the friction rows: |d_f| over both = 0.5 */
    double df = hypot(rows.d[1], rows.d[2]);
    ck_assert_double_eq_tol(df, 0.5, 1e-15);
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
}
END_TEST

/* An oblique plane (normal (1 1 1)) at distance f alarm from the body's
 * corner (0, 0.01, 0), and a sphere at that distance from the corner
 * opposite it (0.2, 0.1, 0.1) along the diagonal: the contacts
 * check_obstacle expects (the corner's, or none). */
static void near_corner(double f, int expect)
{
    const double alarm = 0.01, d = f * alarm, r3 = sqrt(3.0);
    const double n[3] = {1 / r3, 1 / r3, 1 / r3}, c0[3] = {0, 0.01, 0}, c1[3] = {0.2, 0.1, 0.1};
    double p0[3], cs[3];
    for (int k = 0; k < 3; ++k) p0[k] = c0[k] - d * n[k], cs[k] = c1[k] + (d + 0.05) * n[k];
    char obstacles[512];
    snprintf(obstacles, sizeof obstacles,
             "<PlaneObstacle name=\"slab\" point=\"%.17g %.17g %.17g\" normal=\"1 1 1\" "
             "alarmDistance=\"%g\" contactDistance=\"0.001\"/>\n"
             "<SphereObstacle name=\"ball\" center=\"%.17g %.17g %.17g\" radius=\"0.05\" "
             "alarmDistance=\"%g\" contactDistance=\"0.001\"/>",
             p0[0], p0[1], p0[2], alarm, cs[0], cs[1], cs[2], alarm);
    pl_sim *sim = load_scene(obstacles, "<SurfaceCollisionModel/>");
    pl_shape s;
    pl_error err;
    ck_assert_int_eq(shape_plane(&s, p0, n, &err), PL_OK);
    ck_assert_int_eq(check_obstacle(sim, "slab", &s, NULL, alarm, 0.001, 0.0, 0), expect);
    ck_assert_int_eq(shape_sphere(&s, cs, 0.05, &err), PL_OK);
    ck_assert_int_eq(check_obstacle(sim, "ball", &s, NULL, alarm, 0.001, 0.0, 0), expect);
    pl_sim_free(sim);
}

START_TEST(test_clear_models_skipped_near_ones_kept)
{
    near_corner(0.9, 1);
    near_corner(1.1, 0);
}
END_TEST

START_TEST(test_every_shape_rows)
{
    const char *obstacles =
        "<SphereObstacle name=\"ball\" center=\"0.1 -0.05 0.05\" radius=\"0.07\" mu=\"0.2\" "
        "alarmDistance=\"0.02\" contactDistance=\"0.001\"/>\n"
        "<BoxObstacle name=\"block\" center=\"0.05 -0.02 0.05\" halfExtents=\"0.06 0.03 0.2\" "
        "rotation=\"0 0 5\" mu=\"0.1\" alarmDistance=\"0.01\"/>\n"
        "<CapsuleObstacle name=\"rod\" start=\"-0.1 0 0.05\" end=\"0.3 0 0.05\" radius=\"0.008\" "
        "alarmDistance=\"0.01\" contactDistance=\"0.0005\"/>\n"
        "<CylinderObstacle name=\"roller\" center=\"0.1 -0.02 0\" axis=\"0 0 1\" radius=\"0.025\" "
        "length=\"0.3\" rotationAxis=\"0 0 1\" angularVelocity=\"10\" mu=\"0.6\" "
        "alarmDistance=\"0.01\"/>";
    pl_sim *sim = load_scene(obstacles, "<SurfaceCollisionModel/>");
    pl_shape s;
    pl_error err;
    const double cs[3] = {0.1, -0.05, 0.05};
    ck_assert_int_eq(shape_sphere(&s, cs, 0.07, &err), PL_OK);
    ck_assert_int_gt(check_obstacle(sim, "ball", &s, NULL, 0.02, 0.001, 0.2, 0), 0);
    const double cb[3] = {0.05, -0.02, 0.05}, hb[3] = {0.06, 0.03, 0.2}, deg[3] = {0, 0, 5};
    double R[9];
    pl_util_rotation_deg(deg, R);
    ck_assert_int_eq(shape_box(&s, cb, hb, R, &err), PL_OK);
    ck_assert_int_gt(check_obstacle(sim, "block", &s, NULL, 0.01, 0.0, 0.1, 0), 0);
    const double a[3] = {-0.1, 0, 0.05}, b[3] = {0.3, 0, 0.05};
    ck_assert_int_eq(shape_capsule(&s, a, b, 0.008, &err), PL_OK);
    /* the 5 bottom vertices along z = 0.05 are 2 mm above the rod */
    ck_assert_int_eq(check_obstacle(sim, "rod", &s, NULL, 0.01, 0.0005, 0.0, 0), 5);
    const double cc[3] = {0.1, -0.02, 0}, az[3] = {0, 0, 1};
    ck_assert_int_eq(shape_cylinder(&s, cc, az, 0.025, 0.3, &err), PL_OK);
    pl_motion m;
    memset(&m, 0, sizeof m);
    memcpy(m.axis, az, sizeof m.axis);
    m.angular_velocity = 10;
    memcpy(m.center, cc, sizeof m.center); /* default rotationCenter: the centre */
    ck_assert_int_eq(motion_prepare(&m, 0, &err), PL_OK);
    /* the bottom row x = 0.1 touches the roller's top; friction d = t . (w x r) */
    ck_assert_int_gt(check_obstacle(sim, "roller", &s, &m, 0.01, 0.0, 0.6, 0), 0);
    pl_sim_free(sim);
}
END_TEST

static int count_rows(pl_sim *sim, const char *path, const int *prescribed)
{
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, H, prescribed);
    pl_rows rows;
    pl_rows_init(&rows);
    pl_error err;
    ck_assert_int_eq(ct_build_rows(sim, path, &sys.sys, q, n, &rows, &err), PL_OK);
    int count = rows.n;
    for (int r = 0; r < rows.n; ++r) {
        if (prescribed) ck_assert_int_eq(prescribed[rows.vertex[rows.start[r]]], 0);
        if (rows.kind[r] == PL_ROW_NORMAL) ck_assert_double_eq(rows.mu[r], 0.7);
    }
    pl_rows_free(&rows);
    ct_system_free(&sys);
    return count;
}

START_TEST(test_prescribed_groups_and_model_mu)
{
    const char *two = "<PlaneObstacle name=\"floor\" mu=\"0.3\" alarmDistance=\"0.02\"/>\n"
                      "<PlaneObstacle name=\"grouped\" group=\"3 4\" alarmDistance=\"0.02\"/>";
    pl_sim *sim = load_scene(two, "<SurfaceCollisionModel group=\"1 3\" mu=\"0.7\"/>");
    /* the bottom layer: 15 contacts, mu of the model (0.7) over the floor's 0.3 */
    ck_assert_int_eq(count_rows(sim, "floor", NULL), 45);
    ck_assert_int_eq(count_rows(sim, "grouped", NULL), 0); /* both in group 3 */
    /* vertices at x = 0 prescribed: their 3 contacts go */
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    int *pres = calloc((size_t)n, sizeof *pres);
    ck_assert_ptr_nonnull(pres);
    for (int v = 0; v < n; ++v) pres[v] = fabs(q[3 * v]) < 1e-12;
    ck_assert_int_eq(count_rows(sim, "floor", pres), 36);
    free(pres);
    pl_sim_free(sim);
}
END_TEST

START_TEST(test_cloth_every_vertex)
{
    const char *xml = "<Node name=\"root\" dt=\"0.01\">\n"
                      "<RequiredPlugin name=\"collision\"/>\n"
                      "<NewtonSolver/>\n"
                      "<PlaneObstacle name=\"floor\" mu=\"0.7\" alarmDistance=\"0.01\"/>\n"
                      "<Node name=\"body\">\n"
                      "<RegularGridTriangles min=\"0 0.005 0\" max=\"0.1 0.005 0.1\" n=\"3 1 3\"/>\n"
                      "<MechanicalObject name=\"dofs\"/>\n"
                      "<UniformMass totalMass=\"0.1\"/>\n"
                      "<SurfaceCollisionModel/>\n"
                      "</Node></Node>\n";
    pl_sim *sim = ct_load(xml, NULL, 0);
    ck_assert_int_eq(count_rows(sim, "floor", NULL), 27);
    pl_sim_free(sim);
}
END_TEST

START_TEST(test_multipliers_become_forces)
{
    const char *two = "<PlaneObstacle name=\"floor\" normal=\"0 2 0\" rotation=\"0 0 10\" "
                      "mu=\"0.3\" alarmDistance=\"0.03\" contactDistance=\"0.005\"/>\n"
                      "<PlaneObstacle name=\"wall\" point=\"-0.005 0 0\" normal=\"1 0 0\" "
                      "alarmDistance=\"0.01\"/>";
    pl_sim *sim = load_scene(two, "<SurfaceCollisionModel/>");
    int n;
    double *q = ct_positions(sim, "body/dofs", &n);
    ct_system sys;
    ct_system_make(&sys, n, H, NULL);
    pl_rows rows;
    pl_rows_init(&rows);
    pl_error err;
    ck_assert_int_eq(ct_build_rows(sim, "floor", &sys.sys, q, n, &rows, &err), PL_OK);
    int nfloor = rows.n;
    ck_assert_int_eq(ct_build_rows(sim, "wall", &sys.sys, q, n, &rows, &err), PL_OK);
    int nwall = rows.n - nfloor;
    ck_assert_int_eq(nwall, 3 * 9); /* the 9 vertices of the face x = 0 */
    double *lambda = malloc((size_t)rows.n * sizeof *lambda);
    ck_assert_ptr_nonnull(lambda);
    for (int r = 0; r < rows.n; ++r) lambda[r] = rows.kind[r] == PL_ROW_NORMAL ? 1.0 + r : 0.1 * r - 2;
    const char *paths[2] = {"floor", "wall"};
    const int first[2] = {0, nfloor}, count[2] = {nfloor, nwall};
    for (int o = 0; o < 2; ++o) {
        pl_component *c = pl_sim_component(sim, paths[o]);
        const pl_constraint_ops *ops = pl_component_role(c, PL_ROLE_CONSTRAINT);
        ops->accept_multipliers(c, pl_sim_data(sim), &rows, lambda, first[o], count[o]);
    }
    for (int o = 0; o < 2; ++o) {
        char path[64];
        double *f, *p, *nn, *cnt;
        snprintf(path, sizeof path, "%s.contactForces", paths[o]);
        int nf = ct_get_doubles(sim, path, &f);
        snprintf(path, sizeof path, "%s.contactPoints", paths[o]);
        ck_assert_int_eq(ct_get_doubles(sim, path, &p), nf);
        snprintf(path, sizeof path, "%s.contactNormals", paths[o]);
        ck_assert_int_eq(ct_get_doubles(sim, path, &nn), nf);
        snprintf(path, sizeof path, "%s.contactCount", paths[o]);
        ck_assert_int_eq(ct_get_doubles(sim, path, &cnt), 1);
        ck_assert_int_eq(3 * (int)cnt[0], count[o]);
        ck_assert_int_eq(nf, count[o]);
        for (int k = 0; k < count[o] / 3; ++k) {
            int rn = first[o] + 3 * k;
            const double *cn = &rows.coef[3 * rows.start[rn]], *c1 = &rows.coef[3 * rows.start[rn + 1]],
                         *c2 = &rows.coef[3 * rows.start[rn + 2]];
            const double *x = &q[3 * rows.vertex[rows.start[rn]]];
            double phi = dot3(cn, x) - (rows.d[rn] - (o == 0 ? 0.005 : 0.0));
            for (int i = 0; i < 3; ++i) {
                double fi = lambda[rn] * cn[i] + lambda[rn + 1] * c1[i] + lambda[rn + 2] * c2[i];
                ck_assert_double_eq_tol(f[3 * k + i], fi, 1e-12);
                ck_assert_double_eq_tol(nn[3 * k + i], cn[i], 1e-15);
                ck_assert_double_eq_tol(p[3 * k + i], x[i] - phi * cn[i], 1e-14);
            }
        }
        free(f), free(p), free(nn), free(cnt);
    }
    free(lambda);
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_rows");
    TCase *tc = tcase_create("rows");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_tilted_plane_rows);
    tcase_add_test(tc, test_moving_plane_posed_at_end_of_step);
    tcase_add_test(tc, test_clear_models_skipped_near_ones_kept);
    tcase_add_test(tc, test_every_shape_rows);
    tcase_add_test(tc, test_prescribed_groups_and_model_mu);
    tcase_add_test(tc, test_cloth_every_vertex);
    tcase_add_test(tc, test_multipliers_become_forces);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *sr = srunner_create(suite());
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
