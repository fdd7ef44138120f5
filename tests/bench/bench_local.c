/* bench_local.c - the FEM local step per scene (issue 16 item 1; run by hand
 * or by `make bench`, not by ctest).
 *
 * For every scene it runs --frames frames on ONE thread (OpenMP set to 1,
 * PLIANT_DEVICE=cpu), --reps times, and prints from the statistics the FEM
 * terms publish at each end of step (fem_term.c: "<Type>: local solves",
 * "... newton", "... halvings", "... capped", "... its=k", "... seconds"):
 *   - the histogram of Newton iterations per element-call of the prox
 *     (share of the solves with 0, 1, 2, ... iterations; capped ones apart),
 *     and the line-search halvings per solve;
 *   - the cost of the local step per element-call (one element, one
 *     local-global iteration) in microseconds: the terms' own time in
 *     project() (deformation gradient, solve, dual update, scatter and
 *     gather) over their solves, the median over the repetitions, and its
 *     ratio to ARAP's: the ARAP scene of the list (twisting_bar_small), and
 *     the same scene with its Corotational / NeoHookean tags made ARAP
 *     (same mesh, fields and solver; run right after it).  Ratios are only
 *     meaningful within one run on a shared machine.
 *
 *   bench_local [--frames N] [--reps R] [--scenes-dir DIR] [--out-dir DIR]
 *               [FILTER|SCENE.xml ...]
 */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bench_util.h"
#include "pliant/pliant.h"

#ifndef PL_SOURCE_DIR
#define PL_SOURCE_DIR "."
#endif

static const char *const DEFAULT_SCENES[] = {
    "twisting_bar_small.xml", /* ARAP: the reference */
    "pulling_through_gap_small.xml",
    "hanging_bar.xml",
    "cantilever.xml",
    "cloth_extension_neohookean.xml",
    "gingerbread_small.xml",
    "squeezing_ball_small.xml",
    "grabbing_raptor_small.xml",
};
#define NDEFAULT ((int)(sizeof DEFAULT_SCENES / sizeof DEFAULT_SCENES[0]))
#define MAX_SCENES 32
#define MAX_REPS 15
#define NBINS 13 /* the terms' bins: its=0 .. its=11, its>=12 */

static const char *const TYPES[] = {"ARAP", "Corotational", "NeoHookean"};
#define NTYPES 3

typedef struct row {
    const char *scene;
    const char *type;
    int elements;
    double solves, newton, halvings, capped, max_it, hist[NBINS];
    double us[MAX_REPS]; /* per element-call, one per repetition */
    double arap_us[MAX_REPS]; /* the same scene with its terms made ARAP */
    int nreps, narap;
} row;

static int is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static double stat_of(const pl_timers *t, const char *type, const char *what)
{
    char name[96];
    snprintf(name, sizeof name, "%s: local %s", type, what);
    double v = bench_stat(t, name);
    return isnan(v) ? 0.0 : v;
}

/* The median of v, left as it is. */
static double median(const double *v, int n)
{
    double s[MAX_REPS];
    memcpy(s, v, (size_t)n * sizeof *s);
    return bench_median(s, n);
}

/* xml with every "<from " made "<to " (malloc'd). */
static char *replace_tag(const char *xml, const char *from, const char *to)
{
    size_t nf = strlen(from), nt = strlen(to), n = 0;
    for (const char *p = strstr(xml, from); p; p = strstr(p + nf, from)) ++n;
    char *out = malloc(strlen(xml) + n * (nt > nf ? nt - nf : 0) + 1), *o = out;
    if (!out) return NULL;
    for (const char *p = xml;;) {
        const char *hit = strstr(p, from);
        size_t len = hit ? (size_t)(hit - p) : strlen(p);
        memcpy(o, p, len);
        o += len;
        if (!hit) break;
        memcpy(o, to, nt);
        o += nt;
        p = hit + nf;
    }
    *o = '\0';
    return out;
}

