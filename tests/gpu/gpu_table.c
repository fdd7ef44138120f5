/* gpu_table.c - the paper's Table 3 columns for every scene that runs with
 * the whole local-global loop on the GPU (LocalGlobalSolver device="cuda",
 * a CudaDevice added to the scene); needs a GPU: run by
 * tests/bench/run_gpu.sh, not by ctest.
 *
 *   gpu_table TABLE.md PRECISION.md [frames [scene.xml ...]]
 *
 * Per scene (default: the Table 3 scenes and the contact scenes that
 * exist under scenes/): Vert., Elem. and material from the scene; S device
 * memory and contacts max from the solvers' statistics; Frame: median and
 * max of the wall time of one pl_sim_step over `frames` frames after 5
 * warm-up frames (CUDA graphs on, nothing synchronised inside); then the
 * same number of frames with CudaDevice profile="1", where every phase
 * waits for the GPU, for Schur (per frame) and Local, Global, Assem.,
 * Cst. Solve, Corr., Cst. Global (per local-global iteration, as the
 * paper's columns), and the collision detection per frame (CPU; the
 * paper's Frame leaves it out, ours includes it).  Beside each, the
 * paper's RTX 4090 figure and
 * paper / ours, where the scene has the paper's size (vertices within
 * 10%).  PRECISION.md: S in float32 against float64, frame medians and the
 * relative difference of the positions after the same frames.
 * GPU_TABLE_SET="path.field=value;..." adds overrides to every scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gpu_util.h"
#include "test_tmp.h"
#include "pliant/pliant.h"

typedef struct paper_row {
    const char *file;
    double vert;      /* [k] */
    double smb, contacts; /* S MB, contacts max (0: none) */
    double ph[7];     /* Schur, Local*, Global, Assem., Cst. Solve, Corr., Cst. Global (-1: N/A) */
    double frame;     /* Frame max* */
} paper_row;

#define NA -1.0
static const paper_row PAPER[] = {
    {"scenes/twisting_bar.xml", 5.3, 125.02, 0, {NA, 0.87, 0.27, NA, NA, NA, NA}, 6.23},
    {"scenes/twisting_bar_11k.xml", 11.3, 463.03, 0, {NA, 1.67, 0.86, NA, NA, NA, NA}, 13.55},
    {"scenes/twisting_bar_20k.xml", 20.8, 1310.19, 0, {NA, 2.99, 2.41, NA, NA, NA, NA}, 28.55},
    {"scenes/cloth_extension_arap.xml", 10.2, 102.51, 0, {NA, 0.39, 0.33, NA, NA, NA, NA}, 4.44},
    {"scenes/cloth_extension_corotational.xml", 10.2, 102.51, 0, {NA, 0.87, 0.23, NA, NA, NA, NA}, 6.43},
    {"scenes/cloth_extension_neohookean.xml", 10.2, 102.51, 0, {NA, 0.93, 0.23, NA, NA, NA, NA}, 6.65},
    {"scenes/cloth_extension_arap_20k.xml", 20.2, 280.41, 0, {NA, 0.59, 0.58, NA, NA, NA, NA}, 7.53},
    {"scenes/cloth_extension_corotational_20k.xml", 20.2, 280.41, 0, {NA, 1.59, 0.51, NA, NA, NA, NA}, 12.11},
    {"scenes/cloth_extension_neohookean_20k.xml", 20.2, 280.41, 0, {NA, 1.73, 0.52, NA, NA, NA, NA}, 12.88},
    {"scenes/cloth_on_knives.xml", 5.1, 62.37, 760, {3.45, 0.47, 0.13, 0.25, 0.54, 0.18, 0.98}, 14.73},
    {"scenes/sharp_corner.xml", 5.1, 62.37, 4570, {41.45, 0.34, 0.14, 0.87, 2.79, 0.15, 3.82}, 70.77},
    {"scenes/squeezing_ball.xml", 7.1, 266.87, 3180, {11.60, 2.75, 0.50, 0.99, 1.39, 0.51, 2.89}, 46.15},
    {"scenes/pulling_through_gap.xml", 5.3, 67.14, 420, {4.76, 1.25, 0.14, 0.26, 0.54, 0.19, 0.98}, 19.95},
    {"scenes/gingerbread.xml", 11.1, 227.30, 740, {8.37, 2.77, 0.41, 0.59, 0.48, 0.45, 1.52}, 34.75},
};
#define NPAPER ((int)(sizeof PAPER / sizeof PAPER[0]))

/* Scenes without a paper row of their size are run too (no ratio). */
static const char *const EXTRA[] = {
    "scenes/stick_slip.xml",          "scenes/resting_box.xml",
    "scenes/ball_on_plane.xml",       "scenes/cloth_on_knives_small.xml",
    "scenes/sharp_corner_small.xml",  "scenes/squeezing_ball_small.xml",
    "scenes/pulling_through_gap_small.xml", "scenes/gingerbread_small.xml",
};
#define NEXTRA ((int)(sizeof EXTRA / sizeof EXTRA[0]))

