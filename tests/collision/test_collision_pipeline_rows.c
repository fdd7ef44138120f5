/* test_collision_pipeline_rows.c - the CollisionPipeline's rows through its
 * constraint role, on small scenes numbered by a NewtonSolver:
 *  - a moving MeshObstacle (a quad written in the scene) under a grid body:
 *    one contact per bottom vertex within alarmDistance, normal row w n on
 *    that vertex with d = n . p(t + h) + contactDistance, friction rows
 *    orthonormal with d_f = t . v (the obstacle's surface velocity);
 *  - friction of the pair: unset models give the pipeline's mu, one set mu
 *    is used as is, two are combined by frictionRule (min, max, mean,
 *    product); models of one non-zero group give no rows;
 *  - MappedSurfaceCollisionModel: a triangle inside the body follows it by
 *    barycentric weights: its rows spread over tetrahedron vertices with
 *    weights >= 0 summing to 1 and H q equals n . (mapped point);
 *  - MeshObstacle's sides field: inside a closed obstacle a point is pushed
 *    out (one, auto) or kept inside (two);
 *  - broken inputs name the scene line (two sources, an index out of range,
 *    contactDistance > alarmDistance). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"

static const double H = 0.01;

static char *scene(const char *pipeline, const char *obstacle, const char *model)
{
    static const char *FMT =
        "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
        "<RequiredPlugin name=\"collision\"/>\n"
        "<NewtonSolver/>\n"
        "%s\n"
        "<Node name=\"floor\">%s</Node>\n"
        "<Node name=\"body\">\n"
        "<RegularGridTetrahedra name=\"grid\" min=\"0 0.005 0\" max=\"0.2 0.1 0.1\" n=\"3 3 3\"/>\n"
        "<MechanicalObject name=\"dofs\"/>\n"
        "<DiagonalMass massDensity=\"1000\"/>\n"
        "%s\n"
        "</Node></Node>\n";
    size_t len = strlen(FMT) + strlen(pipeline) + strlen(obstacle) + strlen(model) + 1;
    char *s = malloc(len);
    ck_assert_ptr_nonnull(s);
    snprintf(s, len, FMT, pipeline, obstacle, model);
    return s;
}

static const char *PIPE = "<CollisionPipeline name=\"pipeline\" alarmDistance=\"0.01\" "
                          "contactDistance=\"0.001\" mu=\"0.3\"/>";
static const char *QUAD = "<MeshObstacle name=\"quad\" position=\"-1 0 -1  1 0 -1  1 0 1  -1 0 1\" "
                          "triangles=\"0 2 1  0 3 2\" velocity=\"0.5 0 0\" mu=\"0.2\"/>";

static pl_sim *load(const char *pipeline, const char *obstacle, const char *model,
                    const char *const *ov, int nov)
{
    char *xml = scene(pipeline, obstacle, model);
    pl_sim *s = ct_load(xml, ov, nov);
    free(xml);
    return s;
}

static void rows_of(pl_sim *sim, pl_rows *rows, double **q, int *n, ct_system *sys)
{
    *q = ct_positions(sim, "body/dofs", n);
    ct_system_make(sys, *n, H, NULL);
    pl_rows_init(rows);
    pl_error err;
    ck_assert_int_eq(ct_build_rows(sim, "pipeline", &sys->sys, *q, *n, rows, &err), PL_OK);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

START_TEST(test_moving_quad_rows)
{
    pl_sim *sim = load(PIPE, QUAD, "<SurfaceCollisionModel name=\"surface\"/>", NULL, 0);
    pl_rows rows;
    double *q;
    int n;
    ct_system sys;
    rows_of(sim, &rows, &q, &n, &sys);
    int bottom = 0;
    for (int v = 0; v < n; ++v) bottom += q[3 * v + 1] < 0.006;
    ck_assert_int_eq(bottom, 9);
    ck_assert_int_eq(rows.n, 3 * bottom);
    const double v_quad[3] = {0.5, 0, 0};
    for (int c = 0; c < bottom; ++c) {
        int rn = 3 * c;
        ck_assert_int_eq(rows.kind[rn], PL_ROW_NORMAL);
        ck_assert_int_eq(rows.start[rn + 1] - rows.start[rn], 1);
        int v = rows.vertex[rows.start[rn]];
        ck_assert_double_eq_tol(q[3 * v + 1], 0.005, 1e-15);
        const double *cn = &rows.coef[3 * rows.start[rn]];
        ck_assert_double_eq_tol(cn[1], 1.0, 1e-15);
        ck_assert_double_eq_tol(fabs(cn[0]) + fabs(cn[2]), 0.0, 1e-15);
        /* the quad is flat, moving along x: n . p(t + h) = 0 */
        ck_assert_double_eq_tol(rows.d[rn], 0.001, 1e-15);
        ck_assert_double_eq_tol(pl_rows_dot(&rows, rn, q) - rows.d[rn], 0.004, 1e-15);
        ck_assert_double_eq(rows.mu[rn], 0.2);
        for (int k = 1; k <= 2; ++k) {
            const double *t = &rows.coef[3 * rows.start[rn + k]];
            ck_assert_int_eq(rows.kind[rn + k], PL_ROW_FRICTION);
            ck_assert_int_eq(rows.pair[rn + k], rn);
            ck_assert_double_eq_tol(dot3(t, t), 1.0, 1e-14);
            ck_assert_double_eq_tol(dot3(t, cn), 0.0, 1e-14);
            ck_assert_double_eq_tol(rows.d[rn + k], dot3(t, v_quad), 1e-14);
        }
    }
    double *cnt;
    ck_assert_int_eq(ct_get_doubles(sim, "pipeline.contactCount", &cnt), 1);
    free(cnt);
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
}
END_TEST

