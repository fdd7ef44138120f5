/* gpu_check.c - CPU vs GPU from identical inputs (needs a GPU: without one
 * it prints "skipped: no GPU" and exits 77).  `ctest -L gpu` runs the small
 * bar; tests/gpu/run.sh both.
 *
 *   gpu_check [report.md] [scene.xml] [small]     (small: the 44x11x11 bar only)
 *
 * For the twisting bars 44x11x11 and 72x17x17 (gpu_bar.h):
 *  - local step, ARAP / corotational / Neo-Hookean: right-hand-side
 *    contributions and updated duals, GPU (gather and atomic assembly) vs
 *    hyper_elements_project: <= 1e-9 relative;
 *  - global step x = A^-1 b, b the ARAP right-hand side of a twisted state:
 *    float64 <= 1e-9 and float32 <= 1e-4 relative
 *    to the CPU sparse inverse; also a random b (float64 checked, float32
 *    reported), S x and S^T x alone, x = b in place, host copies, float32
 *    S with float64 blocks, and bitwise repeatability of the own kernels;
 *  - small bars (10x3x3, 12x4x3; 12x4x3 in float32 has split tiles): the
 *    single-block solve against the three-launch one (PLIANT_SPINV_SMALL=0),
 *    float64 and float32: bitwise equal, also x = b in place, and float64
 *    <= 1e-9 from the CPU;
 *  - W's diagonal on the device (etree walk and explicit W) vs the host's Y;
 *  - the scene (SparseInverseSolver device=cuda, precision float64 and
 *    float32) against device=cpu after 10 steps.
 * Exit status: the number of failed checks (0: all passed). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_bar.h"
#include "gpu_util.h"
#include "test_tmp.h"
#include "hyper_cuda.h"
#include "pliant/pliant.h"
#include "spinv_cuda.h"

#define PROG "gpu_check"

static FILE *md;

static const char *const mat_name[3] = {"ARAP", "corotational", "Neo-Hookean"};

/* One material's local step on CPU and GPU from the same q and duals. */
static void check_local(gpu_bar *bar, int m)
{
    pl_hyper_elements *e = &bar->el[m];
    size_t n3 = (size_t)bar->n * 3, nd = (size_t)e->n * 9;
    double h2 = bar->h * bar->h;
    double *q = malloc(n3 * sizeof *q), *rc = calloc(n3, sizeof *rc), *rg = malloc(n3 * sizeof *rg);
    double *u0 = malloc(nd * sizeof *u0), *uc = malloc(nd * sizeof *uc), *ug = malloc(nd * sizeof *ug);
    char what[160];
    pl_error err;
    if (!q || !rc || !rg || !u0 || !uc || !ug) goto done;
    gpu_bar_twist(bar, 0.25, 2e-3, 11, q);
    unsigned st = 5;
    for (size_t i = 0; i < nd; ++i) u0[i] = 0.02 * gpu_rand(&st);
    memcpy(uc, u0, nd * sizeof *uc);
    hyper_prox_stats sc = {0};
    int sg[2];
    int admm = e->material != PL_HYPER_ARAP;
    double *work = malloc(hyper_elements_work_size(e) * sizeof *work);
    int cpu_rc = work ? hyper_elements_project(e, 0, h2, q, admm ? uc : NULL, NULL, work, rc, &sc, &err)
                      : pl_error_set(&err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    free(work);
    if (cpu_rc != PL_OK) {
        printf("CPU local step failed: %s\n", err.msg);
        gpu_check_line(md, "local step on the CPU", 1.0, 0.0);
        goto done;
    }
    pl_hyper_cuda *g = hyper_cuda_create(e, &err);
    if (!g) {
        printf("hyper_cuda_create: %s\n", err.msg);
        gpu_check_line(md, "local step device copy", 1.0, 0.0);
        goto done;
    }
    for (int mode = 0; mode < 2; ++mode) {
        double *dq = gpu_put(q, n3, PL_F64), *dr = gpu_put(NULL, n3, PL_F64);
        double *du = admm ? gpu_put(u0, nd, PL_F64) : NULL;
        int rc_ = hyper_cuda_project(g, 0, h2, dq, du, dr, (pl_hyper_cuda_assembly)mode, NULL, &err);
        if (rc_ == PL_OK) rc_ = hyper_cuda_step_stats(g, NULL, sg, NULL, &err);
        if (rc_ != PL_OK) printf("GPU local step: %s\n", err.msg);
        if (rc_ == PL_OK && gpu_get(rg, dr, n3, PL_F64) == 0 &&
            (!admm || gpu_get(ug, du, nd, PL_F64) == 0)) {
            snprintf(what, sizeof what, "%dx%dx%d local %s rhs, %s, float64", bar->nx, bar->ny,
                     bar->nz, mat_name[m], mode ? "atomic" : "gather");
            gpu_check_line(md, what, gpu_rel_diff(rg, rc, n3), 1e-9);
            if (admm && mode == 0) {
                snprintf(what, sizeof what, "%dx%dx%d local %s duals", bar->nx, bar->ny, bar->nz,
                         mat_name[m]);
                gpu_check_line(md, what, gpu_rel_diff(ug, uc, nd), 1e-9);
            }
            if (mode == 0) {
                snprintf(what, sizeof what, "%dx%dx%d local %s Newton its CPU %d GPU %d, missed",
                         bar->nx, bar->ny, bar->nz, mat_name[m], sc.max_iterations, sg[0]);
                gpu_check_line(md, what, (double)(sg[1] + (int)sc.capped), 0.0);
            }
        } else {
            gpu_check_line(md, "GPU local step ran", 1.0, 0.0);
        }
        gpu_free(dq), gpu_free(dr), gpu_free(du);
    }
    hyper_cuda_destroy(g);
done:
    free(q), free(rc), free(rg), free(u0), free(uc), free(ug);
}

/* x = solve(b) on the device in precision io; -1 on failure. */
static int device_solve(pl_spinv_cuda *g, const double *b, double *x, size_t n3, pl_precision io)
{
    void *db = gpu_put(b, n3, io), *dx = gpu_put(NULL, n3, io);
    pl_error err;
    int rc = db && dx ? spinv_cuda_solve(g, db, dx, io, NULL, &err) : PL_EINTERNAL;
    if (rc != PL_OK && db && dx) printf("solve: %s\n", err.msg);
    if (rc == PL_OK) rc = gpu_sync("solve") || gpu_get(x, dx, n3, io) ? -1 : PL_OK;
    gpu_free(db), gpu_free(dx);
    return rc == PL_OK ? 0 : -1;
}

/* S x and S^T x alone, in the permuted numbering, vs the CPU products. */
static void check_products(gpu_bar *bar, pl_spinv_cuda *g, const char *tag, double tol)
{
    const pl_spinv_profile *S = pl_sparse_inverse_S(bar->spinv);
    const pl_spinv_runs *ST = pl_sparse_inverse_ST(bar->spinv);
    size_t n3 = (size_t)bar->n * 3;
    pl_precision p = spinv_cuda_precision(g);
    double *x = malloc(n3 * sizeof *x), *yc = malloc(n3 * sizeof *yc), *yg = malloc(n3 * sizeof *yg);
    int bounds[2] = {0, bar->n};
    char what[160];
    pl_error err;
    unsigned st = 9;
    if (!x || !yc || !yg) goto done;
    for (size_t i = 0; i < n3; ++i) x[i] = gpu_rand(&st);
    for (int op = 0; op < 2; ++op) {
        void *dx = gpu_put(x, n3, p), *dy = gpu_put(NULL, n3, p);
        int rc = op == 0 ? pl_spinv_cuda_apply_S(g, dx, dy, NULL, &err)
                         : pl_spinv_cuda_apply_ST(g, dx, dy, NULL, &err);
        if (rc == PL_OK) rc = gpu_sync("product") || gpu_get(yg, dy, n3, p) ? -1 : PL_OK;
        if (op == 0)
            spinv_profile_mult(S, x, yc, 3, bounds, 1, 1);
        else
            spinv_runs_mult(ST, x, yc, 3, bounds, 1, 1);
        snprintf(what, sizeof what, "%dx%dx%d %s %s, random x", bar->nx, bar->ny, bar->nz,
                 op ? "S^T x" : "S x", tag);
        gpu_check_line(md, what, rc == PL_OK ? gpu_rel_diff(yg, yc, n3) : INFINITY, tol);
        gpu_free(dx), gpu_free(dy);
    }
done:
    free(x), free(yc), free(yg);
}

/* H (3m x n, coordinate-major: row k m + j) filled with random rows of
 * cnt_all distinct ascending unknowns a component, but big for the rows j
 * with j % every == first; H's arrays hold 3 m big entries. */
static void random_rows(pl_csr *H, int m, int n, int cnt_all, int big, int first, int every,
                        unsigned *st)
{
    H->p[0] = 0;
    for (int r = 0; r < 3 * m; ++r) {
        int j = r % m, cnt = j % every == first ? big : cnt_all, base = H->p[r];
        int step = 1 + j % 3, span = n - 1 - (cnt - 1) * step; /* distinct, ascending */
        int v0 = (int)(fabs(gpu_rand(st)) * span) % (span > 0 ? span : 1);
        for (int t = 0; t < cnt; ++t) {
            H->j[base + t] = v0 + t * step;
            H->x[base + t] = gpu_rand(st);
        }
        H->p[r + 1] = base + cnt;
    }
}

/* W's diagonal on the device, alone (W NULL: the etree walk) and from the
 * explicit W (cuBLAS), against the host's |S P h^T|^2 (apply_inverse_to_rows)
 * for 300 random rows of 4 unknowns; a row of 20 unknowns must come back NaN
 * from the walk (the caller then makes it on the host). */
static void check_wdiag(gpu_bar *bar, pl_spinv_cuda *g, const char *tag, double tol)
{
    enum { M = 300, K = 4, BIG = 20 };
    int n = sparse_inverse_size(bar->spinv), m = M;
    pl_csr H = {3 * m, n, malloc((3 * (size_t)m + 1) * sizeof(int)), malloc(3 * (size_t)m * BIG * sizeof(int)),
                malloc(3 * (size_t)m * BIG * sizeof(double))};
    double *ref = calloc(m, sizeof *ref), *dw = malloc(m * sizeof *dw), *dd = malloc(m * sizeof *dd);
    void *W = gpu_put(NULL, (size_t)m * m, PL_F64);
    pl_spinv_cuda_rows R = {0};
    pl_csc Y = {0};
    pl_error err;
    char what[200];
    unsigned st = 23;
    int rc = H.p && H.j && H.x && ref && dw && dd && W ? PL_OK : PL_EINTERNAL;
    if (rc == PL_OK) random_rows(&H, m, n, K, BIG, m - 1, m, &st);
    if (rc == PL_OK) rc = sparse_inverse_apply_inverse_to_rows(bar->spinv, &H, &Y, &err);
    for (int c = 0; rc == PL_OK && c < 3 * m; ++c)
        for (int p = Y.p[c]; p < Y.p[c + 1]; ++p) ref[c % m] += Y.x[p] * Y.x[p];
    if (rc == PL_OK)
        rc = spinv_cuda_rows_build(&H, m, sparse_inverse_perm(bar->spinv), n, &R, &err);
    if (rc == PL_OK) rc = spinv_cuda_delassus(g, &R, W, dw, NULL, &err);
    if (rc == PL_OK) rc = spinv_cuda_delassus(g, &R, NULL, dd, NULL, &err);
    if (rc != PL_OK) printf("W diagonal: %s\n", err.msg);
    snprintf(what, sizeof what, "%dx%dx%d W diagonal %s, explicit W (cuBLAS) vs host Y", bar->nx, bar->ny,
             bar->nz, tag);
    gpu_check_line(md, what, rc == PL_OK ? gpu_rel_diff(dw, ref, (size_t)m) : INFINITY, tol);
    snprintf(what, sizeof what, "%dx%dx%d W diagonal %s, etree walk vs host Y (rows of %d unknowns)",
             bar->nx, bar->ny, bar->nz, tag, K);
    gpu_check_line(md, what, rc == PL_OK ? gpu_rel_diff(dd, ref, (size_t)m - 1) : INFINITY, tol);
    snprintf(what, sizeof what, "%dx%dx%d W diagonal %s, etree walk: a row of %d unknowns is NaN",
             bar->nx, bar->ny, bar->nz, tag, BIG);
    gpu_check_line(md, what, rc == PL_OK && isnan(dd[m - 1]) ? 0.0 : 1.0, 0.0);
    spinv_cuda_rows_free(&R);
    pl_csc_free(&Y);
    gpu_free(W);
    free(H.p), free(H.j), free(H.x), free(ref), free(dw), free(dd);
}

/* The explicit W, every entry, against the host's W = Y^T Y (Y = S P H^T,
 * apply_inverse_to_rows), for 60 random rows of 4 unknowns a component but
 * rows 19, 39 and 59 of 30 (a cable's: more than 64 entries, whose entries
 * a block each sums, spinv_cuda_delassus.cu); and W bitwise symmetric. */
static void check_w_long(gpu_bar *bar, pl_spinv_cuda *g, const char *tag, double tol)
{
    enum { M = 60, K = 4, LONG = 30 };
    int n = sparse_inverse_size(bar->spinv), m = M;
    pl_csr H = {3 * m, n, malloc((3 * (size_t)m + 1) * sizeof(int)),
                malloc(3 * (size_t)m * LONG * sizeof(int)), malloc(3 * (size_t)m * LONG * sizeof(double))};
    double *dense = calloc((size_t)n * 3 * m, sizeof *dense), *ref = calloc((size_t)m * m, sizeof *ref);
    double *w = malloc((size_t)m * m * sizeof *w), *dw = malloc(m * sizeof *dw);
    void *W = gpu_put(NULL, (size_t)m * m, PL_F64);
    pl_spinv_cuda_rows R = {0};
    pl_csc Y = {0};
    pl_error err;
    char what[200];
    unsigned st = 41;
    int rc = H.p && H.j && H.x && dense && ref && w && dw && W ? PL_OK : PL_EINTERNAL;
    if (rc == PL_OK) random_rows(&H, m, n, K, LONG, 19, 20, &st);
    if (rc == PL_OK) rc = sparse_inverse_apply_inverse_to_rows(bar->spinv, &H, &Y, &err);
    for (int c = 0; rc == PL_OK && c < 3 * m; ++c) /* W_ij = sum_k Y_(k m + i) . Y_(k m + j) */
        for (int p = Y.p[c]; p < Y.p[c + 1]; ++p) dense[(size_t)c * n + Y.i[p]] = Y.x[p];
    for (int i = 0; rc == PL_OK && i < m; ++i)
        for (int j = 0; j < m; ++j)
            for (int k = 0; k < 3; ++k)
                for (int t = 0; t < n; ++t)
                    ref[(size_t)i * m + j] +=
                        dense[((size_t)k * m + i) * n + t] * dense[((size_t)k * m + j) * n + t];
    if (rc == PL_OK)
        rc = spinv_cuda_rows_build(&H, m, sparse_inverse_perm(bar->spinv), n, &R, &err);
    if (rc == PL_OK) rc = spinv_cuda_delassus(g, &R, W, dw, NULL, &err);
    if (rc == PL_OK) rc = gpu_get(w, W, (size_t)m * m, PL_F64) ? PL_EINTERNAL : PL_OK;
    if (rc != PL_OK) printf("W with long rows: %s\n", err.msg);
    snprintf(what, sizeof what, "%dx%dx%d W %s with rows of %d entries, every entry vs host Y^T Y",
             bar->nx, bar->ny, bar->nz, tag, 3 * LONG);
    gpu_check_line(md, what, rc == PL_OK ? gpu_rel_diff(w, ref, (size_t)m * m) : INFINITY, tol);
    size_t asym = 0;
    for (int i = 0; rc == PL_OK && i < m; ++i)
        for (int j = 0; j < i; ++j) asym += memcmp(&w[i * m + j], &w[j * m + i], sizeof *w) != 0;
    snprintf(what, sizeof what, "%dx%dx%d W %s with long rows: entries W_ij != W_ji (bitwise)",
             bar->nx, bar->ny, bar->nz, tag);
    gpu_check_line(md, what, rc == PL_OK ? (double)asym : INFINITY, 0.0);
    spinv_cuda_rows_free(&R);
    pl_csc_free(&Y);
    gpu_free(W);
    free(H.p), free(H.j), free(H.x), free(dense), free(ref), free(w), free(dw);
}

/* Extra checks: in place, host copies, repeatability. */
static void check_own_extras(gpu_bar *bar, pl_spinv_cuda *g, const double *b, const double *xc)
{
    size_t n3 = (size_t)bar->n * 3;
    pl_precision p = spinv_cuda_precision(g);
    double *x = malloc(n3 * sizeof *x), *x2 = malloc(n3 * sizeof *x2);
    char what[160];
    pl_error err;
    if (!x || !x2) goto done;
    const char *tag = p == PL_F32 ? "float32" : "float64";
    double tol = p == PL_F32 ? 1e-4 : 1e-9;
    void *d = gpu_put(b, n3, PL_F64);
    int rc = d ? spinv_cuda_solve(g, d, d, PL_F64, NULL, &err) : -1;
    if (rc == PL_OK) rc = gpu_sync("in place") || gpu_get(x, d, n3, PL_F64);
    gpu_free(d);
    snprintf(what, sizeof what, "%dx%dx%d global own %s S, float64 blocks, x = b in place",
             bar->nx, bar->ny, bar->nz, tag);
    gpu_check_line(md, what, rc == PL_OK ? gpu_rel_diff(x, xc, n3) : INFINITY, tol);
    rc = spinv_cuda_solve_host(g, b, x, NULL, &err);
    snprintf(what, sizeof what, "%dx%dx%d global own %s S, host blocks", bar->nx, bar->ny, bar->nz,
             tag);
    gpu_check_line(md, what, rc == PL_OK ? gpu_rel_diff(x, xc, n3) : INFINITY, tol);
    /* two solves of one b: bitwise equal (fixed summation order) */
    if (device_solve(g, b, x, n3, p) == 0 && device_solve(g, b, x2, n3, p) == 0) {
        size_t diff = 0;
        for (size_t i = 0; i < n3; ++i) diff += memcmp(&x[i], &x2[i], sizeof *x) != 0;
        snprintf(what, sizeof what, "%dx%dx%d global own %s: values differing between two runs",
                 bar->nx, bar->ny, bar->nz, tag);
        gpu_check_line(md, what, (double)diff, 0.0);
    }
done:
    free(x), free(x2);
}

static void check_global(gpu_bar *bar)
{
    size_t n3 = (size_t)bar->n * 3;
    double *q = malloc(n3 * sizeof *q), *b = malloc(n3 * sizeof *b), *br = malloc(n3 * sizeof *br);
    double *xc = malloc(n3 * sizeof *xc), *xrc = malloc(n3 * sizeof *xrc), *x = malloc(n3 * sizeof *x);
    char what[200];
    pl_error err;
    if (!q || !b || !br || !xc || !xrc || !x) goto done;
    gpu_bar_twist(bar, 0.25, 1e-3, 3, q);
    unsigned st = 17;
    for (size_t i = 0; i < n3; ++i) br[i] = gpu_rand(&st);
    if (gpu_bar_rhs(bar, q, b, &err) != PL_OK ||
        sparse_inverse_solve(bar->spinv, b, xc, 3, &err) != PL_OK ||
        sparse_inverse_solve(bar->spinv, br, xrc, 3, &err) != PL_OK) {
        printf("CPU global step failed: %s\n", err.msg);
        gpu_check_line(md, "CPU global step", 1.0, 0.0);
        goto done;
    }
    for (int pi = 0; pi < 2; ++pi) {
        pl_precision p = pi ? PL_F32 : PL_F64;
        const char *tag = pi ? "float32" : "float64";
        double tol = pi ? 1e-4 : 1e-9;
        pl_spinv_cuda *g = spinv_cuda_create(bar->spinv, p, &err);
        if (!g) {
            printf("spinv_cuda_create: %s\n", err.msg);
            gpu_check_line(md, "device copy of S", 1.0, 0.0);
            continue;
        }
        snprintf(what, sizeof what, "%dx%dx%d global own %s, twisted-state b", bar->nx, bar->ny,
                 bar->nz, tag);
        gpu_check_line(md, what, device_solve(g, b, x, n3, p) ? INFINITY : gpu_rel_diff(x, xc, n3),
                       tol);
        snprintf(what, sizeof what, "%dx%dx%d global own %s, random b", bar->nx, bar->ny, bar->nz,
                 tag);
        double r = device_solve(g, br, x, n3, p) ? INFINITY : gpu_rel_diff(x, xrc, n3);
        if (pi)
            gpu_note_line(md, what, r);
        else
            gpu_check_line(md, what, r, tol);
        check_products(bar, g, pi ? "float32" : "float64", pi ? 1e-5 : 1e-12);
        check_own_extras(bar, g, b, xc);
        check_wdiag(bar, g, tag, pi ? 1e-5 : 1e-12);
        check_w_long(bar, g, tag, pi ? 1e-5 : 1e-12);
        spinv_cuda_destroy(g);
    }
done:
    free(q), free(b), free(br), free(xc), free(xrc), free(x);
}

/* x = A^-1 b on the device in place (x = b). */
static int device_solve_inplace(pl_spinv_cuda *g, const double *b, double *x, size_t n3,
                                pl_precision io)
{
    void *d = gpu_put(b, n3, io);
    pl_error err;
    int rc = d ? spinv_cuda_solve(g, d, d, io, NULL, &err) : PL_EINTERNAL;
    if (rc == PL_OK) rc = gpu_sync("in place") || gpu_get(x, d, n3, io) ? -1 : PL_OK;
    gpu_free(d);
    return rc == PL_OK ? 0 : -1;
}

/* Values of a and b whose bits differ. */
static double bits_differing(const double *a, const double *b, size_t m)
{
    size_t diff = 0;
    for (size_t i = 0; i < m; ++i) diff += memcmp(&a[i], &b[i], sizeof *a) != 0;
    return (double)diff;
}

/* The single-block solve of a small system against the three launches. */
static void check_small_solve(int nx, int ny, int nz)
{
    gpu_bar bar;
    pl_error err;
    char what[200];
    if (gpu_bar_build(&bar, nx, ny, nz, &err) != PL_OK) {
        gpu_check_line(md, "building the small bar", 1.0, 0.0);
        return;
    }
    size_t n3 = (size_t)bar.n * 3;
    double *b = malloc(n3 * sizeof *b), *xc = malloc(n3 * sizeof *xc);
    double *x1 = malloc(n3 * sizeof *x1), *x3 = malloc(n3 * sizeof *x3);
    unsigned st = 23;
    if (!b || !xc || !x1 || !x3) goto done;
    for (size_t i = 0; i < n3; ++i) b[i] = gpu_rand(&st);
    if (sparse_inverse_solve(bar.spinv, b, xc, 3, &err) != PL_OK) goto done;
    for (int pi = 0; pi < 2; ++pi) {
        pl_precision p = pi ? PL_F32 : PL_F64;
        setenv("PLIANT_SPINV_SMALL", "0", 1);
        pl_spinv_cuda *g3 = spinv_cuda_create(bar.spinv, p, &err);
        unsetenv("PLIANT_SPINV_SMALL");
        pl_spinv_cuda *g1 = spinv_cuda_create(bar.spinv, p, &err);
        snprintf(what, sizeof what, "%dx%dx%d (n = %d) %s: single block chosen (1), not with "
                 "PLIANT_SPINV_SMALL=0 (0)", nx, ny, nz, bar.n, pi ? "float32" : "float64");
        int chosen = g1 && g3 && spinv_cuda_single_block(g1) && !spinv_cuda_single_block(g3);
        gpu_check_line(md, what, chosen ? 0.0 : 1.0, 0.0);
        if (chosen && device_solve(g1, b, x1, n3, p) == 0 && device_solve(g3, b, x3, n3, p) == 0) {
            snprintf(what, sizeof what, "%dx%dx%d %s: single block vs three launches, values "
                     "differing", nx, ny, nz, pi ? "float32" : "float64");
            gpu_check_line(md, what, bits_differing(x1, x3, n3), 0.0);
            if (!pi) {
                snprintf(what, sizeof what, "%dx%dx%d float64 single block vs CPU", nx, ny, nz);
                gpu_check_line(md, what, gpu_rel_diff(x1, xc, n3), 1e-9);
            }
            snprintf(what, sizeof what, "%dx%dx%d %s single block, x = b in place: values "
                     "differing", nx, ny, nz, pi ? "float32" : "float64");
            double d = device_solve_inplace(g1, b, x1, n3, p) ? INFINITY : bits_differing(x1, x3, n3);
            gpu_check_line(md, what, d, 0.0);
        }
        spinv_cuda_destroy(g1);
        spinv_cuda_destroy(g3);
    }
done:
    free(b), free(xc), free(x1), free(x3);
    gpu_bar_free(&bar);
}

/* Positions of bar/dofs after nsteps of the scene with the given overrides. */
static int run_scene(const char *path, const char *const *ov, int nov, int nsteps, double *out,
                     size_t cap, size_t *m)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = test_tmp_dir();
    opt.device = "cpu"; /* a scene without a CudaDevice is the CPU run */
    opt.overrides = ov;
    opt.noverrides = nov;
    pl_sim *sim = pl_sim_load_file(path, &opt, &diag);
    if (!sim) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    if (!sim) return -1;
    pl_error err;
    int rc = pl_sim_step(sim, nsteps, &err);
    if (rc != PL_OK) printf("scene: %s\n", err.msg);
    pl_component *c = pl_sim_component(sim, "bar/dofs");
    const pl_state_ops *ops = c ? pl_component_role(c, PL_ROLE_STATE) : NULL;
    if (rc == PL_OK && ops) {
        pl_buffer x = ops->positions(c, pl_sim_data(sim));
        *m = x.rows * x.cols < cap ? x.rows * x.cols : cap;
        memcpy(out, x.data, *m * sizeof *out);
    }
    pl_sim_free(sim);
    return rc == PL_OK && ops ? 0 : -1;
}

