/* test_collision_messy_mesh.c - a messy real mesh as an obstacle (issue 14
 * item 2).  A soft ball (Neo-Hookean, E 1e5, radius 2.5 cm, 120 vertices)
 * is dropped onto dragon.obj (scenes/meshes, Stanford geometry via SOFA:
 * 38 duplicate triangles, 102 edges of 4-8 triangles, 26 border edges,
 * 106 pairs of triangles crossing each other) scaled to 0.46 m, a
 * MeshObstacle standing on a floor.  After 1 s every ball vertex must be
 * slower than 1 cm/s, the ball must lie on the dragon (its lowest vertex
 * well above the floor), and no vertex may have crossed a triangle of the
 * file as written (duplicates included) in any step (segment against
 * triangle, scene_check.c, not the detection's geometry).
 * Where: a ball rolls on any slope, so it is dropped over a pocket of the
 * dragon's feet where it can rest.  The pocket was found from the file
 * alone (the lowest place a 2.5 cm ball can sit on the upper surface, on a
 * 2 mm grid); the ball starts 3 mm (exact point-triangle distance) clear
 * of every triangle, 6.5 cm over the pocket, rolls in and rests at (0.116,
 * -0.068, 0.019) m touching triangles of non-manifold edges and duplicates
 * (1988 and 2213 of the file: 0.2 mm inside their planes at rest).
 * Measured: 1.8e-6 m/s after 1 s, no crossing.  With sides="two" the ball
 * is thrown out (8e3 m/s, 260 vertex steps through); with the cleaning on
 * load switched off, "auto" reads the file as open, two-sided, and the ball
 * jitters (3.1 m/s, 1506 vertex steps through).
 * What does not pass yet (docs/scenes.md): 2 cm away, where open borders
 * and crossing triangles make a tangle, a 2 cm ball dropped at (0.124,
 * -0.059, 0.024) goes into the solid (its centre's winding number 0.93)
 * and jitters (1.4 m/s, 12150 vertex steps through).  The block of this
 * test's first version slid off the dragon's back (steeper than the
 * friction angle) and on along the floor: 0.92 m/s after 1 s, motion, not
 * jitter.
 * Environment (to explore): BALL="x y z" and R (the ball), SIDES, DBG=1
 * (the ball's centre and fastest vertex every 10 steps). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"
#include "scene_check.h"

#define DT 0.005
#define STEPS 200 /* 1 s */
#define FLOOR -0.148 /* under the dragon: its lowest point, scaled [m] */

static const char *HEAD =
    "<Node name='root' dt='0.005' gravity='0 -9.81 0'>"
    "<RequiredPlugin name='hyperelastic'/><RequiredPlugin name='sparse_inverse'/>"
    "<RequiredPlugin name='ncp_contact'/><RequiredPlugin name='collision'/>"
    "<LocalGlobalSolver name='solver' iterations='10'/><SparseInverseSolver name='global'/>"
    "<NonSmoothNewtonContactSolver name='contact' ncp='fischer-burmeister' crIterations='24' "
    "preconditioner='delassus'/>"
    "<CollisionPipeline name='pipeline' alarmDistance='0.005' contactDistance='0.0005' "
    "mu='0.5'/>";

/* A soft ball (Neo-Hookean, E 1e5), centre c, radius r. */
static int ball(char *out, size_t size, const double c[3], double r)
{
    return snprintf(out, size,
                    "<Node name='ball'><SphereMesh name='mesh' center='%.9g %.9g %.9g' "
                    "radius='%g' volume='1' vertices='120'/>"
                    "<MechanicalObject name='dofs' src='@mesh'/>"
                    "<DiagonalMass massDensity='1000'/>"
                    "<NeoHookean name='material' youngModulus='1e5' poissonRatio='0.4'/>"
                    "<SurfaceCollisionModel name='surface'/></Node>",
                    c[0], c[1], c[2], r);
}

/* The obstacle's triangles as the file has them (positions, indices). */
typedef struct obstacle {
    double *x;
    int *tris, ntris;
} obstacle;

typedef struct result {
    double vmax;     /* fastest vertex after 1 s [m/s] */
    int crossings;   /* vertex steps that crossed an obstacle triangle */
    double lowest;   /* lowest ball vertex after 1 s [m] */
} result;

/* Whether the boxes of segment p q and triangle t are apart along an axis
 * (then the segment cannot cross it; only saves time). */
static int apart(const double *p, const double *q, const obstacle *ob, int t)
{
    for (int k = 0; k < 3; ++k) {
        double lo = fmin(p[k], q[k]), hi = fmax(p[k], q[k]);
        const double *a = &ob->x[3 * ob->tris[3 * t]], *b = &ob->x[3 * ob->tris[3 * t + 1]],
                     *c = &ob->x[3 * ob->tris[3 * t + 2]];
        if (fmin(a[k], fmin(b[k], c[k])) > hi || fmax(a[k], fmax(b[k], c[k])) < lo) return 1;
    }
    return 0;
}

