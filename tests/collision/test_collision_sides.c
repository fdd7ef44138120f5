/* test_collision_sides.c - which side of a thin (two-sided) sheet a contact
 * keeps, on small hand-made configurations:
 *  - a blade's border rule looks where an edge crosses the blade's plane:
 *    through the blade it is pushed out beyond the border, beside its corner
 *    it is left alone;
 *  - a cloth edge wrapped round a blade's border keeps its edge-edge row;
 *  - a vertex under a sheet keeps its side on a neighbouring triangle (the
 *    side memory's neighbour fallback);
 *  - with the predicted end of the step: an edge turning about its end gets
 *    an edge-edge row where the edges will be closest, and a vertex under a
 *    sliding sheet a row at the point it will be under;
 *  - a blade's corner under several layers of a cloth keeps a row with each.
 * Each test fails without the rule it checks (tried when they were added). */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "detect.h"

/* A rigid blade in the plane x = 0 (corner (0,0,0), bottom edge 0-1 along z
 * at y = 0, slanted edge 0-2 along y = z) and one free edge near it.
 * Returns the gap of the edge-edge proximity with the blade's edge b0-b1
 * (NAN if none). */
static double blade_edge_gap(const double q0[3], const double q1[3], int b0, int b1)
{
    double bx[9] = {0, 0, 0, 0, 0, 1, 0, 1, 1}, ex[6];
    int btri[3] = {0, 1, 2}, bedges[6] = {0, 1, 0, 2, 1, 2}, eedge[2] = {0, 1};
    unsigned char rigid[3] = {0, 0, 0};
    memcpy(ex, q0, 3 * sizeof(double));
    memcpy(ex + 3, q1, 3 * sizeof(double));
    pl_coll_mesh B, E;
    coll_mesh_init(&B);
    coll_mesh_init(&E);
    B.nverts = 3, B.ntris = 1, B.nedges = 3, B.x0 = B.x1 = bx, B.tris = btri, B.edges = bedges;
    B.active = rigid, B.sides = PL_SIDES_TWO;
    E.nverts = 2, E.nedges = 1, E.x0 = E.x1 = ex, E.edges = eedge, E.sides = PL_SIDES_TWO;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&B, 0.05, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&E, 0.05, &err), PL_OK);
    pl_detect_params prm = detect_defaults(0.05);
    prm.vertex_face = 0;
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&E, 0, &B, 1, &prm, &p), PL_OK);
    double gap = NAN;
    for (int k = 0; k < p.n; ++k)
        if (p.items[k].kind == PL_PROX_EDGE_EDGE && p.items[k].b[0] == b0 && p.items[k].b[1] == b1)
            gap = p.items[k].gap;
    proximities_free(&p);
    coll_mesh_free(&B);
    coll_mesh_free(&E);
    return gap;
}

/* The gap with the blade's bottom edge (blade_edge_gap). */
static double blade_bottom_gap(const double q0[3], const double q1[3])
{
    return blade_edge_gap(q0, q1, 0, 1);
}

/* The border rule of a blade's edge: an edge through the blade near its
 * bottom edge belongs below it (pushed out: negative gap); an edge wrapped
 * around the blade's corner, crossing the plane beyond the slanted edge but
 * above the bottom edge, is in a legal place: the bottom edge must not
 * claim it (it used to be pulled down through the corner). */
START_TEST(test_blade_border_rule_looks_where_an_edge_crosses)
{
    /* crossing at (0, 0.01, 0.5): inside the blade, 1 cm above its bottom edge */
    double a0[3] = {-0.01, 0.02, 0.45}, a1[3] = {0.01, 0.0, 0.55};
    double g = blade_bottom_gap(a0, a1);
    ck_assert_msg(g < 0.0, "through the blade: gap %g", g);
    /* crossing at (0, 0.02, 0.01): beside the corner, beyond the slanted
     * edge, 2 cm from the bottom edge's line */
    double b0[3] = {-0.01, 0.02, 0.005}, b1[3] = {0.01, 0.02, 0.015};
    g = blade_bottom_gap(b0, b1);
    ck_assert_msg(fabs(g - 0.02) < 1e-12, "beside the corner: gap %g", g);
}
END_TEST