static void check_scene(const char *path)
{
    size_t cap = 3 * 100000, m0 = 0, m1 = 0;
    double *x0 = malloc(cap * sizeof *x0), *x1 = malloc(cap * sizeof *x1);
    const char *ov64[] = {"global.device=cuda", "global.precision=float64"};
    const char *ov32[] = {"global.device=cuda", "global.precision=float32"};
    if (!x0 || !x1) goto done;
    if (run_scene(path, NULL, 0, 10, x0, cap, &m0) != 0) {
        gpu_check_line(md, "scene on the CPU", 1.0, 0.0);
        goto done;
    }
    int rc = run_scene(path, ov64, 2, 10, x1, cap, &m1);
    gpu_check_line(md, "twisting_bar.xml, 10 steps: device=cuda float64 vs cpu, positions",
                   rc == 0 && m1 == m0 ? gpu_rel_diff(x1, x0, m0) : INFINITY, 1e-9);
    rc = run_scene(path, ov32, 2, 10, x1, cap, &m1);
    gpu_check_line(md, "twisting_bar.xml, 10 steps: device=cuda float32 vs cpu, positions",
                   rc == 0 && m1 == m0 ? gpu_rel_diff(x1, x0, m0) : INFINITY, 1e-4);
done:
    free(x0), free(x1);
}

