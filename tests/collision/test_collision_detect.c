/* test_collision_detect.c - mesh-versus-mesh detection of the collision
 * core on random configurations:
 *  - the BVH-based detection finds exactly what brute force over every
 *    primitive pair finds (random wavy sheets moving through each other,
 *    a closed box surface, self-collision of a folded sheet);
 *  - completeness against an independent reference: every vertex closer
 *    than alarmDistance to the other mesh has a vertex-face proximity whose
 *    gap is that distance (a vertex-vertex one from one direction only),
 *    every interior edge-edge pair closer than it with a sharp edge (here
 *    every sheet's boundary) has an edge-edge proximity, and nothing
 *    farther is reported (static).
 *  - the threads change nothing: a few edges over a fine sheet (an
 *    obstacle's edges under a cloth: thousands of candidates, measured by
 *    the threads in chunks) and the fine sheet's vertices (a pass shared by
 *    chunks) give with 4 threads the one thread's list, item by item in the
 *    same order, and brute force's set.
 * Which side a contact pushes to: test_collision_push.c; the sides kept at
 * thin sheets' borders: test_collision_sides.c. */
#include <check.h>
#include <math.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "detect.h"
#include "sheet_pair.h"

static int cmp_prox(const void *a, const void *b)
{
    const pl_proximity *x = a, *y = b;
    int kx[9] = {x->kind, x->model_a, x->model_b, x->a[0], x->a[1], x->b[0], x->b[1], x->b[2], 0};
    int ky[9] = {y->kind, y->model_a, y->model_b, y->a[0], y->a[1], y->b[0], y->b[1], y->b[2], 0};
    for (int k = 0; k < 8; ++k)
        if (kx[k] != ky[k]) return (kx[k] > ky[k]) - (kx[k] < ky[k]);
    return 0;
}

static void expect_same(pl_proximities *p, pl_proximities *q)
{
    ck_assert_int_eq(p->n, q->n);
    if (p->n == 0) return;
    qsort(p->items, (size_t)p->n, sizeof *p->items, cmp_prox);
    qsort(q->items, (size_t)q->n, sizeof *q->items, cmp_prox);
    for (int k = 0; k < p->n; ++k) {
        ck_assert_int_eq(cmp_prox(&p->items[k], &q->items[k]), 0);
        ck_assert(memcmp(&p->items[k], &q->items[k], sizeof p->items[k]) == 0);
    }
}

START_TEST(test_bvh_detection_equals_brute_force)
{
    unsigned seed = 2024u;
    for (int trial = 0; trial < 12; ++trial) {
        double alarm = 0.02 + 0.03 * sheet_urand(&seed);
        sheet_pair sp; /* sheets moved by 0.05 at random in each coordinate */
        sheet_make_ck(&sp.a, 14 + trial % 5, 0.0, 0.15, 0.0, trial % 3 ? 0.05 : 0.0, &seed);
        sheet_make_ck(&sp.b, 11 + trial % 4, 0.02, 0.15, 0.0, 0.05, &seed);
        sheet_pair_mesh(&sp, trial % 2 ? PL_SIDES_TWO : PL_SIDES_AUTO, alarm);
        pl_detect_params prm = detect_defaults(alarm);
        pl_proximities p = {0}, q = {0};
        ck_assert_int_eq(detect_pair(&sp.ma, 0, &sp.mb, 1, &prm, &p), PL_OK);
        ck_assert_int_eq(detect_pair_brute(&sp.ma, 0, &sp.mb, 1, &prm, &q), PL_OK);
        ck_assert_int_gt(p.n, 10);
        expect_same(&p, &q);
        /* self-collision of one sheet */
        p.n = q.n = 0;
        ck_assert_int_eq(detect_pair(&sp.ma, 0, &sp.ma, 0, &prm, &p), PL_OK);
        ck_assert_int_eq(detect_pair_brute(&sp.ma, 0, &sp.ma, 0, &prm, &q), PL_OK);
        expect_same(&p, &q);
        for (int k = 0; k < p.n; ++k) /* nothing adjacent */
            for (int i = 0; i < p.items[k].na; ++i)
                for (int j = 0; j < p.items[k].nb; ++j)
                    ck_assert_int_ne(p.items[k].a[i], p.items[k].b[j]);
        proximities_free(&p);
        proximities_free(&q);
        sheet_pair_free(&sp);
    }
}
END_TEST

/* The height of x over triangle tri of m; *over: its foot is inside (on
 * the inner side of the three edges, in the triangle's plane). */
