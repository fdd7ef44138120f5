/* gpu_bench.c - times of the global and local steps on the GPU (run by
 * tests/gpu/run.sh; not a ctest test).
 *
 *   gpu_bench [tables.md] [repetitions]
 *   gpu_bench chain [tables.md] [repetitions]     (gpu_bench_chain.c)
 *
 * Bars 44x11x11 and 72x17x17 (gpu_bar.h).  Global step x = A^-1 b on
 * device n x 3 blocks, float32 and float64: median over `repetitions` (100)
 * single solves timed with events, the products S a and S^T y alone, and
 * the solve replayed as a CUDA graph.  Achieved bandwidth = bytes of S a
 * step must read (values; spinv_cuda_step_bytes) / time,
 * against a measured device-to-device copy (bytes read + written).  Local
 * steps: GPU gather and atomic assembly, and the CPU's
 * hyper_elements_project on this machine's cores for reference; the CPU
 * global step too. */
#include <cuda_runtime_api.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_bar.h"
#include "gpu_util.h"
#include "hyper_cuda.h"
#include "spinv_cuda.h"

static FILE *md;
static int reps = 100;

typedef int (*work_fn)(void *ctx, cudaStream_t st);

/* Median ms of fn over reps runs, each between two events (after warm-up). */
static double time_events(work_fn fn, void *ctx, cudaStream_t st)
{
    cudaEvent_t a, b;
    double *t = malloc((size_t)reps * sizeof *t), med = NAN;
    if (!t || cudaEventCreate(&a) != cudaSuccess || cudaEventCreate(&b) != cudaSuccess) {
        free(t);
        return NAN;
    }
    int ok = 1;
    for (int r = 0; r < 10 && ok; ++r) ok = fn(ctx, st) == 0;
    for (int r = 0; r < reps && ok; ++r) {
        float ms = 0.0f;
        cudaEventRecord(a, st);
        ok = fn(ctx, st) == 0;
        cudaEventRecord(b, st);
        ok = ok && cudaEventSynchronize(b) == cudaSuccess &&
             cudaEventElapsedTime(&ms, a, b) == cudaSuccess;
        t[r] = ms;
    }
    if (ok && gpu_sync("timed work") == 0) med = gpu_median(t, reps);
    cudaEventDestroy(a);
    cudaEventDestroy(b);
    free(t);
    return med;
}

/* ---- device-to-device copy --------------------------------------------- */
typedef struct copy_ctx {
    void *src, *dst;
    size_t bytes;
} copy_ctx;

static int run_copy(void *ctx, cudaStream_t st)
{
    copy_ctx *c = ctx;
    return cudaMemcpyAsync(c->dst, c->src, c->bytes, cudaMemcpyDeviceToDevice, st) != cudaSuccess;
}

static double copy_bandwidth(cudaStream_t st)
{
    copy_ctx c = {NULL, NULL, (size_t)1 << 30};
    double gbs = NAN;
    if (cudaMalloc(&c.src, c.bytes) == cudaSuccess && cudaMalloc(&c.dst, c.bytes) == cudaSuccess &&
        cudaMemset(c.src, 1, c.bytes) == cudaSuccess) {
        double ms = time_events(run_copy, &c, st);
        gbs = 2.0 * (double)c.bytes / (ms * 1e-3) / 1e9;
    }
    cudaFree(c.src);
    cudaFree(c.dst);
    return gbs;
}

/* ---- global step ------------------------------------------------------- */
typedef struct solve_ctx {
    pl_spinv_cuda *g;
    void *b, *x;
    pl_precision io;
    int stage;            /* -1: the whole solve, else pl_spinv_cuda_stage */
    cudaGraphExec_t exec; /* replayed when set */
} solve_ctx;

static int run_solve(void *ctx, cudaStream_t st)
{
    solve_ctx *c = ctx;
    pl_error err;
    if (c->exec) return cudaGraphLaunch(c->exec, st) != cudaSuccess;
    int rc = c->stage < 0 ? spinv_cuda_solve(c->g, c->b, c->x, c->io, st, &err)
                          : spinv_cuda_run_stage(c->g, (pl_spinv_cuda_stage)c->stage, st, &err);
    if (rc != PL_OK) fprintf(stderr, "solve: %s\n", err.msg);
    return rc != PL_OK;
}

