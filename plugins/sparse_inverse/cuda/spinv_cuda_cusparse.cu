/* spinv_cuda_cusparse.cu - the comparison path: S and S^T as CSR matrices
 * with 32-bit column indices, multiplied by cusparseSpMM on row-major n x 3
 * blocks (CUSPARSE_SPMM_CSR_ALG3 after cusparseSpMM_preprocess; the default
 * algorithm where CSR_ALG3 is refused). */
#include "spinv_cuda_internal.h"

#include <cusparse.h>
#include <stdlib.h>

struct spinv_cusparse {
    cusparseHandle_t h;
    cusparseSpMatDescr_t mat[2];  /* S, S^T */
    cusparseDnMatDescr_t dn[3];   /* a (= g->a, n x 3), y = S a, z = S^T y */
    int *ptr[2], *col[2];
    void *val[2], *y, *z, *buf[2];
    cusparseSpMMAlg_t alg[2];     /* per product: CSR_ALG3 or the default */
    cudaDataType type;
};

namespace {

int sp_fail(pl_error *err, cusparseStatus_t s, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cusparse): %s: %s", what,
                        cusparseGetErrorString(s));
}

#define SP_CK(call, what)                                         \
    do {                                                          \
        cusparseStatus_t sp_s_ = (call);                          \
        if (sp_s_ != CUSPARSE_STATUS_SUCCESS) return sp_fail(err, sp_s_, what); \
    } while (0)

/* CSR of S (rows first[i] .. i) or of S^T (the runs), values in T. */
template <typename T>
int build_csr(const pl_spinv_profile *S, const pl_spinv_runs *ST, int which, int **ptr, int **col,
              T **val)
{
    int n = S->n;
    int64_t nnz = S->start[n];
    *ptr = (int *)malloc(((size_t)n + 1) * sizeof(int));
    *col = (int *)malloc((size_t)nnz * sizeof(int));
    *val = (T *)malloc((size_t)nnz * sizeof(T));
    if (!*ptr || !*col || !*val) return -1;
    for (int i = 0; i <= n; ++i) (*ptr)[i] = (int)(which == 0 ? S->start[i] : ST->start[i]);
    for (int i = 0; i < n; ++i) {
        if (which == 0) {
            for (int64_t q = S->start[i]; q < S->start[i + 1]; ++q) {
                (*col)[q] = S->first[i] + (int)(q - S->start[i]);
                (*val)[q] = (T)S->val[q];
            }
        } else {
            int64_t q = ST->start[i];
            for (int64_t r = ST->run_ptr[i]; r < ST->run_ptr[i + 1]; ++r)
                for (int u = 0; u < ST->run_len[r]; ++u, ++q) {
                    (*col)[q] = ST->run_col[r] + u;
                    (*val)[q] = (T)ST->val[q];
                }
        }
    }
    return 0;
}

template <typename T>
int upload_csr(spinv_cusparse *sp, pl_spinv_cuda *g, const pl_spinv_profile *S,
               const pl_spinv_runs *ST, int which, pl_error *err)
{
    int n = S->n, *ptr = NULL, *col = NULL;
    int64_t nnz = S->start[n];
    T *val = NULL;
    int rc = build_csr<T>(S, ST, which, &ptr, &col, &val);
    cudaError_t e = cudaSuccess;
    if (rc == 0) {
        size_t bp = ((size_t)n + 1) * sizeof(int), bc = (size_t)nnz * sizeof(int),
               bv = (size_t)nnz * sizeof(T);
        if ((e = cudaMalloc((void **)&sp->ptr[which], bp)) == cudaSuccess &&
            (e = cudaMalloc((void **)&sp->col[which], bc)) == cudaSuccess &&
            (e = cudaMalloc(&sp->val[which], bv)) == cudaSuccess &&
            (e = cudaMemcpy(sp->ptr[which], ptr, bp, cudaMemcpyHostToDevice)) == cudaSuccess &&
            (e = cudaMemcpy(sp->col[which], col, bc, cudaMemcpyHostToDevice)) == cudaSuccess)
            e = cudaMemcpy(sp->val[which], val, bv, cudaMemcpyHostToDevice);
        g->bytes_device += (double)(bp + bc + bv);
    }
    free(ptr);
    free(col);
    free(val);
    if (rc != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cusparse): out of memory");
    if (e != cudaSuccess) return spinv_cuda_fail(err, e, "cuSPARSE upload");
    SP_CK(cusparseCreateCsr(&sp->mat[which], n, n, nnz, sp->ptr[which], sp->col[which],
                            sp->val[which], CUSPARSE_INDEX_32I, CUSPARSE_INDEX_32I,
                            CUSPARSE_INDEX_BASE_ZERO, sp->type),
          "cusparseCreateCsr");
    return PL_OK;
}