/* The y component of the first normal row against a closed MeshObstacle (a
 * tetrahedron whose top face is 5 mm above the body's bottom vertices) with
 * the given sides; NAN without rows. */
static double inside_normal_y(const char *sides)
{
    char obstacle[512];
    snprintf(obstacle, sizeof obstacle,
             "<MeshObstacle name=\"tet\" position=\"-1 0.01 -1  1 0.01 -1  0 0.01 1.5  0 -1 0\" "
             "triangles=\"0 1 2  0 3 1  1 3 2  2 3 0\" sides=\"%s\"/>",
             sides);
    pl_sim *sim = load(PIPE, obstacle, "<SurfaceCollisionModel name=\"surface\"/>", NULL, 0);
    pl_rows rows;
    double *q;
    int n;
    ct_system sys;
    rows_of(sim, &rows, &q, &n, &sys);
    double y = NAN;
    for (int j = 0; j < rows.n && isnan(y); ++j)
        if (rows.kind[j] == PL_ROW_NORMAL) y = rows.coef[3 * rows.start[j] + 1];
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
    return y;
}

/* MeshObstacle's sides field decides: a closed surface repels inside points
 * outward (one, and auto), a thin one keeps them on their side (two).  (The
 * field used to be ignored: the type was compared by address, and the
 * registry holds a copy of each type.) */
START_TEST(test_mesh_obstacle_sides_field)
{
    ck_assert_double_eq_tol(inside_normal_y("auto"), 1.0, 1e-12);
    ck_assert_double_eq_tol(inside_normal_y("one"), 1.0, 1e-12);
    ck_assert_double_eq_tol(inside_normal_y("two"), -1.0, 1e-12);
}
END_TEST

/* mu of the first row for given overrides */
static double first_mu(const char *const *ov, int nov, int *nrows)
{
    pl_sim *sim = load(PIPE, QUAD, "<SurfaceCollisionModel name=\"surface\"/>", ov, nov);
    pl_rows rows;
    double *q;
    int n;
    ct_system sys;
    rows_of(sim, &rows, &q, &n, &sys);
    *nrows = rows.n;
    double mu = rows.n ? rows.mu[0] : NAN;
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
    return mu;
}

START_TEST(test_pair_friction_and_groups)
{
    int nr;
    const char *unset[] = {"floor/quad.mu=-1"};
    ck_assert_double_eq(first_mu(unset, 1, &nr), 0.3); /* the pipeline's */
    const char *one[] = {"body/surface.mu=0.4", "floor/quad.mu=-1"};
    ck_assert_double_eq(first_mu(one, 2, &nr), 0.4);
    const char *both[] = {"body/surface.mu=0.4"};
    ck_assert_double_eq(first_mu(both, 1, &nr), 0.2); /* min by default */
    const char *mx[] = {"body/surface.mu=0.4", "pipeline.frictionRule=max"};
    ck_assert_double_eq(first_mu(mx, 2, &nr), 0.4);
    const char *mean[] = {"body/surface.mu=0.4", "pipeline.frictionRule=mean"};
    ck_assert_double_eq_tol(first_mu(mean, 2, &nr), 0.3, 1e-15);
    const char *prod[] = {"body/surface.mu=0.4", "pipeline.frictionRule=product"};
    ck_assert_double_eq_tol(first_mu(prod, 2, &nr), 0.08, 1e-15);
    const char *grp[] = {"body/surface.group=2", "floor/quad.group=2"};
    first_mu(grp, 2, &nr);
    ck_assert_int_eq(nr, 0);
    const char *other[] = {"body/surface.group=2", "floor/quad.group=3"};
    first_mu(other, 2, &nr);
    ck_assert_int_eq(nr, 27);
    /* groups are sets (SoftRobots): sharing any one group is enough */
    const char *share[] = {"body/surface.group=1 2 5", "floor/quad.group=3 5"};
    first_mu(share, 2, &nr);
    ck_assert_int_eq(nr, 0);
    const char *apart[] = {"body/surface.group=1 2 32", "floor/quad.group=3 4 31"};
    first_mu(apart, 2, &nr);
    ck_assert_int_eq(nr, 27);
    const char *none[] = {"body/surface.group=0", "floor/quad.group=0"};
    first_mu(none, 2, &nr);
    ck_assert_int_eq(nr, 27);
}
END_TEST