static double height_over(const pl_coll_mesh *m, int tri, const double *x, int *over)
{
    const double *v[3] = {&m->x0[3 * m->tris[3 * tri]], &m->x0[3 * m->tris[3 * tri + 1]],
                          &m->x0[3 * m->tris[3 * tri + 2]]};
    const double *f = &m->fnormal[3 * tri];
    double h = 0.0;
    for (int k = 0; k < 3; ++k) h += (x[k] - v[0][k]) * f[k];
    *over = 1;
    for (int j = 0; j < 3; ++j) {
        const double *a = v[j], *b = v[(j + 1) % 3];
        double ed[3], ax[3], c[3];
        for (int k = 0; k < 3; ++k) ed[k] = b[k] - a[k], ax[k] = x[k] - h * f[k] - a[k];
        c[0] = ed[1] * ax[2] - ed[2] * ax[1];
        c[1] = ed[2] * ax[0] - ed[0] * ax[2];
        c[2] = ed[0] * ax[1] - ed[1] * ax[0];
        if (c[0] * f[0] + c[1] * f[1] + c[2] * f[2] < 0.0) *over = 0;
    }
    return h;
}

/* The edge-edge direction within 20 degrees of a face beside edge e of m
 * and, when m is a thin sheet, the other edge (o0 o1) over that face, both
 * ends on one side. */
static int flat_on_face(const pl_coll_mesh *m, int e, const double *p0, const double *p1,
                        const double *q0, const double *q1, double s, double t, double d,
                        const double *o0, const double *o1)
{
    double n[3];
    for (int k = 0; k < 3; ++k)
        n[k] = ((p0[k] + s * (p1[k] - p0[k])) - (q0[k] + t * (q1[k] - q0[k]))) / d;
    for (int j = 0; j < 2; ++j) {
        int tri = m->edge_tris[2 * e + j];
        if (tri < 0) continue;
        const double *f = &m->fnormal[3 * tri];
        if (!(fabs(n[0] * f[0] + n[1] * f[1] + n[2] * f[2]) > cos(20.0 * M_PI / 180.0))) continue;
        if (!m->two_sided) return 1; /* a closed surface: flat beside the edge suffices */
        int over0, over1;
        double h0 = height_over(m, tri, o0, &over0), h1 = height_over(m, tri, o1, &over1);
        if (over0 && over1 && h0 * h1 > 0.0) return 1;
    }
    return 0;
}

/* Both ends of p0 p1 within dist of segment q0 q1 (sampled: independent). */
static int ends_near(const double *p0, const double *p1, const double *q0, const double *q1,
                     double dist)
{
    const double *e[2] = {p0, p1};
    for (int k = 0; k < 2; ++k) {
        double best = INFINITY;
        for (int i = 0; i <= 2000; ++i) {
            double u = i / 2000.0, d2 = 0;
            for (int j = 0; j < 3; ++j) d2 += pow(e[k][j] - (q0[j] + u * (q1[j] - q0[j])), 2);
            best = fmin(best, d2);
        }
        if (!(best < dist * dist)) return 0;
    }
    return 1;
}

