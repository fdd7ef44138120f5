/* gpu_graph.c - the device loop's CUDA graph is kept across steps with
 * constraint rows (needs a GPU; ctest -L gpu runs it as gpu_graph_small).
 *
 *   gpu_graph CHECKS.md [steps]
 *
 * For constrained scenes whose rows change from step to step (a ball that
 * lands, the gripper closing on the raptor, a cable, a sliding box), the
 * loop runs `steps` steps (default 100) on the device twice from the
 * start: with CudaDevice graph="1" and graph="0".  Checks:
 *   - the graph run captured at most MAX_CAPTURES graphs (stat "device
 *     graph captures"; before the graph was kept it captured one per step
 *     with rows) and at least one (the graph was used);
 *   - its positions equal those of the run without a graph (relative
 *     1e-12; a graph replaying a former step's rows would differ far
 *     more), so reuse changes nothing computed;
 *   - a third run with a graph and PLIANT_NCP_FUSED_CR=1 (CR's loop in one
 *     kernel where W is explicit and rows are few; at most 32 rows by one
 *     warp) gives those positions too (relative 1e-12; on the H100 they
 *     are equal, 0.0: the fused kernel sums as the phase kernels do);
 *   - a fourth, PLIANT_NCP_FUSED_WARP=0 (the fused kernel's whole block for
 *     few rows too), as well.
 *   - a fifth, PLIANT_NCP_FUSED_CR=1 and PLIANT_NCP_ONE_KERNEL=0 (the few
 *     rows' row values, fused update and dense correction as three kernels,
 *     not one), gives the third run's positions bitwise (the one kernel
 *     runs the three's device code, in their order).
 *   - a sixth, PLIANT_NCP_FUSED_CR=1 and PLIANT_NCP_FUSED_NARROW=0 (the
 *     fused kernel in a block of 512 threads whatever the rows' capacity,
 *     not 128 or 256 for few), gives the third run's positions bitwise.
 *   - a seventh, PLIANT_NCP_FUSED_CR=0 and PLIANT_NCP_PHASE_PAIRS=0 (the
 *     phase kernels one phase a launch, not two where no product comes
 *     between them), gives the second run's positions bitwise.
 *   - an eighth, PLIANT_NCP_FUSED_CR=1 and PLIANT_NCP_SCATTER_WARP=0 (H^T
 *     lambda a thread an unknown, not a warp), gives the third run's
 *     positions bitwise.
 *   - a ninth, with a graph, PLIANT_NCP_FUSED_CR=0 and
 *     PLIANT_NCP_UPDATE_GRAPH=0 (a step's first iteration launches the
 *     phase kernels one by one, not from their recorded graph), gives the
 *     first run's positions bitwise; the first run replayed that graph
 *     (stat "contact update graph replays" > 0), the ninth did not.
 *   - a tenth, PLIANT_NCP_FUSED_CR=1 and PLIANT_DEVICE_BRANCHES=0 (the
 *     local terms' projects one after the other on the main stream, not
 *     each state's on its own branch), gives the third run's positions of
 *     every body bitwise; the third run used a branch a body where the
 *     scene has several (stat "device local-step branches"), the tenth
 *     none.
 *   - an eleventh and a twelfth, PLIANT_NCP_FUSED_CR=0 and
 *     PLIANT_NCP_GRID_MIN=1 (CR's loop over a grid of blocks whatever the
 *     rows, ncp_cuda_grid.cu) without and with a graph: the second run's
 *     positions up to the order of CR's sums (relative GRID_TOL), and the
 *     two grid runs bitwise the same (the grid's sums are deterministic);
 *     and the grid against the block without a graph for
 *     correction="jacobian" and for lineSearch="0" (their own phases).
 * Notes: the median wall time of a step of each run.
 * Exit status: 0, 1 when a check failed, 77 without a GPU. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_util.h"
#include "test_tmp.h"
#include "pliant/pliant.h"

#define PROG "gpu_graph"
#define MAX_CAPTURES 12.0
/* the grid's CR against the block's: the same arithmetic, its sums in
 * another order (round-off, carried through 100 steps of contact) */
#define GRID_TOL 1e-9

static FILE *md;

/* extra: one more override (the grid's other branches), or NULL */
static pl_sim *load(const char *path, int graph, const char *extra)
{
    char *xml = gpu_scene_with_device(path);
    /* forceTolerance (cable fingers) and stickStart (stick_slip) off: a
     * fixed iteration count here (gpu_loop runs them with those on) */
    const char *ov[7] = {"solver.device=cuda", "global.device=cuda", "global.precision=float64",
                         "solver.forceTolerance=0", NULL, NULL, NULL};
    int nov = 4;
    if (extra) ov[nov++] = extra;
    if (strstr(path, "stick_slip")) ov[nov++] = "contact.stickStart=0";
    /* the fingers' 1000 iterations are for forceTolerance: 20 without it */
    if (strstr(path, "cable_finger")) ov[nov++] = "solver.iterations=20";
    pl_sim *sim = gpu_load_scene(xml, path, ov, nov, test_tmp_dir());
    pl_error err;
    if (sim && pl_sim_set(sim, "gpu.graph", graph ? "1" : "0", &err) != PL_OK) {
        printf("set: %s\n", err.msg);
        pl_sim_free(sim);
        return NULL;
    }
    return sim;
}