/* The ARAP cost per element-call of the scene at `path` with its
 * Corotational and NeoHookean terms made ARAP (same mesh, same fields). */
static double arap_same_mesh(const char *path, int frames, const char *out_dir)
{
    char *xml = bench_read_file(path), *a = xml ? replace_tag(xml, "<NeoHookean ", "<ARAP ") : NULL;
    char *b = a ? replace_tag(a, "<Corotational ", "<ARAP ") : NULL;
    free(xml);
    free(a);
    if (!b) return NAN;
    pl_sim *sim = bench_load(path, b, NULL, 0, out_dir);
    free(b);
    pl_error err;
    double us = NAN;
    if (sim && pl_sim_step(sim, frames, &err) == PL_OK) {
        const pl_timers *t = pl_sim_timers(sim);
        us = 1e6 * stat_of(t, "ARAP", "seconds") / stat_of(t, "ARAP", "solves");
    }
    pl_sim_free(sim);
    return us;
}

/* One run of a scene: adds its counts (first repetition) and its cost per
 * element-call to the rows of the types it has; returns the rows used. */
static int run_scene(const char *path, int frames, int rep, const char *out_dir, row *rows,
                     int nrows)
{
    pl_sim *sim = bench_load(path, NULL, NULL, 0, out_dir);
    if (!sim) return -1;
    bench_scene_info info;
    bench_describe(sim, &info);
    pl_error err;
    if (pl_sim_step(sim, frames, &err) != PL_OK) {
        char msg[1600];
        fprintf(stderr, "bench_local: %s: %s\n", path, pl_error_format(&err, msg, sizeof msg));
        pl_sim_free(sim);
        return -1;
    }
    const pl_timers *t = pl_sim_timers(sim);
    int used = 0;
    for (int k = 0; k < NTYPES; ++k) {
        double solves = stat_of(t, TYPES[k], "solves");
        if (!(solves > 0.0)) continue;
        row *r = &rows[nrows + used++];
        if (rep == 0) {
            memset(r, 0, sizeof *r);
            r->scene = base_name(path);
            r->type = TYPES[k];
            r->elements = info.elements;
            r->solves = solves;
            r->newton = stat_of(t, TYPES[k], "newton");
            r->halvings = stat_of(t, TYPES[k], "halvings");
            r->capped = stat_of(t, TYPES[k], "capped");
            char name[96];
            snprintf(name, sizeof name, "%s: local max iterations", TYPES[k]);
            r->max_it = bench_stat(t, name);
            for (int b = 0; b < NBINS; ++b) {
                char bin[16];
                snprintf(bin, sizeof bin, b < NBINS - 1 ? "its=%d" : "its>=%d", b);
                r->hist[b] = stat_of(t, TYPES[k], bin);
            }
        }
        r->us[r->nreps++] = 1e6 * stat_of(t, TYPES[k], "seconds") / solves;
    }
    pl_sim_free(sim);
    for (int u = 0; u < used; ++u) {
        row *r = &rows[nrows + u];
        r->arap_us[r->narap++] = strcmp(r->type, "ARAP") ? arap_same_mesh(path, frames, out_dir)
                                                         : r->us[r->nreps - 1];
    }
    return used;
}

