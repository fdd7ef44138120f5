/* cuda_device_ops.c - CudaDevice's backend in a CUDA build: the GPU and
 * its stream (open/close), and pl_device_ops: memory, copies and kernels
 * queued on the component's stream, and CUDA graphs captured from it
 * (thread-local capture mode: other threads may keep using CUDA). */
#include <stdint.h>
#include <stdlib.h>

#include <cuda_runtime_api.h>

#include "cuda_device.h"
#include "cuda_kernels.h"
#include "cuda_loop.h"

#define DEV(c) ((cuda_device *)(c))
#define STREAM(c) current_stream(c)

/* pl_device_ops.branch's state: side streams made on first use (blocking,
 * as the main one: a term's first project uploads its elements with
 * cudaMemcpy on the legacy default stream), an event on the main stream
 * that opens the branches, one a side stream that closes it, and which
 * side streams the open branches have joined. */
struct cuda_branches {
    cudaStream_t side[PL_DEVICE_BRANCHES + 1]; /* [k], k >= 1 */
    cudaEvent_t done[PL_DEVICE_BRANCHES + 1];
    cudaEvent_t fork;
    int cur;         /* 0: the main stream */
    unsigned joined; /* bit k: side k waits for fork (none: fork not recorded yet) */
};

static cudaStream_t current_stream(const pl_component *c)
{
    const struct cuda_branches *b = DEV(c)->branches;
    return b && b->cur > 0 ? b->side[b->cur] : (cudaStream_t)DEV(c)->stream;
}

/* Fills err from a failed CUDA call about c; returns PL_EINTERNAL. */
static int cuda_fail(const pl_component *c, pl_error *err, cudaError_t e, const char *what)
{
    /* reported here: later cudaGetLastError() calls of other components must
     * not see it again (a sticky error stays anyway) */
    cudaGetLastError();
    return pl_component_fail(c, err, PL_EINTERNAL, "%s: %s (%s)", what, cudaGetErrorString(e),
                             cudaGetErrorName(e));
}

#define CK(c, call, what)                                              \
    do {                                                               \
        cudaError_t ck_ = (call);                                      \
        if (ck_ != cudaSuccess) return cuda_fail(c, err, ck_, what); \
    } while (0)

int cuda_device_open(cuda_device *d, pl_ctx *ctx)
{
    pl_component *c = &d->base;
    int count = 0;
    cudaError_t e = cudaGetDeviceCount(&count);
    if (e != cudaSuccess || count == 0) {
        cudaGetLastError();
        if (!d->absent)
            pl_component_warn(c, ctx, "no CUDA device usable here (%s): the scene runs on the CPU",
                              e != cudaSuccess ? cudaGetErrorString(e) : "none found");
        d->absent = 1;
        return PL_OK;
    }
    if (d->index < 0 || d->index >= count)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "device: %d is not a CUDA device ordinal (this machine has %d: "
                                  "0 .. %d)",
                                  d->index, count, count - 1);
    struct cudaDeviceProp prop;
    e = cudaSetDevice(d->index);
    if (e == cudaSuccess) e = cudaGetDeviceProperties(&prop, d->index);
    /* a blocking stream: work on the legacy default stream (host copies of
     * components that do not know the device) still orders with it */
    int first = !d->stream; /* the loader may have tried an implicit device already */
    cudaStream_t st = NULL;
    if (e == cudaSuccess && first && (e = cudaStreamCreate(&st)) == cudaSuccess) d->stream = st;
    if (e != cudaSuccess)
        return pl_component_error(c, ctx, PL_EINTERNAL, "CUDA device %d: %s", d->index,
                                  cudaGetErrorString(e));
    d->absent = 0;
    d->loops = cuda_loop_supported();
    if (!d->branches && !(d->branches = calloc(1, sizeof *d->branches)))
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (first)
        pl_log_info("%s: CUDA device %d, %s, %d SMs, %.1f GiB, compute capability %d.%d%s%s", c->name,
                    d->index, prop.name, prop.multiProcessorCount,
                    (double)prop.totalGlobalMem / (1024.0 * 1024.0 * 1024.0), prop.major, prop.minor,
                    d->graph && !d->profile ? ", CUDA graphs" : "", d->profile ? ", profiling" : "");
    return PL_OK;
}

