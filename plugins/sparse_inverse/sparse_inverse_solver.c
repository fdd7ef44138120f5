/* sparse_inverse_solver.c - the SparseInverseSolver component: plays the
 * global solver role with the sparse inverse S = L^-1 (or CHOLMOD's own
 * solves in mode "direct"). */
#include "sparse_inverse.h"

#include <stddef.h>
#include <stdio.h>
#include "pliant/component.h"
#include "pliant/log.h"
#include "pliant/node.h"
#include "pliant/plugin.h"
#include "pliant/roles.h"
#include "pliant/timer.h"
#include "pliant/util.h"
#ifdef PLIANT_HAVE_CUDA
#include "cuda/spinv_cuda_buffers.h"
#endif

/* The fields are the same in every build (the scene format does not depend
 * on it); the CUDA code is compiled only with PLIANT_HAVE_CUDA, and without
 * it device="cuda" is an error at init and "auto" means the CPU. */
typedef struct sparse_inverse_solver {
    pl_component base;
    int ordering;              /* pl_spinv_ordering */
    int mode;                  /* pl_spinv_mode */
    int threads;
    int device;                /* 0 cpu, 1 cuda, 2 auto (cuda with a device service) */
    int precision;             /* 0 float64, 1 float32 (pl_precision) */
    pl_sparse_inverse *solver; /* built by factor */
#ifdef PLIANT_HAVE_CUDA
    pl_spinv_cuda *gpu;        /* device copy of S, built by factor when device = cuda */
    struct CUstream_st *stream; /* the scene's device stream (CudaDevice), or NULL */
#endif
} sparse_inverse_solver;

enum { DEVICE_CPU = 0, DEVICE_CUDA = 1, DEVICE_AUTO = 2 };

static const char *const ordering_choices[] = {"metis", "nesdis", "amd", "natural", NULL};
static const char *const mode_choices[] = {"sparse", "direct", NULL};
static const char *const device_choices[] = {"cpu", "cuda", "auto", NULL};
static const char *const precision_choices[] = {"float64", "float32", NULL};

static const pl_field solver_fields[] = {
    PL_FIELD_ENUM(sparse_inverse_solver, ordering, "ordering", ordering_choices, "metis",
                  "fill-reducing ordering of the Cholesky factor: metis, nesdis (CHOLMOD's nested "
                  "dissection), amd or natural; always followed by an etree postorder",
                  0),
    PL_FIELD_ENUM(sparse_inverse_solver, mode, "mode", mode_choices, "sparse",
                  "sparse: global step as S^T S b with the explicit S = L^-1; direct: CHOLMOD's "
                  "triangular solves (the CPU reference)",
                  0),
    PL_FIELD(sparse_inverse_solver, threads, "threads", PL_F_INT, "0",
             "OpenMP threads for the inverse and the products [count] (0 = OpenMP's default)", 0),
    PL_FIELD_ENUM(sparse_inverse_solver, device, "device", device_choices, "auto",
                  "where the global step runs: cpu, cuda (S copied to the GPU; mode sparse; work "
                  "queued on the stream of a CudaDevice in this node or above, if any), or auto "
                  "(cuda when there is such a CudaDevice and mode is sparse)",
                  0),
    PL_FIELD_ENUM(sparse_inverse_solver, precision, "precision", precision_choices, "float64",
                  "values and arithmetic of the device copy of S: float64 or float32 (device cuda)",
                  0),
};

static int solver_init(pl_component *c, pl_ctx *ctx)
{
    sparse_inverse_solver *s = (sparse_inverse_solver *)c;
    if (s->threads < 0)
        return pl_component_error(c, ctx, PL_EINPUT, "threads must be >= 0 (0 = default), got %d",
                                  s->threads);
#ifndef PLIANT_HAVE_CUDA
    if (s->device == DEVICE_CUDA)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "device=\"cuda\": this build has no CUDA (configured without "
                                  "nvcc); use device=\"cpu\" or \"auto\"");
#endif
    if (s->device == DEVICE_CUDA && s->mode != PL_SPINV_SPARSE)
        return pl_component_error(c, ctx, PL_EINPUT, "device cuda needs mode sparse");
    return PL_OK;
}

