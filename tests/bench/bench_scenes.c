/* bench_scenes.c - the paper's Table 3 rows for Pliant's scenes (issue 3,
 * deliverable 8; run by `make bench`, not by ctest).
 *
 * For every scene and both global-solver modes (sparse inverse S^T S b, or
 * the Cholesky solve: --set global.mode=sparse|direct) it loads the scene
 * with exporters off, runs --frames frames and prints one row: vertices,
 * elements, material, nnz(A), nnz(L), nnz(S), the memory of S and S^T, the
 * precompute time (factor, inverse) and the median per frame of the Local,
 * Global, Assembly and Frame phases, also divided by the iterations per
 * frame (the paper's Local and Global columns are per iteration: its Frame
 * is about 5 x (Local + Global) plus the rest).
 *
 *   bench_scenes [--frames N] [--modes sparse,direct] [--scenes-dir DIR]
 *                [--out-dir DIR] [--csv FILE] [FILTER|SCENE.xml ...]
 *
 * A FILTER keeps the default scenes whose file name contains it
 * ("twisting_bar", "_20k", "cantilever.xml"); an existing .xml path is
 * benchmarked as given.  The table goes to stdout (Markdown), progress and
 * the solvers' logs to stderr. */
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

/* Table 3's scenes in the paper's order, then the scenes of the material tests. */
static const char *const DEFAULT_SCENES[] = {
    "twisting_bar.xml",
    "twisting_bar_11k.xml",
    "twisting_bar_20k.xml",
    "cloth_extension_arap.xml",
    "cloth_extension_corotational.xml",
    "cloth_extension_neohookean.xml",
    "cloth_extension_arap_20k.xml",
    "cloth_extension_corotational_20k.xml",
    "cloth_extension_neohookean_20k.xml",
    "hanging_bar.xml",
    "cantilever.xml",
};
#define NDEFAULT ((int)(sizeof DEFAULT_SCENES / sizeof DEFAULT_SCENES[0]))
#define MAX_SCENES 64
#define MAX_MODES 4

typedef struct bench_args {
    int frames;
    const char *scenes_dir;
    const char *out_dir;
    const char *csv;
    char *modes[MAX_MODES];
    int nmodes;
    const char *scenes[MAX_SCENES];
    int nscenes;
} bench_args;

static int is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: bench_scenes [--frames N] [--modes sparse,direct] [--scenes-dir DIR]\n"
            "                    [--out-dir DIR] [--csv FILE] [FILTER|SCENE.xml ...]\n"
            "default scenes (in --scenes-dir, default %s/scenes):\n",
            PL_SOURCE_DIR);
    for (int k = 0; k < NDEFAULT; ++k) fprintf(f, "  %s\n", DEFAULT_SCENES[k]);
}

/* Keeps the default scenes matching any filter, plus explicit files. */
static int select_scenes(bench_args *a, char **filters, int nfilters)
{
    static char paths[MAX_SCENES][1024];
    int n = 0;
    for (int k = 0; k < NDEFAULT; ++k) {
        int keep = nfilters == 0;
        for (int f = 0; f < nfilters && !keep; ++f)
            keep = !(ends_with(filters[f], ".xml") && is_file(filters[f])) &&
                   strstr(DEFAULT_SCENES[k], filters[f]) != NULL;
        if (!keep) continue;
        snprintf(paths[n], sizeof paths[n], "%s/%s", a->scenes_dir, DEFAULT_SCENES[k]);
        a->scenes[n] = paths[n];
        n++;
    }
    for (int f = 0; f < nfilters && n < MAX_SCENES; ++f)
        if (ends_with(filters[f], ".xml") && is_file(filters[f])) a->scenes[n++] = filters[f];
    a->nscenes = n;
    return n;
}

