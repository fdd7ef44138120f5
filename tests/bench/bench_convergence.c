/* bench_convergence.c - the paper's convergence comparison (Fig. "convergence
 * comparison"): relative error of the local-global iterations,
 *     (eps(q^k) - eps(q*)) / (eps(q^0) - eps(q*)),  k = 1..K,
 * with eps the incremental potential, q^0 the initial guess (the predicted
 * state with the prescribed ends moved) and q* Newton's converged solution
 * of the same step, for several Young's moduli, for the scene's global
 * solver (the complete solution) and for the paper's incomplete baseline,
 * JacobiSolver (one Jacobi sweep per iteration from the current iterate,
 * Wang 2015, no Chebyshev), by iterations and by milliseconds.
 *
 * Per stiffness E:
 *   1. the scene (LocalGlobalSolver, its own iterations) runs --frames frames
 *      so that the bar is well twisted; the state is saved;
 *   2. a second load with iterations=K, computeEnergy=1 restores it and takes
 *      ONE step: the timers' series "energy0" (eps(q^0)) and "energy"
 *      (eps(q^k) after each iteration); the step's Local + Assembly + Global
 *      time over K is the cost of one iteration;
 *   3. the same with the scene's <SparseInverseSolver .../> replaced by
 *      <JacobiSolver/> (same name) and --jacobi-iterations iterations;
 *   4. a load of the scene text with <NewtonSolver> in place of the
 *      LocalGlobalSolver (same component name, so the same state slots)
 *      restores it and takes ONE step: the statistic "newton energy" = eps(q*).
 *
 *   bench_convergence [--scene FILE] [--frames N] [--iterations K]
 *       [--jacobi-iterations KJ] [--stiffness 1e5,1e7,1e9]
 *       [--modulus-field arap.youngModulus] [--newton-max N] [--out-dir DIR]
 *       [--csv FILE]
 *
 * Markdown tables go to stdout, progress to stderr; the CSV has one row per
 * iteration k and, per solver and stiffness, two columns: the relative error
 * and the time [ms] after k iterations (empty past that solver's K). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bench_util.h"
#include "pliant/pliant.h"

#ifndef PL_SOURCE_DIR
#define PL_SOURCE_DIR "."
#endif

#define MAX_STIFF 8
#define MAX_ITER 1000

typedef struct conv_args {
    const char *scene;
    int frames, iterations, jacobi_iterations, newton_max;
    char *stiffness[MAX_STIFF];
    int nstiff;
    const char *modulus_field;
    const char *out_dir;
    const char *csv;
} conv_args;

/* One solver's step: eps(q^k) after each iteration and the cost of one. */
typedef struct conv_series {
    double e0;                   /* eps(q^0) */
    double ek[MAX_ITER];         /* eps(q^k), k = 1..nk */
    int nk;
    double ms_per_iteration;     /* (Local + Assembly + Global) of the step / nk */
} conv_series;

typedef struct conv_result {
    const char *E;
    double estar;                /* eps(q*) */
    conv_series lg, jacobi;      /* the scene's global solver; JacobiSolver (nk = 0: not run) */
    double newton_iterations, newton_s;
} conv_result;

static int parse_args(int argc, char **argv, conv_args *a)
{
    static char stiff[128] = "1e5,1e7,1e9";
    a->scene = PL_SOURCE_DIR "/scenes/twisting_bar.xml";
    a->frames = 100;
    a->iterations = 20;
    a->jacobi_iterations = 1000;
    a->newton_max = 200;
    a->modulus_field = "arap.youngModulus";
    a->out_dir = "bench_out";
    a->csv = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i];
        int v = i + 1 < argc;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            printf("usage: bench_convergence [--scene FILE] [--frames N] [--iterations K]\n"
                   "  [--jacobi-iterations KJ (0: no Jacobi)] [--stiffness 1e5,1e7,1e9]\n"
                   "  [--modulus-field arap.youngModulus] [--newton-max N] [--out-dir DIR]\n"
                   "  [--csv FILE]\n");
            return 1;
        } else if (!strcmp(o, "--scene") && v) a->scene = argv[++i];
        else if (!strcmp(o, "--frames") && v) a->frames = atoi(argv[++i]);
        else if (!strcmp(o, "--iterations") && v) a->iterations = atoi(argv[++i]);
        else if (!strcmp(o, "--jacobi-iterations") && v) a->jacobi_iterations = atoi(argv[++i]);
        else if (!strcmp(o, "--newton-max") && v) a->newton_max = atoi(argv[++i]);
        else if (!strcmp(o, "--stiffness") && v) snprintf(stiff, sizeof stiff, "%s", argv[++i]);
        else if (!strcmp(o, "--modulus-field") && v) a->modulus_field = argv[++i];
        else if (!strcmp(o, "--out-dir") && v) a->out_dir = argv[++i];
        else if (!strcmp(o, "--csv") && v) a->csv = argv[++i];
        else {
            fprintf(stderr, "bench_convergence: unknown option or missing value: %s\n", o);
            return 2;
        }
    }
    a->nstiff = bench_split_list(stiff, a->stiffness, MAX_STIFF);
    if (a->frames < 0 || a->iterations < 1 || a->iterations > MAX_ITER ||
        a->jacobi_iterations < 0 || a->jacobi_iterations > MAX_ITER || a->newton_max < 1 ||
        a->nstiff == 0) {
        fprintf(stderr, "bench_convergence: need frames >= 0, 1 <= iterations <= %d, "
                        "0 <= jacobi-iterations <= %d, newton-max >= 1 and at least one "
                        "stiffness\n", MAX_ITER, MAX_ITER);
        return 2;
    }
    return 0;
}

