/* cuda_kernels.h - the vector kernels of the device service (cuda_kernels.cu),
 * launched on a given stream; float64 n x 3 row-major device blocks.
 * Each returns the launch's cudaError_t as an int (0: queued). */
#ifndef PLIANT_CUDA_KERNELS_H
#define PLIANT_CUDA_KERNELS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct CUstream_st;

/* y[i] = s[i] x[i], i < n */
int cuda_scale_rows(struct CUstream_st *st, int n, const double *s, const double *x, double *y);
/* y[f] = x[map[f]], f < m */
int cuda_gather_rows(struct CUstream_st *st, int m, const int *map, const double *x, double *y);
/* x[map[f]] = y[f], f < m; *change = max(*change, max |x_new - x_old|), +inf if not finite */
int cuda_scatter_rows(struct CUstream_st *st, int m, const int *map, const double *y,
                         double *x, double *change);
/* y[r] -= A(r, j) x[j] for the entries of row r in order, r < nrows (CSR p, j, a) */
int cuda_sub_csr(struct CUstream_st *st, int nrows, const int *p, const int *j, const double *a,
                    const double *x, double *y);
/* y[f] = x[map[f]] - sum over row f's entries of A(f, j) q[j], in entry
 * order, f < m (p NULL: no A) */
int cuda_gather_sub_csr(struct CUstream_st *st, int m, const int *map, const double *x,
                        const int *p, const int *j, const double *a, const double *q, double *y);
/* *out = max(*out, max over f < m of |s[v] (x[v] - y[v]) / h2 + g[v] + t[f] / h2|),
 * v = map[f] (t NULL: no t term), +inf if one is not finite */
int cuda_residual_max(struct CUstream_st *st, int m, const int *map, const double *s, double h2,
                      const double *x, const double *y, const double *g, const double *t,
                      double *out);

/* cuda_residual_max with t[f] = b[map[f]] - the sum over row f's entries of
 * A(f, j) x[j], in entry order (cuda_gather_sub_csr's values; p NULL: no A),
 * in one launch */
int cuda_residual_max_csr(struct CUstream_st *st, int m, const int *map, const double *s,
                          double h2, const double *x, const double *y, const double *g,
                          const double *b, const int *p, const int *j, const double *a,
                          double *out);
/* cuda_scale_rows, and bytes (a multiple of 8) at z zeroed, in one launch */
int cuda_scale_rows_zero(struct CUstream_st *st, int n, const double *s, const double *x,
                         double *y, void *z, size_t bytes);

/* A time step's start: q_t = x, sn = x + h v + h^2 g (first_order: x + h g),
 * q = guess ? x + hv v : sn, i < n3, without fused multiply-adds (the host's
 * pl_dynamics_begin, bitwise) */
int cuda_step_begin(struct CUstream_st *st, int n3, double h, int first_order, int guess,
                    double hv, const double *x, const double *v, const double *g, double *q_t,
                    double *sn, double *q);
/* Its end: v = scale (q - q_t) / h, x = q, i < n3 (pl_dynamics_scatter,
 * bitwise); *bad = 1 where a q is not finite */
int cuda_step_end(struct CUstream_st *st, int n3, double h, double scale, const double *q,
                  const double *q_t, double *x, double *v, int *bad);

#ifdef __cplusplus
}
#endif
#endif