/* A cloth edge wrapped round a blade's border, its closest-point direction
 * with the blade's edge within 20 degrees of the blade's normal and both
 * ends near that edge, but not lying over the blade: the contacts of its
 * ends do not hold it, the edge-edge row must exist.  Once dropped as "flat
 * on the face" (cloth_on_knives.xml: a cloth edge 6.8 mm through a blade
 * below its slanted edge, another round its bottom edge). */
START_TEST(test_edge_wrapped_round_a_blade_border_keeps_its_row)
{
    /* one end 3 mm beyond the slanted edge on the -x side, the other over
     * the blade on the +x side: the edge crosses the blade's plane 4 mm
     * inside the blade (through it), to be pushed out: a negative gap */
    const double r = sqrt(0.5), P[3] = {0.0, 0.5, 0.5};
    const double o[3] = {0, 0, 0}, apex[3] = {0, 1, 1}, end[3] = {0, 0, 1};
    double a0[3] = {-0.0023, P[1] + 0.003 * r, P[2] - 0.003 * r};
    double a1[3] = {0.002, P[1] - 0.01 * r + 0.016 * r, P[2] + 0.01 * r + 0.016 * r};
    double s, t, d = sqrt(closest_segments(o, apex, a0, a1, &s, &t));
    ck_assert(s > 0.01 && s < 0.99 && t > 0.01 && t < 0.99 && d < 0.005);
    double g = blade_edge_gap(a0, a1, 0, 2);
    ck_assert_msg(g < 0.0 && fabs(g) <= d + 1e-12, "through the blade: gap %g", g);
    /* both ends on the +x side, one over the blade, the other 8 mm below its
     * bottom edge: the edge passes the bottom edge 1.4 mm from it and keeps
     * that side */
    double b0[3] = {0.002, 0.01, 0.5}, b1[3] = {0.001, -0.008, 0.52};
    d = sqrt(closest_segments(o, end, b0, b1, &s, &t));
    g = blade_bottom_gap(b0, b1);
    ck_assert_msg(fabs(g - d) < 1e-12, "round the bottom edge: gap %g, distance %g", g, d);
}
END_TEST

/* Side hints holding one vertex-face contact of vertex 0 (model 0) with
 * triangle b of model 1, from below (normal -z, side -1). */
static void hint_from_below(pl_side_hints *h, int b0, int b1, int b2)
{
    pl_proximity prev;
    memset(&prev, 0, sizeof prev);
    prev.kind = PL_PROX_VERTEX_FACE, prev.model_a = 0, prev.model_b = 1, prev.na = 1, prev.nb = 3;
    prev.b[0] = b0, prev.b[1] = b1, prev.b[2] = b2;
    prev.normal[2] = -1.0, prev.gap = 0.001, prev.side = -1;
    side_hints_init(h);
    ck_assert_int_eq(side_hints_build(h, &prev, 1), PL_OK);
}

static void sort3(int b[3])
{
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (b[j] < b[i]) {
                int t = b[i];
                b[i] = b[j];
                b[j] = t;
            }
}

/* Brute force of side_hints_find_near over items[0..n-1]: the same
 * vertex's contact (kind, models, vertex) whose triangle shares the most
 * vertices with p's (1 or 2) and has a side; ties: the smallest triangle
 * (b in order), then the first given. */
static const pl_proximity *near_brute(const pl_proximity *items, int n, const pl_proximity *p)
{
    const pl_proximity *best = NULL;
    int shared = 0;
    for (int k = 0; k < n; ++k) {
        const pl_proximity *q = &items[k];
        if (q->kind != PL_PROX_VERTEX_FACE || q->model_a != p->model_a ||
            q->model_b != p->model_b || q->a[0] != p->a[0] || q->side == 0)
            continue;
        int s = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) s += q->b[i] == p->b[j];
        if (s >= 3 || s < shared || s == 0) continue;
        if (s == shared && memcmp(q->b, best->b, sizeof q->b) >= 0) continue;
        best = q, shared = s;
    }
    return best;
}

/* Many hints given out of order (the build sorts them by merging runs and
 * hashes them on the threads from 2048): every lookup is the brute force's,
 * find_near's and find's (the last given with the same identity). */