/* The scene text with its first self-closing <tag .../> element replaced by
 * <new_tag name="(its name, default dflt)" attrs/>; NULL if there is none. */
static char *replace_element(const char *xml, const char *tag, const char *dflt,
                             const char *new_tag, const char *attrs)
{
    char open[64];
    snprintf(open, sizeof open, "<%s", tag);
    const char *start = strstr(xml, open);
    const char *end = start ? strstr(start, "/>") : NULL;
    const char *gt = start ? strchr(start, '>') : NULL;
    if (!start || !end || gt != end + 1) return NULL;
    char name[128];
    snprintf(name, sizeof name, "%s", dflt);
    const char *attr = strstr(start, " name=\"");
    if (attr && attr < end) {
        attr += 7;
        const char *q = strchr(attr, '"');
        if (!q || q > end || (size_t)(q - attr) >= sizeof name) return NULL;
        memcpy(name, attr, (size_t)(q - attr));
        name[q - attr] = '\0';
    }
    char element[256];
    snprintf(element, sizeof element, "<%s name=\"%s\" %s/>", new_tag, name, attrs);
    size_t head = (size_t)(start - xml), tail = strlen(end + 2), len = head + strlen(element) + tail;
    char *out = malloc(len + 1);
    if (!out) return NULL;
    memcpy(out, xml, head);
    memcpy(out + head, element, strlen(element));
    memcpy(out + head + strlen(element), end + 2, tail + 1);
    return out;
}

/* <LocalGlobalSolver .../> -> <NewtonSolver name="(same)" maxIterations="max"/> */
static char *newton_variant(const char *xml, int max_iterations)
{
    char attrs[64];
    snprintf(attrs, sizeof attrs, "maxIterations=\"%d\"", max_iterations);
    return replace_element(xml, "LocalGlobalSolver", "solver", "NewtonSolver", attrs);
}

/* <SparseInverseSolver .../> -> <JacobiSolver name="(same)"/>: the paper's baseline, no
 * Chebyshev */
static char *jacobi_variant(const char *xml)
{
    return replace_element(xml, "SparseInverseSolver", "global", "JacobiSolver", "chebyshev=\"0\"");
}

static void report_error(const char *what, const pl_error *err)
{
    char msg[1600];
    fprintf(stderr, "bench_convergence: %s: %s\n", what, pl_error_format(err, msg, sizeof msg));
}

/* Step 1: the run-up to a twisted state, saved to state_path. */
static int run_up(const conv_args *a, const char *set_E, const char *state_path, conv_result *r)
{
    const char *ov[] = {set_E, "vtk.every=1000000"};
    pl_sim *sim = bench_load(a->scene, NULL, ov, 2, a->out_dir);
    if (!sim) return PL_EINPUT;
    bench_scene_info info;
    pl_error err;
    int rc = bench_describe(sim, &info);
    if (rc == PL_OK && info.iterations < 1) {
        fprintf(stderr, "bench_convergence: %s has no LocalGlobalSolver at its root\n", a->scene);
        rc = PL_EINPUT;
    }
    if (rc == PL_OK && a->frames > 0 && (rc = pl_sim_step(sim, a->frames, &err)))
        report_error("run-up", &err);
    if (rc == PL_OK && (rc = pl_sim_save_state(sim, state_path, &err))) report_error("save", &err);
    (void)r;
    if (rc == PL_OK)
        fprintf(stderr, "bench_convergence: %s: %d vertices, %d elements, %s, run-up %d frames\n",
                set_E, info.vertices, info.elements, info.material, a->frames);
    pl_sim_free(sim);
    return rc;
}

