/* test_collision_tunnelling.c - no tunnelling at any speed (issue 14 item 1).
 * A soft ball (Neo-Hookean, E 1e5, radius 5 cm, coarse) arrives at the
 * speed of a drop from 0.05, 0.5 and 5 m (1 to 9.9 m/s) onto
 *  - a PlaneObstacle,
 *  - a MeshObstacle (a closed box of triangles, through the
 *    CollisionPipeline),
 *  - another ball resting on the floor (body against body),
 * with ball_on_plane.xml's time step (5 ms) and iterations (10 local-global,
 * 24 CR) and the tight distances (alarm 5 mm, kept gap 0.5 mm):
 * the ball starts alarmDistance plus part of a step's fall away, so only
 * look-ahead can see the contact coming.  After every step every surface
 * vertex's signed distance to what it hits is >= -1e-6 m, and no surface
 * edge of one ball passes through the other, measured with
 * geometry written here (the plane's height, the box's closed form, ray
 * parity and triangle distance of scene_check.c), not the detection code.
 * Without the pipeline's look-ahead (vertex-triangle and edge-edge pairs
 * followed over the step) the ball dropped from 5 m went 2.1 mm into the
 * resting ball; a flat face ahead of a falling point (the box's top) was
 * already caught by the approach the start-of-step detection counts. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"
#include "scene_check.h"

#define ALARM 0.005
#define GAP 0.0005
#define DT 0.005
#define RADIUS 0.05
#define STEPS 30

static const char *HEAD =
    "<Node name='root' dt='0.005' gravity='0 -9.81 0'>"
    "<RequiredPlugin name='hyperelastic'/><RequiredPlugin name='sparse_inverse'/>"
    "<RequiredPlugin name='ncp_contact'/><RequiredPlugin name='collision'/>"
    "<LocalGlobalSolver name='solver' iterations='10'/><SparseInverseSolver name='global'/>"
    "<NonSmoothNewtonContactSolver name='contact' ncp='fischer-burmeister' crIterations='24' "
    "preconditioner='delassus'/>";

/* A ball node: centre height y, initial downward speed v. */
static int ball(char *out, size_t size, const char *name, double y, double v)
{
    return snprintf(out, size,
                    "<Node name='%s'><SphereMesh name='mesh' center='0 %.9g 0' radius='%g' "
                    "volume='1' vertices='120'/>"
                    "<MechanicalObject name='dofs' src='@mesh' velocity='0 %.9g 0'/>"
                    "<DiagonalMass massDensity='1000'/>"
                    "<NeoHookean name='material' youngModulus='1e5' poissonRatio='0.4'/>"
                    "<SurfaceCollisionModel name='surface'/></Node>",
                    name, y, RADIUS, -v);
}

typedef enum target { ON_PLANE, ON_MESH, ON_BALL } target;

/* The speed of a drop from height H, and the ball's start: its lowest point
 * alarmDistance plus 60% of a step's travel above the surface at `top`. */
static double impact_speed(double H) { return sqrt(2.0 * 9.81 * H); }
static double start_height(double top, double v) { return top + RADIUS + ALARM + 0.6 * v * DT; }

