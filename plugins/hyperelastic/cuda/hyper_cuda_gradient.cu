/* hyper_cuda_gradient.cu - the elastic gradient d psi / dq of a FEM element
 * set on the GPU (see hyper_cuda_gradient.h): one thread per element writes
 * V P D^T to its k corner slots, then hyper_cuda_gather sums each vertex's
 * slots in the CPU's order (hyper_elements_add_gradient's algorithm, with
 * the same SVD and material law, local_solve.h compiled as CUDA). */
#include "hyper_cuda_gradient.h"

#include <cuda_runtime.h>
#include "pliant/cuda_launch.h"
#include <stdlib.h>

#include "local_solve.h" /* hm_svd3 / hm_svd32, hm_sv_eval */

struct pl_hyper_cuda_grad {
    int n, nverts, material, k;
    int *verts;             /* n x k */
    double *D;              /* n x (k d) */
    double *volume, *mu, *lambda; /* n */
    int *vptr, *vinc;       /* nverts + 1, k n */
    double *slots;          /* n x 3k */
};

namespace {

constexpr int kThreads = 128;

int cuda_fail(pl_error *err, cudaError_t e, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "hyperelastic (cuda gradient): %s: %s",
                        what, cudaGetErrorString(e));
}

/* Element i: F = X D, P = U diag(dpsi/ds) V^T (Neo-Hookean tetrahedra:
 * hm_neohookean_piola3, as hyper_piola on the CPU), slots = V P D^T (K
 * corners, F 3 x Dd).  Outside the law's domain (Neo-Hookean, some s <= 0) P is NaN,
 * as hyper_piola makes it. */
template <int K, int Dd>
__global__ void __launch_bounds__(kThreads)
    k_gradient(int n, int material, const int *__restrict__ verts, const double *__restrict__ D,
               const double *__restrict__ volume, const double *__restrict__ mu,
               const double *__restrict__ lambda, int offset, const double *__restrict__ q,
               double *__restrict__ slots)
{
    PL_CUDA_GRID_WAIT(); /* first: before any global access (cuda_launch.h) */
    PL_CUDA_LAUNCH_DEPENDENTS();
    constexpr int ND = 3 * Dd, KD = K * Dd;
    const int i = (int)(blockIdx.x * (size_t)blockDim.x + threadIdx.x);
    if (i >= n) return;
    double Dl[KD], F[ND], P[ND];
#pragma unroll
    for (int c = 0; c < KD; ++c) Dl[c] = D[KD * (size_t)i + c];
#pragma unroll
    for (int a = 0; a < ND; ++a) F[a] = 0.0;
#pragma unroll
    for (int c = 0; c < K; ++c) {
        const double *x = q + 3 * ((size_t)offset + verts[K * (size_t)i + c]);
#pragma unroll
        for (int a = 0; a < 3; ++a)
#pragma unroll
            for (int b = 0; b < Dd; ++b) F[a * Dd + b] += x[a] * Dl[c * Dd + b];
    }
    if (Dd == 3 && material == PL_HYPER_NEOHOOKEAN) { /* hyper_piola's closed form, no SVD */
        hm_neohookean_piola3(mu[i], lambda[i], F, P);
    } else {
        double U[9], s[3], V[9], g[3], psi;
        if (Dd == 3) {
            hm_svd3(F, U, s, V);
        } else {
            double U2[6]; /* 3 x 2: the first two columns of U */
            hm_svd32(F, U2, s, V);
#pragma unroll
            for (int r = 0; r < 3; ++r) U[r * 3 + 0] = U2[r * 2], U[r * 3 + 1] = U2[r * 2 + 1];
        }
        if (hm_sv_eval(Dd, material, mu[i], lambda[i], s, &psi, g, NULL) != 0) {
#pragma unroll
            for (int a = 0; a < ND; ++a) P[a] = nan("");
        } else {
#pragma unroll
            for (int a = 0; a < 3; ++a)
#pragma unroll
                for (int b = 0; b < Dd; ++b) {
                    double v = 0.0;
#pragma unroll
                    for (int j = 0; j < Dd; ++j) v += U[a * 3 + j] * g[j] * V[b * Dd + j];
                    P[a * Dd + b] = v;
                }
        }
    }
    const double vol = volume[i];
    double *out = slots + 3 * K * (size_t)i;
#pragma unroll
    for (int c = 0; c < K; ++c)
#pragma unroll
        for (int a = 0; a < 3; ++a) {
            double v = 0.0;
#pragma unroll
            for (int b = 0; b < Dd; ++b) v += P[a * Dd + b] * Dl[c * Dd + b];
            out[3 * c + a] = vol * v;
        }
}

