/* fem_term_device.c - the FEM term's local step on device buffers (CUDA
 * builds): ARAP, Corotational and NeoHookean on tetrahedra or membrane
 * triangles through
 * pl_hyper_cuda (cuda/hyper_cuda.h), queued on the stream of the scene's
 * device service (CudaDevice, found in this node or above).
 *
 * Duals (see fem_term.h): the pl_data slot stays the state between steps;
 * each pl_data's workspace holds a device copy of the elements and of the
 * duals, the duals filled from the slot by the first project() of the step
 * and written back by end_step.  So save/restore/clone/reset and several
 * pl_data over one model work as on the CPU, at the price of one copy back
 * per step (none for ARAP, which has no duals).  The slot itself is
 * page-locked (a fixed slot keeps its memory for the data's life), so the
 * copies are DMA straight between it and the device, and the upload is
 * skipped while the slot's version (model.h) is the one end_step saw: no
 * restore, copy, load or writable view has touched it since, so the device
 * copy is still the slot's.  (Before: a page-locked mirror, a memcpy of it
 * into the slot at end_step and a memcmp against it at the next step, about
 * 0.35 ms of host time a step for the 20k cloth's 1.9 MB of duals,
 * docs/benchmarks.md.)  The local step's statistics (largest Newton
 * count, missed tolerances, the first element with a non-finite F) are read
 * once per step, at end_step. */
#include <cuda_runtime_api.h>
#include <stdlib.h>

#include "fem_term.h"
#include "hyper_cuda.h"
#include "hyper_cuda_gradient.h"

typedef struct hyper_fem_gpu {
    pl_hyper_cuda *g;
    pl_hyper_cuda_grad *grad;  /* the gradient's device data, made on first use */
    pl_component *dev;         /* the device service: its current stream at each call (a
                                  branch's during the local step: local_global_device.c) */
    const pl_device_ops *ops;
    double *dual;              /* device n x 3d (ADMM materials), or NULL */
    void *pinned, *pin_failed; /* the duals' slot page-locked; a slot that could not be */
    unsigned long seen;        /* the slot's version when end_step wrote it and the device
                                  copy equalled it (0: they may differ) */
    size_t dual_bytes;
    int fresh;                 /* the device copy holds this step's duals */
    int used;                  /* a device project ran this step */
    int relax_ready;           /* a project of this step ran: over-relaxation may start */
} hyper_fem_gpu;

static int fail_cuda(const hyper_fem *f, pl_error *err, cudaError_t e, const char *what)
{
    return pl_component_fail(&f->base, err, PL_EINTERNAL, "%s: %s", what, cudaGetErrorString(e));
}

/* The device copy of the elements and the stream in *out, made on first
 * use. */
static int prepare(const hyper_fem *f, hyper_fem_gpu **out, pl_error *err)
{
    if (*out) return PL_OK;
    const pl_component *c = &f->base;
    pl_component *dev = pl_util_device(c);
    const pl_device_ops *ops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
    if (!ops || !ops->stream)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: device buffers, but no device service (CudaDevice) in "
                                 "this node or above");
    hyper_fem_gpu *gpu = calloc(1, sizeof *gpu);
    if (!gpu) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    gpu->dev = dev, gpu->ops = ops;
    pl_error e;
    gpu->g = hyper_cuda_create(&f->el, &e);
    if (!gpu->g) {
        free(gpu);
        return pl_component_fail(c, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
    }
    if (f->dual_slot >= 0) {
        gpu->dual_bytes = (size_t)f->el.n * hyper_elements_dual_size(&f->el) * sizeof(double);
        size_t bytes = gpu->dual_bytes ? gpu->dual_bytes : 1;
        cudaError_t ce = cudaMalloc((void **)&gpu->dual, bytes);
        if (ce != cudaSuccess) {
            hyper_cuda_destroy(gpu->g);
            free(gpu);
            return fail_cuda(f, err, ce, "device duals");
        }
    }
    *out = gpu;
    return PL_OK;
}

static struct CUstream_st *stream_of(const hyper_fem_gpu *gpu)
{
    return gpu->ops->stream(gpu->dev);
}