static int parse_args(int argc, char **argv, bench_args *a)
{
    static char modes[64] = "sparse,direct";
    static char *filters[MAX_SCENES];
    int nfilters = 0;
    a->frames = 100;
    a->scenes_dir = PL_SOURCE_DIR "/scenes";
    a->out_dir = "bench_out";
    a->csv = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        int has_value = i + 1 < argc;
        if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0) {
            usage(stdout);
            return 1;
        } else if (strcmp(opt, "--frames") == 0 && has_value) {
            a->frames = atoi(argv[++i]);
        } else if (strcmp(opt, "--modes") == 0 && has_value) {
            snprintf(modes, sizeof modes, "%s", argv[++i]);
        } else if (strcmp(opt, "--scenes-dir") == 0 && has_value) {
            a->scenes_dir = argv[++i];
        } else if (strcmp(opt, "--out-dir") == 0 && has_value) {
            a->out_dir = argv[++i];
        } else if (strcmp(opt, "--csv") == 0 && has_value) {
            a->csv = argv[++i];
        } else if (opt[0] == '-') {
            fprintf(stderr, "bench_scenes: unknown option or missing value: %s\n", opt);
            usage(stderr);
            return 2;
        } else if (nfilters < MAX_SCENES) {
            filters[nfilters++] = argv[i];
        }
    }
    if (a->frames < 1) {
        fprintf(stderr, "bench_scenes: --frames must be >= 1\n");
        return 2;
    }
    a->nmodes = bench_split_list(modes, a->modes, MAX_MODES);
    for (int m = 0; m < a->nmodes; ++m)
        if (strcmp(a->modes[m], "sparse") != 0 && strcmp(a->modes[m], "direct") != 0) {
            fprintf(stderr, "bench_scenes: mode '%s' is neither sparse nor direct\n", a->modes[m]);
            return 2;
        }
    if (select_scenes(a, filters, nfilters) == 0 || a->nmodes == 0) {
        fprintf(stderr, "bench_scenes: no scene or mode selected\n");
        usage(stderr);
        return 2;
    }
    return 0;
}

typedef struct bench_row {
    const char *scene;
    const char *mode;
    bench_scene_info info;
    double load_s;
    double nnz_A, nnz_L, nnz_S, s_mb, factor_s, inverse_s;
    double local_ms, global_ms, assembly_ms, frame_ms;
} bench_row;

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* Loads, runs and measures one scene in one mode. */
static int run_one(const bench_args *a, const char *scene, const char *mode, bench_row *row)
{
    char set_mode[64];
    snprintf(set_mode, sizeof set_mode, "global.mode=%s", mode);
    /* no force residual: the paper's Frame has no such evaluation */
    const char *overrides[] = {set_mode, "vtk.every=1000000", "solver.computeResidual=off"};
    memset(row, 0, sizeof *row);
    row->scene = base_name(scene);
    row->mode = mode;
    double t0 = pl_now();
    pl_sim *sim = bench_load(scene, NULL, overrides, 3, a->out_dir);
    if (!sim) return PL_EINPUT;
    row->load_s = pl_now() - t0;
    int rc = bench_describe(sim, &row->info);
    pl_error err;
    if (rc == PL_OK && (rc = pl_sim_step(sim, a->frames, &err)) != PL_OK) {
        char msg[1600];
        fprintf(stderr, "bench_scenes: %s (%s): %s\n", scene, mode,
                pl_error_format(&err, msg, sizeof msg));
    }
    const pl_timers *t = pl_sim_timers(sim);
    row->nnz_A = bench_stat(t, "nnz(A)");
    row->nnz_L = bench_stat(t, "nnz(L)");
    row->nnz_S = bench_stat(t, "nnz(S)");
    row->s_mb = bench_stat(t, "S memory [MB]");
    row->factor_s = bench_stat(t, "factor [s]");
    row->inverse_s = bench_stat(t, "inverse [s]");
    row->local_ms = bench_phase_median_ms(t, "Local");
    row->global_ms = bench_phase_median_ms(t, "Global");
    row->assembly_ms = bench_phase_median_ms(t, "Assembly");
    row->frame_ms = bench_phase_median_ms(t, "Frame");
    pl_sim_free(sim);
    return rc;
}