START_TEST(test_many_hints_out_of_order_as_brute_force)
{
    enum { N = 3000 };
    pl_proximity *items = calloc(N, sizeof *items);
    unsigned x = 12345u;
    for (int k = 0; k < N; ++k) {
        pl_proximity *q = &items[k];
        x = x * 1103515245u + 12345u;
        q->kind = (x >> 7) % 8 ? PL_PROX_VERTEX_FACE : PL_PROX_EDGE_EDGE;
        q->model_a = (x >> 11) % 2, q->model_b = 2;
        q->na = q->kind == PL_PROX_VERTEX_FACE ? 1 : 2, q->nb = q->na == 1 ? 3 : 2;
        q->a[0] = (x >> 13) % 300, q->a[1] = q->na == 2 ? q->a[0] + 1 : 0;
        for (int i = 0; i < q->nb; ++i) q->b[i] = (int)((x >> (16 + 2 * i)) % 12) + 4 * i;
        q->side = (int)((x >> 24) % 3) - 1;
        q->normal[2] = k;
    }
    pl_side_hints h;
    side_hints_init(&h);
    ck_assert_int_eq(side_hints_build(&h, items, N), PL_OK);
    for (int k = 0; k < N; ++k) {
        const pl_proximity *p = &items[k], *want = near_brute(items, N, p);
        const pl_proximity *got = side_hints_find_near(&h, p);
        if (p->kind != PL_PROX_VERTEX_FACE) want = NULL;
        ck_assert_msg((got == NULL) == (want == NULL), "item %d: near %p, brute %p", k,
                      (const void *)got, (const void *)want);
        if (got) ck_assert_double_eq(got->normal[2], want->normal[2]);
        const pl_proximity *f = side_hints_find(&h, p);
        ck_assert_ptr_nonnull(f);
        int last = -1; /* the last given with p's identity */
        for (int j = 0; j < N; ++j) {
            const pl_proximity *q = &items[j];
            int b1[3] = {q->b[0], q->b[1], q->nb == 3 ? q->b[2] : -1};
            int b2[3] = {p->b[0], p->b[1], p->nb == 3 ? p->b[2] : -1};
            sort3(b1), sort3(b2); /* a triangle whatever vertex comes first */
            if (q->kind == p->kind && q->model_a == p->model_a && q->model_b == p->model_b &&
                q->a[0] == p->a[0] && (q->na > 1 ? q->a[1] : -1) == (p->na > 1 ? p->a[1] : -1) &&
                !memcmp(b1, b2, sizeof b1))
                last = j;
        }
        ck_assert_double_eq(f->normal[2], (double)last);
    }
    side_hints_free(&h);
    free(items);
}
END_TEST

/* A vertex under a thin sheet (in contact with triangle t1 from below last
 * step) that has slid under the neighbouring triangle t2 and a little
 * through it keeps its side: t2 takes the side of its neighbour t1. */
