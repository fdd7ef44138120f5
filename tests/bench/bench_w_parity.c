/* bench_w_parity.c - W explicit against matrix-free on the same states: where
 * NonSmoothNewtonContactSolver's maxExplicitWork should lie on this machine.
 *
 *   bench_w_parity SCENE.xml [STEPS [REPEATS]]
 *
 * The scene runs STEPS steps with its own settings.  Before each step its
 * state is saved; the step is then taken from that state REPEATS times with
 * delassus="explicit" and REPEATS times with "matrix-free" (interleaved), and
 * the contact phases (Schur, and Constraint global: the constrained
 * iterations whole) of each are timed.  Runs of one scene diverge once a frame takes
 * the other path (round-off), so whole runs cannot compare the two paths;
 * the same state can.  Printed per frame: rows, the build work of W over
 * the step's matrix-free products (the quantity maxExplicitWork bounds:
 * 'Schur W work max' / (65 x 6 nnz(S))), the medians of both times; then,
 * over the frames where delassus="auto"'s other rules allow an explicit W
 * (m^2 <= 6 nnz(S)), the time ratio by bins of that work ratio.  One
 * thread unless OMP_NUM_THREADS says otherwise; run it on a quiet machine.
 * The scene's exporters and the saved state go to OUT (bench_out/w_parity). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "pliant/timer.h"

#define MAXREP 9
/* the contact phases: "Constraint global" holds each constrained iteration
 * whole (its global solve, Constraint solve, Correction) */
static const char *const PHASES[] = {"Schur", "Constraint global"};


/* One step from the saved state with W on `path`: the contact phases [ms];
 * *work and *rows from the step's statistics. */
static int timed_step(pl_sim *sim, const char *state, const char *path, double nnz_s,
                      double *ms, double *work, double *rows)
{
    pl_error err;
    pl_timers *t = pl_sim_timers(sim);
    if (pl_sim_restore_state(sim, state, &err) || pl_sim_set(sim, "contact.delassus", path, &err))
        return fprintf(stderr, "restore / set: %s\n", err.msg), 1;
    pl_timers_clear(t);
    pl_stat_set(t, "nnz(S)", nnz_s); /* recorded at the factorization, which a step does not redo */
    if (pl_sim_step(sim, 1, &err)) return fprintf(stderr, "step: %s\n", err.msg), 1;
    *ms = 0.0;
    for (size_t k = 0; k < sizeof PHASES / sizeof PHASES[0]; ++k) {
        int id = pl_timer_id(t, PHASES[k]);
        if (id >= 0 && pl_timers_samples(t, id) > 0) *ms += pl_timers_total_ms(t, id);
    }
    if (pl_stat_get(t, "Schur W work max", work)) *work = 0.0;
    if (pl_stat_get(t, "constraint rows max", rows)) *rows = 0.0;
    return 0;
}

typedef struct bin {
    double lo, hi;
    int n;
    double t_exp, t_mf, ratio[4096];
} bin;

static const double EDGES[] = {0, 0.1, 0.2, 0.3, 0.45, 0.6, 1, 2, INFINITY};
enum { NBINS = sizeof EDGES / sizeof EDGES[0] - 1 };

static void bins_add(bin *bins, double rho, double e, double m)
{
    for (int b = 0; b < NBINS; ++b)
        if (rho >= bins[b].lo && rho < bins[b].hi && bins[b].n < 4096) {
            bins[b].ratio[bins[b].n++] = e / m;
            bins[b].t_exp += e;
            bins[b].t_mf += m;
        }
}

static void bins_print(bin *bins)
{
    printf("\n| work ratio | frames | explicit [ms] | matrix-free [ms] | median explicit / matrix-free |\n");
    printf("|---|--:|--:|--:|--:|\n");
    for (int b = 0; b < NBINS; ++b)
        if (bins[b].n > 0)
            printf("| %g - %g | %d | %.1f | %.1f | %.2f |\n", bins[b].lo, bins[b].hi, bins[b].n,
                   bins[b].t_exp, bins[b].t_mf, bench_median(bins[b].ratio, bins[b].n));
}

/* Frame k: both paths from the saved state, then the step with the scene's
 * own setting (own); the line printed and the bins filled. */
static int frame(pl_sim *sim, const char *state, const char *own, double nnz_s, int k, int reps,
                 bin *bins)
{
    pl_error err;
    pl_timers *t = pl_sim_timers(sim);
    if (pl_sim_save_state(sim, state, &err)) return fprintf(stderr, "save: %s\n", err.msg), 1;
    double te[MAXREP], tm[MAXREP], work = 0.0, rows = 0.0, w2, r2;
    for (int r = 0; r < reps; ++r)
        if (timed_step(sim, state, "explicit", nnz_s, &te[r], &work, &rows) ||
            timed_step(sim, state, "matrix-free", nnz_s, &tm[r], &w2, &r2))
            return 1;
    if (pl_sim_restore_state(sim, state, &err) || pl_sim_set(sim, "contact.delassus", own, &err))
        return fprintf(stderr, "restore / set: %s\n", err.msg), 1;
    pl_timers_clear(t);
    pl_stat_set(t, "nnz(S)", nnz_s);
    if (pl_sim_step(sim, 1, &err)) return fprintf(stderr, "step: %s\n", err.msg), 1;
    if (!(rows > 0)) return 0;
    double e = bench_median(te, reps), m = bench_median(tm, reps), rho = work / (65.0 * 6.0 * nnz_s);
    printf("%d %.0f %.3f %.3f %.3f %.2f\n", k + 1, rows, rho, e, m, e / m);
    if (rows * rows <= 6.0 * nnz_s) bins_add(bins, rho, e, m); /* else auto is matrix-free anyway */
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) return fprintf(stderr, "usage: bench_w_parity SCENE.xml [STEPS [REPEATS [OUT]]]\n"), 2;
    int steps = argc > 2 ? atoi(argv[2]) : 150, reps = argc > 3 ? atoi(argv[3]) : 3;
    const char *out = argc > 4 ? argv[4] : "bench_out/w_parity";
    if (steps < 1 || reps < 1 || reps > MAXREP) return fprintf(stderr, "bad STEPS or REPEATS\n"), 2;
    pl_sim *sim = bench_load(argv[1], NULL, NULL, 0, out);
    if (!sim) return 2;
    char state[1024], own[64];
    snprintf(state, sizeof state, "%s/w_parity.state", out);
    double nnz_s;
    pl_error err;
    int rc = 2;
    if (pl_stat_get(pl_sim_timers(sim), "nnz(S)", &nnz_s) || !(nnz_s > 0))
        fprintf(stderr, "%s: no nnz(S) (not a SparseInverseSolver scene?)\n", argv[1]);
    else if (pl_sim_get(sim, "contact.delassus", own, sizeof own, &err))
        fprintf(stderr, "%s: no NonSmoothNewtonContactSolver named contact\n", argv[1]);
    else {
        static bin bins[NBINS];
        for (int b = 0; b < NBINS; ++b) bins[b].lo = EDGES[b], bins[b].hi = EDGES[b + 1];
        printf("%s: nnz(S) %.0f, %d steps, %d repeats, own delassus=%s\n", argv[1], nnz_s, steps,
               reps, own);
        printf("frame rows work/(65x6nnzS) explicit_ms matrix-free_ms ratio\n");
        rc = 0;
        for (int k = 0; k < steps && !rc; ++k) rc = frame(sim, state, own, nnz_s, k, reps, bins);
        if (!rc) bins_print(bins);
        remove(state);
    }
    pl_sim_free(sim);
    return rc;
}