static void solver_destroy(pl_component *c)
{
    sparse_inverse_solver *s = (sparse_inverse_solver *)c;
    sparse_inverse_destroy(s->solver);
    s->solver = NULL;
#ifdef PLIANT_HAVE_CUDA
    spinv_cuda_destroy(s->gpu);
    s->gpu = NULL;
#endif
}

static void report(pl_component *c, const pl_spinv_stats *st, struct pl_timers *timers)
{
    const sparse_inverse_solver *s = (const sparse_inverse_solver *)c;
    const double mb = 1024.0 * 1024.0; /* MB = 2^20 bytes */
    char path[256];
    if (s->mode == PL_SPINV_SPARSE)
        pl_log_info("%s: %s ordering, n = %d, nnz(A) = %lld, nnz(L) = %lld, nnz(S) = %lld, "
                    "S %.1f MB + S^T %.1f MB (%lld runs), factor %.3f s, inverse %.3f s",
                    pl_component_path(c, path, sizeof path),
                    spinv_ordering_name((pl_spinv_ordering)s->ordering), st->n,
                    (long long)st->nnz_A, (long long)st->nnz_L, (long long)st->nnz_S,
                    st->bytes_S / mb, st->bytes_ST / mb, (long long)st->runs_ST, st->factor_s,
                    st->inverse_s);
    else
        pl_log_info("%s: %s ordering, direct mode, n = %d, nnz(A) = %lld, nnz(L) = %lld "
                    "(nnz(S) would be %lld), factor %.3f s",
                    pl_component_path(c, path, sizeof path),
                    spinv_ordering_name((pl_spinv_ordering)s->ordering), st->n,
                    (long long)st->nnz_A, (long long)st->nnz_L, (long long)st->nnz_S,
                    st->factor_s);
    if (!timers) return;
    pl_stat_set(timers, "nnz(A)", (double)st->nnz_A);
    pl_stat_set(timers, "nnz(L)", (double)st->nnz_L);
    pl_stat_set(timers, "nnz(S)", (double)st->nnz_S);
    pl_stat_set(timers, "S memory [MB]", (st->bytes_S + st->bytes_ST) / mb);
    pl_stat_set(timers, "factor [s]", st->factor_s);
    pl_stat_set(timers, "inverse [s]", st->inverse_s);
}

static int solver_factor(pl_component *c, const pl_csc *A, struct pl_timers *timers,
                         pl_error *err)
{
    sparse_inverse_solver *s = (sparse_inverse_solver *)c;
    pl_spinv_options opt = {(pl_spinv_ordering)s->ordering, (pl_spinv_mode)s->mode, s->threads};
    /* a new object picks up field changes (ordering, mode, threads) */
    sparse_inverse_destroy(s->solver);
    s->solver = sparse_inverse_create(&opt);
    if (!s->solver) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    pl_error e;
    int status = sparse_inverse_factor(s->solver, A, &e);
    if (status != PL_OK) return pl_component_fail(c, err, status, "%s", e.msg);
    report(c, sparse_inverse_stats(s->solver), timers);
#ifdef PLIANT_HAVE_CUDA
    spinv_cuda_destroy(s->gpu);
    s->gpu = NULL;
    pl_component *dev = pl_util_device(c), *svc = pl_node_find_role_up(c->node, PL_ROLE_DEVICE);
    if (s->device == DEVICE_CUDA && svc && !dev)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "device=\"cuda\": the device service %s has no device here (no "
                                 "GPU answers)",
                                 svc->name);
    const pl_device_ops *dops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
    s->stream = dops && dops->stream ? (struct CUstream_st *)dops->stream(dev) : NULL;
    if (s->device == DEVICE_CUDA || (s->device == DEVICE_AUTO && dev && s->mode == PL_SPINV_SPARSE)) {
        s->gpu = spinv_cuda_create(s->solver, s->precision == 1 ? PL_F32 : PL_F64, &e);
        if (!s->gpu) return pl_component_fail(c, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
        if (timers)
            pl_stat_set(timers, "S device memory [MB]",
                        spinv_cuda_device_bytes(s->gpu) / (1024.0 * 1024.0));
    }
#endif
    return PL_OK;
}

