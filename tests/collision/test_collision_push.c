/* test_collision_push.c - which way a contact pushes, and its rows:
 *  - thin (two-sided) triangles push each point back to the side it starts
 *    on, also when the predicted motion crosses the triangle in one step;
 *    closed (one-sided) surfaces push shallow inside points out along the
 *    outward normal and ignore deep ones; a point over a thin plate, beside
 *    a corner, an edge beside a cube keep one consistent side;
 *  (the sides kept at thin sheets' borders, from step to step and from the
 *  predicted end of a step: test_collision_sides.c)
 *  - the rows of a contact between two sides (collision_emit_pair):
 *    +w n on A, -w n on B, merged vertices, d and d_f from fixed parts;
 *    written at offsets in any order (collision_pair_write) they are the
 *    rows appended one by one.
 * (Split from test_collision_detect.c, which keeps detection's
 * completeness against brute force and an independent reference.) */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "detect.h"
#include "rows_compare.h"

/* One thin triangle (a knife blade in the x-y plane) and free points. */
START_TEST(test_thin_triangle_keeps_each_side)
{
    double tri_x[9] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    int tri[3] = {0, 1, 2}, edges[6] = {0, 1, 0, 2, 1, 2};
    /* points: above, below, crossing within the step, far and still */
    double px0[12] = {0, 0, 0.005, 0, 0, -0.007, 0.1, 0, 0.05, 0, 0, 0.5};
    double px1[12] = {0, 0, 0.005, 0, 0, -0.007, 0.1, 0, -0.05, 0, 0, 0.5};
    pl_coll_mesh T, P;
    coll_mesh_init(&T);
    coll_mesh_init(&P);
    T.nverts = 3, T.ntris = 1, T.nedges = 3, T.x0 = T.x1 = tri_x, T.tris = tri, T.edges = edges;
    P.nverts = 4, P.x0 = px0, P.x1 = px1;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&T, 0.01, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
    ck_assert_int_eq(T.two_sided, 1); /* open: auto is two-sided */
    pl_detect_params prm = detect_defaults(0.01);
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&P, 0, &T, 1, &prm, &p), PL_OK);
    ck_assert_int_eq(p.n, 3);
    const double want_nz[3] = {1, -1, 1}, want_gap[3] = {0.005, 0.007, 0.05};
    for (int k = 0; k < 3; ++k) {
        ck_assert_int_eq(p.items[k].a[0], k);
        ck_assert_double_eq_tol(p.items[k].normal[2], want_nz[k], 1e-15);
        ck_assert_double_eq_tol(p.items[k].gap, want_gap[k], 1e-15);
    }
    proximities_free(&p);
    coll_mesh_free(&T);
    coll_mesh_free(&P);
}
END_TEST

/* The unit cube as a detection mesh over its own arrays: corners b = x +
 * 2y + 4z, its 12 faces listed inward (clockwise seen from outside) on
 * purpose: the detection must turn them outward by the enclosed volume's
 * sign. */
typedef struct cube {
    double x[24];
    int tris[36], *edges, ne;
} cube;

