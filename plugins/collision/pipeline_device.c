/* pipeline_device.c - where the CollisionPipeline detects a pair of models:
 * on the host (detect_pair, the BVHs), or with PLIANT_DETECT=cuda in a CUDA
 * build with a GPU, over the candidates the device makes (broad phase and
 * distance filter, detect_device.cu) measured by the host's rules
 * (detect_pair_given): the same proximities in the same order, so that a
 * run is bitwise the same either way.  The choice is made once per data
 * and logged with its reason. */
#include <stdlib.h>
#include <string.h>

#include "pipeline.h"
#include "pliant/log.h"
#include "pliant/timer.h"
#ifdef PLIANT_HAVE_CUDA
#include "detect_device.h"
#endif

/* 1: the device, -1: the host (logged once). */
static int choose(const collision_pipeline *p, coll_ws *w)
{
    if (w->dev_state) return w->dev_state;
    const char *want = getenv("PLIANT_DETECT");
    w->dev_state = -1;
    if (!want || strcmp(want, "cuda") != 0) return w->dev_state; /* the default: host */
#ifdef PLIANT_HAVE_CUDA
    pl_error e;
    if (coll_dev_open(&w->dev, &e) == PL_OK) {
        w->dev_state = 1;
        pl_log_info("CollisionPipeline '%s': detection candidates on the GPU (PLIANT_DETECT=cuda)",
                    p->base.name);
    } else {
        pl_log_warn("CollisionPipeline '%s': detection stays on the host: %s", p->base.name,
                    e.msg);
    }
#else
    pl_log_warn("CollisionPipeline '%s': detection stays on the host: this build has no CUDA",
                p->base.name);
#endif
    return w->dev_state;
}

int coll_detect_models(const collision_pipeline *p, coll_ws *w, int k, int l,
                       const pl_detect_params *prm, pl_error *err)
{
    const pl_coll_mesh *A = &w->models[k].mesh, *B = &w->models[l].mesh;
    double t0 = pl_now();
    if (choose(p, w) < 0) {
        if (detect_pair(A, k, B, l, prm, &w->prox))
            return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
        w->pairs_ms += 1e3 * (pl_now() - t0);
        return PL_OK;
    }
#ifdef PLIANT_HAVE_CUDA
    pl_error e;
    double ms = 0.0;
    if (coll_dev_candidates(w->dev, A, B, prm, w->cand, &ms, &e)) {
        /* the host finds the same contacts: go on there */
        pl_log_warn("CollisionPipeline '%s': detection goes back to the host: %s", p->base.name,
                    e.msg);
        coll_dev_close(w->dev);
        w->dev = NULL;
        w->dev_state = -1;
        return coll_detect_models(p, w, k, l, prm, err);
    }
    w->cand_ms += ms;
    if (detect_pair_given(A, k, B, l, prm, w->cand, &w->prox))
        return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
#endif
    w->pairs_ms += 1e3 * (pl_now() - t0);
    return PL_OK;
}

void coll_detect_ws_free(coll_ws *w)
{
#ifdef PLIANT_HAVE_CUDA
    coll_dev_close(w->dev);
#endif
    w->dev = NULL;
    w->dev_state = 0;
    for (int k = 0; k < 3; ++k) coll_cand_list_free(&w->cand[k]);
}