/* Captures one solve into a graph (own path). */
static int capture(solve_ctx *c, cudaStream_t st)
{
    cudaGraph_t graph;
    c->stage = -1;
    if (cudaStreamBeginCapture(st, cudaStreamCaptureModeThreadLocal) != cudaSuccess) return -1;
    int rc = run_solve(c, st);
    if (cudaStreamEndCapture(st, &graph) != cudaSuccess || rc) return -1;
    rc = cudaGraphInstantiate(&c->exec, graph, 0) != cudaSuccess;
    cudaGraphDestroy(graph);
    return rc ? -1 : 0;
}

static void bench_global(gpu_bar *bar, double copy_gbs, cudaStream_t st)
{
    size_t n3 = (size_t)bar->n * 3;
    double *b = malloc(n3 * sizeof *b), *x = malloc(n3 * sizeof *x);
    unsigned s = 23;
    if (!b || !x) goto done;
    for (size_t i = 0; i < n3; ++i) b[i] = gpu_rand(&s);
    /* the CPU reference on this machine's cores */
    double *t = malloc(20 * sizeof *t);
    pl_error err;
    for (int r = 0; t && r < 21; ++r) {
        double t0 = omp_get_wtime();
        sparse_inverse_solve(bar->spinv, b, x, 3, &err);
        if (r) t[r - 1] = 1e3 * (omp_get_wtime() - t0);
    }
    if (t) {
        double med = gpu_median(t, 20);
        fprintf(md, "| %dx%dx%d | %d | CPU sparse inverse (%d threads) | float64 | %.3f | | | | |\n",
                bar->nx, bar->ny, bar->nz, bar->n, omp_get_max_threads(), med);
        printf("%dx%dx%d CPU global step %.3f ms\n", bar->nx, bar->ny, bar->nz, med);
        free(t);
    }
    for (int pi = 0; pi < 2; ++pi) {
        pl_precision p = pi ? PL_F32 : PL_F64;
        pl_spinv_cuda *g = spinv_cuda_create(bar->spinv, p, &err);
        if (!g) {
            printf("create: %s\n", err.msg);
            continue;
        }
        solve_ctx c = {g, gpu_put(b, n3, p), gpu_put(NULL, n3, p), p, -1, NULL};
        double ms = time_events(run_solve, &c, st);
        c.stage = PL_SPINV_CUDA_STAGE_PERMUTE;
        double ms_p = time_events(run_solve, &c, st);
        c.stage = PL_SPINV_CUDA_STAGE_S;
        double ms_s = time_events(run_solve, &c, st);
        c.stage = PL_SPINV_CUDA_STAGE_ST;
        double ms_st = time_events(run_solve, &c, st);
        double ms_graph = NAN;
        if (capture(&c, st) == 0) {
            ms_graph = time_events(run_solve, &c, st);
            cudaGraphExecDestroy(c.exec);
        }
        double gbs = spinv_cuda_step_bytes(g) / (ms * 1e-3) / 1e9;
        printf("%dx%dx%d own kernels %s: step %.4f ms (graph %.4f), P %.4f, S %.4f, S^T %.4f, %.0f "
               "GB/s = %.0f%% of copy, S on device %.1f MB\n",
               bar->nx, bar->ny, bar->nz, pi ? "float32" : "float64", ms, ms_graph, ms_p, ms_s,
               ms_st, gbs, 100.0 * gbs / copy_gbs, spinv_cuda_device_bytes(g) / 1048576.0);
        fprintf(md, "| %dx%dx%d | %d | own kernels | %s | %.4f | %.4f | %.4f / %.4f / %.4f | %.0f | "
                    "%.0f%% |\n",
                bar->nx, bar->ny, bar->nz, bar->n, pi ? "float32" : "float64", ms, ms_graph, ms_p,
                ms_s, ms_st, gbs, 100.0 * gbs / copy_gbs);
        gpu_free(c.b), gpu_free(c.x);
        spinv_cuda_destroy(g);
    }
done:
    free(b), free(x);
}