template <typename T>
int upload(T **dst, const T *src, size_t count, pl_error *err)
{
    size_t bytes = (count > 0 ? count : 1) * sizeof(T);
    cudaError_t e = cudaMalloc((void **)dst, bytes);
    if (e != cudaSuccess) return cuda_fail(err, e, "cudaMalloc");
    if (src && count) e = cudaMemcpy(*dst, src, count * sizeof(T), cudaMemcpyHostToDevice);
    return e == cudaSuccess ? PL_OK : cuda_fail(err, e, "upload");
}

} // namespace

extern "C" pl_hyper_cuda_grad *hyper_cuda_grad_create(const pl_hyper_elements *e, pl_error *err)
{
    if (!e || !((e->k == 4 && e->d == 3) || (e->k == 3 && e->d == 2)) || e->edge_rotation) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "hyperelastic (cuda): the device gradient takes tetrahedra or triangles "
                     "without the edge rotation");
        return NULL;
    }
    pl_hyper_cuda_grad *g = static_cast<pl_hyper_cuda_grad *>(calloc(1, sizeof *g));
    if (!g) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "hyperelastic (cuda): out of memory");
        return NULL;
    }
    g->n = e->n, g->nverts = e->nverts, g->material = (int)e->material, g->k = e->k;
    size_t n = (size_t)e->n, k = (size_t)e->k;
    if (upload(&g->verts, e->verts, k * n, err) || upload(&g->D, e->D, k * (size_t)e->d * n, err) ||
        upload(&g->volume, e->volume, n, err) || upload(&g->mu, e->mu, n, err) ||
        upload(&g->lambda, e->lambda, n, err) ||
        upload(&g->vptr, e->vptr, (size_t)e->nverts + 1, err) ||
        upload(&g->vinc, e->vinc, k * n, err) ||
        upload(&g->slots, static_cast<const double *>(NULL), 3 * k * n, err)) {
        hyper_cuda_grad_destroy(g);
        return NULL;
    }
    return g;
}

extern "C" void hyper_cuda_grad_destroy(pl_hyper_cuda_grad *g)
{
    if (!g) return;
    void *ptrs[] = {g->verts, g->D, g->volume, g->mu, g->lambda, g->vptr, g->vinc, g->slots};
    for (void *p : ptrs)
        if (p) cudaFree(p);
    free(g);
}

extern "C" int hyper_cuda_grad_add(pl_hyper_cuda_grad *g, int offset, const double *q, double *grad,
                                   struct CUstream_st *stream, pl_error *err)
{
    if (!g || !q || !grad || offset < 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "hyperelastic (cuda): bad arguments");
    cudaStream_t st = stream;
    if (g->n > 0) {
        unsigned nb = (unsigned)((g->n + kThreads - 1) / kThreads);
        if (g->k == 4)
            pl_cuda_launch(k_gradient<4, 3>, nb, kThreads, 0, st, g->n, g->material, g->verts,
                           g->D, g->volume, g->mu, g->lambda, offset, q, g->slots);
        else
            pl_cuda_launch(k_gradient<3, 2>, nb, kThreads, 0, st, g->n, g->material, g->verts,
                           g->D, g->volume, g->mu, g->lambda, offset, q, g->slots);
        cudaError_t e = cudaGetLastError();
        if (e != cudaSuccess) return cuda_fail(err, e, "gradient kernel");
        if (g->nverts > 0) return hyper_cuda_gather(g->nverts, g->vptr, g->vinc, g->slots, offset,
                                                    grad, stream, err);
    }
    return PL_OK;
}