/* Steps 2 and 3: one local-global step of K iterations from the saved
 * state, with the scene's global solver (xml NULL) or the Jacobi variant. */
static int local_global_step(const conv_args *a, const char *xml, int iterations,
                             const char *set_E, const char *state_path, conv_series *out)
{
    char set_it[64];
    snprintf(set_it, sizeof set_it, "solver.iterations=%d", iterations);
    const char *ov[] = {set_E, "vtk.every=1000000", set_it, "solver.computeEnergy=1",
                        "solver.tolerance=0"};
    pl_sim *sim = bench_load(a->scene, xml, ov, 5, a->out_dir);
    if (!sim) return PL_EINPUT;
    pl_error err;
    int rc = pl_sim_restore_state(sim, state_path, &err);
    if (rc) report_error("restore (local-global)", &err);
    if (rc == PL_OK && (rc = pl_sim_step(sim, 1, &err))) report_error("local-global step", &err);
    const double *e0 = NULL, *ek = NULL;
    const pl_timers *t = pl_sim_timers(sim);
    int n0 = pl_series_get(t, "energy0", &e0), nk = pl_series_get(t, "energy", &ek);
    if (rc == PL_OK && (n0 != 1 || nk != iterations)) {
        fprintf(stderr,
                "bench_convergence: expected 1 \"energy0\" and %d \"energy\" values, got %d and %d "
                "(LocalGlobalSolver.computeEnergy must record eps(q^0) as series \"energy0\")\n",
                iterations, n0, nk);
        rc = PL_EINTERNAL;
    }
    if (rc == PL_OK) {
        out->e0 = e0[0];
        out->nk = nk;
        memcpy(out->ek, ek, (size_t)nk * sizeof *ek);
        /* one frame: its median is its total (the energy evaluations are outside these phases) */
        out->ms_per_iteration = (bench_phase_median_ms(t, "Local") +
                                 bench_phase_median_ms(t, "Assembly") +
                                 bench_phase_median_ms(t, "Global")) / nk;
    }
    pl_sim_free(sim);
    return rc;
}

/* Step 4: Newton's solution of the same step from the same state. */
static int newton_step(const conv_args *a, const char *xml, const char *set_E,
                       const char *state_path, conv_result *r)
{
    /* direct mode: Newton never uses the global solver, so do not build S */
    const char *ov[] = {set_E, "vtk.every=1000000", "global.mode=direct"};
    pl_sim *sim = bench_load(a->scene, xml, ov, 3, a->out_dir);
    if (!sim) return PL_EINPUT;
    pl_error err;
    int rc = pl_sim_restore_state(sim, state_path, &err);
    if (rc) report_error("restore (Newton)", &err);
    double t0 = pl_now();
    if (rc == PL_OK && (rc = pl_sim_step(sim, 1, &err))) report_error("Newton step", &err);
    r->newton_s = pl_now() - t0;
    const pl_timers *t = pl_sim_timers(sim);
    r->estar = bench_stat(t, "newton energy");
    r->newton_iterations = bench_stat(t, "newton iterations");
    if (rc == PL_OK && isnan(r->estar)) {
        fprintf(stderr, "bench_convergence: the Newton step left no \"newton energy\"\n");
        rc = PL_EINTERNAL;
    }
    if (rc == PL_OK && r->newton_iterations >= a->newton_max)
        fprintf(stderr, "bench_convergence: warning: Newton used all %d iterations (%s): eps(q*) "
                        "may not be converged\n", a->newton_max, set_E);
    pl_sim_free(sim);
    return rc;
}

static double relative_error(const conv_result *r, const conv_series *c, int k)
{
    return (c->ek[k] - r->estar) / (c->e0 - r->estar);
}

/* The first iteration count whose error is below tol, or 0. */
static int iterations_to(const conv_result *r, const conv_series *c, double tol)
{
    for (int k = 0; k < c->nk; ++k)
        if (relative_error(r, c, k) < tol) return k + 1;
    return 0;
}

static void print_error_at(const conv_result *r, const conv_series *c, int k)
{
    if (k >= 1 && k <= c->nk) printf(" %.3e |", relative_error(r, c, k - 1));
    else printf(" |");
}