/* ---- row-kernel tuning: rows per warp item and item size --------------- */
static void bench_variants(gpu_bar *bar, cudaStream_t st)
{
    static const int groups[] = {1, 1, 2, 2, 4, 4, 8, 8, 8};
    static const int scale[] = {4, 2, 4, 2, 4, 2, 4, 2, 1}; /* item blocks = base * scale / 4 */
    size_t n3 = (size_t)bar->n * 3;
    double *b = malloc(n3 * sizeof *b);
    unsigned s = 37;
    pl_error err;
    if (!b) return;
    for (size_t i = 0; i < n3; ++i) b[i] = gpu_rand(&s);
    for (int pi = 0; pi < 2; ++pi) {
        pl_precision p = pi ? PL_F32 : PL_F64;
        int base = 4096 / (8 * (pi ? 4 : 8));
        for (int v = 0; v < (int)(sizeof groups / sizeof groups[0]); ++v) {
            int blocks = base * scale[v] / 4;
            pl_spinv_cuda *g =
                spinv_cuda_create_tuned(bar->spinv, p, groups[v], blocks, &err);
            if (!g) {
                printf("create: %s\n", err.msg);
                continue;
            }
            solve_ctx c = {g, gpu_put(b, n3, p), gpu_put(NULL, n3, p), p, -1, NULL};
            double ms = time_events(run_solve, &c, st);
            c.stage = PL_SPINV_CUDA_STAGE_S;
            double ms_s = time_events(run_solve, &c, st);
            printf("%dx%dx%d %s group %d, %d blocks/item: S %.4f ms, step %.4f ms\n", bar->nx,
                   bar->ny, bar->nz, pi ? "float32" : "float64", groups[v], blocks, ms_s, ms);
            fprintf(md, "| %dx%dx%d | %s | %d | %d | %.4f | %.4f |\n", bar->nx, bar->ny, bar->nz,
                    pi ? "float32" : "float64", groups[v], blocks, ms_s, ms);
            gpu_free(c.b), gpu_free(c.x);
            spinv_cuda_destroy(g);
        }
    }
    free(b);
}

/* ---- local step -------------------------------------------------------- */
typedef struct local_ctx {
    pl_hyper_cuda *g;
    double h2, *q, *u, *rhs;
    pl_hyper_cuda_assembly mode;
} local_ctx;

static int run_local(void *ctx, cudaStream_t st)
{
    local_ctx *c = ctx;
    pl_error err;
    int rc = hyper_cuda_project(c->g, 0, c->h2, c->q, c->u, c->rhs, c->mode, st, &err);
    if (rc != PL_OK) fprintf(stderr, "local: %s\n", err.msg);
    return rc != PL_OK;
}

