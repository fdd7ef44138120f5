/* spinv_cuda.cu - the device copy of S and the global step on it (see
 * spinv_cuda.h): upload, solve, the building blocks, destroy. */
#include "spinv_cuda_internal.h"

#include <stdlib.h>
#include <string.h>

int spinv_cuda_fail(pl_error *err, cudaError_t e, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cuda): %s: %s", what,
                        cudaGetErrorString(e));
}

namespace {

size_t real_size(pl_precision p)
{
    return p == PL_F32 ? sizeof(float) : sizeof(double);
}

/* cudaMalloc of at least one byte, counted in bytes_device. */
int dev_alloc(pl_spinv_cuda *g, void **p, size_t bytes, pl_error *err)
{
    if (bytes == 0) bytes = 16;
    SPINV_CK(cudaMalloc(p, bytes), "cudaMalloc");
    g->bytes_device += (double)bytes;
    return PL_OK;
}

int upload(pl_spinv_cuda *g, void **dst, const void *src, size_t bytes, pl_error *err)
{
    int rc = dev_alloc(g, dst, bytes, err);
    if (rc != PL_OK) return rc;
    if (bytes) SPINV_CK(cudaMemcpy(*dst, src, bytes, cudaMemcpyHostToDevice), "upload");
    return PL_OK;
}

/* Uploads the layout, its values in the object's precision and perm. */
int upload_layout(pl_spinv_cuda *g, const pl_spinv_cuda_layout *L, const pl_spinv_profile *S,
                  const int *perm, const int *parent, pl_error *err)
{
    size_t rs = real_size(g->prec), nval = (size_t)L->nval;
    void *host = malloc(nval * rs > 0 ? nval * rs : 1);
    if (!host)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cuda): out of memory");
    if (g->prec == PL_F32)
        spinv_cuda_layout_fill_f32(L, S, static_cast<float *>(host));
    else
        spinv_cuda_layout_fill_f64(L, S, static_cast<double *>(host));
    int rc = upload(g, &g->val, host, nval * rs, err);
    free(host);
    if (rc != PL_OK) return rc;
    size_t n = (size_t)g->n;
    if ((rc = upload(g, (void **)&g->perm, perm, n * sizeof(int), err)) ||
        (rc = upload(g, (void **)&g->parent, parent, n * sizeof(int), err)) ||
        (rc = upload(g, (void **)&g->meta, L->meta, n * sizeof *L->meta, err)) ||
        (rc = upload(g, (void **)&g->items_S, L->items_S, (size_t)L->nitems_S * sizeof *L->items_S, err)) ||
        (rc = upload(g, (void **)&g->items_ST, L->items_ST,
                     (size_t)L->nitems_ST * sizeof *L->items_ST, err)) ||
        (rc = upload(g, (void **)&g->short_rows, L->short_rows, (size_t)L->nshort * sizeof(int), err)) ||
        (rc = upload(g, (void **)&g->rowlist, L->rowlist, (size_t)L->nrowlist * sizeof *L->rowlist,
                     err)))
        return rc;
    /* workspaces; the counters start at zero and every launch leaves them so */
    size_t nv = (size_t)L->vc * 3;
    if ((rc = dev_alloc(g, &g->a, (size_t)g->npad * 3 * rs, err)) ||
        (rc = dev_alloc(g, &g->y4, n * 4 * rs, err)) ||
        (rc = dev_alloc(g, &g->part_S, (size_t)L->nparts_S * L->group * 4 * rs, err)) ||
        (rc = dev_alloc(g, &g->part_ST, (size_t)L->nparts_ST * 32 * nv * rs, err)) ||
        (rc = dev_alloc(g, (void **)&g->cnt_S, n * sizeof(int), err)) ||
        (rc = dev_alloc(g, (void **)&g->cnt_ST, (size_t)L->ntiles * sizeof(int), err)))
        return rc;
    SPINV_CK(cudaMemset(g->cnt_S, 0, n * sizeof(int)), "cudaMemset");
    SPINV_CK(cudaMemset(g->cnt_ST, 0, (size_t)L->ntiles * sizeof(int)), "cudaMemset");
    SPINV_CK(cudaMemset(g->y4, 0, n * 4 * rs), "cudaMemset");
    return PL_OK;
}

