/* spinv_cuda_buffers.c - the global solver role's solve(b, x) on pl_buffer
 * descriptors for SparseInverseSolver with device="cuda":
 *  - device blocks (PL_DEVICE, n x 3, float64 or float32, both alike): the
 *    global step is queued on the given stream (the scene's CudaDevice
 *    stream, or the legacy default stream) and not waited for; later work
 *    on that stream (or a blocking copy) sees x;
 *  - host float64 blocks: copied in, solved, copied out (returns with x
 *    written), so scenes work unchanged; blocks of k != 3 columns go to
 *    the CPU solver (the kernels take n x 3 blocks). */
#include "spinv_cuda_buffers.h"

int spinv_cuda_solve_buffers(pl_spinv_cuda *g, pl_sparse_inverse *cpu, const pl_buffer *b,
                                pl_buffer *x, struct CUstream_st *stream, pl_error *err)
{
    int n = spinv_cuda_size(g);
    if (!g || !b || !x)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "solve (cuda): no device copy of S");
    if (b->rows != (size_t)n || x->rows != (size_t)n || b->cols != x->cols || b->cols < 1)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "solve (cuda): expected two %d x k blocks, got %zu x %zu and %zu x %zu",
                            n, b->rows, b->cols, x->rows, x->cols);
    if (b->location != x->location || b->precision != x->precision)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "solve (cuda): b and x must live in one place with one precision");
    if (b->location == PL_DEVICE) {
        if (b->cols != 3)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "solve (cuda): device blocks must be n x 3, got n x %zu", b->cols);
        return spinv_cuda_solve(g, b->data, x->data, b->precision, stream, err);
    }
    double *bd = pl_buffer_f64(b), *xd = pl_buffer_f64(x);
    if (!bd || !xd)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "solve (cuda): host blocks must be float64");
    if (b->cols != 3) return sparse_inverse_solve(cpu, bd, xd, (int)b->cols, err);
    return spinv_cuda_solve_host(g, bd, xd, stream, err);
}
