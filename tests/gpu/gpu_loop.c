/* gpu_loop.c - the soft-robot scenes with their own settings (forceTolerance,
 * stickStart) on the device loop against the CPU loop (needs a GPU; ctest -L
 * gpu runs it as gpu_loop_small).
 *
 *   gpu_loop CHECKS.md [steps]
 *
 * scenes/stick_slip.xml (stickStart, 10 iterations) and
 * scenes/cable_finger.xml (forceTolerance 1e-3 N, up to 1000 iterations) run
 * `steps` steps (default 120) on the CPU (solver.device=cpu) and on the
 * device (device="cuda", graph="1").  Checks, per scene:
 *   - the device run took the device loop (it captured a graph); cable_finger
 *     (forceTolerance decides) ran every step as one WHILE graph (stat
 *     "device loop steps");
 *   - the positions of the first body agree: max |x_gpu - x_cpu| <= TOL_X
 *     (1e-6 m; the bodies are 0.1 m);
 *   - the iterations of each step ("iterations" series, forceTolerance's
 *     count): the totals within 2% and no step more than 3 apart (the device
 *     evaluates the residual with its own rounding, so a step near the
 *     tolerance may stop one iteration earlier or later);
 *   - cable_finger: the cable force (cable.force) of every step within 1e-3
 *     relative of the largest CPU force (the tolerance's 1e-3 N is 2e-4 of
 *     the finger's 5 N pull).
 * Notes: median ms per step (= per 0.01 s frame) on each side, the median
 * iterations, the device's microseconds per iteration.
 * Exit status: 0, 1 when a check failed, 77 without a GPU. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_util.h"
#include "test_tmp.h"
#include "pliant/pliant.h"

#define PROG "gpu_loop"
#define TOL_X 1e-6
#define MAXSTEPS 2000

static FILE *md;

typedef struct run_out {
    double *x;              /* first body's positions (n values) */
    size_t n;
    double ms[MAXSTEPS], its[MAXSTEPS], force[MAXSTEPS];
    int nits;
    double captures;
    double loop_steps;      /* stat "device loop steps": steps run by the WHILE graph */
} run_out;

static int first_state(pl_component *c, void *user)
{
    *(pl_component **)user = c;
    return 1;
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) s[0] = '\0';
    if (s) s[n] = '\0';
    fclose(f);
    return s;
}

/* 0 on success. */
static int run(const char *path, int gpu, int steps, int cable, run_out *o)
{
    const char *ov_gpu[] = {"solver.device=cuda", "global.device=cuda", "global.precision=float64"};
    const char *ov_cpu[] = {"solver.device=cpu"};
    char *xml = gpu ? gpu_scene_with_device(path) : read_file(path);
    pl_sim *sim = gpu_load_scene(xml, path, gpu ? ov_gpu : ov_cpu, gpu ? 3 : 1, test_tmp_dir());
    if (!sim) return 1;
    pl_error err;
    int rc = 0;
    for (int k = 0; k < steps && !rc; ++k) {
        double t0 = pl_now();
        if (pl_sim_step(sim, 1, &err) != PL_OK) {
            printf("%s: step %d (%s): %s\n", path, k + 1, gpu ? "gpu" : "cpu", err.msg);
            rc = 1;
            break;
        }
        o->ms[k] = 1e3 * (pl_now() - t0);
        char buf[64] = "";
        o->force[k] = cable && pl_sim_get(sim, "cable.force", buf, sizeof buf, &err) == PL_OK
                          ? atof(buf) : 0.0;
    }
    const double *its = NULL;
    o->nits = pl_series_get(pl_sim_timers(sim), "iterations", &its);
    if (o->nits > steps) o->nits = steps;
    if (its) memcpy(o->its, its, sizeof(double) * (size_t)o->nits);
    o->captures = 0;
    pl_stat_get(pl_sim_timers(sim), "device graph captures", &o->captures);
    o->loop_steps = 0;
    pl_stat_get(pl_sim_timers(sim), "device loop steps", &o->loop_steps);
    pl_component *c = NULL;
    pl_node_visit_role(pl_sim_model(sim)->root, PL_ROLE_STATE, first_state, &c);
    const pl_state_ops *ops = c ? pl_component_role(c, PL_ROLE_STATE) : NULL;
    if (ops && !rc) {
        pl_buffer p = ops->positions(c, pl_sim_data(sim));
        o->n = p.rows * 3;
        o->x = malloc(o->n * sizeof(double));
        if (o->x) memcpy(o->x, p.data, o->n * sizeof(double));
    }
    pl_sim_free(sim);
    return rc || !o->x;
}

