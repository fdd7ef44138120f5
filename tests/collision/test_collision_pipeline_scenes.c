/* test_collision_pipeline_scenes.c - the paper's contact scenes (small
 * variants in scenes/, over their full runs) measured with independent
 * geometry (scene_check.c) after every step:
 *  - every position stays finite;
 *  - cloth on knives: no cloth vertex crosses a blade within a step, no
 *    cloth edge and blade intersect, no blade edge reaches more than
 *    2 x contactDistance beyond the cloth (edge-edge), and the cloth comes
 *    to rest on the blades' apexes above the floor; the same with W
 *    explicit in every frame (round-off may not decide a contact);
 *  - sharp corner: no cloth vertex deeper than 2 x contactDistance in the
 *    cube, no cube edge beyond the cloth by more, the cloth rests on top;
 *  - squeezing ball: no ball vertex deeper than 2 x contactDistance in a
 *    roller, the ball ends below the rollers (friction drives it: with
 *    mu = 0 it stays on top) and recovers >= 90 % of its rest volume;
 *  - pulling through a gap: the body comes through, no vertex ends inside
 *    a post (the contact depth reached while squeezing is reported);
 *  - gingerbread man: no cookie vertex crosses a plate, no plate edge goes
 *    deeper than 2 x contactDistance into the cookie, the cookie comes
 *    through both plates.
 * COLLISION_SCENE=cloth_on_knives.xml CK_RUN_CASE=knives runs one case's
 * checks on another variant of its scene. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coll_test_util.h"
#include "scene_check.h"

typedef struct run {
    pl_sim *sim;
    double *x;       /* positions of the body's state (offset 0) */
    double *prev;    /* at the start of the step */
    int n;
} run;

static pl_sim *load_scene(const char *name, const char *const *overrides, int noverrides)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", PL_SOURCE_DIR, name);
    pl_sim_options opt;
    memset(&opt, 0, sizeof opt);
    opt.out_dir = PL_BINARY_DIR "/tests/collision/scene_out";
    opt.export_every = 1000000; /* the first frame only */
    opt.overrides = overrides;
    opt.noverrides = noverrides;
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *sim = pl_sim_load_file(path, &opt, &diag);
    if (!sim) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(sim);
    return sim;
}

static void run_open(run *r, const char *scene, const char *state, const char *const *ov, int nov)
{
    /* COLLISION_SCENE=name.xml (in scenes/): the same checks on another
     * variant of the scene (the medium sizes, by hand) */
    const char *alt = getenv("COLLISION_SCENE");
    r->sim = load_scene(alt && *alt ? alt : scene, ov, nov);
    r->x = ct_positions(r->sim, state, &r->n);
    r->prev = malloc((size_t)r->n * 3 * sizeof(double));
    ck_assert_ptr_nonnull(r->prev);
}

/* One step; every position finite afterwards. */
static void run_step(run *r, const char *state)
{
    memcpy(r->prev, r->x, (size_t)r->n * 3 * sizeof(double));
    pl_error err;
    int rc = pl_sim_step(r->sim, 1, &err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
    r->x = ct_positions(r->sim, state, &r->n);
    for (int i = 0; i < 3 * r->n; ++i) ck_assert_msg(isfinite(r->x[i]), "NaN at step");
}

static void run_close(run *r)
{
    free(r->prev);
    pl_sim_free(r->sim);
}

static double get_double(pl_sim *sim, const char *path)
{
    double *v;
    ck_assert_int_eq(ct_get_doubles(sim, path, &v), 1);
    double x = v[0];
    free(v);
    return x;
}

/* The triangles of a topology component. */
static const pl_mesh *mesh_of(pl_sim *sim, const char *path)
{
    pl_component *c = pl_sim_component(sim, path);
    ck_assert_ptr_nonnull(c);
    const pl_topology_ops *ops = pl_component_role(c, PL_ROLE_TOPOLOGY);
    ck_assert_ptr_nonnull(ops);
    return ops->mesh(c);
}

/* Initial side of the obstacles for every cloth triangle: the cloth starts
 * flat above them, so the side along +y is where they must not reach. */
static double *cloth_signs(const pl_mesh *m, const double *x)
{
    double *s = malloc((size_t)m->ntris * sizeof *s);
    ck_assert_ptr_nonnull(s);
    for (int t = 0; t < m->ntris; ++t) {
        const double *a = &x[3 * m->tris[3 * t]], *b = &x[3 * m->tris[3 * t + 1]],
                     *c = &x[3 * m->tris[3 * t + 2]];
        double ny = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]);
        s[t] = ny > 0 ? 1.0 : -1.0;
    }
    return s;
}