static pl_sim *load(target t, double H)
{
    static char xml[8192];
    double v = impact_speed(H);
    int n = snprintf(xml, sizeof xml, "%s", HEAD);
    const char *pipe = "<CollisionPipeline name='pipeline' alarmDistance='0.005' "
                       "contactDistance='0.0005' mu='0.3'/>";
    const char *floor = "<PlaneObstacle name='floor' point='0 0 0' normal='0 1 0' mu='0.3' "
                        "alarmDistance='0.005' contactDistance='0.0005'/>";
    if (t == ON_PLANE) {
        n += snprintf(xml + n, sizeof xml - (size_t)n, "%s", floor);
        n += ball(xml + n, sizeof xml - (size_t)n, "ball", start_height(0.0, v), v);
    } else if (t == ON_MESH) {
        /* a 0.6 m box of 12 triangles, top face at y = 0 */
        n += snprintf(xml + n, sizeof xml - (size_t)n,
                      "%s<Node name='block'><RegularGridTetrahedra name='box' "
                      "min='-0.3 -0.2 -0.3' max='0.3 0 0.3' n='2 2 2'/>"
                      "<MeshObstacle name='obstacle' src='@box'/></Node>",
                      pipe);
        n += ball(xml + n, sizeof xml - (size_t)n, "ball", start_height(0.0, v), v);
    } else {
        /* the lower ball rests on the floor (it starts one kept gap above
         * it); the upper one falls onto it */
        n += snprintf(xml + n, sizeof xml - (size_t)n, "%s%s", pipe, floor);
        n += ball(xml + n, sizeof xml - (size_t)n, "lower", RADIUS + GAP, 0.0);
        n += ball(xml + n, sizeof xml - (size_t)n, "ball", start_height(2 * RADIUS + GAP, v), v);
    }
    snprintf(xml + n, sizeof xml - (size_t)n, "</Node>");
    return ct_load(xml, NULL, 0);
}

static double *positions(pl_sim *sim, const char *path)
{
    pl_component *st = pl_sim_component(sim, path);
    ck_assert_ptr_nonnull(st);
    const pl_state_ops *ops = pl_component_role(st, PL_ROLE_STATE);
    pl_buffer b = ops->positions(st, pl_sim_data(sim));
    return pl_buffer_f64(&b);
}

/* A ball's boundary triangles and which vertices they use. */
typedef struct surface {
    int *tris, ntris;
    char *on;
    int n;
} surface;

static void surface_of(pl_sim *sim, const char *node, surface *s)
{
    char path[64];
    snprintf(path, sizeof path, "%s/mesh", node);
    pl_component *c = pl_sim_component(sim, path);
    ck_assert_ptr_nonnull(c);
    const pl_topology_ops *ops = pl_component_role(c, PL_ROLE_TOPOLOGY);
    const pl_mesh *m = ops->mesh(c);
    s->n = m->nverts;
    s->ntris = sc_boundary(m->tets, m->ntets, &s->tris);
    s->on = calloc((size_t)s->n, 1);
    ck_assert_ptr_nonnull(s->on);
    for (int k = 0; k < 3 * s->ntris; ++k) s->on[s->tris[k]] = 1;
}

static void surface_free(surface *s)
{
    free(s->tris);
    free(s->on);
}

/* Signed distance of x to the box [-0.3, 0.3] x [-0.2, 0] x [-0.3, 0.3]. */
static double box_distance(const double x[3])
{
    const double c[3] = {0.0, -0.1, 0.0}, h[3] = {0.3, 0.1, 0.3};
    double q[3], out = 0.0, in = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        q[k] = fabs(x[k] - c[k]) - h[k];
        out += q[k] > 0.0 ? q[k] * q[k] : 0.0;
        in = fmax(in, q[k]);
    }
    return in > 0.0 ? sqrt(out) : in;
}

/* Signed distance of x to a ball's surface (negative inside). */
static double ball_distance(const surface *s, const double *v, const double x[3])
{
    double d = sc_surface_distance(v, s->tris, s->ntris, x);
    return sc_inside(v, s->tris, s->ntris, x) ? -d : d;
}

/* Lowest signed distance of the surface vertices of `a` (positions xa) to
 * what they may hit. */
static double worst_distance(target t, const surface *a, const double *xa, const surface *b,
                             const double *xb)
{
    double w = INFINITY;
    for (int i = 0; i < a->n; ++i) {
        if (!a->on[i]) continue;
        const double *x = &xa[3 * i];
        if (t == ON_MESH) w = fmin(w, box_distance(x));
        else w = fmin(w, x[1]); /* the floor */
        if (t == ON_BALL) w = fmin(w, ball_distance(b, xb, x));
    }
    if (t == ON_BALL) /* the lower ball's vertices against the upper ball, and the floor */
        for (int i = 0; i < b->n; ++i)
            if (b->on[i]) w = fmin(w, fmin(xb[3 * i + 1], ball_distance(a, xa, &xb[3 * i])));
    return w;
}