/* The duals' slot page-locked (once per data: its memory never moves), so
 * that its copies each way are DMA.  Where that fails (pages shared with
 * memory page-locked already) the copies still work, staged by the driver. */
static void pin_slot(hyper_fem_gpu *gpu, void *host)
{
    if (host == gpu->pinned || host == gpu->pin_failed || !gpu->ops->pin || !gpu->dual_bytes)
        return;
    if (gpu->pinned) gpu->ops->unpin(gpu->dev, gpu->pinned);
    gpu->pinned = NULL;
    pl_error e;
    if (gpu->ops->pin(gpu->dev, host, gpu->dual_bytes, &e) == PL_OK)
        gpu->pinned = host;
    else
        gpu->pin_failed = host;
}

/* d's device copy (NULL if none was made). */
static hyper_fem_gpu **gpu_of(const hyper_fem *f, pl_data *d)
{
    hyper_term_ws *w = pl_data_workspace(d, &f->base);
    return w ? &w->fem : NULL;
}

static int check_block(const hyper_fem *f, const pl_buffer *b, int offset, const char *what,
                       pl_error *err)
{
    if (b->location != PL_DEVICE || b->precision != PL_F64 || b->cols != 3)
        return pl_component_fail(&f->base, err, PL_EINPUT,
                                 "%s: the device local step takes device float64 n x 3 blocks",
                                 what);
    if (offset < 0 || b->rows < (size_t)offset + (size_t)f->el.nverts)
        return pl_component_fail(&f->base, err, PL_EINPUT,
                                 "%s: %zu rows, but its vertices are %d .. %d", what, b->rows,
                                 offset, offset + f->el.nverts - 1);
    return PL_OK;
}