/* Largest depth of the segments (pairs of points) beyond the cloth. */
static double edges_beyond_cloth(const pl_mesh *m, const double *x, const double *sign,
                                 const double *seg, int nseg, double band)
{
    double worst = 0.0;
    for (int e = 0; e < nseg; ++e)
        for (int t = 0; t < m->ntris; ++t)
            worst = fmax(worst, sc_edge_depth_beyond(&seg[6 * e], &seg[6 * e + 3],
                                                     &x[3 * m->tris[3 * t]],
                                                     &x[3 * m->tris[3 * t + 1]],
                                                     &x[3 * m->tris[3 * t + 2]], sign[t], band));
    return worst;
}

/* The knives checks on a run of cloth_on_knives_small.xml with overrides
 * (what = the run's name in messages). */
static void knives_run(const char *what, const char *const *ov, int nov)
{
    run r;
    run_open(&r, "cloth_on_knives_small.xml", "cloth/dofs", ov, nov);
    double cd = get_double(r.sim, "pipeline.contactDistance");
    double *bx;
    int nb = ct_get_doubles(r.sim, "knives/blades.position", &bx) / 3;
    ck_assert_int_eq(nb, 9);
    const pl_mesh *cloth = mesh_of(r.sim, "cloth/grid");
    double *sign = cloth_signs(cloth, r.x);
    /* the blades' 9 edges as segments */
    double seg[9 * 6];
    for (int b = 0; b < 3; ++b)
        for (int k = 0; k < 3; ++k) {
            memcpy(&seg[6 * (3 * b + k)], &bx[3 * (3 * b + k)], 3 * sizeof(double));
            memcpy(&seg[6 * (3 * b + k) + 3], &bx[3 * (3 * b + (k + 1) % 3)], 3 * sizeof(double));
        }
    /* a vertex crossing a blade: how deep inside the blade it crossed and how
     * far it ended beyond; a cloth edge through a blade: how deep inside */
    double vcross = 0.0, epierce = 0.0, depth = 0.0;
    for (int step = 0; step < 150; ++step) {
        run_step(&r, "cloth/dofs");
        for (int b = 0; b < 3; ++b) {
            const double *a = &bx[9 * b], *bb = &bx[9 * b + 3], *c = &bx[9 * b + 6];
            for (int i = 0; i < r.n; ++i) {
                double d = sc_crossing_depth(&r.prev[3 * i], &r.x[3 * i], a, bb, c);
                if (d > 0) vcross = fmax(vcross, fmin(d, sc_plane_distance(&r.x[3 * i], a, bb, c)));
            }
            for (int t = 0; t < cloth->ntris; ++t)
                for (int k = 0; k < 3; ++k)
                    epierce = fmax(epierce, sc_crossing_depth(&r.x[3 * cloth->tris[3 * t + k]],
                                                              &r.x[3 * cloth->tris[3 * t + (k + 1) % 3]],
                                                              a, bb, c));
        }
        depth = fmax(depth, edges_beyond_cloth(cloth, r.x, sign, seg, 9, 0.05));
    }
    printf("cloth on knives (%s): vertex through a blade %.2e m, cloth edge through a blade "
           "%.2e m, blade edge beyond the cloth %.2e m\n",
           what, vcross, epierce, depth);
    ck_assert_msg(vcross < 2 * cd, "a cloth vertex went %g m through a blade (2 cd = %g)", vcross,
                  2 * cd);
    ck_assert_msg(epierce < 2 * cd, "a cloth edge went through a blade %g m inside its border",
                  epierce);
    ck_assert_msg(depth < 2 * cd, "a blade edge reached %g m beyond the cloth (2 cd = %g)", depth,
                  2 * cd);
    /* settled: resting on the highest apex (0.40 m), above the floor, slow */
    double ymax = -INFINITY, ymin = INFINITY, vmax = 0.0;
    for (int i = 0; i < r.n; ++i) {
        ymax = fmax(ymax, r.x[3 * i + 1]);
        ymin = fmin(ymin, r.x[3 * i + 1]);
        double v2 = 0;
        for (int k = 0; k < 3; ++k) v2 += pow((r.x[3 * i + k] - r.prev[3 * i + k]) / 0.01, 2);
        vmax = fmax(vmax, sqrt(v2));
    }
    ck_assert_msg(ymax > 0.38 && ymax < 0.40 + 3 * cd, "cloth top at %g m", ymax);
    ck_assert_msg(ymin > -2 * cd, "cloth went %g m below the floor", -ymin);
    ck_assert_msg(vmax < 0.5, "cloth still moving at %g m/s", vmax);
    printf("cloth on knives (%s): cloth top %.4f m, lowest %.4f m, final speed %.3f m/s\n", what,
           ymax, ymin, vmax);
    free(sign);
    free(bx);
    run_close(&r);
}

