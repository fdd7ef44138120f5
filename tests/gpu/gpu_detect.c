/* gpu_detect.c - detection's candidates on the GPU (detect_device.cu)
 * against the host:
 *   check: random sheets (look-ahead, margins, self-collision): the device's
 *     lists equal the host replay's (coll_cand_host) item for item, alone and
 *     in batches of pairs sharing meshes (with the box overlaps), and the
 *     contacts made from them equal detect_pair's, bitwise and in order;
 *     then the small contact scenes of scenes/ stepped twice on the CPU
 *     loop, host detection against PLIANT_DETECT=cuda: after every step the
 *     contact sets (the pipeline's contactPoints, contactNormals, in their
 *     canonical order) must be equal.  Any difference fails.
 *   bench: scenes given on the command line, N steps each: medians of the
 *     pipeline's Detection phase and of its pairs' part (the part the device
 *     candidates replace), with PLIANT_DETECT=host, cuda and auto (a
 *     markdown table; auto's steps on the GPU).  The loop runs on the CPU,
 *     or as GPU_DETECT_LOOP says (a --device policy; auto detects on the
 *     GPU only when the loop runs there).
 * Usage: gpu_detect check [steps]   |   gpu_detect bench steps SCENE...
 * Exit 0, 1 on a difference, 77 without a GPU. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "detect.h"
#include "detect_device.h"
#include "collision/sheet_fixture.h"
#include "gpu_util.h"
#include "test_tmp.h"

/* The sheets of the check: bumps of 0.1, noise of 0.02 (sheet_fixture.h). */
static int make_sheet(sheet *s, int n, double z0, double dz, unsigned *seed)
{
    return sheet_make(s, n, z0, 0.1, dz, 0.02, seed);
}

static void mesh_of(const sheet *s, pl_coll_mesh *m, pl_mesh_sides sides, double margin)
{
    pl_error err;
    if (sheet_mesh(s, m, sides, margin, &err)) printf("prepare: %s\n", err.msg);
}

/* Lists and contacts of one pair; returns the differences.  Not const:
 * detect_pair refits the trees it walks (coll_mesh_fit). */
static int compare_pair(coll_dev *dev, pl_coll_mesh *A, pl_coll_mesh *B,
                        const pl_detect_params *prm, long *cands, int *found)
{
    coll_cand_list h[3], g[3];
    memset(h, 0, sizeof h);
    memset(g, 0, sizeof g);
    pl_error err;
    int bad = 0;
    if (coll_cand_host(A, B, prm, h) ||
        coll_dev_candidates(dev, A, B, prm, g, NULL, &err)) {
        printf("candidates failed: %s\n", err.msg);
        return 1;
    }
    for (int l = 0; l < 3; ++l) {
        if (h[l].n != g[l].n ||
            memcmp(h[l].start, g[l].start, (size_t)(h[l].n + 1) * sizeof(int)) != 0 ||
            memcmp(h[l].idx, g[l].idx, (size_t)h[l].start[h[l].n] * sizeof(int)) != 0) {
            printf("list %d differs (host %d items %d candidates, device %d items %d)\n", l,
                   h[l].n, h[l].start[h[l].n], g[l].n, g[l].start[g[l].n]);
            bad++;
        }
        *cands += h[l].start[h[l].n];
    }
    pl_proximities p = {0}, q = {0};
    int ib = A == B ? 0 : 1;
    if (detect_pair(A, 0, B, ib, prm, &p) || detect_pair_given(A, 0, B, ib, prm, g, &q)) bad++;
    if (p.n != q.n) bad++;
    for (int k = 0; k < p.n && k < q.n; ++k)
        if (memcmp(&p.items[k], &q.items[k], sizeof p.items[k]) != 0) bad++;
    *found += p.n;
    proximities_free(&p);
    proximities_free(&q);
    for (int l = 0; l < 3; ++l) coll_cand_list_free(&h[l]), coll_cand_list_free(&g[l]);
    return bad;
}