START_TEST(test_mapped_surface_rows)
{
    /* a triangle 3 mm above the body's bottom, inside its first layer of cells */
    const char *model = "<Node name=\"collision\">"
                        "<MappedSurfaceCollisionModel name=\"mapped\" position=\"0.05 0.008 0.02  "
                        "0.15 0.008 0.02  0.1 0.008 0.08\" triangles=\"0 1 2\"/></Node>";
    pl_sim *sim = load(PIPE, QUAD, model, NULL, 0);
    pl_rows rows;
    double *q;
    int n;
    ct_system sys;
    rows_of(sim, &rows, &q, &n, &sys);
    ck_assert_int_eq(rows.n, 9); /* its three points; the quad's corners are far */
    const double pts[3][3] = {{0.05, 0.008, 0.02}, {0.15, 0.008, 0.02}, {0.1, 0.008, 0.08}};
    int seen[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
        int rn = 3 * c, ne = rows.start[rn + 1] - rows.start[rn];
        ck_assert_int_le(ne, 4);
        double wsum = 0, p[3] = {0, 0, 0};
        for (int e = rows.start[rn]; e < rows.start[rn + 1]; ++e) {
            double w = rows.coef[3 * e + 1]; /* n = +y: the coefficient is w */
            ck_assert_double_ge(w, -1e-12);
            wsum += w;
            for (int k = 0; k < 3; ++k) p[k] += w * q[3 * rows.vertex[e] + k];
        }
        ck_assert_double_eq_tol(wsum, 1.0, 1e-12);
        ck_assert_double_eq_tol(pl_rows_dot(&rows, rn, q), 0.008, 1e-12);
        for (int j = 0; j < 3; ++j)
            if (fabs(p[0] - pts[j][0]) < 1e-12 && fabs(p[2] - pts[j][2]) < 1e-12) seen[j]++;
    }
    ck_assert(seen[0] == 1 && seen[1] == 1 && seen[2] == 1);
    pl_rows_free(&rows);
    ct_system_free(&sys);
    pl_sim_free(sim);
}
END_TEST

static void expect_error(const char *pipeline, const char *obstacle, const char *needle, int line)
{
    char *xml = scene(pipeline, obstacle, "<SurfaceCollisionModel/>");
    pl_error e;
    ct_load_fail(xml, &e);
    free(xml);
    ck_assert_msg(strstr(e.msg, needle) != NULL, "'%s' not in: %s", needle, e.msg);
    ck_assert_int_eq(e.line, line);
}

START_TEST(test_broken_inputs_name_the_line)
{
    expect_error(PIPE,
                 "<MeshObstacle filename=\"cube.obj\" position=\"0 0 0 1 0 0 0 1 0\" "
                 "triangles=\"0 1 2\"/>",
                 "one source", 5);
    expect_error(PIPE, "<MeshObstacle position=\"0 0 0 1 0 0 0 1 0\" triangles=\"0 1 3\"/>",
                 "outside the 3 vertices", 5);
    expect_error("<CollisionPipeline alarmDistance=\"0.001\" contactDistance=\"0.002\"/>", QUAD,
                 "exceeds alarmDistance", 4);
    expect_error(PIPE, "<MeshObstacle position=\"0 0 0 1 0 0 0 1 0\" triangles=\"0 1 2\" mu=\"-3\"/>",
                 "mu must be", 5);
    expect_error(PIPE, "<MeshObstacle position=\"0 0 0 1 0 0 0 1 0\" triangles=\"0 1 2\" group=\"1 33\"/>",
                 "group 33: groups are numbered 1..32", 5);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_pipeline_rows");
    TCase *tc = tcase_create("rows");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_moving_quad_rows);
    tcase_add_test(tc, test_pair_friction_and_groups);
    tcase_add_test(tc, test_mapped_surface_rows);
    tcase_add_test(tc, test_broken_inputs_name_the_line);
    tcase_add_test(tc, test_mesh_obstacle_sides_field);
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
