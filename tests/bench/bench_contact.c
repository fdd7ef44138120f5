/* bench_contact.c - the paper's Table 3 rows for the contact scenes of issue 5
 * (cloth on knives, sharp corner, squeezing ball, pulling through a gap,
 * gingerbread man) on the CPU: per scene the vertices, elements, S memory,
 * the maximum number of contacts, and the median per frame [ms] of the
 * phases Schur, Local, Global, Assembly, Constraint solve, Correction,
 * Constraint global and Frame, with the CollisionPipeline's Detection
 * timer apart.  Prints a Markdown table.
 *
 *   bench_contact [--steps N] [--out DIR] [--set PATH=VALUE ...] [SCENE.xml ...]
 *
 * Without scenes it runs the small and medium variants in scenes/.  --set
 * overrides fields of every scene (e.g. contact.delassus=explicit: W
 * explicit against matrix-free) and is shown beside the scene's name. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "pliant/pliant.h"

static const char *const DEFAULT_SCENES[] = {
    "cloth_on_knives_small.xml", "cloth_on_knives.xml",     "sharp_corner_small.xml",
    "sharp_corner.xml",          "squeezing_ball_small.xml", "squeezing_ball.xml",
    "pulling_through_gap_small.xml", "pulling_through_gap.xml", "gingerbread_small.xml",
    "gingerbread.xml",
};

static const char *const PHASES[] = {"Schur",       "Local",      "Global",
                                     "Assembly",    "Constraint solve", "Correction",
                                     "Constraint global", "Frame", "Detection"};

enum { MAX_SETS = 8 };
static const char *sets[MAX_SETS];
static int nsets;

static int run_scene(const char *path, int steps, const char *out_dir)
{
    /* no force residual (the paper's Frame has no such evaluation), then the user's sets */
    const char *all[MAX_SETS + 1] = {"solver.computeResidual=off"};
    for (int k = 0; k < nsets; ++k) all[k + 1] = sets[k];
    pl_sim *sim = bench_load(path, NULL, all, nsets + 1, out_dir);
    if (!sim) return 1;
    bench_scene_info info;
    if (bench_describe(sim, &info) != PL_OK) {
        pl_sim_free(sim);
        return 1;
    }
    pl_error err;
    int rc = pl_sim_step(sim, steps, &err);
    if (rc != PL_OK) {
        char b[1600];
        fprintf(stderr, "%s: %s\n", path, pl_error_format(&err, b, sizeof b));
        pl_sim_free(sim);
        return 1;
    }
    const pl_timers *t = pl_sim_timers(sim);
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    char buf[64];
    double contacts = bench_stat(t, "contacts max");
    char label[512];
    int at = snprintf(label, sizeof label, "%s", name);
    for (int k = 0; k < nsets && at < (int)sizeof label; ++k)
        at += snprintf(label + at, sizeof label - (size_t)at, "%s%s", k ? ", " : " (", sets[k]);
    if (nsets && at < (int)sizeof label) snprintf(label + at, sizeof label - (size_t)at, ")");
    printf("| %s | %d | %d | %s | %s | %s |", label, info.vertices, info.elements, info.material,
           bench_fmt(buf, sizeof buf, "%.2f", bench_stat(t, "S memory [MB]")),
           bench_fmt(buf + 32, 32, "%.0f", contacts));
    for (size_t k = 0; k < sizeof PHASES / sizeof PHASES[0]; ++k)
        printf(" %s |", bench_fmt(buf, sizeof buf, "%.2f", bench_phase_median_ms(t, PHASES[k])));
    printf("\n");
    fflush(stdout);
    pl_sim_free(sim);
    return 0;
}

int main(int argc, char **argv)
{
    int steps = 100, first = 1;
    const char *out_dir = "bench_contact_out";
    while (first < argc && argv[first][0] == '-') {
        if (!strcmp(argv[first], "--steps") && first + 1 < argc) {
            steps = atoi(argv[first + 1]);
            first += 2;
        } else if (!strcmp(argv[first], "--out") && first + 1 < argc) {
            out_dir = argv[first + 1];
            first += 2;
        } else if (!strcmp(argv[first], "--set") && first + 1 < argc && nsets < MAX_SETS) {
            sets[nsets++] = argv[first + 1];
            first += 2;
        } else {
            fprintf(stderr, "usage: %s [--steps N] [--out DIR] [--set PATH=VALUE ...] [SCENE.xml ...]\n",
                    argv[0]);
            return 2;
        }
    }
    if (steps < 1) {
        fprintf(stderr, "--steps must be >= 1\n");
        return 2;
    }
    printf("Contact scenes, %d steps each (medians per frame [ms]; Detection is the "
           "CollisionPipeline's, apart from the paper's columns)\n\n",
           steps);
    printf("| scene | vertices | elements | material | S [MB] | max contacts | Schur | Local | "
           "Global | Assem. | Cst. Solve | Corr. | Cst. Global | Frame | Detection |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    int failures = 0;
    if (first < argc) {
        for (int k = first; k < argc; ++k) failures += run_scene(argv[k], steps, out_dir);
    } else {
        for (size_t k = 0; k < sizeof DEFAULT_SCENES / sizeof DEFAULT_SCENES[0]; ++k) {
            char path[1024];
            snprintf(path, sizeof path, "%s/scenes/%s", PL_SOURCE_DIR, DEFAULT_SCENES[k]);
            failures += run_scene(path, steps, out_dir);
        }
    }
    return failures ? 1 : 0;
}