static void print_header(FILE *f)
{
    fprintf(f, "| scene | mode | vert. | elem. | material | it. | nnz(A) | nnz(L) | nnz(S) | "
               "S+S^T MB | factor s | inverse s | Local ms | Global ms | Assembly ms | Frame ms | "
               "Local/it ms | Global/it ms |\n");
    fprintf(f, "|---|---|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
}

static void print_row(FILE *f, const bench_row *r)
{
    char b[14][32];
    int it = r->info.iterations > 0 ? r->info.iterations : 1;
    /* direct mode keeps no S: its memory is not a cost there */
    double s_mb = strcmp(r->mode, "direct") == 0 ? NAN : r->s_mb;
    fprintf(f, "| %s | %s | %d | %d | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
            r->scene, r->mode, r->info.vertices, r->info.elements, r->info.material,
            r->info.iterations, bench_fmt(b[0], 32, "%.0f", r->nnz_A),
            bench_fmt(b[1], 32, "%.0f", r->nnz_L), bench_fmt(b[2], 32, "%.0f", r->nnz_S),
            bench_fmt(b[3], 32, "%.1f", s_mb), bench_fmt(b[4], 32, "%.3f", r->factor_s),
            bench_fmt(b[5], 32, "%.3f", r->inverse_s), bench_fmt(b[6], 32, "%.2f", r->local_ms),
            bench_fmt(b[7], 32, "%.2f", r->global_ms), bench_fmt(b[8], 32, "%.2f", r->assembly_ms),
            bench_fmt(b[9], 32, "%.2f", r->frame_ms), bench_fmt(b[10], 32, "%.2f", r->local_ms / it),
            bench_fmt(b[11], 32, "%.2f", r->global_ms / it));
    fflush(f);
}

static void print_csv_row(FILE *f, const bench_row *r)
{
    fprintf(f, "%s,%s,%d,%d,%s,%d,%.0f,%.0f,%.0f,%.3f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f\n",
            r->scene, r->mode, r->info.vertices, r->info.elements, r->info.material,
            r->info.iterations, r->nnz_A, r->nnz_L, r->nnz_S, r->s_mb, r->factor_s,
            r->inverse_s, r->local_ms, r->global_ms, r->assembly_ms, r->frame_ms, r->load_s);
    fflush(f);
}

int main(int argc, char **argv)
{
    bench_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc == 1 ? 0 : rc;
    mkdir(a.out_dir, 0777); /* exporters write frame 0 there; an existing folder is fine */
    FILE *csv = NULL;
    if (a.csv && !(csv = fopen(a.csv, "w"))) {
        fprintf(stderr, "bench_scenes: cannot write %s\n", a.csv);
        return 2;
    }
    if (csv)
        fprintf(csv, "scene,mode,vertices,elements,material,iterations,nnz_A,nnz_L,nnz_S,"
                     "S_memory_MB,factor_s,inverse_s,local_ms,global_ms,assembly_ms,frame_ms,"
                     "load_s\n");
    print_header(stdout);
    int failures = 0;
    for (int s = 0; s < a.nscenes; ++s)
        for (int m = 0; m < a.nmodes; ++m) {
            fprintf(stderr, "bench_scenes: %s, mode %s, %d frames\n", a.scenes[s], a.modes[m],
                    a.frames);
            bench_row row;
            if (run_one(&a, a.scenes[s], a.modes[m], &row) != PL_OK) {
                failures++;
                continue;
            }
            print_row(stdout, &row);
            if (csv) print_csv_row(csv, &row);
        }
    if (csv) fclose(csv);
    if (failures) fprintf(stderr, "bench_scenes: %d run(s) failed\n", failures);
    return failures ? 1 : 0;
}
