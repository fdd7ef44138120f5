/* stencil_device.c - bending and PositionTarget project() on device
 * buffers (see stencil_device.h), CUDA builds only. */
#include "stencil_device.h"

#include <stdlib.h>

#include "stencil_cuda.h"

struct hyper_stencil_gpu {
    pl_stencil_cuda *g;
    pl_component *dev; /* the device service: its current stream at each call (a branch's) */
    const pl_device_ops *ops;
    const pl_data *fresh; /* whose targets the device copy holds this step, or NULL */
};

static int check_block(const pl_component *c, const pl_buffer *b, int offset, int nverts,
                       const char *what, pl_error *err)
{
    if (b->location != PL_DEVICE || b->precision != PL_F64 || b->cols != 3)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "%s: the device local step takes device float64 n x 3 blocks",
                                 what);
    if (offset < 0 || b->rows < (size_t)offset + (size_t)nverts)
        return pl_component_fail(c, err, PL_EINPUT, "%s: %zu rows, but its vertices are %d .. %d",
                                 what, b->rows, offset, offset + nverts - 1);
    return PL_OK;
}

static int prepare(const pl_component *c, const pl_hyper_stencils *s, hyper_stencil_gpu **gpu,
                   pl_error *err)
{
    if (*gpu) return PL_OK;
    pl_component *dev = pl_util_device(c);
    const pl_device_ops *ops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
    if (!ops || !ops->stream)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: device buffers, but no device service (CudaDevice) in "
                                 "this node or above");
    hyper_stencil_gpu *g = calloc(1, sizeof *g);
    if (!g) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    g->dev = dev, g->ops = ops;
    pl_error e;
    g->g = stencil_cuda_create(s, &e);
    if (!g->g) {
        free(g);
        return pl_component_fail(c, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
    }
    *gpu = g;
    return PL_OK;
}

int hyper_stencil_project_device(const pl_component *c, const pl_hyper_stencils *s,
                                 hyper_stencil_gpu **gpu, const pl_data *d, const double *targets,
                                 int offset, double h2, const pl_buffer *q, pl_buffer *rhs,
                                 pl_error *err)
{
    int rc = check_block(c, q, offset, s->nverts, "positions", err);
    if (!rc) rc = check_block(c, rhs, offset, s->nverts, "right-hand side", err);
    if (rc) return rc;
    /* FIXED rows with zero targets add h2 w c 0 = 0: nothing to queue */
    if (s->kind == PL_HYPER_STENCIL_FIXED && !targets) return PL_OK;
    if ((rc = prepare(c, s, gpu, err))) return rc;
    hyper_stencil_gpu *g = *gpu;
    struct CUstream_st *stream = g->ops->stream(g->dev);
    pl_error e;
    if (targets && g->fresh != d) {
        if (stencil_cuda_set_targets(g->g, targets, stream, &e) != PL_OK)
            return pl_component_fail(c, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
        g->fresh = d;
    }
    if (stencil_cuda_project(g->g, offset, h2, q->data, targets != NULL, rhs->data, stream, &e) !=
        PL_OK)
        return pl_component_fail(c, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
    return PL_OK;
}

void hyper_stencil_device_begin_step(hyper_stencil_gpu *gpu)
{
    if (gpu) gpu->fresh = NULL;
}

void hyper_stencil_device_free(hyper_stencil_gpu **gpu)
{
    if (!*gpu) return;
    stencil_cuda_destroy((*gpu)->g);
    free(*gpu);
    *gpu = NULL;
}