int check_io(const pl_spinv_cuda *g, pl_precision io, pl_error *err)
{
    if (!g)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse (cuda): no device copy");
    if (io != PL_F64 && io != PL_F32)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse (cuda): blocks must be float64 or float32");
    return PL_OK;
}

} // namespace

extern "C" pl_spinv_cuda *spinv_cuda_create(const pl_sparse_inverse *s, pl_precision precision,
                                               pl_error *err)
{
    return spinv_cuda_create_tuned(s, precision, 0, 0, err);
}

extern "C" pl_spinv_cuda *spinv_cuda_create_tuned(const pl_sparse_inverse *s,
                                                     pl_precision precision, int group,
                                                     int item_blocks, pl_error *err)
{
    const pl_spinv_profile *S = s ? pl_sparse_inverse_S(s) : NULL;
    const pl_spinv_runs *ST = s ? pl_sparse_inverse_ST(s) : NULL;
    const int *perm = s ? sparse_inverse_perm(s) : NULL;
    if (!S || !ST || !perm || !sparse_inverse_parent(s)) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "sparse inverse (cuda): needs a factored solver in sparse mode");
        return NULL;
    }
    if (precision != PL_F64 && precision != PL_F32) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "sparse inverse (cuda): precision must be float64 or float32");
        return NULL;
    }
    pl_spinv_cuda *g = static_cast<pl_spinv_cuda *>(calloc(1, sizeof *g));
    if (!g) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cuda): out of memory");
        return NULL;
    }
    g->n = S->n;
    g->prec = precision;
    pl_spinv_cuda_layout L;
    int rc = spinv_cuda_layout_build(S, ST, (int)real_size(precision), group, item_blocks, &L,
                                        err);
    if (rc == PL_OK) {
        g->npad = L.npad;
        g->nitems_S = L.nitems_S, g->nitems_ST = L.nitems_ST;
        g->nparts_S = L.nparts_S, g->nparts_ST = L.nparts_ST;
        g->ntiles = L.ntiles, g->vc = L.vc, g->tile = L.tile, g->nval = L.nval;
        g->group = L.group, g->item_blocks = L.item_blocks;
        rc = upload_layout(g, &L, S, perm, sparse_inverse_parent(s), err);
        spinv_cuda_layout_free(&L);
    }
    /* bytes a step must read: the values of S, twice (S a, then S^T y) */
    g->bytes_step = 2.0 * (double)S->start[S->n] * (double)real_size(precision);
    if (rc == PL_OK) rc = spinv_cuda_small_setup(g, err);
    if (rc == PL_OK) rc = dev_alloc(g, (void **)&g->hb, (size_t)g->n * 3 * sizeof(double), err);
    if (rc == PL_OK) rc = dev_alloc(g, (void **)&g->hx, (size_t)g->n * 3 * sizeof(double), err);
    if (rc != PL_OK) {
        spinv_cuda_destroy(g);
        return NULL;
    }
    return g;
}

extern "C" void spinv_cuda_destroy(pl_spinv_cuda *g)
{
    if (!g) return;
    spinv_delassus_destroy(g->dl);
    void *ptrs[] = {g->perm, g->parent, g->val, g->meta, g->items_S, g->items_ST, g->short_rows, g->rowlist,
                    g->a, g->y4, g->part_S, g->part_ST, g->cnt_S, g->cnt_ST, g->hb, g->hx};
    for (void *p : ptrs)
        if (p) cudaFree(p);
    free(g);
}