/* One batch of several pairs sharing meshes (a self pair, both orders):
 * every pair's lists and box overlaps equal the host replay's. */
static int compare_batch(coll_dev *dev, const pl_coll_mesh *a, const pl_coll_mesh *b,
                         const pl_detect_params *prm)
{
    const pl_coll_mesh *A[3] = {a, a, b}, *B[3] = {b, a, a};
    coll_cand_list g[9], h[3];
    long long broad[3], hb;
    memset(g, 0, sizeof g);
    memset(h, 0, sizeof h);
    pl_error err;
    int bad = 0;
    if (coll_dev_batch(dev, 3, A, B, prm, g, broad, NULL, &err)) {
        printf("batch failed: %s\n", err.msg);
        return 1;
    }
    for (int p = 0; p < 3; ++p) {
        if (coll_cand_host_counted(A[p], B[p], prm, h, &hb)) bad++;
        if (hb != broad[p]) {
            printf("batch pair %d: %lld box overlaps, host %lld\n", p, broad[p], hb);
            bad++;
        }
        for (int l = 0; l < 3; ++l) {
            const coll_cand_list *x = &h[l], *y = &g[3 * p + l];
            if (x->n != y->n ||
                memcmp(x->start, y->start, (size_t)(x->n + 1) * sizeof(int)) != 0 ||
                memcmp(x->idx, y->idx, (size_t)x->start[x->n] * sizeof(int)) != 0) {
                printf("batch pair %d list %d differs\n", p, l);
                bad++;
            }
        }
    }
    for (int l = 0; l < 9; ++l) coll_cand_list_free(&g[l]);
    for (int l = 0; l < 3; ++l) coll_cand_list_free(&h[l]);
    return bad;
}

static void check_sheets(coll_dev *dev, FILE *md)
{
    unsigned seed = 99u;
    long cands = 0;
    int found = 0, bad = 0;
    for (int trial = 0; trial < 12; ++trial) {
        double alarm = 0.01 + 0.03 * sheet_urand(&seed);
        sheet a, b;
        if (make_sheet(&a, 30 + 7 * trial, 0.0, 0.0, &seed) ||
            make_sheet(&b, 25 + 9 * trial, 0.06, trial % 2 ? -0.12 : 0.0, &seed)) {
            printf("out of memory\n");
            exit(1);
        }
        double margin = alarm + (trial % 4 == 3 ? 0.04 : 0.0);
        pl_coll_mesh ma, mb;
        mesh_of(&a, &ma, trial % 3 ? PL_SIDES_TWO : PL_SIDES_ONE, margin);
        mesh_of(&b, &mb, PL_SIDES_TWO, margin);
        pl_detect_params prm = detect_defaults(alarm);
        prm.contact = 0.5 * alarm;
        prm.margin = trial % 4 == 3 ? 0.02 : 0.0;
        bad += compare_pair(dev, &ma, &mb, &prm, &cands, &found);
        bad += compare_pair(dev, &ma, &ma, &prm, &cands, &found);
        if (trial % 3 == 0) bad += compare_batch(dev, &ma, &mb, &prm); /* the host replay is slow */
        coll_mesh_free(&ma);
        coll_mesh_free(&mb);
        free(a.x0), free(a.x1), free(a.tris), free(a.edges);
        free(b.x0), free(b.x1), free(b.tris), free(b.edges);
    }
    printf("sheets: %ld candidates, %d contacts\n", cands, found);
    gpu_check_line(md, "sheets: device lists and contacts != host's", bad, 0);
    gpu_check_line(md, "sheets: no contacts found (test broken)", found > 1000 ? 0 : 1, 0);
}

