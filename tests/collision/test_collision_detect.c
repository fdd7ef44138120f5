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
 *    farther is reported (static);
 *  - thin (two-sided) triangles push each point back to the side it starts
 *    on, also when the predicted motion crosses the triangle in one step;
 *    closed (one-sided) surfaces push shallow inside points out along the
 *    outward normal and ignore deep ones;
 *  (the sides kept at thin sheets' borders, from step to step and from the
 *  predicted end of a step: test_collision_sides.c)
 *  - the rows of a contact between two sides (collision_emit_pair):
 *    +w n on A, -w n on B, merged vertices, d and d_f from fixed parts. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "detect.h"

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / (double)0xffffff;
}

/* A sheet of n x n vertices over [0,1]^2 at height z0 with random bumps. */
typedef struct sheet {
    int nv, nt, ne;
    double *x0, *x1;
    int *tris, *edges;
} sheet;

static void make_sheet(sheet *s, int n, double z0, double bump, double motion, unsigned *seed)
{
    s->nv = n * n;
    s->nt = 2 * (n - 1) * (n - 1);
    s->x0 = malloc((size_t)s->nv * 3 * sizeof(double));
    s->x1 = malloc((size_t)s->nv * 3 * sizeof(double));
    s->tris = malloc((size_t)s->nt * 3 * sizeof(int));
    ck_assert(s->x0 && s->x1 && s->tris);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double *p = &s->x0[3 * (i + n * j)];
            p[0] = (double)i / (n - 1) + 0.2 * bump * (urand(seed) - 0.5);
            p[1] = (double)j / (n - 1) + 0.2 * bump * (urand(seed) - 0.5);
            p[2] = z0 + bump * (urand(seed) - 0.5);
            for (int k = 0; k < 3; ++k)
                s->x1[3 * (i + n * j) + k] = p[k] + motion * (urand(seed) - 0.5);
        }
    int t = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            int a = i + n * j, b = a + 1, c = a + n, d = c + 1;
            int *q = &s->tris[3 * t++];
            q[0] = a, q[1] = b, q[2] = d;
            q = &s->tris[3 * t++];
            q[0] = a, q[1] = d, q[2] = c;
        }
    ck_assert_int_eq(triangle_edges(s->tris, s->nt, &s->edges, &s->ne), PL_OK);
}

static void free_sheet(sheet *s)
{
    free(s->x0);
    free(s->x1);
    free(s->tris);
    free(s->edges);
}