void cuda_device_close(cuda_device *d)
{
    struct cuda_branches *b = d->branches;
    if (b) {
        for (int k = 1; k <= PL_DEVICE_BRANCHES; ++k) {
            if (b->side[k]) cudaStreamSynchronize(b->side[k]), cudaStreamDestroy(b->side[k]);
            if (b->done[k]) cudaEventDestroy(b->done[k]);
        }
        if (b->fork) cudaEventDestroy(b->fork);
        free(b);
        d->branches = NULL;
    }
    if (!d->stream) return;
    cudaStreamSynchronize((cudaStream_t)d->stream);
    cudaStreamDestroy((cudaStream_t)d->stream);
    d->stream = NULL;
}

static int dev_flags(const pl_component *c)
{
    const cuda_device *d = (const cuda_device *)c;
    if (d->absent) return PL_DEVICE_ABSENT;
    if (d->profile) return PL_DEVICE_PROFILE;
    return d->graph ? PL_DEVICE_GRAPHS | (d->loops ? PL_DEVICE_LOOPS : 0) : 0;
}

static void *dev_stream(const pl_component *c)
{
    return current_stream(c);
}

/* Opens branch k (>= 1): its side stream waits for the main stream's work
 * queued so far (one fork event for all the branches opened together);
 * k = 0 closes them: the main stream waits for each one's work. */
static int dev_branch(pl_component *c, int k, pl_error *err)
{
    struct cuda_branches *b = DEV(c)->branches;
    cudaStream_t main = (cudaStream_t)DEV(c)->stream;
    if (!b || k < 0 || k > PL_DEVICE_BRANCHES)
        return pl_component_fail(c, err, PL_EINPUT, "branch %d: 0 .. %d, on an open device", k,
                                 PL_DEVICE_BRANCHES);
    if (k == 0) {
        b->cur = 0;
        for (int j = 1; j <= PL_DEVICE_BRANCHES; ++j)
            if (b->joined & (1u << j)) {
                CK(c, cudaEventRecord(b->done[j], b->side[j]), "cudaEventRecord (branch)");
                CK(c, cudaStreamWaitEvent(main, b->done[j], 0), "cudaStreamWaitEvent (join)");
            }
        b->joined = 0;
        return PL_OK;
    }
    if (!b->side[k]) {
        CK(c, cudaStreamCreate(&b->side[k]), "cudaStreamCreate");
        CK(c, cudaEventCreateWithFlags(&b->done[k], cudaEventDisableTiming), "cudaEventCreate");
    }
    if (!b->fork)
        CK(c, cudaEventCreateWithFlags(&b->fork, cudaEventDisableTiming), "cudaEventCreate");
    if (!b->joined) CK(c, cudaEventRecord(b->fork, main), "cudaEventRecord (fork)");
    if (!(b->joined & (1u << k))) {
        CK(c, cudaStreamWaitEvent(b->side[k], b->fork, 0), "cudaStreamWaitEvent (fork)");
        b->joined |= 1u << k;
    }
    b->cur = k;
    return PL_OK;
}

static void *dev_alloc(pl_component *c, size_t bytes, pl_error *err)
{
    void *p = NULL;
    cudaError_t e = cudaMalloc(&p, bytes ? bytes : 1);
    if (e != cudaSuccess) {
        cuda_fail(c, err, e, "cudaMalloc");
        return NULL;
    }
    if (DEV(c)->live) ++*DEV(c)->live;
    return p;
}

static void dev_free(pl_component *c, void *p)
{
    if (!p) return;
    cudaFree(p);
    if (DEV(c)->live) --*DEV(c)->live;
}

static int dev_zero(pl_component *c, void *p, size_t bytes, pl_error *err)
{
    CK(c, cudaMemsetAsync(p, 0, bytes, STREAM(c)), "cudaMemsetAsync");
    return PL_OK;
}