static void bench_local(gpu_bar *bar, int m, cudaStream_t st)
{
    static const char *const names[3] = {"ARAP", "corotational", "Neo-Hookean"};
    pl_hyper_elements *e = &bar->el[m];
    size_t n3 = (size_t)bar->n * 3, nd = (size_t)e->n * 9;
    double *q = malloc(n3 * sizeof *q), *u = calloc(nd, sizeof *u), *rhs = calloc(n3, sizeof *rhs);
    double t[10];
    pl_error err;
    if (!q || !u || !rhs) goto done;
    gpu_bar_twist(bar, 0.25, 1e-3, 29, q);
    int admm = e->material != PL_HYPER_ARAP;
    double *work = malloc(hyper_elements_work_size(e) * sizeof *work);
    if (!work) goto done;
    for (int r = 0; r < 11; ++r) {
        double t0 = omp_get_wtime();
        hyper_elements_project(e, 0, bar->h * bar->h, q, admm ? u : NULL, NULL, work, rhs, NULL, &err);
        if (r) t[r - 1] = 1e3 * (omp_get_wtime() - t0);
    }
    free(work);
    double cpu = gpu_median(t, 10), gms[2] = {NAN, NAN};
    pl_hyper_cuda *g = hyper_cuda_create(e, &err);
    if (g) {
        local_ctx c = {g, bar->h * bar->h, gpu_put(q, n3, PL_F64), admm ? gpu_put(u, nd, PL_F64) : NULL,
                       gpu_put(NULL, n3, PL_F64), PL_HYPER_CUDA_GATHER};
        gms[0] = time_events(run_local, &c, st);
        c.mode = PL_HYPER_CUDA_ATOMIC;
        gms[1] = time_events(run_local, &c, st);
        gpu_free(c.q), gpu_free(c.u), gpu_free(c.rhs);
        hyper_cuda_destroy(g);
    }
    printf("%dx%dx%d local %-13s %d tets: GPU gather %.4f ms, atomic %.4f ms, CPU %.3f ms\n",
           bar->nx, bar->ny, bar->nz, names[m], e->n, gms[0], gms[1], cpu);
    fprintf(md, "| %dx%dx%d | %d | %s | %.4f | %.4f | %.3f |\n", bar->nx, bar->ny, bar->nz, e->n,
            names[m], gms[0], gms[1], cpu);
done:
    free(q), free(u), free(rhs);
}

/* ---- one iteration on the device: local ARAP + global step ------------- */
typedef struct iter_ctx {
    local_ctx local;
    solve_ctx global;
    size_t n3;
    cudaGraphExec_t exec;
} iter_ctx;

static int run_iter(void *ctx, cudaStream_t st)
{
    iter_ctx *c = ctx;
    if (c->exec) return cudaGraphLaunch(c->exec, st) != cudaSuccess;
    if (cudaMemsetAsync(c->local.rhs, 0, c->n3 * sizeof(double), st) != cudaSuccess) return 1;
    return run_local(&c->local, st) || run_solve(&c->global, st);
}

static void bench_iteration(gpu_bar *bar, cudaStream_t st)
{
    size_t n3 = (size_t)bar->n * 3;
    double *q = malloc(n3 * sizeof *q);
    pl_error err;
    if (!q) return;
    gpu_bar_twist(bar, 0.25, 1e-3, 31, q);
    pl_hyper_cuda *h = hyper_cuda_create(&bar->el[0], &err);
    for (int pi = 0; h && pi < 2; ++pi) {
        pl_precision p = pi ? PL_F32 : PL_F64;
        pl_spinv_cuda *g = spinv_cuda_create(bar->spinv, p, &err);
        if (!g) continue;
        iter_ctx c;
        memset(&c, 0, sizeof c);
        c.n3 = n3;
        c.local = (local_ctx){h, bar->h * bar->h, gpu_put(q, n3, PL_F64), NULL,
                              gpu_put(NULL, n3, PL_F64), PL_HYPER_CUDA_GATHER};
        c.global = (solve_ctx){g, c.local.rhs, gpu_put(NULL, n3, PL_F64), PL_F64, -1, NULL};
        double plain = time_events(run_iter, &c, st), graph = NAN;
        cudaGraph_t gr;
        if (cudaStreamBeginCapture(st, cudaStreamCaptureModeThreadLocal) == cudaSuccess) {
            int rc = run_iter(&c, st);
            if (cudaStreamEndCapture(st, &gr) == cudaSuccess && !rc) {
                if (cudaGraphInstantiate(&c.exec, gr, 0) == cudaSuccess) {
                    graph = time_events(run_iter, &c, st);
                    cudaGraphExecDestroy(c.exec);
                }
                cudaGraphDestroy(gr);
            }
        }
        printf("%dx%dx%d iteration (ARAP local + global %s): %.4f ms, graph %.4f ms\n", bar->nx,
               bar->ny, bar->nz, pi ? "float32" : "float64", plain, graph);
        fprintf(md, "| %dx%dx%d | %s | %.4f | %.4f |\n", bar->nx, bar->ny, bar->nz,
                pi ? "float32" : "float64", plain, graph);
        gpu_free(c.local.q), gpu_free(c.local.rhs), gpu_free(c.global.x);
        spinv_cuda_destroy(g);
    }
    hyper_cuda_destroy(h);
    free(q);
}