START_TEST(test_side_of_a_neighbouring_triangle)
{
    double sx[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    int stris[6] = {0, 1, 3, 0, 3, 2}, *sedges, sne;
    ck_assert_int_eq(triangle_edges(stris, 2, &sedges, &sne), PL_OK);
    double px[3] = {0.3, 0.7, 0.002}; /* over t2 (y > x), 2 mm above: through */
    pl_coll_mesh S, P;
    coll_mesh_init(&S);
    coll_mesh_init(&P);
    S.nverts = 4, S.ntris = 2, S.nedges = sne, S.x0 = S.x1 = sx, S.tris = stris, S.edges = sedges;
    S.sides = PL_SIDES_TWO;
    P.nverts = 1, P.x0 = P.x1 = px;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&S, 0.01, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
    pl_side_hints h;
    hint_from_below(&h, 0, 1, 3); /* t1 */
    for (int with = 0; with < 2; ++with) {
        pl_detect_params prm = detect_defaults(0.01);
        prm.hints = with ? &h : NULL;
        pl_proximities p = {0};
        ck_assert_int_eq(detect_pair(&P, 0, &S, 1, &prm, &p), PL_OK);
        ck_assert_int_ge(p.n, 1);
        const pl_proximity *q = &p.items[0];
        ck_assert_int_eq(q->b[0] + q->b[1] + q->b[2], 0 + 3 + 2); /* t2 */
        /* without the memory: above, as it is now; with it: below, 2 mm through */
        ck_assert_double_eq_tol(q->normal[2], with ? -1.0 : 1.0, 1e-12);
        ck_assert_double_eq_tol(q->gap, with ? -0.002 : 0.002, 1e-12);
        ck_assert_int_eq(q->side, with ? -1 : 1);
        proximities_free(&p);
    }
    side_hints_free(&h);
    coll_mesh_free(&S);
    coll_mesh_free(&P);
    free(sedges);
}
END_TEST

/* An edge that turns about its end vertex, which sits at a blade edge's
 * end now: the closest points are at the ends (no edge-edge row from the
 * start of the step), but at the predicted end of the step the edges cross
 * in their insides, so the row is made there. */
START_TEST(test_edge_turning_about_its_end_gets_a_row)
{
    /* a blade in the plane x = 0; its edge 0-1 runs up the y axis to the apex (0, 1, 0) */
    double bx[9] = {0, 0, 0, 0, 1, 0, 0, 0, 1};
    int btri[3] = {0, 1, 2}, be[6] = {0, 1, 0, 2, 1, 2};
    unsigned char rigid[3] = {0, 0, 0};
    /* the free edge from beside the apex down along -x now, predicted to
     * sweep across the blade edge, closest to it at y = 0.9 */
    double ex0[6] = {0.003, 1.003, 0.0, -0.3, 0.9, 0.0}, ex1[6] = {0.05, 1.0, 0.0, -0.05, 0.8, 0.001};
    int ee[2] = {0, 1};
    pl_coll_mesh B, E;
    coll_mesh_init(&B);
    coll_mesh_init(&E);
    B.nverts = 3, B.ntris = 1, B.nedges = 3, B.x0 = B.x1 = bx, B.tris = btri, B.edges = be;
    B.active = rigid, B.sides = PL_SIDES_TWO;
    E.nverts = 2, E.nedges = 1, E.x0 = ex0, E.x1 = ex1, E.edges = ee, E.sides = PL_SIDES_TWO;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&B, 0.05, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&E, 0.05, &err), PL_OK);
    pl_detect_params prm = detect_defaults(0.05);
    prm.vertex_face = 0;
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&E, 0, &B, 1, &prm, &p), PL_OK);
    int found = 0;
    for (int k = 0; k < p.n; ++k)
        if (p.items[k].kind == PL_PROX_EDGE_EDGE && p.items[k].b[0] == 0 && p.items[k].b[1] == 1) {
            /* inside both edges: not at the apex, not at the free edge's end */
            ck_assert_double_eq_tol(p.items[k].wb[1], 0.9, 1e-3);
            ck_assert(p.items[k].wa[1] > 0.01 && p.items[k].wa[1] < 0.99);
            found = 1;
        }
    ck_assert_msg(found, "no edge-edge row with the blade edge (%d proximities)", p.n);
    proximities_free(&p);
    coll_mesh_free(&B);
    coll_mesh_free(&E);
}
END_TEST

/* A blade's apex under a thin sheet, at a triangle's corner now, predicted
 * to be under the triangle's inside at the end of the step (the sheet
 * slides over it): the row holds the predicted point, on the remembered
 * side. */
START_TEST(test_vertex_under_a_sliding_sheet)
{
    double sx0[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, sx1[9];
    for (int k = 0; k < 9; k += 3) sx1[k] = sx0[k] - 0.3, sx1[k + 1] = sx0[k + 1] - 0.3, sx1[k + 2] = 0.0;
    int stri[3] = {0, 1, 2}, *sedges, sne;
    ck_assert_int_eq(triangle_edges(stri, 1, &sedges, &sne), PL_OK);
    double px[3] = {0.01, 0.01, -0.003}; /* under the corner, 3 mm below */
    unsigned char rigid[1] = {0};
    pl_coll_mesh S, P;
    coll_mesh_init(&S);
    coll_mesh_init(&P);
    S.nverts = 3, S.ntris = 1, S.nedges = sne, S.x0 = sx0, S.x1 = sx1, S.tris = stri, S.edges = sedges;
    S.sides = PL_SIDES_TWO;
    P.nverts = 1, P.x0 = P.x1 = px, P.active = rigid;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&S, 0.01, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
    pl_side_hints h;
    hint_from_below(&h, 0, 1, 2);
    pl_detect_params prm = detect_defaults(0.01);
    prm.hints = &h;
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&P, 0, &S, 1, &prm, &p), PL_OK);
    ck_assert_int_eq(p.n, 1);
    /* at the end of the step the apex is under (0.31, 0.31) of the sheet */
    ck_assert_double_eq_tol(p.items[0].wb[1], 0.31, 1e-12);
    ck_assert_double_eq_tol(p.items[0].wb[2], 0.31, 1e-12);
    ck_assert_double_eq_tol(p.items[0].normal[2], -1.0, 1e-12);
    ck_assert_double_eq_tol(p.items[0].gap, 0.003, 1e-12);
    proximities_free(&p);
    side_hints_free(&h);
    coll_mesh_free(&S);
    coll_mesh_free(&P);
    free(sedges);
}
END_TEST