/* Work buffer and preprocessing of one product with algorithm alg. */
cusparseStatus_t try_alg(spinv_cusparse *sp, int which, cusparseSpMMAlg_t alg, cudaError_t *ce)
{
    double one64 = 1.0, zero64 = 0.0;
    float one32 = 1.0f, zero32 = 0.0f;
    const void *one = sp->type == CUDA_R_32F ? (const void *)&one32 : (const void *)&one64;
    const void *zero = sp->type == CUDA_R_32F ? (const void *)&zero32 : (const void *)&zero64;
    cusparseDnMatDescr_t in = sp->dn[which], out = sp->dn[which + 1];
    size_t bytes = 0;
    cusparseStatus_t s = cusparseSpMM_bufferSize(
        sp->h, CUSPARSE_OPERATION_NON_TRANSPOSE, CUSPARSE_OPERATION_NON_TRANSPOSE, one,
        sp->mat[which], in, zero, out, sp->type, alg, &bytes);
    if (s != CUSPARSE_STATUS_SUCCESS) return s;
    *ce = cudaMalloc(&sp->buf[which], bytes > 0 ? bytes : 16);
    if (*ce != cudaSuccess) return CUSPARSE_STATUS_ALLOC_FAILED;
    s = cusparseSpMM_preprocess(sp->h, CUSPARSE_OPERATION_NON_TRANSPOSE,
                                CUSPARSE_OPERATION_NON_TRANSPOSE, one, sp->mat[which], in, zero,
                                out, sp->type, alg, sp->buf[which]);
    if (s != CUSPARSE_STATUS_SUCCESS) {
        cudaFree(sp->buf[which]);
        sp->buf[which] = NULL;
    }
    return s;
}

/* CSR_ALG3 when cuSPARSE takes it for this product, else the default. */
int prepare(spinv_cusparse *sp, int which, pl_error *err)
{
    cudaError_t ce = cudaSuccess;
    sp->alg[which] = CUSPARSE_SPMM_CSR_ALG3;
    cusparseStatus_t s = try_alg(sp, which, sp->alg[which], &ce);
    if (s == CUSPARSE_STATUS_SUCCESS) return PL_OK;
    if (ce != cudaSuccess) return spinv_cuda_fail(err, ce, "cuSPARSE buffer");
    sp->alg[which] = CUSPARSE_SPMM_ALG_DEFAULT; /* refused: fall back (path_name says so) */
    s = try_alg(sp, which, sp->alg[which], &ce);
    if (ce != cudaSuccess) return spinv_cuda_fail(err, ce, "cuSPARSE buffer");
    return s == CUSPARSE_STATUS_SUCCESS ? PL_OK : sp_fail(err, s, "cusparseSpMM setup");
}

} // namespace