void gpu_bench_chain(FILE *md, int reps, cudaStream_t st);

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "chain")) {
        cudaStream_t st;
        FILE *out = argc > 2 ? fopen(argv[2], "w") : stdout;
        if (cudaStreamCreate(&st) != cudaSuccess || !out) return 1;
        gpu_bench_chain(out, argc > 3 && atoi(argv[3]) > 0 ? atoi(argv[3]) : 100, st);
        if (out != stdout) fclose(out);
        cudaStreamDestroy(st);
        return 0;
    }
    md = argc > 1 ? fopen(argv[1], "w") : stdout;
    if (!md) md = stdout;
    if (argc > 2) reps = atoi(argv[2]) > 0 ? atoi(argv[2]) : 100;
    struct cudaDeviceProp prop;
    cudaStream_t st;
    if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess || cudaStreamCreate(&st) != cudaSuccess) {
        fprintf(stderr, "no CUDA device\n");
        return 1;
    }
    double copy = copy_bandwidth(st);
    printf("device %s, %d SMs, L2 %d MB; device-to-device copy %.0f GB/s (read + write)\n",
           prop.name, prop.multiProcessorCount, prop.l2CacheSize >> 20, copy);
    fprintf(md, "Device: %s (%d SMs, L2 %d MB); device-to-device copy %.0f GB/s (bytes read + "
            "written, 1 GiB); medians of %d runs; host CPU: %d OpenMP threads.\n\n",
            prop.name, prop.multiProcessorCount, prop.l2CacheSize >> 20, copy, reps,
            omp_get_max_threads());
    const int sizes[2][3] = {{44, 11, 11}, {72, 17, 17}};
    gpu_bar bars[2];
    int built[2] = {0, 0};
    fprintf(md, "Global step x = P^T S^T S P b, n x 3 device blocks:\n\n"
                "| bar | n | path | precision | step [ms] | graph [ms] | P / S / S^T [ms] | GB/s | "
                "of copy |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int s = 0; s < 2; ++s) {
        pl_error err;
        built[s] = gpu_bar_build(&bars[s], sizes[s][0], sizes[s][1], sizes[s][2], &err) == PL_OK;
        if (!built[s]) {
            printf("bar: %s\n", err.msg);
            continue;
        }
        bench_global(&bars[s], copy, st);
    }
    fprintf(md, "\nRow kernel y = S a, tuning: rows of S per warp item at most "
                "(group: consecutive rows with one first column) and blocks of 8 columns per "
                "item:\n\n| bar | precision | group | blocks/item | S [ms] | step [ms] |\n"
                "|---|---|---|---|---|---|\n");
    for (int s = 0; s < 2; ++s)
        if (built[s]) bench_variants(&bars[s], st);
    fprintf(md, "\nLocal step (float64), rhs assembly by vertex gather or atomics:\n\n"
                "| bar | tets | material | GPU gather [ms] | GPU atomic [ms] | CPU [ms] |\n"
                "|---|---|---|---|---|---|\n");
    for (int s = 0; s < 2; ++s)
        if (built[s])
            for (int m = 0; m < 3; ++m) bench_local(&bars[s], m, st);
    fprintf(md, "\nOne iteration on the device (zero rhs, ARAP local step with gather, global "
                "step of float64 blocks; S in the precision shown), 7 launches:\n\n"
                "| bar | S precision | launches [ms] | CUDA graph [ms] |\n|---|---|---|---|\n");
    for (int s = 0; s < 2; ++s)
        if (built[s]) bench_iteration(&bars[s], st);
    for (int s = 0; s < 2; ++s)
        if (built[s]) gpu_bar_free(&bars[s]);
    cudaStreamDestroy(st);
    if (md != stdout) fclose(md);
    return gpu_failures() ? 1 : 0;
}