START_TEST(test_cloth_on_knives_no_tunnelling)
{
    knives_run("scene's settings", NULL, 0);
}
END_TEST

/* The same checks with W explicit in every frame: the same operator as the
 * matrix-free W up to round-off, so the same guarantees.  A look-ahead that
 * let round-off choose between "arrived" and "crept" (lookahead.c) lost a
 * cloth vertex's blade contact at step 39 in this run: a cloth edge ended
 * 0.113 m inside a blade (docs/benchmarks.md, knives). */
START_TEST(test_cloth_on_knives_explicit_w)
{
    const char *ov[] = {"contact.delassus=explicit"};
    knives_run("W explicit", ov, 1);
}
END_TEST

START_TEST(test_sharp_corner_cloth_stays_out_of_the_cube)
{
    run r;
    run_open(&r, "sharp_corner_small.xml", "cloth/dofs", NULL, 0);
    double cd = get_double(r.sim, "pipeline.contactDistance");
    const pl_mesh *cloth = mesh_of(r.sim, "cloth/grid");
    double *sign = cloth_signs(cloth, r.x);
    /* the vertex nearest the cloth's middle (n / 2 only for odd grid sizes) */
    int mid = 0;
    for (int i = 1; i < r.n; ++i)
        if (hypot(r.x[3 * i], r.x[3 * i + 2]) < hypot(r.x[3 * mid], r.x[3 * mid + 2])) mid = i;
    const double lo[3] = {-0.25, -0.5, -0.25}, hi[3] = {0.25, 0.0, 0.25};
    double seg[12 * 6]; /* the cube's 12 edges */
    int ns = 0;
    for (int a = 0; a < 8; ++a)
        for (int k = 0; k < 3; ++k)
            if (!((a >> k) & 1)) {
                int b = a | (1 << k);
                for (int j = 0; j < 3; ++j) {
                    seg[6 * ns + j] = (a >> j) & 1 ? hi[j] : lo[j];
                    seg[6 * ns + 3 + j] = (b >> j) & 1 ? hi[j] : lo[j];
                }
                ns++;
            }
    ck_assert_int_eq(ns, 12);
    double vdepth = 0.0, edepth = 0.0;
    for (int step = 0; step < 150; ++step) {
        run_step(&r, "cloth/dofs");
        for (int i = 0; i < r.n; ++i) {
            double d = INFINITY;
            for (int k = 0; k < 3; ++k) d = fmin(d, fmin(r.x[3 * i + k] - lo[k], hi[k] - r.x[3 * i + k]));
            vdepth = fmax(vdepth, d);
        }
        edepth = fmax(edepth, edges_beyond_cloth(cloth, r.x, sign, seg, 12, 0.05));
    }
    printf("sharp corner: vertex depth %.2e m, cube edge depth %.2e m\n", vdepth, edepth);
    ck_assert_msg(vdepth < 2 * cd, "a cloth vertex went %g m into the cube (2 cd = %g)", vdepth,
                  2 * cd);
    ck_assert_msg(edepth < 2 * cd, "a cube edge reached %g m beyond the cloth", edepth);
    /* the middle of the cloth rests on the top face at the kept gap */
    ck_assert_msg(fabs(r.x[3 * mid + 1] - cd) < cd, "centre at y = %g", r.x[3 * mid + 1]);
    free(sign);
    run_close(&r);
}
END_TEST