START_TEST(test_static_detection_is_complete)
{
    unsigned seed = 31u;
    const double alarm = 0.04;
    sheet_pair sp;
    sheet_make_ck(&sp.a, 12, 0.0, 0.1, 0.0, 0.0, &seed);
    sheet_make_ck(&sp.b, 9, 0.05, 0.1, 0.0, 0.0, &seed);
    sheet_pair_mesh(&sp, PL_SIDES_TWO, alarm);
    const sheet *a = &sp.a, *b = &sp.b;
    pl_coll_mesh *ma = &sp.ma, *mb = &sp.mb;
    pl_detect_params prm = detect_defaults(alarm);
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(ma, 0, mb, 1, &prm, &p), PL_OK);
    /* vertex-face, both directions */
    const sheet *S[2] = {a, b};
    int nvf = 0, nee = 0;
    for (int side = 0; side < 2; ++side) {
        const sheet *P = S[side], *T = S[1 - side];
        for (int v = 0; v < P->nv; ++v) {
            double best = INFINITY, w[3], wmax = 0;
            for (int t = 0; t < T->nt; ++t) {
                double d = sqrt(closest_point_triangle(&P->x0[3 * v], &T->x0[3 * T->tris[3 * t]],
                                                          &T->x0[3 * T->tris[3 * t + 1]],
                                                          &T->x0[3 * T->tris[3 * t + 2]], w));
                if (d < best) best = d, wmax = fmax(w[0], fmax(w[1], w[2]));
            }
            double found = INFINITY;
            for (int k = 0; k < p.n; ++k)
                if (p.items[k].kind == PL_PROX_VERTEX_FACE && p.items[k].model_a == side &&
                    p.items[k].a[0] == v)
                    found = fmin(found, p.items[k].gap);
            /* a vertex-vertex proximity is kept by the first direction only
             * (the same row twice would make W singular) */
            if (side == 1 && wmax > 1.0 - 1e-3) continue;
            if (best < alarm) {
                nvf++;
                ck_assert_msg(fabs(found - best) < 1e-12, "vertex %d of mesh %d: %g vs %g", v,
                              side, found, best);
            } else {
                ck_assert_msg(isinf(found), "vertex %d at %g got a contact", v, best);
            }
        }
    }
    /* edge-edge with interior closest points */
    for (int e = 0; e < a->ne; ++e)
        for (int f = 0; f < b->ne; ++f) {
            double s, t;
            const double *p0 = &a->x0[3 * a->edges[2 * e]], *p1 = &a->x0[3 * a->edges[2 * e + 1]];
            const double *q0 = &b->x0[3 * b->edges[2 * f]], *q1 = &b->x0[3 * b->edges[2 * f + 1]];
            double d = sqrt(closest_segments(p0, p1, q0, q1, &s, &t));
            double ea[3], eb[3], c[3];
            for (int k = 0; k < 3; ++k) ea[k] = p1[k] - p0[k], eb[k] = q1[k] - q0[k];
            c[0] = ea[1] * eb[2] - ea[2] * eb[1];
            c[1] = ea[2] * eb[0] - ea[0] * eb[2];
            c[2] = ea[0] * eb[1] - ea[1] * eb[0];
            double c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
            double l2 = (ea[0] * ea[0] + ea[1] * ea[1] + ea[2] * ea[2]) *
                        (eb[0] * eb[0] + eb[1] * eb[1] + eb[2] * eb[2]);
            int expect = d < alarm && s > 1e-3 && s < 1 - 1e-3 && t > 1e-3 && t < 1 - 1e-3 &&
                         c2 > 0.04 * l2 && (coll_edge_sharp(ma, e) || coll_edge_sharp(mb, f)) && d > 0 &&
                         !(flat_on_face(ma, e, p0, p1, q0, q1, s, t, d, q0, q1) &&
                           ends_near(q0, q1, p0, p1, alarm)) &&
                         !(flat_on_face(mb, f, p0, p1, q0, q1, s, t, d, p0, p1) &&
                           ends_near(p0, p1, q0, q1, alarm));
            int got = 0;
            for (int k = 0; k < p.n; ++k)
                if (p.items[k].kind == PL_PROX_EDGE_EDGE && p.items[k].a[0] == a->edges[2 * e] &&
                    p.items[k].a[1] == a->edges[2 * e + 1] && p.items[k].b[0] == b->edges[2 * f] &&
                    p.items[k].b[1] == b->edges[2 * f + 1]) {
                    got++;
                    ck_assert_double_eq_tol(p.items[k].gap, d, 1e-12);
                }
            ck_assert_int_eq(got, expect);
            nee += expect;
        }
    ck_assert_int_gt(nvf, 20);
    ck_assert_int_gt(nee, 5);
    proximities_free(&p);
    sheet_pair_free(&sp);
}
END_TEST

START_TEST(test_threads_give_the_serial_lists)
{
#ifdef _OPENMP
    unsigned seed = 77u;
    const double alarm = 0.08;
    sheet_pair sp; /* a: 3 x 3 vertices (16 edges), b: fine, 2 cm below, moving through */
    sheet_make_ck(&sp.a, 3, 0.0, 0.02, 0.0, 0.0, &seed);
    sheet_make_ck(&sp.b, 60, -0.02, 0.02, 0.03, 0.01, &seed);
    sheet_pair_mesh(&sp, PL_SIDES_TWO, alarm);
    pl_proximities p[2] = {{0}, {0}}, q = {0};
    pl_detect_counts counts[2] = {{0}, {0}};
    int saved = omp_get_max_threads();
    for (int k = 0; k < 2; ++k) {
        omp_set_num_threads(k ? 4 : 1);
        pl_detect_params prm = detect_defaults(alarm);
        prm.counts = &counts[k];
        ck_assert_int_eq(detect_pair(&sp.ma, 0, &sp.mb, 1, &prm, &p[k]), PL_OK);
    }
    omp_set_num_threads(saved);
    ck_assert_int_ge(counts[0].candidates, 2048); /* the edges' pass is measured wide */
    ck_assert(counts[1].candidates == counts[0].candidates);
    ck_assert_int_gt(p[0].n, 100);
    ck_assert_int_eq(p[1].n, p[0].n);
    for (int k = 0; k < p[0].n; ++k) /* the same order, bitwise */
        ck_assert(memcmp(&p[0].items[k], &p[1].items[k], sizeof p[0].items[k]) == 0);
    pl_detect_params prm = detect_defaults(alarm);
    ck_assert_int_eq(detect_pair_brute(&sp.ma, 0, &sp.mb, 1, &prm, &q), PL_OK);
    expect_same(&p[1], &q);
    proximities_free(&p[0]);
    proximities_free(&p[1]);
    proximities_free(&q);
    sheet_pair_free(&sp);
#endif
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_detect");
    TCase *tc = tcase_create("detect");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_bvh_detection_equals_brute_force);
    tcase_add_test(tc, test_static_detection_is_complete);
    tcase_add_test(tc, test_threads_give_the_serial_lists);
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
