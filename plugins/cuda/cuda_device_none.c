/* cuda_device_none.c - CudaDevice's backend in a build without CUDA: the
 * device is always absent (PL_DEVICE_ABSENT), so every component stays on
 * the host; the operations fail, naming the reason, should a caller use
 * them anyway. */
#include "cuda_device.h"

#define NO_CUDA "this build has no CUDA"

int cuda_device_open(cuda_device *d, pl_ctx *ctx)
{
    if (!d->absent)
        pl_component_warn(&d->base, ctx, NO_CUDA " (configured without nvcc): the scene runs on "
                                         "the CPU");
    d->absent = 1;
    return PL_OK;
}

void cuda_device_close(cuda_device *d) { (void)d; }

static int none(pl_component *c, pl_error *err)
{
    return pl_component_fail(c, err, PL_EINPUT, NO_CUDA);
}

static int dev_flags(const pl_component *c) { return PL_DEVICE_ABSENT; }
static void *dev_stream(const pl_component *c) { return NULL; }
static void *dev_alloc(pl_component *c, size_t bytes, pl_error *err)
{
    none(c, err);
    return NULL;
}
static void dev_free(pl_component *c, void *p) {}
static int dev_zero(pl_component *c, void *p, size_t bytes, pl_error *err) { return none(c, err); }
static int dev_copy(pl_component *c, void *dst, pl_location to, const void *src, pl_location from,
                    size_t bytes, pl_error *err)
{
    return none(c, err);
}
static int dev_pin(pl_component *c, void *host, size_t bytes, pl_error *err) { return none(c, err); }
static void dev_unpin(pl_component *c, void *host) {}
static int dev_sync(pl_component *c, pl_error *err) { return none(c, err); }
static int dev_rows(pl_component *c, int n, const double *s, const double *x, double *y,
                    pl_error *err)
{
    return none(c, err);
}
static int dev_map(pl_component *c, int m, const int *map, const double *x, double *y,
                   pl_error *err)
{
    return none(c, err);
}
static int dev_scatter(pl_component *c, int m, const int *map, const double *y, double *x,
                       double *change, pl_error *err)
{
    return none(c, err);
}
static int dev_sub_csr(pl_component *c, const pl_csr *A, const double *x, double *y, pl_error *err)
{
    return none(c, err);
}
static int dev_capture_begin(pl_component *c, pl_error *err) { return none(c, err); }
static int dev_capture_end(pl_component *c, void **graph, pl_error *err)
{
    *graph = NULL;
    return none(c, err);
}
static int dev_replay(pl_component *c, void *graph, pl_error *err) { return none(c, err); }
static void dev_graph_free(pl_component *c, void *graph) {}

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
    .scale_rows = dev_rows,
    .gather_rows = dev_map,
    .scatter_rows = dev_scatter,
    .sub_csr = dev_sub_csr,
    .capture_begin = dev_capture_begin,
    .capture_end = dev_capture_end,
    .replay = dev_replay,
    .graph_free = dev_graph_free,
};