/* Depth of the ball's vertices in the rollers (circles of radius 0.1 m about
 * z at x = -0.13 and 0.13: a bound of the depth into the 32-sided prisms). */
static double roller_depth(const double *x, int n)
{
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
        if (fabs(x[3 * i + 2]) > 0.2) continue;
        for (int s = -1; s <= 1; s += 2)
            worst = fmax(worst, 0.1 - hypot(x[3 * i] - 0.13 * s, x[3 * i + 1]));
    }
    return worst;
}

static double centroid_y(const double *x, int n)
{
    double y = 0;
    for (int i = 0; i < n; ++i) y += x[3 * i + 1];
    return y / n;
}

START_TEST(test_squeezing_ball_passes_by_friction_and_recovers)
{
    run r;
    run_open(&r, "squeezing_ball_small.xml", "ball/dofs", NULL, 0);
    double cd = get_double(r.sim, "pipeline.contactDistance");
    const pl_mesh *m = mesh_of(r.sim, "ball/mesh");
    double rest = sc_volume(m->verts, m->tets, m->ntets);
    double depth = 0.0;
    for (int step = 0; step < 150; ++step) {
        run_step(&r, "ball/dofs");
        depth = fmax(depth, roller_depth(r.x, r.n));
    }
    double cy = centroid_y(r.x, r.n), vol = sc_volume(r.x, m->tets, m->ntets);
    ck_assert_msg(depth < 2 * cd, "a ball vertex went %g m into a roller (2 cd = %g)", depth,
                  2 * cd);
    ck_assert_msg(cy < -0.1, "the ball's centre is at y = %g, not below the rollers", cy);
    ck_assert_msg(vol > 0.9 * rest, "volume %g of %g at rest", vol, rest);
    printf("squeezing_ball_small: roller depth %.2e m, centre y %.3f m, volume %.1f %%\n", depth,
           cy, 100 * vol / rest);
    run_close(&r);
    /* without friction the rollers cannot pull it: it stays on top */
    const char *ov[] = {"left/roller.mu=0", "right/roller.mu=0"};
    run_open(&r, "squeezing_ball_small.xml", "ball/dofs", ov, 2);
    for (int step = 0; step < 150; ++step) run_step(&r, "ball/dofs");
    cy = centroid_y(r.x, r.n);
    ck_assert_msg(cy > 0.0, "without friction the ball's centre reached y = %g", cy);
    run_close(&r);
}
END_TEST