static pl_sim *load(const char *path, const char *detect)
{
    setenv("PLIANT_DETECT", detect, 1);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = test_tmp_dir();
    opt.export_every = 1000000;
    opt.device = getenv("GPU_DETECT_LOOP") ? getenv("GPU_DETECT_LOOP") : "cpu";
    pl_sim *sim = pl_sim_load_file(path, &opt, &diag);
    if (!sim) pl_diag_print(&diag, stdout);
    pl_diag_free(&diag);
    pl_error err;
    /* the choice is made at the first detection, while the variable is set */
    if (sim && pl_sim_step(sim, 1, &err)) {
        printf("%s: %s\n", path, err.msg);
        pl_sim_free(sim);
        sim = NULL;
    }
    unsetenv("PLIANT_DETECT");
    return sim;
}

static char *get(pl_sim *sim, const char *path)
{
    size_t size = 1 << 24;
    char *buf = malloc(size);
    pl_error err;
    if (buf && pl_sim_get(sim, path, buf, size, &err)) buf[0] = 0;
    return buf;
}

/* Steps host and device-candidate runs side by side; differences. */
static int check_scene(const char *path, int steps, FILE *md)
{
    pl_sim *h = load(path, "host"), *g = load(path, "cuda");
    int bad = 0, contacts = 0, with = 0;
    if (!h || !g) bad = 1;
    const char *fields[] = {"pipeline.contactPoints", "pipeline.contactNormals",
                            "pipeline.contactCount"};
    pl_error err;
    for (int s = 1; s <= steps && !bad; ++s) {
        if (s > 1 && (pl_sim_step(h, 1, &err) || pl_sim_step(g, 1, &err))) {
            printf("%s: step %d: %s\n", path, s, err.msg);
            bad = 1;
            break;
        }
        for (int f = 0; f < 3; ++f) {
            char *a = get(h, fields[f]), *b = get(g, fields[f]);
            if (!a || !b || strcmp(a, b) != 0) {
                printf("%s: step %d: %s differs\n", path, s, fields[f]);
                bad++;
            }
            if (f == 2 && a) {
                int n = atoi(a);
                contacts += n;
                with += n > 0;
            }
            free(a);
            free(b);
        }
    }
    char what[256];
    snprintf(what, sizeof what, "%s: %d steps, %d with contacts, %d contacts: differences",
             path, steps, with, contacts);
    gpu_check_line(md, what, bad, 0);
    /* every step's pairs went through the device (no fall back to the host) */
    const double *v;
    int on_device = g ? pl_series_get(pl_sim_timers(g), "detection candidates ms", &v) : 0;
    snprintf(what, sizeof what, "  steps detected on the host instead (of %d)", steps);
    if (!bad) gpu_check_line(md, what, steps - on_device, 0);
    if (!bad && with == 0) gpu_check_line(md, "  no step had contacts (test too short)", 1, 0);
    pl_sim_free(h);
    pl_sim_free(g);
    return bad;
}

/* Medians over the steps: the Detection phase, the pairs' part of it, the
 * device's candidates' part of that (over the steps that used the device)
 * [ms], the box overlaps; *contacts at the last step, steps on the GPU. */
typedef struct det_times {
    double detection, pairs, cand, overlaps;
    int contacts, gpu_steps;
} det_times;

static double series_median(pl_timers *t, const char *name)
{
    const double *v;
    int n = pl_series_get(t, name, &v);
    if (n <= 1) return -1.0;
    double *c = malloc((size_t)n * sizeof *c);
    if (!c) return -1.0;
    memcpy(c, v + 1, (size_t)(n - 1) * sizeof *c); /* the first step: allocations */
    double m = gpu_median(c, n - 1);
    free(c);
    return m;
}

/* GPU_DETECT_CSV=FILE: every step's box overlaps, pairs' and candidates'
 * times appended (scene, mode, step, overlaps, pairs ms, candidates ms;
 * -1: the step's pairs were on the host), to fit auto's rule. */
static void dump_steps(pl_timers *t, const char *path, const char *detect)
{
    const char *file = getenv("GPU_DETECT_CSV");
    FILE *f = file ? fopen(file, "a") : NULL;
    if (!f) return;
    const double *ov, *pm, *cm;
    int n = pl_series_get(t, "detection box overlaps", &ov);
    int np = pl_series_get(t, "detection pairs ms", &pm);
    int nc = pl_series_get(t, "detection candidates ms", &cm);
    for (int k = 0; k < n && k < np; ++k)
        fprintf(f, "%s,%s,%d,%.0f,%.4f,%.4f\n", path, detect, k, ov[k], pm[k],
                nc == n ? cm[k] : -1.0);
    fclose(f);
}