static const char *const PHASES[8] = {"Schur", "Local", "Global", "Assembly",
                                      "Constraint solve", "Correction", "Constraint global",
                                      "Detection"};

static pl_sim *load(const char *path, int f32)
{
    char *xml = gpu_scene_with_device(path);
    const char *ov[8] = {"solver.device=cuda", "global.device=cuda",
                         f32 ? "global.precision=float32" : "global.precision=float64"};
    int nov = 3;
    /* the first step from rest (stickStart, stick_slip.xml) is host-only: a
     * device loop refuses it, so the device's row is timed without it */
    if (strstr(path, "stick_slip")) ov[nov++] = "contact.stickStart=0";
    /* GPU_TABLE_SET="a.b=v;c.d=w": more overrides (at most 5), e.g.
     * contact.delassus=explicit to compare the ways of applying W */
    static char set[1024];
    const char *env = getenv("GPU_TABLE_SET");
    snprintf(set, sizeof set, "%s", env ? env : "");
    for (char *save = NULL, *kv = strtok_r(set, ";", &save); kv && nov < 8; kv = strtok_r(NULL, ";", &save))
        ov[nov++] = kv;
    pl_sim *sim = gpu_load_scene(xml, path, ov, nov, test_tmp_dir());
    return sim;
}

typedef struct counts {
    int verts, elems, iterations;
    char material[96];
} counts;

static int add_state(pl_component *c, void *user)
{
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    ((counts *)user)->verts += ops->count(c);
    return 0;
}

/* Elements and material names of the FEM terms (those with a youngModulus). */
static int add_term(pl_component *c, void *user)
{
    counts *n = user;
    if (!pl_component_field(c, "youngModulus")) return 0;
    for (int k = 0; k < c->node->ncomponents; ++k) {
        const pl_topology_ops *t = pl_component_role(c->node->components[k], PL_ROLE_TOPOLOGY);
        if (!t) continue;
        const pl_mesh *m = t->mesh(c->node->components[k]);
        if (m) n->elems += m->ntets > 0 ? m->ntets : m->ntris;
        break;
    }
    if (!strstr(n->material, c->type->name)) {
        size_t len = strlen(n->material);
        snprintf(n->material + len, sizeof n->material - len, "%s%s", len ? ", " : "", c->type->name);
    }
    return 0;
}

static counts scene_counts(pl_sim *sim)
{
    counts n = {0, 0, 5, ""};
    pl_node *root = pl_sim_model(sim)->root;
    pl_node_visit_role(root, PL_ROLE_STATE, add_state, &n);
    pl_node_visit_role(root, PL_ROLE_LOCAL_TERM, add_term, &n);
    char buf[32];
    pl_error err;
    if (pl_sim_get(sim, "solver.iterations", buf, sizeof buf, &err) == PL_OK) n.iterations = atoi(buf);
    return n;
}

/* Positions of every state, concatenated (malloc'ed), count in *m. */
typedef struct collect {
    pl_data *d;
    double *x;
    size_t m;
} collect;

static int add_positions(pl_component *c, void *user)
{
    collect *k = user;
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer b = ops->positions(c, k->d);
    double *x = realloc(k->x, (k->m + 3 * b.rows) * sizeof *x);
    if (!x) return 1;
    memcpy(x + k->m, b.data, 3 * b.rows * sizeof *x);
    k->x = x, k->m += 3 * b.rows;
    return 0;
}

static double *positions(pl_sim *sim, size_t *m)
{
    collect k = {pl_sim_data(sim), NULL, 0};
    pl_node_visit_role(pl_sim_model(sim)->root, PL_ROLE_STATE, add_positions, &k);
    *m = k.m;
    return k.x;
}

/* Frame wall times over `frames` frames after 5 warm-up frames. */
static int time_frames(pl_sim *sim, int frames, double *median, double *max)
{
    pl_error err;
    double *ms = malloc((size_t)(frames > 0 ? frames : 1) * sizeof *ms);
    if (!ms || pl_sim_step(sim, 5, &err) != PL_OK) {
        printf("  step: %s\n", ms ? err.msg : "out of memory");
        free(ms);
        return -1;
    }
    *max = 0.0;
    for (int k = 0; k < frames; ++k) {
        double t0 = pl_now();
        if (pl_sim_step(sim, 1, &err) != PL_OK) {
            printf("  step: %s\n", err.msg);
            free(ms);
            return -1;
        }
        ms[k] = 1e3 * (pl_now() - t0);
        *max = fmax(*max, ms[k]);
    }
    *median = gpu_median(ms, frames);
    free(ms);
    return 0;
}

/* "ours (paper, paper/ours x)", "ours" (no paper figure of this size) or
 * "" (not measured: the phase does not exist in the scene). */
static void cell(char *buf, size_t size, double ours, double paper, int sized)
{
    if (!(ours >= 0.0)) {
        buf[0] = '\0';
        return;
    }
    if (sized && paper > 0.0 && ours > 0.0)
        snprintf(buf, size, "%.3f (%.2f, %.1fx)", ours, paper, paper / ours);
    else
        snprintf(buf, size, "%.3f", ours);
}