/* One run: every body's positions, one after the other (malloc'ed, n
 * values; NULL on failure), its graph captures, its replays of the update
 * graph, its local-step branches and its median step [ms]. */
typedef struct run_result {
    double *x;
    size_t n;
    double captures, replays, branches, ms;
} run_result;

typedef struct positions_of {
    run_result *r;
    const pl_data *d;
} positions_of;

static int append_state(pl_component *c, void *user)
{
    positions_of *po = user;
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer p = ops->positions(c, po->d);
    size_t add = p.rows * 3;
    double *x = realloc(po->r->x, (po->r->n + add + 1) * sizeof(double));
    if (!x) return 1;
    memcpy(x + po->r->n, p.data, add * sizeof(double));
    po->r->x = x, po->r->n += add;
    return 0;
}

static run_result run(const char *path, int graph, int fused, int one, int steps, const char *extra)
{
    /* 6: the phase kernels over a grid of blocks */
    if (fused == 6) setenv("PLIANT_NCP_GRID_MIN", "1", 1);
    else unsetenv("PLIANT_NCP_GRID_MIN");
    run_result r = {NULL, 0, 0.0, 0.0, 0.0, NAN};
    /* read by the contact solver's device path (fused 2: without the warp;
     * 3: always a block of 512; 4: the scatters a thread an unknown; -1:
     * the phase kernels one a launch; -2: the phase kernels, a step's first
     * update launched one by one; 5: fused, the local terms on the main
     * stream; one 0: the few rows' iteration as three kernels) */
    setenv("PLIANT_NCP_FUSED_CR", fused > 0 && fused != 6 ? "1" : "0", 1);
    setenv("PLIANT_NCP_FUSED_WARP", fused == 2 ? "0" : "2", 1);
    setenv("PLIANT_NCP_FUSED_NARROW", fused == 3 ? "0" : "1", 1);
    setenv("PLIANT_NCP_PHASE_PAIRS", fused == -1 ? "0" : "1", 1);
    setenv("PLIANT_NCP_SCATTER_WARP", fused == 4 ? "0" : "1", 1);
    setenv("PLIANT_NCP_ONE_KERNEL", one ? "1" : "0", 1);
    setenv("PLIANT_NCP_UPDATE_GRAPH", fused == -2 ? "0" : "1", 1);
    setenv("PLIANT_DEVICE_BRANCHES", fused == 5 ? "0" : "1", 1); /* read at load */
    pl_sim *sim = load(path, graph, extra);
    if (!sim) return r;
    double *t = malloc(sizeof(double) * (size_t)steps);
    pl_error err;
    for (int k = 0; t && k < steps; ++k) {
        double t0 = pl_now();
        if (pl_sim_step(sim, 1, &err) != PL_OK) {
            printf("%s: step %d: %s\n", path, k + 1, err.msg);
            goto done;
        }
        t[k] = 1e3 * (pl_now() - t0);
    }
    r.ms = t ? gpu_median(t, steps) : NAN;
    pl_stat_get(pl_sim_timers(sim), "device graph captures", &r.captures);
    pl_stat_get(pl_sim_timers(sim), "contact update graph replays", &r.replays);
    pl_stat_get(pl_sim_timers(sim), "device local-step branches", &r.branches);
    positions_of po = {&r, pl_sim_data(sim)};
    if (pl_node_visit_role(pl_sim_model(sim)->root, PL_ROLE_STATE, append_state, &po) || !r.n) {
        free(r.x);
        r.x = NULL, r.n = 0;
    }
done:
    free(t);
    pl_sim_free(sim);
    return r;
}

static double rel(const double *a, const double *b, size_t n)
{
    double d = 0.0, r = 0.0;
    for (size_t i = 0; i < n; ++i) d += (a[i] - b[i]) * (a[i] - b[i]), r += b[i] * b[i];
    return n ? (r > 0 ? sqrt(d / r) : sqrt(d)) : 0.0;
}

/* The check line "PATH: LABEL (relative[; bitwise])": x's positions against y's. */
static void same_line(const char *path, const char *label, const run_result *x,
                      const run_result *y, double tol)
{
    char what[256];
    snprintf(what, sizeof what, "%s: %s (relative%s)", path, label, tol == 0.0 ? "; bitwise" : "");
    gpu_check_line(md, what, x->x && y->x && x->n == y->n ? rel(x->x, y->x, y->n) : INFINITY, tol);
}

