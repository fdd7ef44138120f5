/* stick_slip_sweep.c - finds the stick/slide threshold of the stick-slip
 * scene by bisection on mu, for each complementarity preconditioner, and
 * reports it against mu* = tan(10 deg) = 0.17632698 (the paper's Fig.
 * "Stick-Sliding test").  A run "slides" when the box moves more than
 * --moved metres (default 1e-3) along the slope in --steps steps.
 *
 *   stick_slip_sweep [--scene scenes/stick_slip.xml] [--steps 100] [--tol 1e-4]
 *                    [--moved 1e-3] [--lo 0.05] [--hi 0.35] [--markdown]
 *                    [--set component.field=value ...]
 *
 * --set passes overrides to every run (up to 8), e.g. with a scene that has
 * a CudaDevice in its root: --set solver.device=cuda --set global.device=cuda
 * (tests/bench/run_gpu.sh does that on the GPU machine).
 */
#include <math.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_tmp.h"

static const double MU_STAR = 0.17632698070846498;

enum { MAX_SETS = 8 };

typedef struct sweep {
    const char *scene;
    int steps;
    double tol, moved, lo, hi;
    int markdown;
    const char *sets[MAX_SETS];
    int nsets;
} sweep;

/* Displacement of the box along the slope after the run [m], or NAN. */
static double run(const sweep *sw, const char *precond, double mu)
{
    char set_mu[64], set_pc[64];
    snprintf(set_mu, sizeof set_mu, "slope.mu=%.10g", mu);
    snprintf(set_pc, sizeof set_pc, "contact.preconditioner=%s", precond);
    const char *sets[3 + MAX_SETS] = {set_mu, set_pc, "vtk.every=100000000"};
    for (int k = 0; k < sw->nsets; ++k) sets[3 + k] = sw->sets[k];
    pl_sim_options opt = {.out_dir = test_tmp_dir(), .overrides = sets, .noverrides = 3 + sw->nsets};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_file(sw->scene, &opt, &diag);
    if (!s) {
        pl_diag_print(&diag, stderr);
        pl_diag_free(&diag);
        return NAN;
    }
    pl_diag_free(&diag);
    pl_component *c = pl_sim_component(s, "box/dofs");
    const pl_state_ops *ops = c ? pl_component_role(c, PL_ROLE_STATE) : NULL;
    if (!ops) {
        fprintf(stderr, "stick_slip_sweep: the scene has no box/dofs\n");
        pl_sim_free(s);
        return NAN;
    }
    pl_buffer b = ops->positions(c, pl_sim_data(s));
    size_t n = b.rows;
    double *x0 = malloc(n * 3 * sizeof *x0);
    memcpy(x0, b.data, n * 3 * sizeof *x0);
    pl_error err;
    double d = NAN;
    if (pl_sim_step(s, sw->steps, &err) == PL_OK) {
        const double a = 10.0 * M_PI / 180.0, dir[3] = {-cos(a), -sin(a), 0.0};
        const double *x = ops->positions(c, pl_sim_data(s)).data;
        d = 0;
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) d += dir[k] * (x[3 * i + k] - x0[3 * i + k]) / (double)n;
    }
    free(x0);
    pl_sim_free(s);
    return d;
}

static void bisect(const sweep *sw, const char *precond)
{
    double lo = sw->lo, hi = sw->hi; /* lo slides, hi sticks */
    int runs = 0;
    double dlo = run(sw, precond, lo), dhi = run(sw, precond, hi);
    runs += 2;
    if (!(dlo > sw->moved) || !(fabs(dhi) <= sw->moved)) {
        printf("%-10s  bracket failed: mu=%.4f moved %.3g m, mu=%.4f moved %.3g m\n", precond, lo,
               dlo, hi, dhi);
        return;
    }
    while (hi - lo > sw->tol) {
        double mid = 0.5 * (lo + hi), d = run(sw, precond, mid);
        runs++;
        if (d > sw->moved)
            lo = mid;
        else
            hi = mid;
    }
    double thr = 0.5 * (lo + hi);
    if (sw->markdown)
        printf("| %s | %.5f | %.5f | %+.5f | %d |\n", precond, thr, MU_STAR, thr - MU_STAR, runs);
    else
        printf("%-10s  threshold %.5f  (mu* %.5f, error %+.5f, %d runs)\n", precond, thr, MU_STAR,
               thr - MU_STAR, runs);
}

int main(int argc, char **argv)
{
    sweep sw = {"scenes/stick_slip.xml", 100, 1e-4, 1e-3, 0.05, 0.35, 0, {NULL}, 0};
    for (int k = 1; k < argc; ++k) {
        const char *a = argv[k], *v = k + 1 < argc ? argv[k + 1] : NULL;
        if (!strcmp(a, "--markdown")) sw.markdown = 1;
        else if (!v) { fprintf(stderr, "stick_slip_sweep: %s needs a value\n", a); return 2; }
        else if (!strcmp(a, "--scene")) sw.scene = v, k++;
        else if (!strcmp(a, "--steps")) sw.steps = atoi(v), k++;
        else if (!strcmp(a, "--tol")) sw.tol = atof(v), k++;
        else if (!strcmp(a, "--moved")) sw.moved = atof(v), k++;
        else if (!strcmp(a, "--lo")) sw.lo = atof(v), k++;
        else if (!strcmp(a, "--hi")) sw.hi = atof(v), k++;
        else if (!strcmp(a, "--set") && sw.nsets < MAX_SETS) sw.sets[sw.nsets++] = v, k++;
        else { fprintf(stderr, "stick_slip_sweep: unknown option %s\n", a); return 2; }
    }
    pl_log_set_level(PL_LOG_WARN);
    if (sw.markdown)
        printf("| preconditioner | threshold | mu* | error | runs |\n| --- | --- | --- | --- | --- |\n");
    bisect(&sw, "delassus");
    bisect(&sw, "mass");
    return 0;
}