int main(int argc, char **argv)
{
    gpu_require(PROG);
    md = argc > 1 ? fopen(argv[1], "w") : NULL;
    const char *scene = argc > 2 ? argv[2] : "scenes/twisting_bar.xml";
    if (md) fprintf(md, "| check | value | tolerance | result |\n|---|---|---|---|\n");
    const int sizes[2][3] = {{44, 11, 11}, {72, 17, 17}};
    int nsizes = argc > 3 && !strcmp(argv[3], "small") ? 1 : 2;
    for (int s = 0; s < nsizes; ++s) {
        gpu_bar bar;
        pl_error err;
        if (gpu_bar_build(&bar, sizes[s][0], sizes[s][1], sizes[s][2], &err) != PL_OK) {
            printf("bar: %s\n", err.msg);
            gpu_check_line(md, "building the bar", 1.0, 0.0);
            continue;
        }
        printf("bar %dx%dx%d: n = %d, tets = %d, nnz(S) = %lld\n", bar.nx, bar.ny, bar.nz, bar.n,
               bar.ntets, (long long)sparse_inverse_stats(bar.spinv)->nnz_S);
        for (int m = 0; m < 3; ++m) check_local(&bar, m);
        check_global(&bar);
        gpu_bar_free(&bar);
    }
    check_small_solve(10, 3, 3);
    check_small_solve(12, 4, 3);
    if (nsizes == 2) check_scene(scene);
    printf("gpu_check: %d failed\n", gpu_failures());
    if (md) fclose(md);
    return gpu_failures() > 100 ? 100 : gpu_failures();
}
