/* spinv_cuda_delassus.cu - the Delassus operator W = H A^-1 H^T built on
 * the device (see spinv_cuda_delassus in spinv_cuda.h).
 *
 * A^-1 = P^T S^T S P, so between two unknowns a and b, [A^-1]_ab is the dot
 * product of the columns P a and P b of S.  The rows of one step touch few
 * unknowns (nu; a contact row at most 4): their columns of S go into a dense
 * n x nu block Y (the profile layout gives S(i, c) without a search), one
 * cuBLAS SYRK forms G = Y^T Y = A^-1 on those unknowns (the product that
 * costs: n nu^2 multiply-adds, on the tensor cores), and a last kernel sums
 * W_ij = sum_k sum_{a in row i} sum_{b in row j} h_ka h_kb G_ab with one
 * thread per entry of the lower triangle, which writes W_ij and W_ji from
 * one sum (bitwise symmetric, deterministic); the entries of a row with
 * many entries (a cable's) take a block each.  Buffers are kept between
 * steps and grow by half.  With W NULL only the diagonal is made, along the
 * etree paths (spinv_cuda_wdiag.cu): a matrix-free W's scaling. */
#include "spinv_cuda_internal.h"

#include <cublas_v2.h>
#include <stdlib.h>
#include <string.h>

struct spinv_delassus {
    cublasHandle_t blas;
    double *Y, *G, *diag;
    size_t Y_cap, G_cap, diag_cap;
    char *in;   /* pos, rp, ru, rx packed */
    size_t in_cap;
    char *h_in; /* page-locked staging of the same */
    size_t h_in_cap;
    int prepared; /* spinv_cuda_delassus_prepare ran */
};

namespace {

int blas_fail(pl_error *err, cublasStatus_t s, const char *what)
{
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse (cuda): %s: cuBLAS status %d",
                        what, (int)s);
}

/* Device memory of at least `bytes` in *p (capacity *cap). */
int grow(void **p, size_t *cap, size_t bytes, pl_error *err)
{
    if (*p && bytes <= *cap) return PL_OK;
    if (*p) SPINV_CK(cudaFree(*p), "cudaFree");
    *p = NULL;
    *cap = bytes + bytes / 2 + 256;
    SPINV_CK(cudaMalloc(p, *cap), "cudaMalloc (Delassus)");
    return PL_OK;
}

int grow_host(void **p, size_t *cap, size_t bytes, pl_error *err)
{
    if (*p && bytes <= *cap) return PL_OK;
    if (*p) SPINV_CK(cudaFreeHost(*p), "cudaFreeHost");
    *p = NULL;
    *cap = bytes + bytes / 2 + 256;
    SPINV_CK(cudaMallocHost(p, *cap), "cudaMallocHost (Delassus)");
    return PL_OK;
}

/* Y(i, u) = S(i, pos[u]) (column-major, n x nup, float64); the columns
 * u >= nu (the order's padding, syrk_order) are zero. */
template <typename T>
__global__ void gather_columns(int n, int nu, int nup, const pl_spinv_cuda_rowmeta *meta,
                               const T *val, const int *pos, double *Y)
{
    size_t total = (size_t)n * (size_t)nup;
    for (size_t t = blockIdx.x * (size_t)blockDim.x + threadIdx.x; t < total;
         t += (size_t)gridDim.x * blockDim.x) {
        int i = (int)(t % (size_t)n), u = (int)(t / (size_t)n), c = u < nu ? pos[u] : -1;
        pl_spinv_cuda_rowmeta r = meta[i];
        /* columns f0 .. e are stored (zero past the diagonal) */
        Y[t] = c >= r.f0 && c <= r.e ? (double)val[r.vbase + c] : 0.0;
    }
}

/* A row of more entries than this (over its three components) is long: a
 * cable's or a cavity's mapped points, not a contact's (at most 12 between
 * two meshes; up to 48 where a face's corners are mapped into tetrahedra,
 * 4 vertices each, as on the soft fingers).  An entry W_ij sums
 * len_i x len_j products per component in one thread's chain of dependent
 * loads: 507 for two mapped contacts, but 9408 for two cable rows of 56
 * vertex entries a component (about 280 us on the H100, the whole
 * assembly's time for the small raptor).  So an entry with a long row is
 * summed by a block (assemble_w_long).  Set so that only such rows are
 * long: with 16, the small raptor's mapped contacts (hundreds of rows)
 * made hundreds of thousands of blocks, 190 us a step. */
constexpr int kLongEntries = 64;