static void cube_make(cube *c)
{
    static const int T[36] = {0, 1, 3, 0, 3, 2, 4, 7, 5, 4, 6, 7, 0, 5, 1, 0, 4, 5,
                              2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
    for (int b = 0; b < 8; ++b)
        for (int k = 0; k < 3; ++k) c->x[3 * b + k] = (b >> k) & 1;
    memcpy(c->tris, T, sizeof T);
    ck_assert_int_eq(triangle_edges(c->tris, 12, &c->edges, &c->ne), PL_OK);
    ck_assert_int_eq(c->ne, 18);
}

/* T initialised over c (sides auto: closed, so one-sided), not prepared. */
static void cube_mesh(const cube *c, pl_coll_mesh *T)
{
    coll_mesh_init(T);
    T->nverts = 8, T->ntris = 12, T->nedges = c->ne, T->x0 = T->x1 = c->x, T->tris = c->tris;
    T->edges = c->edges;
}

/* The unit cube's closed surface, outward, with points inside. */
START_TEST(test_closed_surface_pushes_out)
{
    cube c;
    cube_make(&c);
    double px[9] = {0.5, 0.5, 1.004, 0.4, 0.55, 0.996, 0.5, 0.5, 0.5};
    pl_coll_mesh T, P;
    cube_mesh(&c, &T);
    coll_mesh_init(&P);
    P.nverts = 3, P.x0 = P.x1 = px;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&T, 0.01, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
    ck_assert_int_eq(T.two_sided, 0);
    ck_assert_double_eq(T.orientation, -1.0);
    pl_detect_params prm = detect_defaults(0.01);
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&P, 0, &T, 1, &prm, &p), PL_OK);
    ck_assert_int_eq(p.n, 2); /* the centre point is deep: none */
    for (int k = 0; k < 2; ++k) {
        ck_assert_double_eq_tol(p.items[k].normal[2], 1.0, 1e-15);
        ck_assert_double_eq_tol(p.items[k].gap, k == 0 ? 0.004 : -0.004, 1e-12);
    }
    proximities_free(&p);
    coll_mesh_free(&T);
    coll_mesh_free(&P);
    free(c.edges);
}
END_TEST

/* A closed plate 2 mm thick (the unit cube squashed along z), thinner than
 * alarm: a point 1 mm over its top is in front of the top face and also
 * behind the bottom one, 3 mm away.  Its only row is the top's; a second
 * one out of the bottom face (gap -3 mm, normal -z) pushed it through the
 * plate (a ball on dragon.obj's spines: vertices through them every step). */
START_TEST(test_point_over_a_thin_plate_has_one_side)
{
    cube c;
    cube_make(&c);
    for (int b = 0; b < 8; ++b) c.x[3 * b + 2] *= 0.002;
    double px[3] = {0.5, 0.4, 0.003};
    pl_coll_mesh T, P;
    cube_mesh(&c, &T);
    coll_mesh_init(&P);
    P.nverts = 1, P.x0 = P.x1 = px;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&T, 0.01, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
    ck_assert_int_eq(T.two_sided, 0);
    pl_detect_params prm = detect_defaults(0.01);
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&P, 0, &T, 1, &prm, &p), PL_OK);
    ck_assert_int_eq(p.n, 1);
    ck_assert_double_eq_tol(p.items[0].normal[2], 1.0, 1e-15);
    ck_assert_double_eq_tol(p.items[0].gap, 0.001, 1e-12);
    proximities_free(&p);
    coll_mesh_free(&T);
    coll_mesh_free(&P);
    free(c.edges);
}
END_TEST

/* A cloth point beside a closed cube's corner, not the corner's nearest
 * cloth feature: the corner keeps only its nearest proximity beside the
 * faces (here a triangle over it), and the point, over none of the cube's
 * faces, is closest to the corner itself (a vertex-vertex proximity).  The
 * second direction must keep it (on sharp_corner.xml such a point had no
 * row, went into the cube and let its edges through the cloth); when the
 * corner's nearest is that point, it is found once. */