START_TEST(test_pulled_body_comes_through_the_gap)
{
    run r;
    run_open(&r, "pulling_through_gap_small.xml", "body/dofs", NULL, 0);
    double cd = get_double(r.sim, "pipeline.contactDistance");
    const double post_x = -0.35, post_z = 0.09, post_r = 0.04;
    double depth = 0.0, vmax = 0.0;
    for (int step = 0; step < 150; ++step) {
        run_step(&r, "body/dofs");
        for (int i = 0; i < r.n; ++i) {
            for (int s = -1; s <= 1; s += 2)
                depth = fmax(depth, post_r - hypot(r.x[3 * i] - post_x, r.x[3 * i + 2] - s * post_z));
            double v2 = 0.0;
            for (int k = 0; k < 3; ++k) v2 += pow((r.x[3 * i + k] - r.prev[3 * i + k]) / 0.01, 2);
            vmax = fmax(vmax, sqrt(v2));
        }
    }
    double xmax = -INFINITY, end_depth = 0.0;
    for (int i = 0; i < r.n; ++i) {
        xmax = fmax(xmax, r.x[3 * i]);
        for (int s = -1; s <= 1; s += 2)
            end_depth = fmax(end_depth, post_r - hypot(r.x[3 * i] - post_x, r.x[3 * i + 2] - s * post_z));
    }
    ck_assert_msg(xmax < post_x - post_r - cd, "the body's front is at x = %g, not through", xmax);
    ck_assert_msg(end_depth <= 0.0, "a vertex ends %g m inside a post", end_depth);
    ck_assert_msg(depth < 2 * cd, "a vertex went %g m into a post (2 cd = %g)", depth, 2 * cd);
    /* pulled at 0.4 m/s and squeezed: no part is ever thrown (an unbalanced
     * contact force on a body squeezed at a few kN once threw it at 7.5 m/s;
     * the squeezed body springs back at about 2 m/s) */
    ck_assert_msg(vmax < 4.0, "a vertex moved at %g m/s", vmax);
    printf("pulling_through_gap_small: deepest contact while squeezing %.2e m (2 cd = %.1e), "
           "front at x = %.3f m, fastest vertex %.2f m/s\n",
           depth, 2 * cd, xmax, vmax);
    run_close(&r);
}
END_TEST

START_TEST(test_gingerbread_crosses_the_plates)
{
    run r;
    run_open(&r, "gingerbread_small.xml", "man/dofs", NULL, 0);
    double cd = get_double(r.sim, "pipeline.contactDistance");
    double *px, *pt;
    int npv = ct_get_doubles(r.sim, "plates/obstacles.position", &px) / 3;
    int npt = ct_get_doubles(r.sim, "plates/obstacles.triangles", &pt) / 3;
    ck_assert_int_eq(npv, 24);
    const pl_mesh *m = mesh_of(r.sim, "man/shape");
    int *bt;
    int nbt = sc_boundary(m->tets, m->ntets, &bt);
    /* the holes' rims: edges between the inner vertices 6..11 and 18..23 */
    double rim[12 * 6];
    for (int p = 0; p < 2; ++p)
        for (int k = 0; k < 6; ++k) {
            memcpy(&rim[6 * (6 * p + k)], &px[3 * (12 * p + 6 + k)], 3 * sizeof(double));
            memcpy(&rim[6 * (6 * p + k) + 3], &px[3 * (12 * p + 6 + (k + 1) % 6)], 3 * sizeof(double));
        }
    double vcross = 0.0, depth = 0.0;
    for (int step = 0; step < 160; ++step) {
        run_step(&r, "man/dofs");
        for (int t = 0; t < npt; ++t) {
            const double *a = &px[3 * (int)pt[3 * t]], *b = &px[3 * (int)pt[3 * t + 1]],
                         *c = &px[3 * (int)pt[3 * t + 2]];
            for (int i = 0; i < r.n; ++i) {
                double d = sc_crossing_depth(&r.prev[3 * i], &r.x[3 * i], a, b, c);
                if (d > 0) vcross = fmax(vcross, fmin(d, sc_plane_distance(&r.x[3 * i], a, b, c)));
            }
        }
        /* points along the rims inside the cookie: their depth below its surface */
        for (int e = 0; e < 12 && step % 2 == 0; ++e)
            for (int s = 0; s <= 40; ++s) {
                double q[3];
                for (int k = 0; k < 3; ++k)
                    q[k] = rim[6 * e + k] + s / 40.0 * (rim[6 * e + 3 + k] - rim[6 * e + k]);
                if (sc_inside(r.x, bt, nbt, q))
                    depth = fmax(depth, sc_surface_distance(r.x, bt, nbt, q));
            }
    }
    ck_assert_msg(vcross < 2 * cd, "a cookie vertex went %g m through a plate (2 cd = %g)", vcross,
                  2 * cd);
    ck_assert_msg(depth < 2 * cd, "a rim went %g m into the cookie (2 cd = %g)", depth, 2 * cd);
    /* through both plates: every vertex above the tilted upper one */
    for (int i = 0; i < r.n; ++i)
        ck_assert_msg(r.x[3 * i + 1] > 0.6 + 0.15 * r.x[3 * i] + cd, "vertex %d at y = %g", i,
                      r.x[3 * i + 1]);
    printf("gingerbread_small: vertex through a plate %.2e m, rim depth in the cookie %.2e m\n",
           vcross, depth);
    free(bt);
    free(px);
    free(pt);
    run_close(&r);
}
END_TEST