/* The note line "PATH: LABEL" with value v. */
static void note(const char *path, const char *label, double v)
{
    char what[256];
    snprintf(what, sizeof what, "%s: %s", path, label);
    gpu_note_line(md, what, v);
}

/* The runs of check(), by what they set. */
enum { GRAPH, NO_GRAPH, FUSED, FUSED_BLOCK, THREE_KERNELS, WIDE, ONE_PHASE, SCATTER_THREAD,
       NO_UPDATE_GRAPH, NO_BRANCHES, GRID, GRID_GRAPH, JACOBIAN, GRID_JACOBIAN, NO_LS, GRID_NO_LS,
       NRUNS };
/* the runs' extra override: the grid's branches for the jacobian
 * correction and without the line search, each against the block's */
static const char *const EXTRA[NRUNS] = {[JACOBIAN] = "contact.correction=jacobian",
                                         [GRID_JACOBIAN] = "contact.correction=jacobian",
                                         [NO_LS] = "contact.lineSearch=0",
                                         [GRID_NO_LS] = "contact.lineSearch=0"};

static void check(const char *path, int steps)
{
    /* graph, fused (see run), one kernel */
    static const int how[NRUNS][3] = {{1, 0, 1}, {0, 0, 1}, {1, 1, 1},  {1, 2, 1}, {1, 1, 0},
                                      {1, 3, 1}, {0, -1, 1}, {1, 4, 1}, {1, -2, 1},
                                      {1, 5, 1}, {0, 6, 1}, {1, 6, 1}, {0, 0, 1},
                                      {0, 6, 1}, {0, 0, 1}, {0, 6, 1}};
    /* Without the line search the raptor's grasp amplifies the grid's
     * other order of CR's sums (5e-15 apart after 100 steps with the line
     * search) to 1.2e-2 after 100 steps, from 0.0 after 20 (measured on an
     * H100): that pair runs 20 steps there, with 80-173 rows (the body on
     * the floor; the runs with the line search cover the grid's blocks
     * past the first, from the grasp on). */
    const int ls_steps = strstr(path, "raptor") && steps > 20 ? 20 : steps;
    run_result r[NRUNS];
    for (int k = 0; k < NRUNS; ++k)
        r[k] = run(path, how[k][0], how[k][1], how[k][2],
                   k == NO_LS || k == GRID_NO_LS ? ls_steps : steps, EXTRA[k]);
    const run_result *a = &r[GRAPH], *b = &r[NO_GRAPH], *c = &r[FUSED];
    char what[256];
    snprintf(what, sizeof what, "%s: %d steps ran with and without a graph", path, steps);
    gpu_check_line(md, what, a->x && b->x && a->n == b->n ? 0.0 : INFINITY, 0.0);
    if (a->x && b->x && a->n == b->n) {
        snprintf(what, sizeof what, "%s: graph captures in %d steps (<= %g)", path, steps,
                 MAX_CAPTURES);
        gpu_check_line(md, what, a->captures, MAX_CAPTURES);
        snprintf(what, sizeof what, "%s: a graph was captured (1 - min(captures, 1))", path);
        gpu_check_line(md, what, 1.0 - fmin(a->captures, 1.0), 0.0);
        snprintf(what, sizeof what, "%s: positions, graph vs no graph (relative)", path);
        gpu_check_line(md, what, rel(a->x, b->x, a->n), 1e-12);
        note(path, "median step ms with a graph", a->ms);
        note(path, "median step ms without a graph", b->ms);
    }
    same_line(path, "PLIANT_NCP_FUSED_CR=1 with a graph vs no graph", c, b, 1e-12);
    note(path, "median step ms, graph and PLIANT_NCP_FUSED_CR=1", c->ms);
    note(path, "graph captures with PLIANT_NCP_FUSED_CR=1", c->captures);
    same_line(path, "PLIANT_NCP_FUSED_CR=1 PLIANT_NCP_FUSED_WARP=0 with a graph vs no graph",
              &r[FUSED_BLOCK], b, 1e-12);
    same_line(path, "PLIANT_NCP_FUSED_CR=1, PLIANT_NCP_ONE_KERNEL=1 vs =0, graph", c,
              &r[THREE_KERNELS], 0.0);
    note(path, "median step ms, graph, FUSED_CR=1 and ONE_KERNEL=0", r[THREE_KERNELS].ms);
    same_line(path, "PLIANT_NCP_FUSED_CR=1, PLIANT_NCP_FUSED_NARROW=1 vs =0, graph", c, &r[WIDE],
              0.0);
    note(path, "median step ms, graph, FUSED_CR=1 and FUSED_NARROW=0", r[WIDE].ms);
    same_line(path, "PLIANT_NCP_FUSED_CR=0, PLIANT_NCP_PHASE_PAIRS=1 vs =0, no graph", b,
              &r[ONE_PHASE], 0.0);
    same_line(path, "PLIANT_NCP_FUSED_CR=1, PLIANT_NCP_SCATTER_WARP=1 vs =0, graph", c,
              &r[SCATTER_THREAD], 0.0);
    same_line(path, "PLIANT_NCP_FUSED_CR=0, PLIANT_NCP_UPDATE_GRAPH=1 vs =0, graph", a,
              &r[NO_UPDATE_GRAPH], 0.0);
    note(path, "median step ms, graph, FUSED_CR=0 and UPDATE_GRAPH=0", r[NO_UPDATE_GRAPH].ms);
    snprintf(what, sizeof what,
             "%s: FUSED_CR=0, update graph replayed with UPDATE_GRAPH=1 (1 - min(replays, 1)), "
             "%g replays",
             path, a->replays);
    gpu_check_line(md, what, 1.0 - fmin(a->replays, 1.0), 0.0);
    snprintf(what, sizeof what, "%s: FUSED_CR=0, update graph replays with UPDATE_GRAPH=0", path);
    gpu_check_line(md, what, r[NO_UPDATE_GRAPH].replays, 0.0);
    same_line(path, "PLIANT_NCP_FUSED_CR=1, PLIANT_DEVICE_BRANCHES=1 vs =0, graph", c,
              &r[NO_BRANCHES], 0.0);
    note(path, "median step ms, graph, FUSED_CR=1 and DEVICE_BRANCHES=0", r[NO_BRANCHES].ms);
    snprintf(what, sizeof what, "%s: local-step branches used with DEVICE_BRANCHES=0", path);
    gpu_check_line(md, what, r[NO_BRANCHES].branches, 0.0);
    if (strstr(path, "grabbing_raptor")) { /* three bodies: a branch each */
        snprintf(what, sizeof what, "%s: 3 - local-step branches with DEVICE_BRANCHES=1", path);
        gpu_check_line(md, what, fabs(3.0 - c->branches), 0.0);
    }
    same_line(path, "PLIANT_NCP_FUSED_CR=0, PLIANT_NCP_GRID_MIN=1 vs unset, no graph", &r[GRID], b,
              GRID_TOL);
    same_line(path, "PLIANT_NCP_FUSED_CR=0, PLIANT_NCP_GRID_MIN=1, graph vs no graph",
              &r[GRID_GRAPH], &r[GRID], 0.0);
    note(path, "median step ms, graph, FUSED_CR=0 and GRID_MIN=1", r[GRID_GRAPH].ms);
    same_line(path, "correction=jacobian, FUSED_CR=0, GRID_MIN=1 vs unset, no graph",
              &r[GRID_JACOBIAN], &r[JACOBIAN], GRID_TOL);
    same_line(path, "lineSearch=0, FUSED_CR=0, GRID_MIN=1 vs unset, no graph", &r[GRID_NO_LS],
              &r[NO_LS], GRID_TOL);
    for (int k = 0; k < NRUNS; ++k) free(r[k].x);
    static const char *const env[] = {"PLIANT_NCP_FUSED_CR",     "PLIANT_NCP_FUSED_WARP",
                                      "PLIANT_NCP_FUSED_NARROW", "PLIANT_NCP_PHASE_PAIRS",
                                      "PLIANT_NCP_SCATTER_WARP", "PLIANT_NCP_ONE_KERNEL",
                                      "PLIANT_NCP_UPDATE_GRAPH", "PLIANT_DEVICE_BRANCHES",
                                      "PLIANT_NCP_GRID_MIN"};
    for (size_t k = 0; k < sizeof env / sizeof env[0]; ++k) unsetenv(env[k]);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s CHECKS.md [steps]\n", PROG);
        return 2;
    }
    gpu_require(PROG);
    int steps = argc > 2 ? atoi(argv[2]) : 100;
    if (steps < 2) steps = 2;
    md = fopen(argv[1], "w");
    if (!md) {
        perror(argv[1]);
        return 2;
    }
    fprintf(md, "# gpu_graph: one CUDA graph kept across steps with rows\n\n| check | value | "
                "tolerance | |\n|---|--:|--:|---|\n");
    const char *scenes[] = {"scenes/ball_on_plane.xml", "scenes/stick_slip.xml",
                            "scenes/cable_finger_small.xml", "scenes/grabbing_raptor_small.xml"};
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; ++k) check(scenes[k], steps);
    fclose(md);
    printf("%s: %d check(s) failed\n", PROG, gpu_failures());
    return gpu_failures() ? 1 : 0;
}
