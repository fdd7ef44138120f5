/* test_collision_lookahead.c - the instant at which look-ahead measures a
 * pair that is farther than alarmDistance at the start of the step
 * (lookahead.c), on hand-made motions that pass through a thin blade
 * within the step:
 *  - a vertex moving towards a blade's face, head-on or slanted, gets its
 *    vertex-face proximity on the side it comes from;
 *  - the instant, for a vertex and for an edge, is never past the moment
 *    the path reaches the blade.
 * Conservative advancement converges on contactDistance geometrically when
 * the motion is slanted to the normal; whether its last step landed at or a
 * round-off above that distance used to decide between that instant and the
 * end of the step, beyond the blade, where the pair is dropped (on
 * cloth_on_knives_small.xml, with W explicit, a cloth vertex went through a
 * blade at step 39 and its edges ended 0.11 m inside it).  Fails without
 * the fix: the slanted motions below lost their proximity. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "detect.h"
#include "detect_internal.h"

#define ALARM 0.006   /* cloth_on_knives_small.xml's distances [m] */
#define CONTACT 0.002
#define START 0.0076  /* the vertex's distance to the blade's plane at the start [m] */
#define NORMAL 0.0083 /* its predicted motion along the normal over the step [m] */

/* tangential parts of the motion [m]: head-on to a 75-degree slant */
static const double TANGENT[] = {0.0, 0.0001, 0.0005, 0.001, 0.002, 0.004,
                                 0.006, 0.008, 0.012, 0.02, 0.031};
#define NT ((int)(sizeof TANGENT / sizeof TANGENT[0]))

/* A rigid two-sided blade, the triangle (0,-1,-1) (0,-1,1) (0,1,0) in the
 * plane x = 0, its face normal along +-x. */
static double BX[9] = {0, -1, -1, 0, -1, 1, 0, 1, 0};
static int BTRI[3] = {0, 1, 2}, BEDGES[6] = {0, 1, 1, 2, 2, 0};
static unsigned char RIGID[3] = {0, 0, 0};

static void blade(pl_coll_mesh *b)
{
    coll_mesh_init(b);
    b->nverts = 3, b->ntris = 1, b->nedges = 3, b->x0 = b->x1 = BX, b->tris = BTRI;
    b->edges = BEDGES, b->active = RIGID, b->sides = PL_SIDES_TWO;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(b, ALARM, &err), PL_OK);
}

static pl_detect_params params(void)
{
    pl_detect_params prm = detect_defaults(ALARM);
    prm.contact = CONTACT;
    return prm;
}

/* A vertex START in front of the blade moving NORMAL through it and
 * tangent along y: one vertex-face proximity, normal -x (the side it comes
 * from), gap START; and the look-ahead's instant before it reaches the
 * plane, within alarm of it. */
START_TEST(test_vertex_through_a_blade_keeps_its_side)
{
    pl_coll_mesh B;
    blade(&B);
    pl_detect_params prm = params();
    int kept = 0;
    for (int k = 0; k < NT; ++k) {
        double x0[3] = {-START, 0.0, 0.1}, x1[3] = {-START + NORMAL, TANGENT[k], 0.1};
        pl_coll_mesh P;
        coll_mesh_init(&P);
        P.nverts = 1, P.x0 = x0, P.x1 = x1, P.sides = PL_SIDES_TWO;
        pl_error err;
        ck_assert_int_eq(coll_mesh_prepare(&P, ALARM, &err), PL_OK);
        double s = -1.0;
        int found = coll_vf_lookahead(&P, 0, &B, BTRI, START, &prm, &s);
        ck_assert_msg(found, "tangent %g: look-ahead found nothing", TANGENT[k]);
        double xs = -START + s * NORMAL; /* the vertex's x at s */
        ck_assert_msg(xs < 0.0 && xs > -ALARM, "tangent %g: measured at s = %.17g, x = %g m",
                      TANGENT[k], s, xs);
        pl_proximities px = {0};
        ck_assert_int_eq(detect_pair(&P, 0, &B, 1, &prm, &px), PL_OK);
        int n = 0;
        for (int i = 0; i < px.n; ++i) {
            const pl_proximity *x = &px.items[i];
            if (x->kind != PL_PROX_VERTEX_FACE || x->model_a != 0) continue;
            n++;
            ck_assert_msg(x->normal[0] < -0.999999, "tangent %g: normal %g %g %g", TANGENT[k],
                          x->normal[0], x->normal[1], x->normal[2]);
            ck_assert_msg(fabs(x->gap - START) < 1e-12, "tangent %g: gap %g", TANGENT[k], x->gap);
        }
        printf("tangent %.4f m: s = %.6f, x(s) = %.3f mm, %d proximity\n", TANGENT[k], s,
               1e3 * xs, n);
        kept += n == 1;
        proximities_free(&px);
        coll_mesh_free(&P);
    }
    coll_mesh_free(&B);
    ck_assert_msg(kept == NT, "%d of %d motions through the blade kept their proximity", kept, NT);
}
END_TEST

/* A rigid edge along y at x = 0 (a blade's edge) and a free edge along z,
 * START in front of it, moving NORMAL along x through it and tangent along
 * y: the look-ahead's instant is before the edges meet, within alarm. */
START_TEST(test_edge_through_an_edge_is_measured_before)
{
    double bx[6] = {0, -0.5, 0, 0, 0.5, 0};
    int be[2] = {0, 1}, ae[2] = {0, 1};
    unsigned char rigid[2] = {0, 0};
    pl_coll_mesh E;
    coll_mesh_init(&E);
    E.nverts = 2, E.nedges = 1, E.x0 = E.x1 = bx, E.edges = be, E.active = rigid;
    E.sides = PL_SIDES_TWO;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&E, ALARM, &err), PL_OK);
    pl_detect_params prm = params();
    for (int k = 0; k < NT; ++k) {
        double x0[6] = {-START, 0.0, -0.5, -START, 0.0, 0.5};
        double x1[6] = {-START + NORMAL, TANGENT[k], -0.5, -START + NORMAL, TANGENT[k], 0.5};
        pl_coll_mesh A;
        coll_mesh_init(&A);
        A.nverts = 2, A.nedges = 1, A.x0 = x0, A.x1 = x1, A.edges = ae, A.sides = PL_SIDES_TWO;
        ck_assert_int_eq(coll_mesh_prepare(&A, ALARM, &err), PL_OK);
        double s = -1.0;
        ck_assert_msg(coll_ee_lookahead(&A, ae, &E, be, START, &prm, &s), "tangent %g: none",
                      TANGENT[k]);
        double xs = -START + s * NORMAL;
        ck_assert_msg(xs < 0.0 && xs > -ALARM, "tangent %g: measured at s = %.17g, x = %g m",
                      TANGENT[k], s, xs);
        coll_mesh_free(&A);
    }
    coll_mesh_free(&E);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_lookahead");
    TCase *tc = tcase_create("lookahead");
    tcase_add_test(tc, test_vertex_through_a_blade_keeps_its_side);
    tcase_add_test(tc, test_edge_through_an_edge_is_measured_before);
    suite_add_tcase(s, tc);
    SRunner *r = srunner_create(s);
    srunner_run_all(r, CK_NORMAL);
    int failed = srunner_ntests_failed(r);
    srunner_free(r);
    return failed ? 1 : 0;
}
