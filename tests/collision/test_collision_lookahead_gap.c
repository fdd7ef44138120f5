/* test_collision_lookahead_gap.c - a contact that look-ahead finds at a
 * positive gap is a unilateral constraint with that gap (issue 14 item 1).
 * A block 7 mm above a surface (alarmDistance 5 mm) moves down at 2 m/s:
 * its predicted motion over the 5 ms step (x + h v + h^2 g) reaches the
 * surface, so detection gives its bottom vertices contacts although they
 * are farther than alarmDistance.  An upward load (300 m/s^2) brakes it and
 * it ends the step 2.75 mm above (its lightest vertices brake most): every contact stays open, so
 *  - every contact force is zero and the block moves exactly as the same
 *    block with no surface at all (the rows did nothing);
 *  - the normal rows' gaps at the end, n . (x - p) - contactDistance
 *    measured from the reported contact points, are positive.
 * Without the load the block reaches the surface in the step: the same
 * rows then push (positive normal force) and hold the kept gap.  For a
 * PlaneObstacle and a MeshObstacle (a box of triangles through the
 * CollisionPipeline). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"

#define GAP 0.0005   /* contactDistance [m] */
#define START 0.007  /* block bottom above the surface [m] (> alarmDistance 5 mm) */

static const char *HEAD =
    "<Node name='root' dt='0.005' gravity='0 -9.81 0'>"
    "<RequiredPlugin name='hyperelastic'/><RequiredPlugin name='sparse_inverse'/>"
    "<RequiredPlugin name='ncp_contact'/><RequiredPlugin name='collision'/>"
    "<LocalGlobalSolver name='solver' iterations='10'/><SparseInverseSolver name='global'/>"
    "<NonSmoothNewtonContactSolver name='contact' ncp='fischer-burmeister' crIterations='24' "
    "preconditioner='delassus'/>";

typedef enum target { NONE, PLANE, MESH } target;

/* The scene: the surface (top at y = 0), a 0.1 m block (1 kg) START above
 * it moving down at 2 m/s, with an upward load of `up` N in all. */
static pl_sim *load(target t, double up)
{
    char xml[4096];
    int n = snprintf(xml, sizeof xml, "%s", HEAD);
    if (t == PLANE)
        n += snprintf(xml + n, sizeof xml - (size_t)n,
                      "<PlaneObstacle name='surface' point='0 0 0' normal='0 1 0' mu='0.3' "
                      "alarmDistance='0.005' contactDistance='%g'/>",
                      GAP);
    if (t == MESH)
        n += snprintf(xml + n, sizeof xml - (size_t)n,
                      "<CollisionPipeline name='surface' alarmDistance='0.005' "
                      "contactDistance='%g' mu='0.3'/><Node name='floor'><RegularGridTetrahedra "
                      "name='box' min='-0.3 -0.2 -0.3' max='0.3 0 0.3' n='2 2 2'/>"
                      "<MeshObstacle name='obstacle' src='@box'/></Node>",
                      GAP);
    snprintf(xml + n, sizeof xml - (size_t)n,
             "<Node name='block'><RegularGridTetrahedra name='mesh' min='-0.05 %g -0.05' "
             "max='0.05 %g 0.05' n='3 3 3'/><MechanicalObject name='dofs' src='@mesh' "
             "velocity='0 -2 0'/><DiagonalMass massDensity='1000'/>"
             "<NeoHookean name='material' youngModulus='1e5' poissonRatio='0.4'/>"
             "<ConstantForceField box='-1 -1 -1 1 1 1' totalForce='0 %g 0'/>"
             "<SurfaceCollisionModel name='collision'/></Node></Node>",
             START, START + 0.1, up);
    return ct_load(xml, NULL, 0);
}

static void step(pl_sim *sim)
{
    pl_error err;
    int rc = pl_sim_step(sim, 1, &err);
    if (rc) {
        char m[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, m, sizeof m));
    }
    ck_assert_int_eq(rc, PL_OK);
}

/* The surface's contacts of the last step: count, largest |force| [N],
 * smallest normal force [N] and smallest end gap of the normal rows [m]
 * (n . (x - p) - contactDistance for the block vertex nearest p). */
typedef struct contacts {
    int n;
    double fmax, fn_min, gap_min;
} contacts;