__host__ __device__ __forceinline__ int row_len(const int *rp, int m, int i)
{
    return rp[i + 1] - rp[i] + rp[m + i + 1] - rp[m + i] + rp[2 * m + i + 1] - rp[2 * m + i];
}

/* W_ij = W_ji for j <= i from G (lower triangle, column-major nu x nu),
 * one thread an entry; the entries with a long row are assemble_w_long's. */
__global__ void assemble_w(int m, int nu, const int *rp, const int *ru, const double *rx,
                           const double *G, double *W, double *diag)
{
    size_t total = (size_t)m * (size_t)m;
    for (size_t t = blockIdx.x * (size_t)blockDim.x + threadIdx.x; t < total;
         t += (size_t)gridDim.x * blockDim.x) {
        int i = (int)(t / (size_t)m), j = (int)(t % (size_t)m);
        if (j > i) continue;
        if (row_len(rp, m, i) > kLongEntries || row_len(rp, m, j) > kLongEntries) continue;
        double s = 0.0;
        for (int k = 0; k < 3; ++k) {
            int ri = k * m + i, rj = k * m + j;
            for (int p = rp[ri]; p < rp[ri + 1]; ++p)
                for (int q = rp[rj]; q < rp[rj + 1]; ++q) {
                    int a = ru[p], b = ru[q];
                    int hi = a > b ? a : b, lo = a > b ? b : a;
                    s += rx[p] * rx[q] * G[(size_t)lo * nu + hi];
                }
        }
        W[(size_t)i * m + j] = s;
        W[(size_t)j * m + i] = s;
        if (i == j) diag[i] = s;
    }
}

/* The entries W_aj = W_ja of the long rows a = longr[l] (nl of them), one
 * block of kLongThreads an entry (l, j): its threads take the components'
 * products (entry p of row a, q of row j) in turn, and their partial sums
 * meet by a fixed tree (shuffles, then the warps' sums in order:
 * deterministic).  A pair of long rows a < b is summed once, by the block
 * (b, a): the block (a, b) returns. */
constexpr int kLongThreads = 256;

__global__ void __launch_bounds__(kLongThreads)
    assemble_w_long(int m, int nu, const int *longr, const int *rp, const int *ru,
                    const double *rx, const double *G, double *W, double *diag)
{
    __shared__ double part[kLongThreads / 32];
    const int a = longr[blockIdx.x / m], j = (int)(blockIdx.x % m), tid = threadIdx.x;
    if (j > a && row_len(rp, m, j) > kLongEntries) return; /* the whole block */
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        const int pa = rp[k * m + a], la = rp[k * m + a + 1] - pa;
        const int pj = rp[k * m + j], lj = rp[k * m + j + 1] - pj;
        for (int t = tid; t < la * lj; t += kLongThreads) {
            const int p = pa + t / lj, q = pj + t % lj;
            const int u = ru[p], v = ru[q];
            const int hi = u > v ? u : v, lo = u > v ? v : u;
            s += rx[p] * rx[q] * G[(size_t)lo * nu + hi];
        }
    }
    for (int o = 16; o > 0; o >>= 1) s += __shfl_down_sync(0xffffffffu, s, o);
    if ((tid & 31) == 0) part[tid >> 5] = s;
    __syncthreads();
    if (tid == 0) {
        s = part[0];
        for (int w = 1; w < kLongThreads / 32; ++w) s += part[w];
        W[(size_t)a * m + j] = s;
        W[(size_t)j * m + a] = s;
        if (a == j) diag[a] = s;
    }
}

int blocks_for(size_t total)
{
    size_t b = (total + 255) / 256;
    return (int)(b < 4096 ? (b > 0 ? b : 1) : 4096);
}

size_t align16(size_t b)
{
    return (b + 15) & ~(size_t)15;
}

} // namespace

extern "C" void spinv_delassus_destroy(struct spinv_delassus *d)
{
    if (!d) return;
    if (d->blas) cublasDestroy(d->blas);
    void *p[] = {d->Y, d->G, d->diag, d->in};
    for (void *q : p)
        if (q) cudaFree(q);
    if (d->h_in) cudaFreeHost(d->h_in);
    free(d);
}

/* g->dl with its cuBLAS handle, made on first use. */
static int delassus_state(pl_spinv_cuda *g, pl_error *err)
{
    if (g->dl) return PL_OK;
    g->dl = (struct spinv_delassus *)calloc(1, sizeof *g->dl);
    if (!g->dl) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    cublasStatus_t s = cublasCreate(&g->dl->blas);
    if (s != CUBLAS_STATUS_SUCCESS) {
        g->dl->blas = NULL;
        return blas_fail(err, s, "cublasCreate");
    }
    return PL_OK;
}