static void print_tables(const row *rows, int n)
{
    double arap = NAN; /* the first ARAP scene of the list */
    for (int i = n - 1; i >= 0; --i)
        if (!strcmp(rows[i].type, "ARAP")) arap = median(rows[i].us, rows[i].nreps);
    printf("| scene | term | elements | solves | Newton/solve | halvings/solve | capped | max its "
           "| us per element-iteration (median) | x ARAP (reference scene) | ARAP same mesh us | x ARAP "
           "(same mesh) |\n");
    printf("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int i = 0; i < n; ++i) {
        const row *r = &rows[i];
        double us = median(r->us, r->nreps);
        double au = median(r->arap_us, r->narap);
        printf("| %s | %s | %d | %.0f | %.2f | %.2f | %.0f | %.0f | %.3f | %.2f | %.3f | %.2f |\n",
               r->scene, r->type, r->elements, r->solves, r->newton / r->solves,
               r->halvings / r->solves, r->capped, r->max_it, us, us / arap, au, us / au);
    }
    printf("\nNewton iterations per element-call, %% of the solves:\n\n| scene | term |");
    for (int b = 0; b < NBINS; ++b) printf(b < NBINS - 1 ? " %d |" : " >=%d |", b);
    printf(" capped |\n|---|---|");
    for (int b = 0; b <= NBINS; ++b) printf("--:|");
    printf("\n");
    for (int i = 0; i < n; ++i) {
        const row *r = &rows[i];
        printf("| %s | %s |", r->scene, r->type);
        for (int b = 0; b < NBINS; ++b) {
            double pc = 100.0 * r->hist[b] / r->solves;
            if (r->hist[b] == 0.0)
                printf(" |");
            else
                printf(pc >= 0.1 ? " %.1f |" : " %.1e |", pc);
        }
        printf(" %s |\n", r->capped > 0 ? "yes" : "");
    }
}

int main(int argc, char **argv)
{
    int frames = 10, reps = 3;
    const char *dir = PL_SOURCE_DIR "/scenes", *out_dir = "out/bench_local";
    const char *filters[MAX_SCENES];
    int nfilters = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc)
            frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc)
            reps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--scenes-dir") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--out-dir") && i + 1 < argc)
            out_dir = argv[++i];
        else if (argv[i][0] == '-') {
            fprintf(stderr, "usage: bench_local [--frames N] [--reps R] [--scenes-dir DIR] "
                            "[--out-dir DIR] [FILTER|SCENE.xml ...]\n");
            return argv[i][1] == 'h' ? 0 : 2;
        } else if (nfilters < MAX_SCENES)
            filters[nfilters++] = argv[i];
    }
    if (frames < 1 || reps < 1 || reps > MAX_REPS) {
        fprintf(stderr, "bench_local: --frames >= 1 and 1 <= --reps <= %d\n", MAX_REPS);
        return 2;
    }
    setenv("PLIANT_DEVICE", "cpu", 1);
    omp_set_num_threads(1);
    char paths[MAX_SCENES][512];
    int nscenes = 0;
    for (int k = 0; k < NDEFAULT; ++k) {
        int keep = nfilters == 0;
        for (int f = 0; f < nfilters; ++f) keep |= strstr(DEFAULT_SCENES[k], filters[f]) != NULL;
        if (keep) snprintf(paths[nscenes++], sizeof paths[0], "%s/%s", dir, DEFAULT_SCENES[k]);
    }
    for (int f = 0; f < nfilters && nscenes < MAX_SCENES; ++f)
        if (is_file(filters[f])) snprintf(paths[nscenes++], sizeof paths[0], "%s", filters[f]);
    mkdir("out", 0777);
    mkdir(out_dir, 0777);
    printf("bench_local: %d frames, %d repetitions, %d thread(s)\n\n", frames, reps,
           omp_get_max_threads());
    row rows[MAX_SCENES * NTYPES];
    int first[MAX_SCENES], nrows = 0, status = 0;
    for (int s = 0; s < nscenes; ++s) {
        first[s] = nrows;
        fprintf(stderr, "bench_local: %s\n", paths[s]);
    }
    /* repetitions outermost: each pass sees the machine's load of its moment */
    for (int rep = 0; rep < reps; ++rep)
        for (int s = 0; s < nscenes; ++s) {
            if (rep == 0) first[s] = nrows;
            int used = run_scene(paths[s], frames, rep, out_dir, rows, first[s]);
            if (used < 0) {
                status = 1;
                continue;
            }
            if (rep == 0) nrows += used;
        }
    print_tables(rows, nrows);
    return status;
}