/* Surface edges of `a` that pass through `b` (both balls): an edge whose
 * ends are outside b but which crosses one of b's triangles goes into b.
 * Against the plane and the box (convex) an edge with both ends outside
 * stays outside, so the vertices' distances say all there. */
static int edges_through(const surface *a, const double *xa, const surface *b, const double *xb)
{
    int n = 0;
    for (int t = 0; t < a->ntris; ++t)
        for (int k = 0; k < 3; ++k) {
            int i = a->tris[3 * t + k], j = a->tris[3 * t + (k + 1) % 3];
            if (i > j) continue; /* each edge once (from one of its triangles) */
            for (int u = 0; u < b->ntris; ++u)
                if (sc_segment_hits_triangle(&xa[3 * i], &xa[3 * j], &xb[3 * b->tris[3 * u]],
                                             &xb[3 * b->tris[3 * u + 1]],
                                             &xb[3 * b->tris[3 * u + 2]])) {
                    n++;
                    break;
                }
        }
    return n;
}

static void drop(target t, double H)
{
    static const char *NAME[] = {"plane", "box mesh", "ball"};
    pl_sim *sim = load(t, H);
    surface a, b = {0};
    surface_of(sim, "ball", &a);
    if (t == ON_BALL) surface_of(sim, "lower", &b);
    double worst = INFINITY, vmin = INFINITY;
    int at = -1;
    for (int step = 0; step < STEPS; ++step) {
        pl_error err;
        int rc = pl_sim_step(sim, 1, &err);
        if (rc) {
            char m[1600];
            fprintf(stderr, "%s\n", pl_error_format(&err, m, sizeof m));
        }
        ck_assert_int_eq(rc, PL_OK);
        double *xa = positions(sim, "ball/dofs");
        const double *xb = t == ON_BALL ? positions(sim, "lower/dofs") : NULL;
        double d = worst_distance(t, &a, xa, &b, xb);
        if (d < worst) worst = d, at = step;
        if (t == ON_BALL)
            ck_assert_msg(!edges_through(&a, xa, &b, xb) && !edges_through(&b, xb, &a, xa),
                          "%g m drop onto the ball: a surface edge passes through the other "
                          "ball after step %d",
                          H, step);
        /* the ball's mean vertical velocity: it must have been stopped */
        double vy = 0.0;
        pl_component *st = pl_sim_component(sim, "ball/dofs");
        const pl_state_ops *ops = pl_component_role(st, PL_ROLE_STATE);
        pl_buffer vb = ops->velocities(st, pl_sim_data(sim));
        const double *vel = pl_buffer_f64(&vb);
        for (int i = 0; i < a.n; ++i) vy += vel[3 * i + 1] / a.n;
        vmin = fmin(vmin, vy);
        if (step == STEPS - 1)
            ck_assert_msg(vy > -0.5 * impact_speed(H), "the ball still falls at %g m/s", -vy);
    }
    printf("drop from %g m (%.2f m/s) onto the %s: lowest signed distance %.3e m (step %d)\n", H,
           impact_speed(H), NAME[t], worst, at);
    ck_assert_msg(worst >= -1e-6, "%g m drop onto the %s: a surface vertex %g m through (step %d)",
                  H, NAME[t], -worst, at);
    surface_free(&a);
    if (t == ON_BALL) surface_free(&b);
    pl_sim_free(sim);
}

static const double HEIGHTS[] = {0.05, 0.5, 5.0};

START_TEST(test_drop_on_plane) { drop(ON_PLANE, HEIGHTS[_i]); }
END_TEST

START_TEST(test_drop_on_mesh) { drop(ON_MESH, HEIGHTS[_i]); }
END_TEST

START_TEST(test_drop_on_ball) { drop(ON_BALL, HEIGHTS[_i]); }
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_tunnelling");
    TCase *tc = tcase_create("drops");
    tcase_set_timeout(tc, 600);
    tcase_add_loop_test(tc, test_drop_on_plane, 0, 3);
    tcase_add_loop_test(tc, test_drop_on_mesh, 0, 3);
    tcase_add_loop_test(tc, test_drop_on_ball, 0, 3);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
