/* test_collision_damaged_mesh.c - a mesh damaged on purpose as an obstacle
 * (issue 14 item 2).  A slab 20 x 5 x 20 cm, its top an 8 x 8 grid, carries
 * under and beside a soft block (Neo-Hookean, E 1e5, 4 cm) a duplicate
 * triangle, a reversed copy of another, a triangle with no area (three
 * vertices on a line), one with a repeated vertex, a fin (a third triangle on
 * an edge of the top, hanging into the slab) and a hole (a top triangle
 * missing: three border edges).  The block falls 8 mm onto it.  After 1 s
 * every block vertex must be slower than 1 cm/s and no vertex may have
 * crossed any triangle of the damaged mesh in any step (segment against
 * triangle, scene_check.c: not the detection's geometry).
 * The damage is what dragon.obj carries (docs/scenes.md); the dragon itself
 * is test_collision_messy_mesh. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"
#include "scene_check.h"

#define DT 0.005
#define STEPS 200 /* 1 s */
#define G 8       /* top and bottom grids: G x G cells */
#define HALF 0.1  /* half width [m] */
#define DEPTH 0.05

typedef struct slab {
    double x[3 * (2 * (G + 1) * (G + 1) + 1)];
    int tris[3 * 400], ntris, nverts;
} slab;

static int vid(int layer, int i, int j) { return layer * (G + 1) * (G + 1) + i * (G + 1) + j; }

/* Adds triangle a b c turned outward (away from the slab's centre): the
 * slab is convex, so the centre is behind every face. */
static void add(slab *s, int a, int b, int c)
{
    const double *p = &s->x[3 * a], *q = &s->x[3 * b], *r = &s->x[3 * c];
    double u[3], w[3], m[3];
    for (int k = 0; k < 3; ++k) u[k] = q[k] - p[k], w[k] = r[k] - p[k];
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                   u[0] * w[1] - u[1] * w[0]};
    for (int k = 0; k < 3; ++k) m[k] = (p[k] + q[k] + r[k]) / 3.0;
    m[1] += DEPTH / 2; /* from the centre (0, -DEPTH/2, 0) */
    int flip = n[0] * m[0] + n[1] * m[1] + n[2] * m[2] < 0.0;
    int *t = &s->tris[3 * s->ntris++];
    t[0] = a, t[1] = flip ? c : b, t[2] = flip ? b : c;
}

/* Two triangles per quad a b c d (in turn round it). */
static void quad(slab *s, int a, int b, int c, int d)
{
    add(s, a, b, c);
    add(s, a, c, d);
}

/* The closed slab, then the damage. */
static void make_slab(slab *s)
{
    s->ntris = 0;
    for (int l = 0; l < 2; ++l)
        for (int i = 0; i <= G; ++i)
            for (int j = 0; j <= G; ++j) {
                double *x = &s->x[3 * vid(l, i, j)];
                x[0] = -HALF + 2 * HALF * i / G, x[1] = l ? -DEPTH : 0.0;
                x[2] = -HALF + 2 * HALF * j / G;
            }
    s->nverts = 2 * (G + 1) * (G + 1);
    for (int l = 0; l < 2; ++l)
        for (int i = 0; i < G; ++i)
            for (int j = 0; j < G; ++j)
                if (!(l == 0 && i == G / 2 + 1 && j == G / 2)) /* the hole: one triangle left */
                    quad(s, vid(l, i, j), vid(l, i + 1, j), vid(l, i + 1, j + 1), vid(l, i, j + 1));
                else
                    add(s, vid(l, i, j), vid(l, i + 1, j), vid(l, i + 1, j + 1));
    for (int k = 0; k < G; ++k) { /* the four sides */
        quad(s, vid(0, k, 0), vid(0, k + 1, 0), vid(1, k + 1, 0), vid(1, k, 0));
        quad(s, vid(0, k, G), vid(0, k + 1, G), vid(1, k + 1, G), vid(1, k, G));
        quad(s, vid(0, 0, k), vid(0, 0, k + 1), vid(1, 0, k + 1), vid(1, 0, k));
        quad(s, vid(0, G, k), vid(0, G, k + 1), vid(1, G, k + 1), vid(1, G, k));
    }
    int c = G / 2;
    int *t = &s->tris[3 * s->ntris];
    /* a duplicate of a top triangle under the block, a reversed copy of
     * another, no area (a row of the grid), a repeated vertex */
    memcpy(t, &s->tris[3 * (2 * (c * G + c))], 3 * sizeof *t);
    t[3] = s->tris[3 * (2 * ((c - 1) * G + c)) + 2];
    t[4] = s->tris[3 * (2 * ((c - 1) * G + c)) + 1];
    t[5] = s->tris[3 * (2 * ((c - 1) * G + c))];
    t[6] = vid(0, c - 1, c), t[7] = vid(0, c, c), t[8] = vid(0, c + 1, c);
    t[9] = vid(0, c, c), t[10] = vid(0, c, c), t[11] = vid(0, c, c + 1);
    s->ntris += 4;
    /* a fin on the top edge (c, c)-(c, c + 1), its tip 3 cm down inside */
    double *tip = &s->x[3 * s->nverts];
    tip[0] = 0.0, tip[1] = -0.03, tip[2] = HALF / G / 2;
    t = &s->tris[3 * s->ntris++];
    t[0] = vid(0, c, c), t[1] = vid(0, c, c + 1), t[2] = s->nverts++;
}