START_TEST(test_point_beside_a_corner_keeps_its_contact)
{
    cube c;
    cube_make(&c);
    /* triangle 0 flat 2 mm over the corner (1, 1, 1); triangle 1 from
     * vertex 3, 5 mm beside the corner (0.3 mm below the top), away */
    double sx[18] = {0.95, 1.002, 0.95, 1.1,   1.002, 0.95, 0.95, 1.002, 1.1,
                     1.004, 0.9997, 1.003, 1.05, 0.95, 1.003, 1.004, 0.95, 1.05};
    int stris[6] = {0, 1, 2, 3, 4, 5};
    int *sedges, nse;
    ck_assert_int_eq(triangle_edges(stris, 2, &sedges, &nse), PL_OK);
    const double *o = &c.x[21], *v = &sx[9];
    double d = sqrt(pow(v[0] - o[0], 2) + pow(v[1] - o[1], 2) + pow(v[2] - o[2], 2));
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) /* triangle 0 away: the corner's nearest is vertex 3 */
            for (int i = 0; i < 3; ++i) sx[3 * i + 1] = 1.5;
        pl_coll_mesh T, P;
        cube_mesh(&c, &T);
        coll_mesh_init(&P);
        P.nverts = 6, P.ntris = 2, P.nedges = nse, P.x0 = P.x1 = sx, P.tris = stris;
        P.edges = sedges, P.sides = PL_SIDES_TWO;
        pl_error err;
        ck_assert_int_eq(coll_mesh_prepare(&T, 0.01, &err), PL_OK);
        ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
        pl_detect_params prm = detect_defaults(0.01);
        pl_proximities p = {0};
        ck_assert_int_eq(detect_pair(&T, 0, &P, 1, &prm, &p), PL_OK);
        /* the contacts of vertex 3: its own (second direction: closest
         * to the corner's edge 0.3 mm below it, 5 mm away) or the
         * corner's with vertex 3 as the closest point */
        int own = 0, corner = 0, of_corner = 0;
        for (int k = 0; k < p.n; ++k) {
            const pl_proximity *x = &p.items[k];
            if (x->kind != PL_PROX_VERTEX_FACE) continue;
            if (x->model_a == 1 && x->a[0] == 3) {
                own++;
                const double n[3] = {0.8, 0.0, 0.6};
                ck_assert_double_eq_tol(x->gap, 0.005, 1e-12);
                for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(x->normal[i], n[i], 1e-9);
            }
            if (x->model_a != 0 || x->a[0] != 7) continue;
            corner++;
            for (int i = 0; i < 3; ++i)
                if (x->b[i] == 3 && x->wb[i] > 1.0 - 1e-3) {
                    of_corner++;
                    ck_assert_double_eq_tol(x->gap, d, 1e-12);
                }
        }
        ck_assert_int_eq(own, pass == 0);
        ck_assert_int_eq(of_corner, pass == 1);
        ck_assert_int_eq(corner, 1); /* its nearest alone */
        proximities_free(&p);
        coll_mesh_free(&T);
        coll_mesh_free(&P);
    }
    free(c.edges);
    free(sedges);
}
END_TEST

/* A cloth edge beside a closed cube's side just below its top edge, across
 * it: both sides of the edge-edge direction lie outside the cube (beyond the
 * top's plane one way, the side's the other), so the outward bisector of the
 * two faces does not say which side the cloth belongs on; the side it is on
 * does.  The bisector's choice put it 15 mm through (a negative gap), and
 * the solver pushed the cloth up through the cube's edge. */
