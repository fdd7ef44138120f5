/* stencil_cuda.cu - stencil terms' local step on the GPU (stencil_cuda.h):
 * one thread per row writes its entries' slots, one thread per vertex sums
 * its slots in increasing order (hyper_incidence_gather on the CPU). */
#include "stencil_cuda.h"

#include <cuda_runtime.h>
#include <stdlib.h>

#include "hyper_cuda.h"    /* hyper_cuda_gather */
#include "keep_norm.h" /* the CPU's KEEP_NORM projection (compiled as CUDA) */

struct pl_stencil_cuda {
    int n, nverts, nnz, keep_norm;
    int *ptr, *vert, *vptr, *vinc;
    double *coef, *w, *rest, *targets, *work;
};

namespace {

int cuda_fail(pl_error *err, cudaError_t e, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "stencils (cuda): %s: %s", what,
                        cudaGetErrorString(e));
}

template <typename T>
int upload(pl_stencil_cuda *g, T **dst, const T *src, size_t count, pl_error *err)
{
    size_t bytes = (count > 0 ? count : 1) * sizeof(T);
    cudaError_t e = cudaMalloc((void **)dst, bytes);
    if (e != cudaSuccess) return cuda_fail(err, e, "cudaMalloc");
    if (src && count) {
        e = cudaMemcpy(*dst, src, count * sizeof(T), cudaMemcpyHostToDevice);
        if (e != cudaSuccess) return cuda_fail(err, e, "upload");
    }
    return PL_OK;
}

/* Row r: y = g_r x, p_r (stencils.c, apply_row and target_of), slots of
 * its entries h2 w_r c_k p_r. */
__global__ void k_rows(int n, int keep_norm, const int *__restrict__ ptr,
                       const int *__restrict__ vert, const double *__restrict__ coef,
                       const double *__restrict__ w, const double *__restrict__ rest,
                       const double *__restrict__ targets, int offset, double h2,
                       const double *__restrict__ q, double *__restrict__ work)
{
    const int r = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (r >= n) return;
    const int b = ptr[r], e = ptr[r + 1];
    double y[3] = {0.0, 0.0, 0.0}, p[3];
    for (int k = b; k < e; ++k) {
        const double *x = q + 3 * ((size_t)offset + vert[k]);
        const double c = coef[k];
        y[0] += c * x[0];
        y[1] += c * x[1];
        y[2] += c * x[2];
    }
    if (!keep_norm) {
        for (int a = 0; a < 3; ++a) p[a] = targets ? targets[3 * (size_t)r + a] : 0.0;
    } else {
        hm_keep_norm_target(rest + 3 * (size_t)r, y, p);
    }
    const double hw = h2 * w[r];
    for (int k = b; k < e; ++k) {
        const double s = hw * coef[k];
        work[3 * (size_t)k] = s * p[0];
        work[3 * (size_t)k + 1] = s * p[1];
        work[3 * (size_t)k + 2] = s * p[2];
    }
}

} // namespace

extern "C" pl_stencil_cuda *stencil_cuda_create(const pl_hyper_stencils *s, pl_error *err)
{
    pl_stencil_cuda *g = static_cast<pl_stencil_cuda *>(calloc(1, sizeof *g));
    if (!g) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "stencils (cuda): out of memory");
        return NULL;
    }
    g->n = s->n, g->nverts = s->nverts, g->nnz = s->ptr[s->n];
    g->keep_norm = s->kind == PL_HYPER_STENCIL_KEEP_NORM;
    size_t n = (size_t)s->n, nnz = (size_t)g->nnz;
    if (upload(g, &g->ptr, s->ptr, n + 1, err) || upload(g, &g->vert, s->vert, nnz, err) ||
        upload(g, &g->coef, s->coef, nnz, err) || upload(g, &g->w, s->w, n, err) ||
        upload(g, &g->rest, g->keep_norm ? s->rest : static_cast<const double *>(NULL),
               g->keep_norm ? 3 * n : 0, err) ||
        upload(g, &g->targets, static_cast<const double *>(NULL), g->keep_norm ? 0 : 3 * n, err) ||
        upload(g, &g->vptr, s->vptr, (size_t)s->nverts + 1, err) ||
        upload(g, &g->vinc, s->vinc, nnz, err) ||
        upload(g, &g->work, static_cast<const double *>(NULL), 3 * nnz, err)) {
        stencil_cuda_destroy(g);
        return NULL;
    }
    return g;
}

extern "C" void stencil_cuda_destroy(pl_stencil_cuda *g)
{
    if (!g) return;
    void *ptrs[] = {g->ptr, g->vert, g->vptr, g->vinc, g->coef, g->w, g->rest, g->targets, g->work};
    for (void *p : ptrs)
        if (p) cudaFree(p);
    free(g);
}

extern "C" int stencil_cuda_set_targets(pl_stencil_cuda *g, const double *targets,
                                           struct CUstream_st *stream, pl_error *err)
{
    if (g->keep_norm || g->n == 0) return PL_OK;
    cudaError_t e = cudaMemcpyAsync(g->targets, targets, 3 * (size_t)g->n * sizeof(double),
                                    cudaMemcpyHostToDevice, stream);
    return e == cudaSuccess ? PL_OK : cuda_fail(err, e, "targets to the device");
}

extern "C" int stencil_cuda_project(pl_stencil_cuda *g, int offset, double h2, const double *q,
                                       int with_targets, double *rhs, struct CUstream_st *stream,
                                       pl_error *err)
{
    if (!g || !q || !rhs || offset < 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "stencils (cuda): bad arguments");
    if (g->n == 0) return PL_OK;
    k_rows<<<(unsigned)((g->n + 127) / 128), 128, 0, stream>>>(
        g->n, g->keep_norm, g->ptr, g->vert, g->coef, g->w, g->rest,
        with_targets && !g->keep_norm ? g->targets : NULL, offset, h2, q, g->work);
    cudaError_t e = cudaGetLastError();
    if (e != cudaSuccess) return cuda_fail(err, e, "stencil kernels");
    /* the FEM local step's gather: the same incidence layout (hyper_cuda.h) */
    return g->nverts > 0 ? hyper_cuda_gather(g->nverts, g->vptr, g->vinc, g->work, offset, rhs,
                                             stream, err)
                         : PL_OK;
}