static void print_tables(const conv_args *a, const conv_result *res, int n)
{
    char b1[32], b2[32];
    printf("| E [Pa] | eps(q^0) [J] | eps(q*) [J] | Newton it. | Newton s | ms/iteration: complete | "
           "Jacobi | error after %d: complete | after %d: Jacobi | iterations to 1e-3: complete | "
           "Jacobi |\n|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n",
           a->iterations, a->jacobi_iterations);
    for (int s = 0; s < n; ++s) {
        const conv_result *r = &res[s];
        int kl = iterations_to(r, &r->lg, 1e-3), kj = iterations_to(r, &r->jacobi, 1e-3);
        snprintf(b1, sizeof b1, kl ? "%d" : "> %d", kl ? kl : r->lg.nk);
        snprintf(b2, sizeof b2, kj ? "%d" : "> %d", kj ? kj : r->jacobi.nk);
        printf("| %s | %.10g | %.10g | %.0f | %.2f | %.2f | %.2f | %.3e | %.3e | %s | %s |\n", r->E,
               r->lg.e0, r->estar, r->newton_iterations, r->newton_s, r->lg.ms_per_iteration,
               r->jacobi.ms_per_iteration, relative_error(r, &r->lg, r->lg.nk - 1),
               r->jacobi.nk ? relative_error(r, &r->jacobi, r->jacobi.nk - 1) : NAN, b1,
               r->jacobi.nk ? b2 : "n/a");
    }
    /* by iterations: all of the complete solver's, then a log scale */
    int kmax = a->iterations > a->jacobi_iterations ? a->iterations : a->jacobi_iterations;
    printf("\nBy iterations (complete = the scene's global solver):\n\n| k |");
    for (int s = 0; s < n; ++s) printf(" complete E = %s | Jacobi E = %s |", res[s].E, res[s].E);
    printf("\n|--:|");
    for (int s = 0; s < n; ++s) printf("--:|--:|");
    printf("\n");
    static const int LOG_K[] = {50, 100, 200, 500, 1000};
    for (int i = 0, k = 1; k <= kmax; ++i) {
        printf("| %d |", k);
        for (int s = 0; s < n; ++s) {
            print_error_at(&res[s], &res[s].lg, k);
            print_error_at(&res[s], &res[s].jacobi, k);
        }
        printf("\n");
        (void)i;
        if (k < 5 || (k < 20 && k < a->iterations)) k++;
        else if (k < 20) k = 20;
        else {
            int next = kmax + 1;
            for (size_t j = 0; j < sizeof LOG_K / sizeof LOG_K[0]; ++j)
                if (LOG_K[j] > k) { next = LOG_K[j]; break; }
            k = next;
        }
    }
    /* by time: the last iteration done within each budget */
    static const double BUDGET_MS[] = {16.7, 33.3, 100, 300, 1000, 3000, 10000, 30000};
    printf("\nBy time (the error of the last iteration finished within the budget; iterations "
           "cost the ms/iteration above; 16.7 and 33.3 ms are the 60 and 30 FPS frames):\n\n"
           "| budget ms |");
    for (int s = 0; s < n; ++s) printf(" complete E = %s | Jacobi E = %s |", res[s].E, res[s].E);
    printf("\n|--:|");
    for (int s = 0; s < n; ++s) printf("--:|--:|");
    printf("\n");
    for (size_t b = 0; b < sizeof BUDGET_MS / sizeof BUDGET_MS[0]; ++b) {
        int running = 0; /* a row only while some run had not stopped before the budget */
        for (int s = 0; s < n; ++s)
            running |= BUDGET_MS[b] < (res[s].lg.nk + 1) * res[s].lg.ms_per_iteration ||
                       BUDGET_MS[b] < (res[s].jacobi.nk + 1) * res[s].jacobi.ms_per_iteration;
        if (!running) break;
        printf("| %g |", BUDGET_MS[b]);
        for (int s = 0; s < n; ++s) {
            const conv_series *cs[2] = {&res[s].lg, &res[s].jacobi};
            for (int c = 0; c < 2; ++c) {
                int k = cs[c]->ms_per_iteration > 0 ? (int)(BUDGET_MS[b] / cs[c]->ms_per_iteration) : 0;
                if (k > cs[c]->nk) printf(" (%d it.) |", cs[c]->nk);
                else if (k < 1) printf(" - |");
                else print_error_at(&res[s], cs[c], k);
            }
        }
        printf("\n");
    }
    printf("\n(\"-\": not one iteration within the budget; \"(K it.)\": the run stopped after K "
           "iterations, before the budget.)\n");
}

static void csv_cell(FILE *f, const conv_result *r, const conv_series *c, int k)
{
    if (k < c->nk) fprintf(f, ",%.6e,%.6g", relative_error(r, c, k), (k + 1) * c->ms_per_iteration);
    else fprintf(f, ",,");
}