static void to_mesh(const sheet *s, pl_coll_mesh *m, pl_mesh_sides sides, double alarm)
{
    coll_mesh_init(m);
    m->nverts = s->nv;
    m->ntris = s->nt;
    m->nedges = s->ne;
    m->x0 = s->x0;
    m->x1 = s->x1;
    m->tris = s->tris;
    m->edges = s->edges;
    m->sides = sides;
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(m, alarm, &err), PL_OK);
}

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
        double alarm = 0.02 + 0.03 * urand(&seed);
        sheet a, b;
        make_sheet(&a, 14 + trial % 5, 0.0, 0.15, trial % 3 ? 0.05 : 0.0, &seed);
        make_sheet(&b, 11 + trial % 4, 0.02, 0.15, 0.05, &seed);
        pl_coll_mesh ma, mb;
        to_mesh(&a, &ma, trial % 2 ? PL_SIDES_TWO : PL_SIDES_AUTO, alarm);
        to_mesh(&b, &mb, PL_SIDES_TWO, alarm);
        pl_detect_params prm = detect_defaults(alarm);
        pl_proximities p = {0}, q = {0};
        ck_assert_int_eq(detect_pair(&ma, 0, &mb, 1, &prm, &p), PL_OK);
        ck_assert_int_eq(detect_pair_brute(&ma, 0, &mb, 1, &prm, &q), PL_OK);
        ck_assert_int_gt(p.n, 10);
        expect_same(&p, &q);
        /* self-collision of one sheet */
        p.n = q.n = 0;
        ck_assert_int_eq(detect_pair(&ma, 0, &ma, 0, &prm, &p), PL_OK);
        ck_assert_int_eq(detect_pair_brute(&ma, 0, &ma, 0, &prm, &q), PL_OK);
        expect_same(&p, &q);
        for (int k = 0; k < p.n; ++k) /* nothing adjacent */
            for (int i = 0; i < p.items[k].na; ++i)
                for (int j = 0; j < p.items[k].nb; ++j)
                    ck_assert_int_ne(p.items[k].a[i], p.items[k].b[j]);
        proximities_free(&p);
        proximities_free(&q);
        coll_mesh_free(&ma);
        coll_mesh_free(&mb);
        free_sheet(&a);
        free_sheet(&b);
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
    sheet a, b;
    make_sheet(&a, 12, 0.0, 0.1, 0.0, &seed);
    make_sheet(&b, 9, 0.05, 0.1, 0.0, &seed);
    pl_coll_mesh ma, mb;
    to_mesh(&a, &ma, PL_SIDES_TWO, alarm);
    to_mesh(&b, &mb, PL_SIDES_TWO, alarm);
    pl_detect_params prm = detect_defaults(alarm);
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(&ma, 0, &mb, 1, &prm, &p), PL_OK);
    /* vertex-face, both directions */
    const sheet *S[2] = {&a, &b};
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
    for (int e = 0; e < a.ne; ++e)
        for (int f = 0; f < b.ne; ++f) {
            double s, t;
            const double *p0 = &a.x0[3 * a.edges[2 * e]], *p1 = &a.x0[3 * a.edges[2 * e + 1]];
            const double *q0 = &b.x0[3 * b.edges[2 * f]], *q1 = &b.x0[3 * b.edges[2 * f + 1]];
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
                         c2 > 0.04 * l2 && (ma.sharp[e] || mb.sharp[f]) && d > 0 &&
                         !(flat_on_face(&ma, e, p0, p1, q0, q1, s, t, d, q0, q1) &&
                           ends_near(q0, q1, p0, p1, alarm)) &&
                         !(flat_on_face(&mb, f, p0, p1, q0, q1, s, t, d, p0, p1) &&
                           ends_near(p0, p1, q0, q1, alarm));
            int got = 0;
            for (int k = 0; k < p.n; ++k)
                if (p.items[k].kind == PL_PROX_EDGE_EDGE && p.items[k].a[0] == a.edges[2 * e] &&
                    p.items[k].a[1] == a.edges[2 * e + 1] && p.items[k].b[0] == b.edges[2 * f] &&
                    p.items[k].b[1] == b.edges[2 * f + 1]) {
                    got++;
                    ck_assert_double_eq_tol(p.items[k].gap, d, 1e-12);
                }
            ck_assert_int_eq(got, expect);
            nee += expect;
        }
    ck_assert_int_gt(nvf, 20);
    ck_assert_int_gt(nee, 5);
    proximities_free(&p);
    coll_mesh_free(&ma);
    coll_mesh_free(&mb);
    free_sheet(&a);
    free_sheet(&b);
}
END_TEST

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

static Suite *suite(void)
{
    Suite *s = suite_create("collision_detect");
    TCase *tc = tcase_create("detect");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_bvh_detection_equals_brute_force);
    tcase_add_test(tc, test_static_detection_is_complete);
    tcase_add_test(tc, test_thin_triangle_keeps_each_side);
    tcase_add_test(tc, test_closed_surface_pushes_out);
    tcase_add_test(tc, test_point_over_a_thin_plate_has_one_side);
    tcase_add_test(tc, test_point_beside_a_corner_keeps_its_contact);
    tcase_add_test(tc, test_edge_beside_a_cube_keeps_its_side);
    tcase_add_test(tc, test_pair_rows);
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
