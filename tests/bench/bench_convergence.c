/* bench_convergence.c - the paper's convergence comparison (Fig. "convergence
 * comparison"): relative error of the local-global iterations,
 *     (eps(q^k) - eps(q*)) / (eps(q^0) - eps(q*)),  k = 1..K,
 * with eps the incremental potential, q^0 the initial guess (the predicted
 * state with the prescribed ends moved) and q* Newton's converged solution
 * of the same step, for several Young's moduli.
 *
 * Per stiffness E:
 *   1. the scene (LocalGlobalSolver, its own iterations) runs --frames frames
 *      so that the bar is well twisted; the state is saved;
 *   2. a second load with iterations=K, computeEnergy=1 restores it and takes
 *      ONE step: the timers' series "energy0" (eps(q^0)) and "energy"
 *      (eps(q^k) after each iteration);
 *   3. a third load of the scene text with <NewtonSolver> in place of the
 *      LocalGlobalSolver (same component name, so the same state slots)
 *      restores it and takes ONE step: the statistic "newton energy" = eps(q*).
 *
 *   bench_convergence [--scene FILE] [--frames N] [--iterations K]
 *       [--stiffness 1e5,1e7,1e9] [--modulus-field arap.youngModulus]
 *       [--newton-max N] [--out-dir DIR] [--csv FILE]
 *
 * Markdown tables go to stdout, progress to stderr; the CSV has one row per
 * iteration k and one column per stiffness. */
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
    int frames, iterations, newton_max;
    char *stiffness[MAX_STIFF];
    int nstiff;
    const char *modulus_field;
    const char *out_dir;
    const char *csv;
} conv_args;

typedef struct conv_result {
    const char *E;
    double e0, estar;            /* eps(q^0), eps(q*) */
    double ek[MAX_ITER];         /* eps(q^k), k = 1..K */
    int nk;
    double newton_iterations, newton_s;
    double lg_iteration_ms;      /* (Local + Assembly + Global) per iteration, median of the run-up */
} conv_result;

static int parse_args(int argc, char **argv, conv_args *a)
{
    static char stiff[128] = "1e5,1e7,1e9";
    a->scene = PL_SOURCE_DIR "/scenes/twisting_bar.xml";
    a->frames = 100;
    a->iterations = 20;
    a->newton_max = 200;
    a->modulus_field = "arap.youngModulus";
    a->out_dir = "bench_out";
    a->csv = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i];
        int v = i + 1 < argc;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            printf("usage: bench_convergence [--scene FILE] [--frames N] [--iterations K]\n"
                   "  [--stiffness 1e5,1e7,1e9] [--modulus-field arap.youngModulus]\n"
                   "  [--newton-max N] [--out-dir DIR] [--csv FILE]\n");
            return 1;
        } else if (!strcmp(o, "--scene") && v) a->scene = argv[++i];
        else if (!strcmp(o, "--frames") && v) a->frames = atoi(argv[++i]);
        else if (!strcmp(o, "--iterations") && v) a->iterations = atoi(argv[++i]);
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
    if (a->frames < 0 || a->iterations < 1 || a->iterations > MAX_ITER || a->newton_max < 1 ||
        a->nstiff == 0) {
        fprintf(stderr, "bench_convergence: need frames >= 0, 1 <= iterations <= %d, "
                        "newton-max >= 1 and at least one stiffness\n", MAX_ITER);
        return 2;
    }
    return 0;
}

/* The scene text with its <LocalGlobalSolver .../> element replaced by
 * <NewtonSolver name="(same name)" maxIterations="max"/>; NULL if the scene
 * has no self-closing LocalGlobalSolver element. */
static char *newton_variant(const char *xml, int max_iterations)
{
    const char *start = strstr(xml, "<LocalGlobalSolver");
    const char *end = start ? strstr(start, "/>") : NULL;
    const char *gt = start ? strchr(start, '>') : NULL;
    if (!start || !end || gt != end + 1) return NULL;
    char name[128] = "solver";
    const char *attr = strstr(start, " name=\"");
    if (attr && attr < end) {
        attr += 7;
        const char *q = strchr(attr, '"');
        if (!q || q > end || (size_t)(q - attr) >= sizeof name) return NULL;
        memcpy(name, attr, (size_t)(q - attr));
        name[q - attr] = '\0';
    }
    char element[256];
    snprintf(element, sizeof element, "<NewtonSolver name=\"%s\" maxIterations=\"%d\"/>", name,
             max_iterations);
    size_t head = (size_t)(start - xml), tail = strlen(end + 2), len = head + strlen(element) + tail;
    char *out = malloc(len + 1);
    if (!out) return NULL;
    memcpy(out, xml, head);
    memcpy(out + head, element, strlen(element));
    memcpy(out + head + strlen(element), end + 2, tail + 1);
    return out;
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
    const pl_timers *t = pl_sim_timers(sim);
    r->lg_iteration_ms = (bench_phase_median_ms(t, "Local") + bench_phase_median_ms(t, "Assembly") +
                          bench_phase_median_ms(t, "Global")) /
                         (info.iterations > 0 ? info.iterations : 1);
    if (rc == PL_OK)
        fprintf(stderr, "bench_convergence: %s: %d vertices, %d elements, %s, run-up %d frames\n",
                set_E, info.vertices, info.elements, info.material, a->frames);
    pl_sim_free(sim);
    return rc;
}