static int dev_copy(pl_component *c, void *dst, pl_location to, const void *src, pl_location from,
                    size_t bytes, pl_error *err)
{
    enum cudaMemcpyKind kind = to == PL_HOST ? (from == PL_HOST ? cudaMemcpyHostToHost
                                                                 : cudaMemcpyDeviceToHost)
                                             : (from == PL_HOST ? cudaMemcpyHostToDevice
                                                                 : cudaMemcpyDeviceToDevice);
    if (bytes == 0) return PL_OK;
    CK(c, cudaMemcpyAsync(dst, src, bytes, kind, STREAM(c)), "cudaMemcpyAsync");
    if (to == PL_HOST) CK(c, cudaStreamSynchronize(STREAM(c)), "copy to the host");
    return PL_OK;
}

static int dev_pin(pl_component *c, void *host, size_t bytes, pl_error *err)
{
    if (!host || bytes == 0) return PL_OK;
    CK(c, cudaHostRegister(host, bytes, cudaHostRegisterDefault), "cudaHostRegister");
    return PL_OK;
}

static void dev_unpin(pl_component *c, void *host)
{
    (void)c;
    if (host) cudaHostUnregister(host);
}

static int dev_sync(pl_component *c, pl_error *err)
{
    CK(c, cudaStreamSynchronize(STREAM(c)), "device work");
    return PL_OK;
}

static int launched(pl_component *c, int code, const char *what, pl_error *err)
{
    return code ? cuda_fail(c, err, (cudaError_t)code, what) : PL_OK;
}

static int dev_scale_rows(pl_component *c, int n, const double *s, const double *x, double *y,
                          pl_error *err)
{
    return launched(c, cuda_scale_rows(STREAM(c), n, s, x, y), "scale_rows", err);
}

static int dev_gather_rows(pl_component *c, int m, const int *map, const double *x, double *y,
                           pl_error *err)
{
    return launched(c, cuda_gather_rows(STREAM(c), m, map, x, y), "gather_rows", err);
}

static int dev_scatter_rows(pl_component *c, int m, const int *map, const double *y, double *x,
                            double *change, pl_error *err)
{
    return launched(c, cuda_scatter_rows(STREAM(c), m, map, y, x, change), "scatter_rows",
                    err);
}

static int dev_sub_csr(pl_component *c, const pl_csr *A, const double *x, double *y, pl_error *err)
{
    return launched(c, cuda_sub_csr(STREAM(c), A->nrows, A->p, A->j, A->x, x, y), "sub_csr",
                    err);
}

static int dev_gather_sub_csr(pl_component *c, int m, const int *map, const double *x,
                              const pl_csr *A, const double *q, double *y, pl_error *err)
{
    return launched(c,
                    cuda_gather_sub_csr(STREAM(c), m, map, x, A ? A->p : NULL, A ? A->j : NULL,
                                        A ? A->x : NULL, q, y),
                    "gather_sub_csr", err);
}

static int dev_residual_max(pl_component *c, int m, const int *map, const double *s, double h2,
                            const double *x, const double *y, const double *g, const double *t,
                            double *out, pl_error *err)
{
    return launched(c, cuda_residual_max(STREAM(c), m, map, s, h2, x, y, g, t, out),
                    "residual_max", err);
}

static int dev_residual_max_csr(pl_component *c, int m, const int *map, const double *s,
                                double h2, const double *x, const double *y, const double *g,
                                const double *b, const pl_csr *A, double *out, pl_error *err)
{
    return launched(c,
                    cuda_residual_max_csr(STREAM(c), m, map, s, h2, x, y, g, b, A ? A->p : NULL,
                                          A ? A->j : NULL, A ? A->x : NULL, out),
                    "residual_max_csr", err);
}

static int dev_scale_rows_zero(pl_component *c, int n, const double *s, const double *x,
                               double *y, void *z, size_t bytes, pl_error *err)
{
    return launched(c, cuda_scale_rows_zero(STREAM(c), n, s, x, y, z, bytes), "scale_rows_zero",
                    err);
}