static int solver_solve(const pl_component *c, const pl_buffer *b, pl_buffer *x, pl_error *err)
{
    const sparse_inverse_solver *s = (const sparse_inverse_solver *)c;
    int n = sparse_inverse_size(s->solver);
    if (n == 0) return pl_component_fail(c, err, PL_EINPUT, "solve called before factor");
#ifdef PLIANT_HAVE_CUDA
    if (s->gpu) return spinv_cuda_solve_buffers(s->gpu, s->solver, b, x, s->stream, err);
#endif
    double *bd = pl_buffer_f64(b), *xd = pl_buffer_f64(x);
    if (!bd || !xd)
        return pl_component_fail(c, err, PL_EINPUT, "solve takes host float64 buffers");
    if (b->rows != (size_t)n || x->rows != (size_t)n || b->cols != x->cols || b->cols < 1 ||
        b->cols > 1024)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "solve: expected two %d x k blocks, got %zu x %zu and %zu x %zu",
                                 n, b->rows, b->cols, x->rows, x->cols);
    return sparse_inverse_solve(s->solver, bd, xd, (int)b->cols, err);
}

static int solver_apply_rows(const pl_component *c, const pl_csr *H, pl_csc *Y, pl_error *err)
{
    const sparse_inverse_solver *s = (const sparse_inverse_solver *)c;
    if (!s->solver) return pl_component_fail(c, err, PL_EINPUT, "rows applied before factor");
    return sparse_inverse_apply_inverse_to_rows(s->solver, H, Y, err);
}

static int solver_inverse_diagonal(const pl_component *c, double *diag, pl_error *err)
{
    const sparse_inverse_solver *s = (const sparse_inverse_solver *)c;
    if (!s->solver) return pl_component_fail(c, err, PL_EINPUT, "diagonal asked before factor");
    return sparse_inverse_inverse_diagonal(s->solver, diag, err);
}

static int solver_size(const pl_component *c)
{
    return sparse_inverse_size(((const sparse_inverse_solver *)c)->solver);
}

/* Host float64 blocks always; device blocks (float64 or float32) once S is
 * on the GPU. */
static int solver_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    if (where == PL_HOST) return prec == PL_F64;
#ifdef PLIANT_HAVE_CUDA
    const sparse_inverse_solver *s = (const sparse_inverse_solver *)c;
    return s->gpu && (prec == PL_F64 || prec == PL_F32);
#else
    (void)c;
    return 0;
#endif
}

#ifdef PLIANT_HAVE_CUDA
static int solver_delassus_device(const pl_component *c, const pl_csr *H, int m, double *W,
                                  double *diag, pl_error *err)
{
    const sparse_inverse_solver *s = (const sparse_inverse_solver *)c;
    if (!s->gpu) return pl_component_fail(c, err, PL_EINPUT, "delassus_device: S is not on a device");
    int st;
    if (m == 0) { /* prepare only (roles.h) */
        st = spinv_cuda_delassus_prepare(s->gpu, s->stream, err);
    } else {
        pl_spinv_cuda_rows R;
        st = spinv_cuda_rows_build(H, m, sparse_inverse_perm(s->solver), sparse_inverse_size(s->solver),
                                   &R, err);
        if (st == PL_OK) st = spinv_cuda_delassus(s->gpu, &R, W, diag, s->stream, err);
        spinv_cuda_rows_free(&R);
    }
    if (st == PL_OK) return PL_OK;
    char msg[sizeof err->msg];
    snprintf(msg, sizeof msg, "%s", err->msg);
    return pl_component_fail(c, err, st, "%s", msg);
}
#endif

static const pl_global_solver_ops solver_ops = {
    .version = PL_GLOBAL_SOLVER_OPS_VERSION,
    .factor = solver_factor,
    .solve = solver_solve,
    .apply_inverse_to_rows = solver_apply_rows,
    .inverse_diagonal = solver_inverse_diagonal,
    .size = solver_size,
    .accepts = solver_accepts,
#ifdef PLIANT_HAVE_CUDA
    .delassus_device = solver_delassus_device,
#endif
};

const pl_type pl_sparse_inverse_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "SparseInverseSolver",
    .help = "global step A^-1 b = P^T S^T S P b through the explicit sparse inverse S = L^-1 of "
            "the Cholesky factor (CHOLMOD, METIS)",
    .size = sizeof(sparse_inverse_solver),
    .fields = solver_fields,
    .nfields = (int)(sizeof solver_fields / sizeof solver_fields[0]),
    .ops = {.init = solver_init, .destroy = solver_destroy},
    .roles = {[PL_ROLE_GLOBAL_SOLVER] = &solver_ops},
};