/* A blade's corner (no DOF) under four layers of a cloth crumpled round
 * it, their triangles sharing no vertex, 1 to 2.5 mm above it and tilted
 * by at most 17 degrees: each layer needs its row (their rows act on
 * different vertices, none a combination of the others).  The per-vertex
 * rule (nearest, then only faces with a different normal, three at most)
 * kept the nearest alone, and on cloth_on_knives.xml a blade's apex came
 * 6 mm through the face it was under.  A vertex with DOFs keeps that rule
 * (its rows would all act on it along nearly the same normal). */
START_TEST(test_corner_under_cloth_layers_keeps_each)
{
    const double h[4] = {0.001, 0.0015, 0.002, 0.0025}, a[4] = {0.0, 0.2, -0.2, 0.3};
    double sx[36];
    int stris[12];
    for (int k = 0; k < 4; ++k) { /* in the plane y = h + a z, round (0, h, 0) */
        const double v[3][2] = {{-0.01, -0.01}, {0.0, 0.015}, {0.01, -0.01}};
        for (int j = 0; j < 3; ++j) {
            sx[9 * k + 3 * j] = v[j][0];
            sx[9 * k + 3 * j + 1] = h[k] + a[k] * v[j][1];
            sx[9 * k + 3 * j + 2] = v[j][1];
            stris[3 * k + j] = 3 * k + j;
        }
    }
    int *sedges, sne;
    ck_assert_int_eq(triangle_edges(stris, 4, &sedges, &sne), PL_OK);
    double px[3] = {0.0, 0.0, 0.0};
    unsigned char rigid[1] = {0};
    for (int dof = 0; dof < 2; ++dof) {
        pl_coll_mesh S, P;
        coll_mesh_init(&S);
        coll_mesh_init(&P);
        S.nverts = 12, S.ntris = 4, S.nedges = sne, S.x0 = S.x1 = sx, S.tris = stris;
        S.edges = sedges, S.sides = PL_SIDES_TWO;
        P.nverts = 1, P.x0 = P.x1 = px, P.active = dof ? NULL : rigid;
        pl_error err;
        ck_assert_int_eq(coll_mesh_prepare(&S, 0.01, &err), PL_OK);
        ck_assert_int_eq(coll_mesh_prepare(&P, 0.01, &err), PL_OK);
        pl_detect_params prm = detect_defaults(0.01);
        pl_proximities p = {0};
        ck_assert_int_eq(detect_pair(&P, 0, &S, 1, &prm, &p), PL_OK);
        int want = dof ? 1 : 4;
        ck_assert_int_eq(p.n, want);
        for (int i = 0; i < p.n; ++i) {
            int k = p.items[i].b[0] / 3;
            ck_assert_double_eq_tol(p.items[i].gap, h[k] / sqrt(1.0 + a[k] * a[k]), 1e-12);
            ck_assert(p.items[i].normal[1] < -0.9); /* the cloth above the corner */
        }
        if (dof) ck_assert_int_eq(p.items[0].b[0], 0); /* the nearest */
        proximities_free(&p);
        coll_mesh_free(&S);
        coll_mesh_free(&P);
    }
    free(sedges);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_sides");
    TCase *tc = tcase_create("sides");
    tcase_add_test(tc, test_blade_border_rule_looks_where_an_edge_crosses);
    tcase_add_test(tc, test_edge_wrapped_round_a_blade_border_keeps_its_row);
    tcase_add_test(tc, test_side_of_a_neighbouring_triangle);
    tcase_add_test(tc, test_many_hints_out_of_order_as_brute_force);
    tcase_add_test(tc, test_edge_turning_about_its_end_gets_a_row);
    tcase_add_test(tc, test_vertex_under_a_sliding_sheet);
    tcase_add_test(tc, test_corner_under_cloth_layers_keeps_each);
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