static double median_of(const double *v, int n)
{
    double *c = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (!c || n <= 0) return free(c), NAN;
    memcpy(c, v, sizeof(double) * (size_t)n);
    double m = gpu_median(c, n);
    free(c);
    return m;
}

static void check(const char *path, int steps, int cable)
{
    static run_out cpu, gpu;
    char what[256];
    memset(&cpu, 0, sizeof cpu), memset(&gpu, 0, sizeof gpu);
    int bad = run(path, 0, steps, cable, &cpu) || run(path, 1, steps, cable, &gpu) ||
              cpu.n != gpu.n;
    snprintf(what, sizeof what, "%s: %d steps ran on the CPU and on the device", path, steps);
    gpu_check_line(md, what, bad ? INFINITY : 0.0, 0.0);
    if (bad) goto done;
    snprintf(what, sizeof what, "%s: the device loop ran (1 - min(graph captures, 1))", path);
    gpu_check_line(md, what, 1.0 - fmin(gpu.captures, 1.0), 0.0);
    /* forceTolerance decides: every step's iterations in one WHILE graph
     * (local_global_device_loop.c); a fixed count keeps the replays */
    snprintf(what, sizeof what, "%s: steps not run by the WHILE graph (of %d)", path, steps);
    if (cable)
        gpu_check_line(md, what, steps - gpu.loop_steps, 0.0);
    else
        gpu_note_line(md, what, steps - gpu.loop_steps);
    double dx = 0;
    for (size_t i = 0; i < cpu.n; ++i) dx = fmax(dx, fabs(gpu.x[i] - cpu.x[i]));
    snprintf(what, sizeof what, "%s: max |x_gpu - x_cpu| [m]", path);
    gpu_check_line(md, what, dx, TOL_X);
    if (cpu.nits > 0 || gpu.nits > 0) {
        double tc = 0, tg = 0, worst = 0;
        int n = cpu.nits == gpu.nits ? cpu.nits : 0;
        for (int k = 0; k < n; ++k)
            tc += cpu.its[k], tg += gpu.its[k], worst = fmax(worst, fabs(cpu.its[k] - gpu.its[k]));
        snprintf(what, sizeof what, "%s: iterations, total relative difference (%g CPU, %g GPU)",
                 path, tc, tg);
        gpu_check_line(md, what, n ? fabs(tg - tc) / fmax(tc, 1.0) : INFINITY, 0.02);
        snprintf(what, sizeof what, "%s: iterations, largest difference in a step", path);
        gpu_check_line(md, what, n ? worst : INFINITY, 3.0);
        snprintf(what, sizeof what, "%s: median iterations per step (CPU)", path);
        gpu_note_line(md, what, median_of(cpu.its, cpu.nits));
        snprintf(what, sizeof what, "%s: device us per iteration (median step / median its)", path);
        gpu_note_line(md, what, 1e3 * median_of(gpu.ms, steps) / median_of(gpu.its, gpu.nits));
    }
    if (cable) {
        double fmaxc = 0, df = 0;
        for (int k = 0; k < steps; ++k) fmaxc = fmax(fmaxc, fabs(cpu.force[k]));
        for (int k = 0; k < steps; ++k) df = fmax(df, fabs(gpu.force[k] - cpu.force[k]));
        snprintf(what, sizeof what, "%s: cable force, max difference / max CPU force (%.4g N)",
                 path, fmaxc);
        gpu_check_line(md, what, fmaxc > 0 ? df / fmaxc : INFINITY, 1e-3);
    }
    snprintf(what, sizeof what, "%s: median ms per step, CPU", path);
    gpu_note_line(md, what, median_of(cpu.ms, steps));
    snprintf(what, sizeof what, "%s: median ms per step, device loop", path);
    gpu_note_line(md, what, median_of(gpu.ms, steps));
done:
    free(cpu.x), free(gpu.x);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s CHECKS.md [steps]\n", PROG);
        return 2;
    }
    gpu_require(PROG);
    int steps = argc > 2 ? atoi(argv[2]) : 120;
    if (steps < 2) steps = 2;
    if (steps > MAXSTEPS) steps = MAXSTEPS;
    md = fopen(argv[1], "w");
    if (!md) {
        perror(argv[1]);
        return 2;
    }
    fprintf(md, "# gpu_loop: forceTolerance and stickStart scenes, device loop vs CPU loop\n\n"
                "| check | value | tolerance | |\n|---|--:|--:|---|\n");
    check("scenes/stick_slip.xml", steps, 0);
    check("scenes/cable_finger.xml", steps, 1);
    fclose(md);
    printf("%s: %d check(s) failed\n", PROG, gpu_failures());
    return gpu_failures() ? 1 : 0;
}