/* The SYRK's order for nu unknowns: nu rounded up to a multiple of 32, of
 * an eighth of the power of two below it past 256 (zero columns of Y).
 * cuBLAS plans a SYRK on the host for each new shape: the contacts' nu
 * changes nearly every step, and the small raptor's steps spent about 110
 * us of host time in cublasDsyrk before its kernel started (a gap in the
 * GPU's timeline); a few orders keep its plans (docs/benchmarks.md, "The
 * Delassus SYRK's order").  PLIANT_SPINV_SYRK_PAD=0: nu itself. */
static int syrk_order(int nu)
{
    static int pad = -1;
    if (pad < 0) {
        const char *e = getenv("PLIANT_SPINV_SYRK_PAD");
        pad = !(e && !strcmp(e, "0"));
    }
    if (!pad || nu <= 0) return nu;
    int q = 32;
    while (q * 16 <= nu) q *= 2; /* nu >= 512: q = 64, >= 1024: 128, ... */
    return (nu + q - 1) / q * q;
}

/* SYRKs of this solver's inner size n and a few orders nu (cuBLAS picks its
 * kernel by size, and each is loaded on its first use) and an empty
 * assemble_w: what the first real calls would load is loaded here. */
extern "C" int spinv_cuda_delassus_prepare(pl_spinv_cuda *g, struct CUstream_st *stream, pl_error *err)
{
    int rc = delassus_state(g, err);
    if (rc || g->dl->prepared) return rc;
    struct spinv_delassus *d = g->dl;
    cudaStream_t st = stream;
    const int orders[] = {syrk_order(12), syrk_order(96)};
    int n = g->n > 0 ? g->n : 1, top = orders[1];
    rc = grow((void **)&d->Y, &d->Y_cap, sizeof(double) * (size_t)n * top, err);
    if (!rc) rc = grow((void **)&d->G, &d->G_cap, sizeof(double) * (size_t)top * top, err);
    if (rc) return rc;
    SPINV_CK(cudaMemsetAsync(d->Y, 0, sizeof(double) * (size_t)n * top, st), "Delassus prepare: zero Y");
    const double one = 1.0, zero = 0.0;
    cublasStatus_t s = cublasSetStream(d->blas, st);
    for (int k = 0; k < 2 && s == CUBLAS_STATUS_SUCCESS; ++k)
        s = cublasDsyrk(d->blas, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, orders[k], n, &one, d->Y, n, &zero,
                        d->G, orders[k]);
    if (s != CUBLAS_STATUS_SUCCESS) return blas_fail(err, s, "Delassus prepare: SYRK");
    assemble_w<<<1, 32, 0, st>>>(0, 0, NULL, NULL, NULL, d->G, NULL, NULL);
    SPINV_CK(cudaGetLastError(), "Delassus prepare: assemble W");
    pl_spinv_cuda_drows none = {0, 0, NULL, NULL, NULL, NULL, 0, NULL};
    if ((rc = spinv_cuda_launch_wdiag(g, &none, d->G, st, err))) return rc;
    SPINV_CK(cudaStreamSynchronize(st), "Delassus prepare: wait");
    d->prepared = 1;
    return PL_OK;
}

/* Row i has more than kLongEntries entries (its three components'). */
static int is_long(const pl_spinv_cuda_rows *R, int i)
{
    return row_len(R->rp, R->m, i) > kLongEntries;
}

/* The rows into d->in (pos, rp, ru, rx and the long rows' indices packed,
 * through the page-locked staging buffer), queued on st; the device
 * pointers into *A. */
