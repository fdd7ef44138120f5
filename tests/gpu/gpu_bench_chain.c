/* gpu_bench_chain.c - `gpu_bench chain [tables.md] [repetitions]`: what
 * one link of a device iteration costs at a small scene's size, where the
 * kernels have almost no work and the GPU's time goes to the dependency
 * between one launch and the next.
 *
 * A bar of 12 x 4 x 3 vertices (144 vertices, 396 tetrahedra: about the
 * cable finger's 158 and 389) and the 10 x 3 x 3 and 16 x 4 x 4 bars.  Each
 * operation is captured CHAIN times back to back into one CUDA graph (every
 * copy depending on the previous one, as in a device-loop iteration); the
 * graph's median time over `repetitions` launches, divided by CHAIN, is the
 * cost of one link: kernel time plus the gap to the next.  Operations: an
 * 8-byte memset (a node with no kernel), the global step x = A^-1 b on
 * float64 blocks as one single-block launch and as three launches
 * (PLIANT_SPINV_SMALL=0), the Neo-Hookean local step (project and gather,
 * two launches) and the Neo-Hookean gradient (one launch).  Run it with
 * PLIANT_PDL=1 too for programmatic dependent launch (pliant/cuda_launch.h). */
#include <cuda_runtime_api.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_bar.h"
#include "gpu_util.h"
#include "hyper_cuda.h"
#include "hyper_cuda_gradient.h"
#include "spinv_cuda.h"

#define CHAIN 50

typedef struct chain_ctx {
    pl_spinv_cuda *g;         /* solve */
    pl_hyper_cuda *h;         /* local step */
    pl_hyper_cuda_grad *gr;   /* gradient */
    double h2, *q, *u, *rhs, *x, *grad, *scratch;
} chain_ctx;

typedef int (*link_fn)(chain_ctx *c, cudaStream_t st);

static int link_memset(chain_ctx *c, cudaStream_t st)
{
    return cudaMemsetAsync(c->scratch, 0, sizeof(double), st) != cudaSuccess;
}

static int link_solve(chain_ctx *c, cudaStream_t st)
{
    pl_error err;
    return spinv_cuda_solve(c->g, c->rhs, c->x, PL_F64, st, &err) != PL_OK;
}

static int link_local(chain_ctx *c, cudaStream_t st)
{
    pl_error err;
    return hyper_cuda_project(c->h, 0, c->h2, c->q, c->u, c->rhs, PL_HYPER_CUDA_GATHER, st,
                              &err) != PL_OK;
}

static int link_gradient(chain_ctx *c, cudaStream_t st)
{
    pl_error err;
    return hyper_cuda_grad_add(c->gr, 0, c->q, c->grad, st, &err) != PL_OK;
}

/* Median us of one link: CHAIN links captured into one graph. */
static double link_us(link_fn fn, chain_ctx *c, int reps, cudaStream_t st)
{
    cudaGraph_t graph = NULL;
    cudaGraphExec_t exec = NULL;
    cudaEvent_t a = NULL, b = NULL;
    double *t = malloc((size_t)reps * sizeof *t), med = NAN;
    int rc = !t || cudaStreamBeginCapture(st, cudaStreamCaptureModeThreadLocal) != cudaSuccess;
    for (int k = 0; !rc && k < CHAIN; ++k) rc = fn(c, st);
    if (!t) goto done;
    if (cudaStreamEndCapture(st, &graph) != cudaSuccess || rc ||
        cudaGraphInstantiate(&exec, graph, 0) != cudaSuccess || cudaEventCreate(&a) != cudaSuccess ||
        cudaEventCreate(&b) != cudaSuccess)
        goto done;
    for (int r = 0; r < 3; ++r) cudaGraphLaunch(exec, st);
    int ok = gpu_sync("warm-up") == 0;
    for (int r = 0; r < reps && ok; ++r) {
        float ms = 0.0f;
        cudaEventRecord(a, st);
        ok = cudaGraphLaunch(exec, st) == cudaSuccess;
        cudaEventRecord(b, st);
        ok = ok && cudaEventSynchronize(b) == cudaSuccess &&
             cudaEventElapsedTime(&ms, a, b) == cudaSuccess;
        t[r] = 1e3 * ms / CHAIN;
    }
    if (ok) med = gpu_median(t, reps);
done:
    if (exec) cudaGraphExecDestroy(exec);
    if (graph) cudaGraphDestroy(graph);
    if (a) cudaEventDestroy(a);
    if (b) cudaEventDestroy(b);
    cudaGetLastError();
    free(t);
    return med;
}