START_TEST(test_edge_beside_a_cube_keeps_its_side)
{
    cube c;
    cube_make(&c);
    /* cloth edge 0-1 through (1.01, 0.988, 0.5) along (0.9, 0.436, 0): under
     * the cube's edge 3-7 (x = y = 1, along z), beside its +x face */
    const double P[3] = {1.01, 0.988, 0.5}, u[3] = {0.9, 0.4358898943540674, 0.0};
    double sx[9];
    for (int k = 0; k < 3; ++k) {
        sx[k] = P[k] - 0.007 * u[k];
        sx[3 + k] = P[k] + 0.007 * u[k];
    }
    sx[6] = P[0] + 0.004, sx[7] = P[1] - 0.008, sx[8] = P[2] + 0.01;
    int stris[3] = {0, 1, 2};
    int *sedges, nse;
    ck_assert_int_eq(triangle_edges(stris, 1, &sedges, &nse), PL_OK);
    pl_coll_mesh T, C;
    cube_mesh(&c, &T);
    coll_mesh_init(&C);
    C.nverts = 3, C.ntris = 1, C.nedges = nse, C.x0 = C.x1 = sx, C.tris = stris;
    C.edges = sedges, C.sides = PL_SIDES_TWO;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&T, 0.02, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&C, 0.02, &err), PL_OK);
    pl_detect_params prm = detect_defaults(0.02);
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&T, 0, &C, 1, &prm, &p), PL_OK);
    double s, t, d = sqrt(closest_segments(&c.x[9], &c.x[21], &sx[0], &sx[3], &s, &t));
    ck_assert(d > 0.015 && d < 0.016);
    int found = 0;
    for (int k = 0; k < p.n; ++k) {
        const pl_proximity *x = &p.items[k];
        if (x->kind != PL_PROX_EDGE_EDGE || x->a[0] + x->a[1] != 10 || x->b[0] + x->b[1] != 1)
            continue;
        found++;
        ck_assert_double_eq_tol(x->gap, d, 1e-12); /* on the side it is on, not through */
        ck_assert(x->normal[0] < 0.0 && x->normal[1] > 0.0); /* from the cloth up to the cube */
    }
    ck_assert_int_eq(found, 1);
    proximities_free(&p);
    coll_mesh_free(&T);
    coll_mesh_free(&C);
    free(c.edges);
    free(sedges);
}
END_TEST

START_TEST(test_pair_rows)
{
    pl_rows rows;
    pl_rows_init(&rows);
    pl_contact_side a = {0}, b = {0};
    a.n = 1, a.vertex[0] = 3, a.weight[0] = 1.0;
    b.n = 3;
    for (int k = 0; k < 3; ++k) b.vertex[k] = k, b.weight[k] = (k + 1) / 6.0;
    double n[3] = {0, 0, 1}, t1[3], t2[3];
    ck_assert_int_eq(collision_emit_pair(&rows, NULL, &a, &b, n, 0.4, 0.002, t1, t2), 0);
    ck_assert_int_eq(rows.n, 3);
    ck_assert_int_eq(rows.start[1] - rows.start[0], 4);
    ck_assert_int_eq(rows.kind[0], PL_ROW_NORMAL);
    ck_assert_int_eq(rows.kind[1], PL_ROW_FRICTION);
    ck_assert_double_eq(rows.mu[0], 0.4);
    ck_assert_double_eq(rows.d[0], 0.002);
    ck_assert_int_eq(rows.pair[0], 1);
    ck_assert_int_eq(rows.pair[2], 0);
    /* H q = n . (x_3 - sum w x_b): q with vertex 3 at z 1, others at z 0.25 */
    double q[12] = {0, 0, 0.25, 0, 0, 0.25, 0, 0, 0.25, 0, 0, 1};
    ck_assert_double_eq_tol(pl_rows_dot(&rows, 0, q), 0.75, 1e-15);
    /* B an obstacle point at z 0.5 moving along x: d and d_f from it */
    pl_rows_clear(&rows);
    pl_contact_side c = {0};
    c.fixed[2] = 0.5;
    c.fixed_v[0] = 2.0;
    ck_assert_int_eq(collision_emit_pair(&rows, NULL, &a, &c, n, 0.4, 0.002, t1, t2), 0);
    ck_assert_double_eq_tol(rows.d[0], 0.502, 1e-15);
    ck_assert_double_eq_tol(rows.d[1], 2.0 * t1[0], 1e-15);
    ck_assert_double_eq_tol(rows.d[2], 2.0 * t2[0], 1e-15);
    /* a vertex on both sides gets the difference; all cancelled: no rows */
    pl_rows_clear(&rows);
    pl_contact_side d = {0};
    d.n = 2, d.vertex[0] = 3, d.weight[0] = 0.25, d.vertex[1] = 5, d.weight[1] = 0.75;
    ck_assert_int_eq(collision_emit_pair(&rows, NULL, &a, &d, n, 0, 0, t1, t2), 0);
    ck_assert_int_eq(rows.start[1] - rows.start[0], 2);
    ck_assert_double_eq_tol(rows.coef[3 * rows.start[0] + 2], 0.75, 1e-15);
    ck_assert_double_eq_tol(rows.coef[3 * (rows.start[0] + 1) + 2], -0.75, 1e-15);
    pl_rows_clear(&rows);
    ck_assert_int_eq(collision_emit_pair(&rows, NULL, &a, &a, n, 0, 0, t1, t2), -2);
    ck_assert_int_eq(rows.n, 0);
    pl_rows_free(&rows);
}
END_TEST