static void run_scene(FILE *tab, FILE *prec, const char *path, const paper_row *p, int frames)
{
    struct stat st;
    if (stat(path, &st) != 0) return;
    printf("== %s\n", path);
    fflush(stdout);
    pl_sim *sim = load(path, 0);
    if (!sim) {
        fprintf(tab, "| %s | load failed | | | | | | | | | | | | |\n", path);
        gpu_check_line(NULL, "table scene loads", INFINITY, 0.0);
        return;
    }
    counts n = scene_counts(sim);
    int sized = p && fabs(n.verts / 1000.0 - p->vert) <= 0.1 * p->vert;
    double med = 0, mx = 0, ph[8];
    pl_error err;
    pl_timers *t = pl_sim_timers(sim);
    int ok = time_frames(sim, frames, &med, &mx) == 0;
    size_t m64 = 0;
    double *x64 = ok ? positions(sim, &m64) : NULL;
    /* the phases: profiled frames only */
    if (ok && pl_sim_set(sim, "gpu.profile", "1", &err) != PL_OK) ok = 0;
    if (ok) { /* the device path times its phases only when profiling */
        double dm, dx;
        ok = time_frames(sim, frames, &dm, &dx) == 0;
    }
    for (int k = 0; k < 8; ++k) {
        int id = pl_timer_id(t, PHASES[k]);
        ph[k] = ok && pl_timers_samples(t, id) > 0 ? pl_timers_median_ms(t, id) : -1.0;
        if (k > 0 && k < 7 && ph[k] >= 0.0) ph[k] /= n.iterations; /* per local-global iteration */
    }
    double smb = -1, contacts = 0;
    pl_stat_get(t, "S device memory [MB]", &smb);
    pl_stat_get(t, "contacts max", &contacts);
    pl_sim_free(sim);
    char c[10][64];
    for (int k = 0; k < 7; ++k) cell(c[k], sizeof c[k], ph[k], p ? p->ph[k] : -1.0, sized);
    cell(c[7], sizeof c[7], ok ? mx : -1.0, p ? p->frame : -1.0, sized);
    cell(c[8], sizeof c[8], ok ? med : -1.0, p ? p->frame : -1.0, sized);
    cell(c[9], sizeof c[9], ph[7], -1.0, 0);
    fprintf(tab,
            "| %s | %.1fk | %.1fk | %s | %.1f | %.0f | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
            path + (strncmp(path, "scenes/", 7) ? 0 : 7), n.verts / 1000.0, n.elems / 1000.0,
            n.material, smb, contacts, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9]);
    fflush(tab);
    if (!ok) gpu_check_line(NULL, "table scene runs", INFINITY, 0.0);
    /* float32 S: same frames from the start */
    pl_sim *s32 = ok ? load(path, 1) : NULL;
    double med32 = 0, mx32 = 0;
    if (s32 && time_frames(s32, frames, &med32, &mx32) == 0) {
        size_t m32 = 0;
        double *x32 = positions(s32, &m32), d = 0.0, r = 0.0;
        for (size_t i = 0; i < m32 && m32 == m64; ++i)
            d += (x32[i] - x64[i]) * (x32[i] - x64[i]), r += x64[i] * x64[i];
        fprintf(prec, "| %s | %.3f | %.3f | %.2fx | %.2e |\n",
                path + (strncmp(path, "scenes/", 7) ? 0 : 7), med, med32, med / med32,
                r > 0 ? sqrt(d / r) : sqrt(d));
        fflush(prec);
        free(x32);
    }
    pl_sim_free(s32);
    free(x64);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: gpu_table TABLE.md PRECISION.md [frames [scene.xml ...]]\n");
        return 2;
    }
    FILE *tab = fopen(argv[1], "w"), *prec = fopen(argv[2], "w");
    int frames = argc > 3 ? atoi(argv[3]) : 50;
    if (!tab || !prec) return 1;
    pl_log_set_level(PL_LOG_WARN);
    fprintf(tab, "| scene | Vert. | Elem. | material | S MB (device) | contacts max | Schur | "
                 "Local | Global | Assem. | Cst. Solve | Corr. | Cst. Global | Frame max | "
                 "Frame median | Detection (CPU) |\n"
                 "|---|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    fprintf(prec, "| scene | float64 frame ms | float32 S frame ms | speed-up | positions "
                  "rel. diff. |\n|---|--:|--:|--:|--:|\n");
    if (argc > 4) {
        for (int k = 4; k < argc; ++k) {
            const paper_row *p = NULL;
            for (int r = 0; r < NPAPER; ++r)
                if (!strcmp(PAPER[r].file, argv[k])) p = &PAPER[r];
            run_scene(tab, prec, argv[k], p, frames);
        }
    } else {
        for (int r = 0; r < NPAPER; ++r) run_scene(tab, prec, PAPER[r].file, &PAPER[r], frames);
        for (int k = 0; k < NEXTRA; ++k) run_scene(tab, prec, EXTRA[k], NULL, frames);
    }
    fclose(tab);
    fclose(prec);
    printf("gpu_table: %d failed\n", gpu_failures());
    return gpu_failures() ? 1 : 0;
}