static int upload_rows(struct spinv_delassus *d, const pl_spinv_cuda_rows *R, cudaStream_t st,
                       pl_spinv_cuda_drows *A, pl_error *err)
{
    int m = R->m, nu = R->nu, nl = 0;
    size_t nent = (size_t)R->rp[3 * m];
    for (int i = 0; i < m; ++i) nl += is_long(R, i); /* assemble_w_long's rows */
    size_t b_pos = align16(sizeof(int) * (size_t)nu), b_rp = align16(sizeof(int) * (3 * (size_t)m + 1)),
           b_ru = align16(sizeof(int) * nent), b_rx = align16(sizeof(double) * nent),
           b_long = sizeof(int) * (size_t)nl;
    size_t bytes = b_pos + b_rp + b_ru + b_rx + b_long;
    int rc = grow((void **)&d->in, &d->in_cap, bytes, err);
    if (!rc) rc = grow_host((void **)&d->h_in, &d->h_in_cap, bytes, err);
    if (!rc) rc = grow((void **)&d->diag, &d->diag_cap, sizeof(double) * (size_t)m, err);
    if (rc) return rc;
    /* the staging buffer may still feed the last step's copy */
    SPINV_CK(cudaStreamSynchronize(st), "Delassus: wait for the stream");
    char *h = d->h_in;
    memcpy(h, R->pos, sizeof(int) * (size_t)nu);
    memcpy(h + b_pos, R->rp, sizeof(int) * (3 * (size_t)m + 1));
    memcpy(h + b_pos + b_rp, R->ru, sizeof(int) * nent);
    memcpy(h + b_pos + b_rp + b_ru, R->rx, sizeof(double) * nent);
    int *hl = (int *)(h + b_pos + b_rp + b_ru + b_rx);
    for (int i = 0, l = 0; i < m; ++i)
        if (is_long(R, i)) hl[l++] = i;
    SPINV_CK(cudaMemcpyAsync(d->in, h, bytes, cudaMemcpyHostToDevice, st), "Delassus: upload rows");
    A->m = m, A->nu = nu;
    A->pos = (const int *)d->in;
    A->rp = (const int *)(d->in + b_pos);
    A->ru = (const int *)(d->in + b_pos + b_rp);
    A->rx = (const double *)(d->in + b_pos + b_rp + b_ru);
    A->nl = nl;
    A->longr = (const int *)(d->in + b_pos + b_rp + b_ru + b_rx);
    return PL_OK;
}

extern "C" int spinv_cuda_delassus(pl_spinv_cuda *g, const pl_spinv_cuda_rows *R, double *W,
                                      double *diag_host, struct CUstream_st *stream, pl_error *err)
{
    int n = g->n, m = R->m, nu = R->nu;
    if (m <= 0) return PL_OK;
    int rc = delassus_state(g, err);
    if (rc) return rc;
    struct spinv_delassus *d = g->dl;
    cudaStream_t st = stream;
    pl_spinv_cuda_drows A;
    if ((rc = upload_rows(d, R, st, &A, err))) return rc;
    if (!W) { /* the diagonal alone, along the etree paths (spinv_cuda_wdiag.cu) */
        if ((rc = spinv_cuda_launch_wdiag(g, &A, d->diag, st, err))) return rc;
    } else {
        const int nup = syrk_order(nu); /* G's order and leading dimension */
        rc = grow((void **)&d->Y, &d->Y_cap, sizeof(double) * (size_t)n * (size_t)(nup > 0 ? nup : 1), err);
        if (!rc) rc = grow((void **)&d->G, &d->G_cap, sizeof(double) * (size_t)nup * (size_t)(nup > 0 ? nup : 1), err);
        if (rc) return rc;
        size_t ny = (size_t)n * (size_t)nup;
        if (g->prec == PL_F32)
            gather_columns<float><<<blocks_for(ny), 256, 0, st>>>(n, nu, nup, g->meta, (const float *)g->val, A.pos, d->Y);
        else
            gather_columns<double><<<blocks_for(ny), 256, 0, st>>>(n, nu, nup, g->meta, (const double *)g->val, A.pos, d->Y);
        SPINV_CK(cudaGetLastError(), "Delassus: gather columns");
        cublasStatus_t s = cublasSetStream(d->blas, st);
        const double one = 1.0, zero = 0.0;
        /* G = Y^T Y, lower triangle (column-major nup x nup) */
        if (s == CUBLAS_STATUS_SUCCESS)
            s = cublasDsyrk(d->blas, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, nup, n, &one, d->Y, n, &zero, d->G, nup);
        if (s != CUBLAS_STATUS_SUCCESS) return blas_fail(err, s, "Delassus: SYRK");
        size_t mm = (size_t)m * (size_t)m;
        assemble_w<<<blocks_for(mm), 256, 0, st>>>(m, nup, A.rp, A.ru, A.rx, d->G, W, d->diag);
        SPINV_CK(cudaGetLastError(), "Delassus: assemble W");
        if (A.nl > 0) {
            assemble_w_long<<<(unsigned)A.nl * (unsigned)m, kLongThreads, 0, st>>>(
                m, nup, A.longr, A.rp, A.ru, A.rx, d->G, W, d->diag);
            SPINV_CK(cudaGetLastError(), "Delassus: assemble W (long rows)");
        }
    }
    SPINV_CK(cudaMemcpyAsync(diag_host, d->diag, sizeof(double) * (size_t)m, cudaMemcpyDeviceToHost, st),
             "Delassus: diagonal down");
    SPINV_CK(cudaStreamSynchronize(st), "Delassus: wait");
    return PL_OK;
}