/* Step 2: one local-global step of K iterations from the saved state. */
static int local_global_step(const conv_args *a, const char *set_E, const char *state_path,
                             conv_result *r)
{
    char set_it[64];
    snprintf(set_it, sizeof set_it, "solver.iterations=%d", a->iterations);
    const char *ov[] = {set_E, "vtk.every=1000000", set_it, "solver.computeEnergy=1",
                        "solver.tolerance=0"};
    pl_sim *sim = bench_load(a->scene, NULL, ov, 5, a->out_dir);
    if (!sim) return PL_EINPUT;
    pl_error err;
    int rc = pl_sim_restore_state(sim, state_path, &err);
    if (rc) report_error("restore (local-global)", &err);
    if (rc == PL_OK && (rc = pl_sim_step(sim, 1, &err))) report_error("local-global step", &err);
    const double *e0 = NULL, *ek = NULL;
    const pl_timers *t = pl_sim_timers(sim);
    int n0 = pl_series_get(t, "energy0", &e0), nk = pl_series_get(t, "energy", &ek);
    if (rc == PL_OK && (n0 != 1 || nk != a->iterations)) {
        fprintf(stderr,
                "bench_convergence: expected 1 \"energy0\" and %d \"energy\" values, got %d and %d "
                "(LocalGlobalSolver.computeEnergy must record eps(q^0) as series \"energy0\")\n",
                a->iterations, n0, nk);
        rc = PL_EINTERNAL;
    }
    if (rc == PL_OK) {
        r->e0 = e0[0];
        r->nk = nk;
        memcpy(r->ek, ek, (size_t)nk * sizeof *ek);
    }
    pl_sim_free(sim);
    return rc;
}

/* Step 3: Newton's solution of the same step from the same state. */
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

static double relative_error(const conv_result *r, int k)
{
    return (r->ek[k] - r->estar) / (r->e0 - r->estar);
}

static void print_tables(const conv_args *a, const conv_result *res, int n)
{
    printf("| E [Pa] | eps(q^0) [J] | eps(q^K) [J] | eps(q*) [J] | Newton it. | Newton s | "
           "LG ms/iteration |\n|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int s = 0; s < n; ++s)
        printf("| %s | %.10g | %.10g | %.10g | %.0f | %.2f | %.2f |\n", res[s].E, res[s].e0,
               res[s].ek[res[s].nk - 1], res[s].estar, res[s].newton_iterations, res[s].newton_s,
               res[s].lg_iteration_ms);
    printf("\n| k |");
    for (int s = 0; s < n; ++s) printf(" E = %s |", res[s].E);
    printf("\n|--:|");
    for (int s = 0; s < n; ++s) printf("--:|");
    printf("\n");
    for (int k = 0; k < a->iterations; ++k) {
        printf("| %d |", k + 1);
        for (int s = 0; s < n; ++s) printf(" %.3e |", relative_error(&res[s], k));
        printf("\n");
    }
}

static int write_csv(const conv_args *a, const conv_result *res, int n)
{
    FILE *f = fopen(a->csv, "w");
    if (!f) {
        fprintf(stderr, "bench_convergence: cannot write %s\n", a->csv);
        return PL_EINPUT;
    }
    fprintf(f, "k");
    for (int s = 0; s < n; ++s) fprintf(f, ",E=%s", res[s].E);
    fprintf(f, "\n");
    for (int k = 0; k < a->iterations; ++k) {
        fprintf(f, "%d", k + 1);
        for (int s = 0; s < n; ++s) fprintf(f, ",%.6e", relative_error(&res[s], k));
        fprintf(f, "\n");
    }
    return fclose(f) == 0 ? PL_OK : PL_EINPUT;
}

int main(int argc, char **argv)
{
    conv_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc == 1 ? 0 : rc;
    mkdir(a.out_dir, 0777); /* state files and frame 0 of the exporters; may exist */
    char *text = bench_read_file(a.scene);
    char *newton_xml = text ? newton_variant(text, a.newton_max) : NULL;
    free(text);
    if (!newton_xml) {
        fprintf(stderr, "bench_convergence: cannot read %s or it has no self-closing "
                        "<LocalGlobalSolver .../> element\n", a.scene);
        return 2;
    }
    static conv_result res[MAX_STIFF];
    for (int s = 0; s < a.nstiff && rc == PL_OK; ++s) {
        conv_result *r = &res[s];
        memset(r, 0, sizeof *r);
        r->E = a.stiffness[s];
        char set_E[160], state_path[1200];
        snprintf(set_E, sizeof set_E, "%s=%s", a.modulus_field, r->E);
        snprintf(state_path, sizeof state_path, "%s/convergence_E%s.state", a.out_dir, r->E);
        fprintf(stderr, "bench_convergence: E = %s: run-up, local-global step, Newton step\n", r->E);
        rc = run_up(&a, set_E, state_path, r);
        if (rc == PL_OK) rc = local_global_step(&a, set_E, state_path, r);
        if (rc == PL_OK) rc = newton_step(&a, newton_xml, set_E, state_path, r);
        if (rc == PL_OK && r->ek[r->nk - 1] < r->estar)
            fprintf(stderr, "bench_convergence: warning: E = %s: the local-global energy %.10g is "
                            "below Newton's %.10g (relative errors turn negative)\n",
                    r->E, r->ek[r->nk - 1], r->estar);
    }
    free(newton_xml);
    if (rc != PL_OK) return 1;
    printf("Scene %s, state after %d frames, one step of %d local-global iterations vs Newton.\n\n",
           a.scene, a.frames, a.iterations);
    print_tables(&a, res, a.nstiff);
    return a.csv ? (write_csv(&a, res, a.nstiff) == PL_OK ? 0 : 1) : 0;
}