int hyper_fem_project_device(const hyper_fem *f, pl_data *d, int offset, double h2,
                             const pl_buffer *q, pl_buffer *rhs, pl_error *err)
{
    hyper_fem_gpu **slot = gpu_of(f, d);
    if (!slot) return pl_component_fail(&f->base, err, PL_EINTERNAL, "out of memory (workspace)");
    int rc = check_block(f, q, offset, "positions", err);
    if (!rc) rc = check_block(f, rhs, offset, "right-hand side", err);
    if (!rc) rc = prepare(f, slot, err);
    if (rc) return rc;
    hyper_fem_gpu *gpu = *slot;
    if (gpu->dual && !gpu->fresh) {
        /* first device project of the step: the duals of d go up (a pl_data
         * made before the model knew its size gets zero duals, as on the CPU) */
        if (pl_data_slot_bytes(d, f->dual_slot) != gpu->dual_bytes &&
            pl_data_resize_slot(d, f->dual_slot, gpu->dual_bytes) != 0)
            return pl_component_fail(&f->base, err, PL_EINTERNAL, "out of memory (duals)");
        void *host = pl_data_slot(d, f->dual_slot);
        unsigned long version = pl_data_slot_version(d, f->dual_slot);
        if (version == 0 || version != gpu->seen) {
            pin_slot(gpu, host);
            cudaError_t ce = cudaMemcpyAsync(gpu->dual, host, gpu->dual_bytes,
                                             cudaMemcpyHostToDevice, stream_of(gpu));
            if (ce != cudaSuccess) return fail_cuda(f, err, ce, "duals to the device");
        }
    }
    gpu->seen = 0; /* the kernels below change dual: the slot differs until end_step */
    gpu->fresh = 1;
    gpu->used = 1;
    /* as the host: alpha from the step's second project on (the first is
     * never captured in a graph: local_global_device.c runs it eagerly) */
    int relax = gpu->dual && f->admm_relaxation != 1.0;
    double alpha = relax && gpu->relax_ready ? f->admm_relaxation : 1.0;
    gpu->relax_ready = 1;
    pl_error e;
    if (hyper_cuda_project_relaxed(gpu->g, offset, h2, q->data, gpu->dual, relax, alpha, rhs->data,
                                   PL_HYPER_CUDA_GATHER, stream_of(gpu), &e) != PL_OK)
        return pl_component_fail(&f->base, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
    return PL_OK;
}

int hyper_fem_gradient_device(const hyper_fem *f, pl_data *d, int offset, const pl_buffer *q,
                              pl_buffer *grad, pl_error *err)
{
    hyper_fem_gpu **slot = gpu_of(f, d);
    if (!slot) return pl_component_fail(&f->base, err, PL_EINTERNAL, "out of memory (workspace)");
    int rc = check_block(f, q, offset, "positions", err);
    if (!rc) rc = check_block(f, grad, offset, "gradient", err);
    if (!rc) rc = prepare(f, slot, err);
    if (rc) return rc;
    hyper_fem_gpu *gpu = *slot;
    pl_error e;
    pl_error_clear(&e);
    if (!gpu->grad && !(gpu->grad = hyper_cuda_grad_create(&f->el, &e)))
        return pl_component_fail(&f->base, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
    if (hyper_cuda_grad_add(gpu->grad, offset, q->data, grad->data, stream_of(gpu), &e) != PL_OK)
        return pl_component_fail(&f->base, err, e.code ? e.code : PL_EINTERNAL, "%s", e.msg);
    return PL_OK;
}

int hyper_fem_device_end_step(const hyper_fem *f, pl_data *d, pl_error *err)
{
    hyper_fem_gpu **slot = gpu_of(f, d), *gpu = slot ? *slot : NULL;
    if (!gpu || !gpu->used) return PL_OK;
    gpu->used = 0;
    int back = gpu->dual && gpu->fresh;
    if (back) { /* straight into the slot (project sized it) */
        void *host = pl_data_slot(d, f->dual_slot);
        pin_slot(gpu, host);
        cudaError_t ce = cudaMemcpyAsync(host, gpu->dual, gpu->dual_bytes,
                                         cudaMemcpyDeviceToHost, stream_of(gpu));
        if (ce != cudaSuccess) return fail_cuda(f, err, ce, "duals to the host");
    }
    gpu->fresh = 0;
    int stats[2];
    pl_error e;
    /* the step's counts join the host's (fem_term.c publishes them); one
     * copy and one wait for the stream, the duals' copy included */
    hyper_term_ws *w = pl_data_workspace(d, &f->base);
    if (hyper_cuda_step_stats(gpu->g, stream_of(gpu), stats, w ? &w->prox : NULL, &e) != PL_OK)
        return pl_component_fail(&f->base, err, e.code ? e.code : PL_EINTERNAL,
                                 "local step on the device, step %ld: %s", d->step, e.msg);
    if (back) /* the wait above covered the copy: slot and device copy are equal */
        gpu->seen = pl_data_slot_version(d, f->dual_slot);
    if (stats[1] > 0)
        pl_log_debug("%s: %d local solves stopped before their tolerance (this step)",
                     f->base.name, stats[1]);
    if (w && stats[0] > w->prox.max_iterations) w->prox.max_iterations = stats[0];
    return PL_OK;
}

void hyper_fem_device_begin_step(const hyper_fem *f, pl_data *d)
{
    hyper_fem_gpu **slot = gpu_of(f, d);
    if (!slot || !*slot) return;
    (*slot)->fresh = 0, (*slot)->used = 0, (*slot)->relax_ready = 0;
    /* each step's prox starts cold, as on the host; queued before the
     * step's kernels (or its graph) on the same stream.  An error here
     * (a broken context) shows again at the next CUDA call, which reports. */
    pl_error e;
    (void)hyper_cuda_begin_step((*slot)->g, stream_of(*slot), &e);
}

void hyper_fem_device_free(hyper_fem_gpu **slot)
{
    hyper_fem_gpu *gpu = *slot;
    if (!gpu) return;
    hyper_cuda_destroy(gpu->g);
    hyper_cuda_grad_destroy(gpu->grad);
    if (gpu->dual) cudaFree(gpu->dual);
    if (gpu->pinned) gpu->ops->unpin(gpu->dev, gpu->pinned); /* before pl_data frees the slot */
    free(gpu);
    *slot = NULL;
}