int spinv_cusparse_create(pl_spinv_cuda *g, const pl_spinv_profile *S, const pl_spinv_runs *ST,
                          pl_error *err)
{
    if (S->start[S->n] >= 0x7fffffff)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse (cusparse): nnz(S) needs 64-bit indices");
    spinv_cusparse *sp = (spinv_cusparse *)calloc(1, sizeof *sp);
    if (!sp)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cusparse): out of memory");
    g->sp = sp;
    sp->type = g->prec == PL_F32 ? CUDA_R_32F : CUDA_R_64F;
    sp->alg[0] = sp->alg[1] = CUSPARSE_SPMM_CSR_ALG3;
    SP_CK(cusparseCreate(&sp->h), "cusparseCreate");
    int rc = g->prec == PL_F32 ? upload_csr<float>(sp, g, S, ST, 0, err) : upload_csr<double>(sp, g, S, ST, 0, err);
    if (rc == PL_OK)
        rc = g->prec == PL_F32 ? upload_csr<float>(sp, g, S, ST, 1, err)
                               : upload_csr<double>(sp, g, S, ST, 1, err);
    if (rc != PL_OK) return rc;
    size_t rs = g->prec == PL_F32 ? 4 : 8, bytes = (size_t)g->n * 3 * rs;
    SPINV_CK(cudaMalloc(&sp->y, bytes), "cudaMalloc");
    SPINV_CK(cudaMalloc(&sp->z, bytes), "cudaMalloc");
    void *bufs[3] = {g->a, sp->y, sp->z};
    for (int k = 0; k < 3; ++k)
        SP_CK(cusparseCreateDnMat(&sp->dn[k], g->n, 3, 3, bufs[k], sp->type, CUSPARSE_ORDER_ROW),
              "cusparseCreateDnMat");
    if ((rc = prepare(sp, 0, err)) || (rc = prepare(sp, 1, err))) return rc;
    /* values and column indices of both matrices, read once each */
    g->bytes_step = 2.0 * (double)S->start[S->n] * (double)(rs + sizeof(int));
    return PL_OK;
}

void spinv_cusparse_destroy(spinv_cusparse *sp)
{
    if (!sp) return;
    for (int k = 0; k < 2; ++k) {
        if (sp->mat[k]) cusparseDestroySpMat(sp->mat[k]);
        cudaFree(sp->ptr[k]);
        cudaFree(sp->col[k]);
        cudaFree(sp->val[k]);
        cudaFree(sp->buf[k]);
    }
    for (int k = 0; k < 3; ++k)
        if (sp->dn[k]) cusparseDestroyDnMat(sp->dn[k]);
    cudaFree(sp->y);
    cudaFree(sp->z);
    if (sp->h) cusparseDestroy(sp->h);
    free(sp);
}

int spinv_cusparse_mult(pl_spinv_cuda *g, int which, cudaStream_t st, pl_error *err)
{
    spinv_cusparse *sp = g->sp;
    double one64 = 1.0, zero64 = 0.0;
    float one32 = 1.0f, zero32 = 0.0f;
    const void *one = sp->type == CUDA_R_32F ? (const void *)&one32 : (const void *)&one64;
    const void *zero = sp->type == CUDA_R_32F ? (const void *)&zero32 : (const void *)&zero64;
    SP_CK(cusparseSetStream(sp->h, st), "cusparseSetStream");
    SP_CK(cusparseSpMM(sp->h, CUSPARSE_OPERATION_NON_TRANSPOSE, CUSPARSE_OPERATION_NON_TRANSPOSE, one,
                       sp->mat[which], sp->dn[which], zero, sp->dn[which + 1], sp->type, sp->alg[which],
                       sp->buf[which]),
          "cusparseSpMM");
    return PL_OK;
}

void *spinv_cusparse_y(spinv_cusparse *sp)
{
    return sp->y;
}

void *spinv_cusparse_z(spinv_cusparse *sp)
{
    return sp->z;
}

const char *spinv_cusparse_alg(const spinv_cusparse *sp)
{
    if (!sp) return "cusparse";
    int a3 = (sp->alg[0] == CUSPARSE_SPMM_CSR_ALG3) + (sp->alg[1] == CUSPARSE_SPMM_CSR_ALG3);
    return a3 == 2 ? "cusparse CSR_ALG3" : a3 == 1 ? "cusparse CSR_ALG3 + DEFAULT" : "cusparse DEFAULT";
}