/* A run restored from a saved state into a freshly loaded scene goes on
 * exactly as the run that saved it: the detection's contact order may not
 * depend on history (its trees are built from the first step they see). */
START_TEST(test_restored_run_repeats_bitwise)
{
    const char *scenes[] = {"sharp_corner_small.xml", "cloth_on_knives_small.xml"};
    const char *path = PL_BINARY_DIR "/tests/collision/restore_state.bin";
    for (int k = 0; k < 2; ++k) {
        pl_error err;
        pl_sim *a = load_scene(scenes[k], NULL, 0), *b = load_scene(scenes[k], NULL, 0);
        ck_assert_int_eq(pl_sim_step(a, 30, &err), PL_OK); /* cloth on the obstacle */
        ck_assert_int_eq(pl_sim_save_state(a, path, &err), PL_OK);
        ck_assert_int_eq(pl_sim_step(a, 3, &err), PL_OK);
        ck_assert_int_eq(pl_sim_restore_state(b, path, &err), PL_OK);
        ck_assert_int_eq(pl_sim_step(b, 3, &err), PL_OK);
        int na, nb;
        double *xa = ct_positions(a, "cloth/dofs", &na), *xb = ct_positions(b, "cloth/dofs", &nb);
        ck_assert_int_eq(na, nb);
        int differ = 0;
        for (int i = 0; i < 3 * na; ++i) differ += memcmp(&xa[i], &xb[i], sizeof(double)) != 0;
        ck_assert_msg(differ == 0, "%s: %d of %d coordinates differ after the restore", scenes[k], differ, 3 * na);
        pl_sim_free(a);
        pl_sim_free(b);
    }
    remove(path);
}
END_TEST

/* One case per scene, so that ctest runs them apart (CK_RUN_CASE). */
static Suite *suite(void)
{
    Suite *s = suite_create("collision_pipeline_scenes");
    struct {
        const char *name;
        const TTest *test;
    } cases[] = {
        {"knives", test_cloth_on_knives_no_tunnelling},
        {"knives_explicit", test_cloth_on_knives_explicit_w},
        {"corner", test_sharp_corner_cloth_stays_out_of_the_cube},
        {"ball", test_squeezing_ball_passes_by_friction_and_recovers},
        {"gap", test_pulled_body_comes_through_the_gap},
        {"gingerbread", test_gingerbread_crosses_the_plates},
        {"restore", test_restored_run_repeats_bitwise},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        TCase *tc = tcase_create(cases[k].name);
        tcase_set_timeout(tc, 600);
        tcase_add_test(tc, cases[k].test);
        suite_add_tcase(s, tc);
    }
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