static void read_contacts(pl_sim *sim, contacts *c)
{
    double *f, *p, *nrm;
    int n = ct_get_doubles(sim, "surface.contactForces", &f) / 3;
    ck_assert_int_eq(ct_get_doubles(sim, "surface.contactPoints", &p) / 3, n);
    ck_assert_int_eq(ct_get_doubles(sim, "surface.contactNormals", &nrm) / 3, n);
    int nv;
    const double *x = ct_positions(sim, "block/dofs", &nv);
    c->n = n;
    c->fmax = 0.0, c->fn_min = INFINITY, c->gap_min = INFINITY;
    for (int k = 0; k < n; ++k) {
        const double *nk = &nrm[3 * k], *pk = &p[3 * k], *fk = &f[3 * k];
        c->fmax = fmax(c->fmax, sqrt(fk[0] * fk[0] + fk[1] * fk[1] + fk[2] * fk[2]));
        c->fn_min = fmin(c->fn_min, fk[0] * nk[0] + fk[1] * nk[1] + fk[2] * nk[2]);
        /* the block's bottom vertex under the contact point (the point is
         * reported on the surface or on the block: y = 0 or at the block) */
        double best = INFINITY, g = 0.0;
        for (int i = 0; i < nv; ++i) {
            double dx = x[3 * i] - pk[0], dz = x[3 * i + 2] - pk[2];
            double d2 = dx * dx + dz * dz + (x[3 * i + 1] < 0.05 ? 0.0 : 1.0);
            if (d2 < best) best = d2, g = x[3 * i + 1] - GAP; /* n = +y, surface y = 0 */
        }
        c->gap_min = fmin(c->gap_min, g);
    }
    free(f);
    free(p);
    free(nrm);
}

static void open_and_closed(target t)
{
    static const char *NAME[] = {"", "plane", "box mesh"};
    /* braked: the block stays 2.75 mm above; the same block with no surface */
    pl_sim *sim = load(t, 300.0), *free_sim = load(NONE, 300.0);
    step(sim);
    step(free_sim);
    contacts c;
    read_contacts(sim, &c);
    int nv, nf;
    const double *x = ct_positions(sim, "block/dofs", &nv);
    const double *xf = ct_positions(free_sim, "block/dofs", &nf);
    ck_assert_int_eq(nv, nf);
    double dev = 0.0, low = INFINITY;
    for (int i = 0; i < nv; ++i) {
        low = fmin(low, x[3 * i + 1]);
        for (int k = 0; k < 3; ++k) dev = fmax(dev, fabs(x[3 * i + k] - xf[3 * i + k]));
    }
    printf("%s, braked: %d look-ahead contacts, largest force %.3e N, lowest point %.3f mm, "
           "smallest row gap %.3f mm, deviation from the free block %.3e m\n",
           NAME[t], c.n, c.fmax, 1e3 * low, 1e3 * c.gap_min, dev);
    ck_assert_msg(c.n >= 9, "%s: look-ahead found %d contacts (the 9 bottom vertices)", NAME[t],
                  c.n);
    ck_assert_msg(low > 0.002 && low < START - 0.002, "%s: lowest point %g m", NAME[t], low);
    ck_assert_msg(c.gap_min > 0.001, "%s: a row's gap %g m at the end", NAME[t], c.gap_min);
    ck_assert_msg(c.fmax <= 1e-12, "%s: an open contact carries %g N", NAME[t], c.fmax);
    ck_assert_msg(dev <= 1e-12, "%s: the open contacts moved the block by %g m", NAME[t], dev);
    pl_sim_free(sim);
    pl_sim_free(free_sim);

    /* unbraked: the block reaches the surface in the step; the rows push */
    sim = load(t, 0.0);
    step(sim);
    read_contacts(sim, &c);
    x = ct_positions(sim, "block/dofs", &nv);
    low = INFINITY;
    for (int i = 0; i < nv; ++i) low = fmin(low, x[3 * i + 1]);
    printf("%s, unbraked: %d contacts, smallest normal force %.3e N, lowest point %.4f mm\n",
           NAME[t], c.n, c.fn_min, 1e3 * low);
    ck_assert_msg(c.n >= 9 && c.fn_min > 0.0, "%s: closed contacts must push (%d, %g N)",
                  NAME[t], c.n, c.fn_min);
    ck_assert_msg(low > GAP - 1e-6, "%s: lowest point %g m, below the kept gap", NAME[t], low);
    pl_sim_free(sim);
}

START_TEST(test_open_plane) { open_and_closed(PLANE); }
END_TEST

START_TEST(test_open_mesh) { open_and_closed(MESH); }
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_lookahead_gap");
    TCase *tc = tcase_create("gap");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_open_plane);
    tcase_add_test(tc, test_open_mesh);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