static int dev_step_begin(pl_component *c, int n3, double h, int first_order, int guess,
                          double hv, const double *x, const double *v, const double *g,
                          double *q_t, double *sn, double *q, pl_error *err)
{
    return launched(c, cuda_step_begin(STREAM(c), n3, h, first_order, guess, hv, x, v, g, q_t, sn, q),
                    "step_begin", err);
}

static int dev_step_end(pl_component *c, int n3, double h, double scale, const double *q,
                        const double *q_t, double *x, double *v, int *bad, pl_error *err)
{
    return launched(c, cuda_step_end(STREAM(c), n3, h, scale, q, q_t, x, v, bad), "step_end", err);
}

static int dev_capture_begin(pl_component *c, pl_error *err)
{
    CK(c, cudaStreamBeginCapture(STREAM(c), cudaStreamCaptureModeThreadLocal),
       "cudaStreamBeginCapture");
    return PL_OK;
}

static int dev_capture_end(pl_component *c, void **graph, pl_error *err)
{
    cudaGraph_t g = NULL;
    cudaGraphExec_t exec = NULL;
    *graph = NULL;
    CK(c, cudaStreamEndCapture(STREAM(c), &g), "cudaStreamEndCapture");
    cudaError_t e = cudaGraphInstantiate(&exec, g, 0);
    cudaGraphDestroy(g);
    if (e != cudaSuccess) return cuda_fail(c, err, e, "cudaGraphInstantiate");
    *graph = exec;
    return PL_OK;
}

static int dev_replay(pl_component *c, void *graph, pl_error *err)
{
    CK(c, cudaGraphLaunch((cudaGraphExec_t)graph, STREAM(c)), "cudaGraphLaunch");
    return PL_OK;
}

/* The caller's body with its error, as cuda_loop_build's plain callback. */
typedef struct loop_body {
    int (*body)(void *arg, pl_error *err);
    void *arg;
    pl_error *err;
} loop_body;

static int run_body(void *p)
{
    loop_body *b = p;
    return b->body(b->arg, b->err);
}

/* Builds the WHILE graph on first use (cuda_loop.cu), then launches it. */
static int dev_loop(pl_component *c, int (*body)(void *arg, pl_error *err), void *arg,
                    pl_device_loop *state, const double *change, const double *residual,
                    void **graph, pl_error *err)
{
    if (!DEV(c)->loops)
        return pl_component_fail(c, err, PL_EINTERNAL,
                                 "loop: this driver has no conditional graph nodes (CUDA 12.4)");
    if (!*graph) {
        loop_body b = {body, arg, err};
        int body_rc = 0;
        int e = cuda_loop_build(STREAM(c), run_body, &b, state, change, residual, graph, &body_rc);
        if (body_rc) return body_rc;
        if (e) return cuda_fail(c, err, (cudaError_t)e, "loop graph");
    }
    CK(c, cudaGraphLaunch((cudaGraphExec_t)*graph, STREAM(c)), "cudaGraphLaunch (loop)");
    return PL_OK;
}

static void dev_graph_free(pl_component *c, void *graph)
{
    (void)c;
    if (graph) cudaGraphExecDestroy((cudaGraphExec_t)graph);
}

const pl_device_ops pl_cuda_device_ops = {
    .version = PL_DEVICE_OPS_VERSION,
    .flags = dev_flags,
    .stream = dev_stream,
    .alloc = dev_alloc,
    .free = dev_free,
    .zero = dev_zero,
    .copy = dev_copy,
    .pin = dev_pin,
    .unpin = dev_unpin,
    .sync = dev_sync,
    .scale_rows = dev_scale_rows,
    .gather_rows = dev_gather_rows,
    .scatter_rows = dev_scatter_rows,
    .sub_csr = dev_sub_csr,
    .capture_begin = dev_capture_begin,
    .capture_end = dev_capture_end,
    .replay = dev_replay,
    .graph_free = dev_graph_free,
    .residual_max = dev_residual_max,
    .loop = dev_loop,
    .gather_sub_csr = dev_gather_sub_csr,
    .scale_rows_zero = dev_scale_rows_zero,
    .residual_max_csr = dev_residual_max_csr,
    .branch = dev_branch,
    .step_begin = dev_step_begin,
    .step_end = dev_step_end,
};