static int detect_times(const char *path, const char *detect, int steps, det_times *dt)
{
    pl_sim *sim = load(path, detect);
    pl_error err;
    if (!sim || pl_sim_step(sim, steps, &err)) {
        pl_sim_free(sim);
        return -1;
    }
    pl_timers *t = pl_sim_timers(sim);
    dump_steps(t, path, detect);
    const double *v;
    dt->detection = pl_timers_median_ms(t, pl_timer_id(t, "Detection"));
    dt->pairs = series_median(t, "detection pairs ms");
    dt->cand = series_median(t, "detection candidates ms");
    dt->overlaps = series_median(t, "detection box overlaps");
    dt->gpu_steps = pl_series_get(t, "detection candidates ms", &v);
    char *c = get(sim, "pipeline.contactCount");
    dt->contacts = c ? atoi(c) : -1;
    free(c);
    pl_sim_free(sim);
    return 0;
}

/* Host, device (PLIANT_DETECT=cuda) and auto, each scene N steps. */
static int bench(int steps, int nscenes, char **scenes)
{
    printf("| scene | contacts | box overlaps | Detection host | cuda | auto | pairs host | "
           "pairs cuda | of which GPU | pairs auto | auto's GPU steps | host/cuda |\n");
    printf("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int k = 0; k < nscenes; ++k) {
        det_times h = {0}, g = {0}, a = {0};
        if (detect_times(scenes[k], "host", steps, &h) ||
            detect_times(scenes[k], "cuda", steps, &g) ||
            detect_times(scenes[k], "auto", steps, &a)) {
            printf("| %s | failed |\n", scenes[k]);
            continue;
        }
        printf("| %s | %d / %d / %d | %.0f | %.2f | %.2f | %.2f | %.3f | %.3f | %.3f | %.3f | "
               "%d of %d | %.2f |\n", scenes[k], h.contacts, g.contacts, a.contacts, h.overlaps,
               h.detection, g.detection, a.detection, h.pairs, g.pairs, g.cand, a.pairs,
               a.gpu_steps, steps, g.pairs > 0.0 ? h.pairs / g.pairs : 0.0);
        fflush(stdout);
    }
    return 0;
}

int main(int argc, char **argv)
{
    gpu_require("gpu_detect");
    setvbuf(stdout, NULL, _IOLBF, 0); /* lines survive a time limit */
    const char *mode = argc > 1 ? argv[1] : "check";
    if (strcmp(mode, "bench") == 0)
        return bench(argc > 2 ? atoi(argv[2]) : 30, argc > 3 ? argc - 3 : 0, argv + 3);
    int steps = argc > 2 ? atoi(argv[2]) : 40;
    coll_dev *dev = NULL;
    pl_error err;
    if (coll_dev_open(&dev, &err)) {
        printf("gpu_detect: %s\n", err.msg);
        return 1;
    }
    check_sheets(dev, NULL);
    coll_dev_close(dev);
    /* the pulled body reaches the gap after about 68 steps */
    const char *scenes[] = {"scenes/cloth_on_knives_small.xml", "scenes/sharp_corner_small.xml",
                            "scenes/gingerbread_small.xml", "scenes/pulling_through_gap_small.xml",
                            "scenes/squeezing_ball_small.xml", "scenes/grabbing_raptor_small.xml"};
    const int more[] = {0, 0, 0, 60, 0, 0};
    for (size_t k = 0; k < sizeof scenes / sizeof *scenes; ++k)
        check_scene(scenes[k], steps + more[k], NULL);
    test_tmp_dir_remove();
    printf("gpu_detect: %d failed\n", gpu_failures());
    return gpu_failures() ? 1 : 0;
}