/* Pairs written at offsets, in any order, after room was reserved
 * (collision_pair_write: the pipeline's parallel emission) give the rows of
 * collision_pair_append one by one, after a row another component began. */
START_TEST(test_pairs_written_at_offsets_are_the_appended_rows)
{
    enum { NP = 40 };
    pl_pair_rows pr[NP];
    for (int k = 0; k < NP; ++k) {
        pl_contact_side a = {0}, b = {0};
        a.n = 1 + k % 3;
        for (int j = 0; j < a.n; ++j) a.vertex[j] = 7 * k + j, a.weight[j] = 0.2 + 0.1 * j;
        b.n = 1 + (k + 1) % 3;
        for (int j = 0; j < b.n; ++j) b.vertex[j] = 300 + k + j, b.weight[j] = 0.5 - 0.1 * j;
        if (k % 5 == 0) b.vertex[0] = a.vertex[0], b.weight[0] = a.weight[0]; /* cancels: 0 */
        b.fixed[1] = 0.001 * k, b.fixed_v[0] = 0.1 * k;
        double n[3] = {sin(k), cos(k), 0.0};
        ck_assert_int_eq(collision_pair_prepare(&pr[k], &a, &b, n, 0.002), 0);
    }
    pl_component owner = {0}, cable = {0};
    pl_rows ap, wr;
    pl_rows_init(&ap);
    pl_rows_init(&wr);
    for (pl_rows *r = &ap; r; r = r == &ap ? &wr : NULL) { /* a row before the pairs */
        ck_assert_int_eq(pl_rows_begin(r, PL_ROW_BILATERAL, &cable), 0);
        ck_assert_int_eq(pl_rows_add(r, 3, 1.0, 2.0, 3.0), 0);
        r->compliance[0] = 1e-3;
    }
    int entries = 0, at[NP];
    for (int k = 0; k < NP; ++k) {
        ck_assert_int_eq(collision_pair_append(&ap, &owner, &pr[k], 0.1 * k), 1 + 3 * k);
        at[k] = wr.nent + entries;
        entries += collision_pair_entries(&pr[k]);
    }
    ck_assert_int_eq(ap.nent, wr.nent + entries);
    ck_assert_int_eq(pl_rows_reserve(&wr, 3 * NP, entries), 0);
    for (int k = NP - 1; k >= 0; --k) /* the last first: no pair leans on the one before */
        collision_pair_write(&wr, &owner, &pr[k], 0.1 * k, 1 + 3 * k, at[k]);
    wr.n += 3 * NP;
    wr.nent += entries;
    wr.start[wr.n] = wr.nent;
    same_rows(&ap, &wr, 1);
    pl_rows_free(&ap);
    pl_rows_free(&wr);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_push");
    TCase *tc = tcase_create("push");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_thin_triangle_keeps_each_side);
    tcase_add_test(tc, test_closed_surface_pushes_out);
    tcase_add_test(tc, test_point_over_a_thin_plate_has_one_side);
    tcase_add_test(tc, test_point_beside_a_corner_keeps_its_contact);
    tcase_add_test(tc, test_edge_beside_a_cube_keeps_its_side);
    tcase_add_test(tc, test_pair_rows);
    tcase_add_test(tc, test_pairs_written_at_offsets_are_the_appended_rows);
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