static void chain_bar(FILE *md, int nx, int ny, int nz, int reps, cudaStream_t st)
{
    gpu_bar bar;
    pl_error err;
    if (gpu_bar_build(&bar, nx, ny, nz, &err) != PL_OK) {
        printf("bar: %s\n", err.msg);
        return;
    }
    pl_hyper_elements *e = &bar.el[2]; /* Neo-Hookean */
    size_t n3 = (size_t)bar.n * 3, nd = (size_t)e->n * 9;
    double *q = malloc(n3 * sizeof *q), *u = calloc(nd, sizeof *u);
    chain_ctx c;
    memset(&c, 0, sizeof c);
    if (!q || !u) goto done;
    gpu_bar_twist(&bar, 0.25, 1e-3, 29, q);
    c.h2 = bar.h * bar.h;
    c.q = gpu_put(q, n3, PL_F64), c.u = gpu_put(u, nd, PL_F64), c.rhs = gpu_put(q, n3, PL_F64);
    c.x = gpu_put(NULL, n3, PL_F64), c.grad = gpu_put(NULL, n3, PL_F64);
    c.scratch = gpu_put(NULL, 1, PL_F64);
    double us[5] = {NAN, NAN, NAN, NAN, NAN};
    us[0] = link_us(link_memset, &c, reps, st);
    setenv("PLIANT_SPINV_SMALL", "0", 1);
    pl_spinv_cuda *g3 = spinv_cuda_create(bar.spinv, PL_F64, &err);
    unsetenv("PLIANT_SPINV_SMALL");
    pl_spinv_cuda *g1 = spinv_cuda_create(bar.spinv, PL_F64, &err);
    if (g1 && spinv_cuda_single_block(g1)) c.g = g1, us[1] = link_us(link_solve, &c, reps, st);
    if (g3) c.g = g3, us[2] = link_us(link_solve, &c, reps, st);
    if ((c.h = hyper_cuda_create(e, &err)) && hyper_cuda_begin_step(c.h, st, &err) == PL_OK)
        us[3] = link_us(link_local, &c, reps, st);
    if ((c.gr = hyper_cuda_grad_create(e, &err))) us[4] = link_us(link_gradient, &c, reps, st);
    const char *pdl = getenv("PLIANT_PDL");
    printf("%dx%dx%d (n %d, %d tets) us a link: memset %.2f, solve single block %.2f, three "
           "launches %.2f, NeoHookean local step %.2f, gradient %.2f (PLIANT_PDL=%s)\n",
           nx, ny, nz, bar.n, e->n, us[0], us[1], us[2], us[3], us[4], pdl ? pdl : "0");
    fprintf(md, "| %dx%dx%d | %d | %d | %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n", nx, ny, nz,
            bar.n, e->n, pdl ? pdl : "0", us[0], us[1], us[2], us[3], us[4]);
    spinv_cuda_destroy(g1);
    spinv_cuda_destroy(g3);
    hyper_cuda_destroy(c.h);
    hyper_cuda_grad_destroy(c.gr);
done:
    gpu_free(c.q), gpu_free(c.u), gpu_free(c.rhs), gpu_free(c.x), gpu_free(c.grad);
    gpu_free(c.scratch);
    free(q), free(u);
    gpu_bar_free(&bar);
}

void gpu_bench_chain(FILE *md, int reps, cudaStream_t st);
void gpu_bench_chain(FILE *md, int reps, cudaStream_t st)
{
    fprintf(md, "Cost of one link of a dependent chain (%d copies of the operation captured in "
                "one CUDA graph; median graph time / %d, us):\n\n"
                "| bar | n | tets | PLIANT_PDL | memset | solve, single block | solve, three "
                "launches | Neo-Hookean local step | Neo-Hookean gradient |\n"
                "|---|---|---|---|---|---|---|---|---|\n", CHAIN, CHAIN);
    chain_bar(md, 12, 4, 3, reps, st);
    chain_bar(md, 10, 3, 3, reps, st);
    chain_bar(md, 16, 4, 4, reps, st);
}