static pl_sim *load(const slab *s, const char *sides)
{
    size_t cap = 64 * 1024;
    char *xml = malloc(cap);
    ck_assert_ptr_nonnull(xml);
    int n = snprintf(
        xml, cap,
        "<Node name='root' dt='0.005' gravity='0 -9.81 0'>"
        "<RequiredPlugin name='hyperelastic'/><RequiredPlugin name='sparse_inverse'/>"
        "<RequiredPlugin name='ncp_contact'/><RequiredPlugin name='collision'/>"
        "<LocalGlobalSolver name='solver' iterations='10'/><SparseInverseSolver name='global'/>"
        "<NonSmoothNewtonContactSolver name='contact' ncp='fischer-burmeister' crIterations='24' "
        "preconditioner='delassus'/>"
        "<CollisionPipeline name='pipeline' alarmDistance='0.005' contactDistance='0.0005' "
        "mu='0.5'/><Node name='slab'><MeshObstacle name='obstacle' sides='%s' position='",
        sides);
    for (int i = 0; i < s->nverts; ++i)
        n += snprintf(xml + n, cap - (size_t)n, "%.17g %.17g %.17g ", s->x[3 * i],
                      s->x[3 * i + 1], s->x[3 * i + 2]);
    n += snprintf(xml + n, cap - (size_t)n, "' triangles='");
    for (int k = 0; k < 3 * s->ntris; ++k) n += snprintf(xml + n, cap - (size_t)n, "%d ", s->tris[k]);
    n += snprintf(xml + n, cap - (size_t)n,
                  "'/></Node><Node name='block'><RegularGridTetrahedra name='mesh' "
                  "min='-0.02 0.008 -0.02' max='0.02 0.048 0.02' n='4 4 4'/>"
                  "<MechanicalObject name='dofs' src='@mesh'/><DiagonalMass massDensity='1000'/>"
                  "<NeoHookean name='material' youngModulus='1e5' poissonRatio='0.4'/>"
                  "<SurfaceCollisionModel name='surface'/></Node></Node>");
    ck_assert_uint_lt((size_t)n, cap);
    pl_sim *sim = ct_load(xml, NULL, 0);
    free(xml);
    return sim;
}

/* Steps 1 s; returns the fastest vertex at the end, *crossings the vertex
 * steps through a triangle of s. */
static double run(const slab *s, const char *sides, int *crossings)
{
    pl_sim *sim = load(s, sides);
    int n;
    double *x = ct_positions(sim, "block/dofs", &n), *prev = malloc((size_t)n * 3 * sizeof *prev);
    ck_assert_ptr_nonnull(prev);
    *crossings = 0;
    for (int step = 0; step < STEPS; ++step) {
        memcpy(prev, x, (size_t)n * 3 * sizeof *prev);
        pl_error err;
        ck_assert_int_eq(pl_sim_step(sim, 1, &err), PL_OK);
        x = ct_positions(sim, "block/dofs", &n);
        for (int i = 0; i < n; ++i)
            for (int t = 0; t < s->ntris; ++t)
                *crossings += sc_segment_hits_triangle(&prev[3 * i], &x[3 * i],
                                                       &s->x[3 * s->tris[3 * t]],
                                                       &s->x[3 * s->tris[3 * t + 1]],
                                                       &s->x[3 * s->tris[3 * t + 2]]);
    }
    double vmax = 0.0;
    for (int i = 0; i < n; ++i) {
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k) d2 += (x[3 * i + k] - prev[3 * i + k]) * (x[3 * i + k] - prev[3 * i + k]);
        vmax = fmax(vmax, sqrt(d2) / DT);
    }
    free(prev);
    pl_sim_free(sim);
    return vmax;
}

START_TEST(test_block_rests_on_a_damaged_slab)
{
    static slab s;
    make_slab(&s);
    const char *sides = getenv("SIDES") ? getenv("SIDES") : "auto";
    int crossings;
    double vmax = run(&s, sides, &crossings);
    printf("block on the damaged slab (sides %s): after 1 s fastest vertex %.2e m/s, %d vertex "
           "steps through\n",
           sides, vmax, crossings);
    ck_assert_msg(crossings == 0, "%d block vertex steps crossed the slab", crossings);
    ck_assert_msg(vmax < 0.01, "a block vertex still moves at %g m/s after 1 s", vmax);
}
END_TEST

int main(void)
{
    Suite *su = suite_create("collision_damaged_mesh");
    TCase *tc = tcase_create("damaged");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_block_rests_on_a_damaged_slab);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