extern "C" int spinv_cuda_solve(pl_spinv_cuda *g, const void *b, void *x, pl_precision io,
                                   struct CUstream_st *stream, pl_error *err)
{
    int rc = check_io(g, io, err);
    if (rc != PL_OK) return rc;
    if (!b || !x)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse (cuda): NULL block");
    g->last_b = b, g->last_x = x, g->last_io = io;
    cudaStream_t st = stream;
    if (g->small) return spinv_cuda_launch_small(g, b, x, io, st, err);
    if ((rc = spinv_cuda_launch_permute(g, b, io, g->perm, st, err))) return rc;
    if ((rc = spinv_cuda_launch_S(g, st, err))) return rc;
    return spinv_cuda_launch_ST(g, x, io, g->perm, st, err);
}

extern "C" int spinv_cuda_solve_host(pl_spinv_cuda *g, const double *b, double *x,
                                        struct CUstream_st *stream, pl_error *err)
{
    int rc = check_io(g, PL_F64, err);
    if (rc != PL_OK) return rc;
    size_t bytes = (size_t)g->n * 3 * sizeof(double);
    SPINV_CK(cudaMemcpyAsync(g->hb, b, bytes, cudaMemcpyHostToDevice, stream), "copy in");
    if ((rc = spinv_cuda_solve(g, g->hb, g->hx, PL_F64, stream, err))) return rc;
    SPINV_CK(cudaMemcpyAsync(x, g->hx, bytes, cudaMemcpyDeviceToHost, stream), "copy out");
    SPINV_CK(cudaStreamSynchronize(stream), "global step");
    return PL_OK;
}

extern "C" int pl_spinv_cuda_apply_S(pl_spinv_cuda *g, const void *x, void *y,
                                     struct CUstream_st *stream, pl_error *err)
{
    int rc = check_io(g, g ? g->prec : PL_F64, err);
    if (rc != PL_OK) return rc;
    if ((rc = spinv_cuda_launch_permute(g, x, g->prec, NULL, stream, err))) return rc;
    if ((rc = spinv_cuda_launch_S(g, stream, err))) return rc;
    return spinv_cuda_launch_from4(g, y, stream, err);
}

extern "C" int pl_spinv_cuda_apply_ST(pl_spinv_cuda *g, const void *x, void *y,
                                      struct CUstream_st *stream, pl_error *err)
{
    int rc = check_io(g, g ? g->prec : PL_F64, err);
    if (rc != PL_OK) return rc;
    if ((rc = spinv_cuda_launch_to4(g, x, stream, err))) return rc;
    return spinv_cuda_launch_ST(g, y, g->prec, NULL, stream, err);
}

extern "C" int spinv_cuda_run_stage(pl_spinv_cuda *g, pl_spinv_cuda_stage stage,
                                       struct CUstream_st *stream, pl_error *err)
{
    if (!g || !g->last_b)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse (cuda): run_stage before a solve");
    switch (stage) {
    case PL_SPINV_CUDA_STAGE_PERMUTE:
        return spinv_cuda_launch_permute(g, g->last_b, g->last_io, g->perm, stream, err);
    case PL_SPINV_CUDA_STAGE_S:
        return spinv_cuda_launch_S(g, stream, err);
    case PL_SPINV_CUDA_STAGE_ST:
        return spinv_cuda_launch_ST(g, g->last_x, g->last_io, g->perm, stream, err);
    }
    return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse (cuda): unknown stage");
}

extern "C" int spinv_cuda_size(const pl_spinv_cuda *g)
{
    return g ? g->n : 0;
}

extern "C" int spinv_cuda_single_block(const pl_spinv_cuda *g)
{
    return g ? g->small : 0;
}

extern "C" pl_precision spinv_cuda_precision(const pl_spinv_cuda *g)
{
    return g ? g->prec : PL_F64;
}

extern "C" double spinv_cuda_device_bytes(const pl_spinv_cuda *g)
{
    return g ? g->bytes_device : 0.0;
}

extern "C" double spinv_cuda_step_bytes(const pl_spinv_cuda *g)
{
    return g ? g->bytes_step : 0.0;
}