static int write_csv(const conv_args *a, const conv_result *res, int n)
{
    FILE *f = fopen(a->csv, "w");
    if (!f) {
        fprintf(stderr, "bench_convergence: cannot write %s\n", a->csv);
        return PL_EINPUT;
    }
    fprintf(f, "k");
    for (int s = 0; s < n; ++s)
        fprintf(f, ",complete E=%s,complete E=%s ms,Jacobi E=%s,Jacobi E=%s ms", res[s].E, res[s].E,
                res[s].E, res[s].E);
    fprintf(f, "\n");
    int kmax = a->iterations > a->jacobi_iterations ? a->iterations : a->jacobi_iterations;
    for (int k = 0; k < kmax; ++k) {
        fprintf(f, "%d", k + 1);
        for (int s = 0; s < n; ++s) {
            csv_cell(f, &res[s], &res[s].lg, k);
            csv_cell(f, &res[s], &res[s].jacobi, k);
        }
        fprintf(f, "\n");
    }
    return fclose(f) == 0 ? PL_OK : PL_EINPUT;
}

static int run_stiffness(const conv_args *a, const char *newton_xml, const char *jacobi_xml,
                         conv_result *r)
{
    char set_E[160], state_path[1200];
    snprintf(set_E, sizeof set_E, "%s=%s", a->modulus_field, r->E);
    snprintf(state_path, sizeof state_path, "%s/convergence_E%s.state", a->out_dir, r->E);
    fprintf(stderr, "bench_convergence: E = %s: run-up, local-global steps, Newton step\n", r->E);
    int rc = run_up(a, set_E, state_path, r);
    if (rc == PL_OK) rc = local_global_step(a, NULL, a->iterations, set_E, state_path, &r->lg);
    if (rc == PL_OK && jacobi_xml)
        rc = local_global_step(a, jacobi_xml, a->jacobi_iterations, set_E, state_path, &r->jacobi);
    if (rc == PL_OK) rc = newton_step(a, newton_xml, set_E, state_path, r);
    if (rc == PL_OK && r->lg.ek[r->lg.nk - 1] < r->estar)
        fprintf(stderr, "bench_convergence: warning: E = %s: the local-global energy %.10g is "
                        "below Newton's %.10g (relative errors turn negative)\n",
                r->E, r->lg.ek[r->lg.nk - 1], r->estar);
    if (rc == PL_OK && jacobi_xml && fabs(r->jacobi.e0 - r->lg.e0) > 1e-12 * fabs(r->lg.e0))
        fprintf(stderr, "bench_convergence: warning: E = %s: eps(q^0) differs between the solvers "
                        "(%.15g, %.15g)\n", r->E, r->lg.e0, r->jacobi.e0);
    return rc;
}

int main(int argc, char **argv)
{
    conv_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc == 1 ? 0 : rc;
    mkdir(a.out_dir, 0777); /* state files and frame 0 of the exporters; may exist */
    char *text = bench_read_file(a.scene);
    char *newton_xml = text ? newton_variant(text, a.newton_max) : NULL;
    char *jacobi_xml = text && a.jacobi_iterations > 0 ? jacobi_variant(text) : NULL;
    free(text);
    if (!newton_xml || (a.jacobi_iterations > 0 && !jacobi_xml)) {
        fprintf(stderr, "bench_convergence: cannot read %s or it has no self-closing "
                        "<LocalGlobalSolver .../> and <SparseInverseSolver .../> elements\n",
                a.scene);
        free(newton_xml);
        free(jacobi_xml);
        return 2;
    }
    static conv_result res[MAX_STIFF];
    for (int s = 0; s < a.nstiff && rc == PL_OK; ++s) {
        memset(&res[s], 0, sizeof res[s]);
        res[s].E = a.stiffness[s];
        rc = run_stiffness(&a, newton_xml, jacobi_xml, &res[s]);
    }
    free(newton_xml);
    free(jacobi_xml);
    if (rc != PL_OK) return 1;
    printf("Scene %s, state after %d frames, one step of %d local-global iterations with the "
           "scene's global solver (complete) and %d with JacobiSolver (one sweep per iteration, "
           "no Chebyshev), against Newton.\n\n",
           a.scene, a.frames, a.iterations, a.jacobi_iterations);
    print_tables(&a, res, a.nstiff);
    return a.csv ? (write_csv(&a, res, a.nstiff) == PL_OK ? 0 : 1) : 0;
}