static void run(const char *xml, const obstacle *ob, result *r)
{
    pl_sim *sim = ct_load(xml, NULL, 0);
    pl_component *st = pl_sim_component(sim, "ball/dofs");
    ck_assert_ptr_nonnull(st);
    const pl_state_ops *ops = pl_component_role(st, PL_ROLE_STATE);
    pl_buffer b = ops->positions(st, pl_sim_data(sim));
    int n = (int)b.rows;
    double *prev = malloc((size_t)n * 3 * sizeof *prev);
    ck_assert_ptr_nonnull(prev);
    memset(r, 0, sizeof *r);
    r->lowest = INFINITY;
    for (int step = 0; step < STEPS; ++step) {
        b = ops->positions(st, pl_sim_data(sim));
        memcpy(prev, pl_buffer_f64(&b), (size_t)n * 3 * sizeof *prev);
        pl_error err;
        int rc = pl_sim_step(sim, 1, &err);
        if (rc) {
            char m[1600];
            fprintf(stderr, "%s\n", pl_error_format(&err, m, sizeof m));
        }
        ck_assert_int_eq(rc, PL_OK);
        b = ops->positions(st, pl_sim_data(sim));
        const double *x = pl_buffer_f64(&b);
        if (getenv("DBG") && step % 10 == 9) {
            double c[3] = {0, 0, 0}, vm = 0;
            for (int i = 0; i < n; ++i) {
                double d2 = 0;
                for (int k = 0; k < 3; ++k) c[k] += x[3 * i + k] / n, d2 += pow(x[3 * i + k] - prev[3 * i + k], 2);
                vm = fmax(vm, sqrt(d2) / DT);
            }
            printf("step %d centre %.4f %.4f %.4f vmax %.3f\n", step, c[0], c[1], c[2], vm);
        }
        for (int i = 0; i < n; ++i) {
            ck_assert(isfinite(x[3 * i]) && isfinite(x[3 * i + 1]) && isfinite(x[3 * i + 2]));
            if (step == STEPS - 1) r->lowest = fmin(r->lowest, x[3 * i + 1]);
            for (int t = 0; t < ob->ntris; ++t)
                if (!apart(&prev[3 * i], &x[3 * i], ob, t))
                    r->crossings += sc_segment_hits_triangle(
                    &prev[3 * i], &x[3 * i], &ob->x[3 * ob->tris[3 * t]],
                    &ob->x[3 * ob->tris[3 * t + 1]], &ob->x[3 * ob->tris[3 * t + 2]]);
        }
    }
    pl_buffer vb = ops->velocities(st, pl_sim_data(sim));
    const double *v = pl_buffer_f64(&vb);
    for (int i = 0; i < n; ++i)
        r->vmax = fmax(r->vmax, sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] +
                                     v[3 * i + 2] * v[3 * i + 2]));
    free(prev);
    pl_sim_free(sim);
}

/* ---- the dragon ---------------------------------------------------------- */

#define DRAGON_SCALE 0.02

/* dragon.obj's vertices and triangles, scaled as in the scene (a plain OBJ
 * reader: "v x y z" and "f a b c" lines, 1-based, written here). */
static void read_dragon(obstacle *ob)
{
    char *text = ct_read_source("scenes/meshes/dragon.obj");
    int nv = 0, nt = 0, cv = 4096, ct = 8192;
    ob->x = malloc((size_t)cv * 3 * sizeof *ob->x);
    ob->tris = malloc((size_t)ct * 3 * sizeof *ob->tris);
    ck_assert(ob->x && ob->tris);
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        double a, b, c;
        int i, j, k;
        if (sscanf(line, "v %lf %lf %lf", &a, &b, &c) == 3) {
            ck_assert_int_lt(nv, cv);
            ob->x[3 * nv] = DRAGON_SCALE * a;
            ob->x[3 * nv + 1] = DRAGON_SCALE * b;
            ob->x[3 * nv++ + 2] = DRAGON_SCALE * c;
        } else if (sscanf(line, "f %d %d %d", &i, &j, &k) == 3) {
            ck_assert_int_lt(nt, ct);
            ob->tris[3 * nt] = i - 1;
            ob->tris[3 * nt + 1] = j - 1;
            ob->tris[3 * nt++ + 2] = k - 1;
        }
    }
    ob->ntris = nt;
    free(text);
}

START_TEST(test_ball_rests_on_dragon)
{
    obstacle ob;
    read_dragon(&ob);
    char xml[4096];
    int n = snprintf(xml, sizeof xml,
                     "%s<PlaneObstacle name='floor' point='0 %g 0' normal='0 1 0' mu='0.5' "
                     "alarmDistance='0.005' contactDistance='0.0005'/>"
                     "<Node name='dragon'><MeshObstacle name='obstacle' "
                     "filename='" PL_SOURCE_DIR "/scenes/meshes/dragon.obj' "
                     "scale3d='0.02 0.02 0.02' sides='%s'/></Node>",
                     HEAD, FLOOR, getenv("SIDES") ? getenv("SIDES") : "auto");
    double c[3] = {0.132, 0.026, 0.028};
    if (getenv("BALL"))
        ck_assert_int_eq(sscanf(getenv("BALL"), "%lf %lf %lf", &c[0], &c[1], &c[2]), 3);
    n += ball(xml + n, sizeof xml - (size_t)n, c, getenv("R") ? atof(getenv("R")) : 0.025);
    snprintf(xml + n, sizeof xml - (size_t)n, "</Node>");
    result r;
    run(xml, &ob, &r);
    printf("ball on the dragon: after 1 s fastest vertex %.2e m/s, %d crossings, lowest %.4f m\n",
           r.vmax, r.crossings, r.lowest);
    ck_assert_msg(r.crossings == 0, "%d ball vertex steps crossed the dragon", r.crossings);
    ck_assert_msg(r.vmax < 0.01, "a ball vertex still moves at %g m/s after 1 s", r.vmax);
    ck_assert_msg(r.lowest > FLOOR + 0.03, "the ball left the dragon (lowest vertex %g m)",
                  r.lowest);
    free(ob.x);
    free(ob.tris);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_messy_mesh");
    TCase *tc = tcase_create("messy");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_ball_rests_on_dragon);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
