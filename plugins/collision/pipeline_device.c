/* pipeline_device.c - where the CollisionPipeline detects its pairs of
 * models: on the host (detect_pair, the BVHs), or in a CUDA build with a
 * GPU over the candidates the device makes for all pairs of a step at once
 * (broad phase and distance filter, detect_device.cu) measured by the
 * host's rules (detect_pair_given): the same proximities in the same
 * order, so that a run is bitwise the same either way.
 *
 * PLIANT_DETECT: host, cuda (the device in every step), or auto (the
 * default; anything else is bad input): the device only when the loop runs there (the scene's device
 * service: device=auto chose the GPU) and in steps after one whose pairs
 * had at least COLL_DEV_MIN_OVERLAPS box overlaps (the broad phase's pairs,
 * counted alike on both paths: detection's "candidates" statistic).  Below
 * that the host's BVHs were faster than the device's fixed costs (kernel
 * launches, transfers, two waits): docs/benchmarks.md, "Detection on the
 * device: the batch". The rule only picks where the same contacts are
 * made, so it never changes a result.  The choice is made once per data and
 * logged with its reason. */
#include <stdlib.h>
#include <string.h>

#include "pipeline.h"
#include "pliant/log.h"
#include "pliant/timer.h"
#include "pliant/util.h"
#ifdef PLIANT_HAVE_CUDA
#include "detect_device.h"
#endif

/* dev_state: 1 the device in every step, 2 as the rule says, -1 the host;
 * choose() also answers DEV_BAD: PLIANT_DETECT is none of its values */
enum { DEV_ALWAYS = 1, DEV_AUTO = 2, DEV_NEVER = -1, DEV_BAD = -2 };

static int choose(const collision_pipeline *p, coll_ws *w)
{
    if (w->dev_state) return w->dev_state;
    const char *want = getenv("PLIANT_DETECT");
    if (want && *want && strcmp(want, "host") && strcmp(want, "cuda") && strcmp(want, "auto"))
        return DEV_BAD; /* bad input, like a bad PLIANT_DEVICE (sim_device.c) */
    w->dev_state = DEV_NEVER;
    if (want && strcmp(want, "host") == 0) return w->dev_state;
    int forced = want && strcmp(want, "cuda") == 0;
#ifdef PLIANT_HAVE_CUDA
    if (!forced && !pl_util_device(&p->base)) return w->dev_state; /* the loop is on the CPU */
    pl_error e;
    if (coll_dev_open(&w->dev, &e) == PL_OK) {
        w->dev_state = forced ? DEV_ALWAYS : DEV_AUTO;
        if (forced)
            pl_log_info("CollisionPipeline '%s': detection candidates on the GPU "
                        "(PLIANT_DETECT=cuda)", p->base.name);
        else
            pl_log_info("CollisionPipeline '%s': detection candidates on the GPU in steps "
                        "after one with >= %d box overlaps, else on the host (PLIANT_DETECT="
                        "auto)", p->base.name, COLL_DEV_MIN_OVERLAPS);
    } else {
        pl_log_warn("CollisionPipeline '%s': detection stays on the host: %s", p->base.name,
                    e.msg);
    }
#else
    if (forced)
        pl_log_warn("CollisionPipeline '%s': detection stays on the host: this build has no "
                    "CUDA", p->base.name);
#endif
    return w->dev_state;
}

static int host_pairs(const collision_pipeline *p, coll_ws *w, int n, const int *kl,
                      const pl_detect_params *prm, pl_error *err)
{
    for (int i = 0; i < n; ++i) {
        int k = kl[2 * i], l = kl[2 * i + 1];
        if (detect_pair(&w->models[k].mesh, k, &w->models[l].mesh, l, prm, &w->prox))
            return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
    }
    return PL_OK;
}

#ifdef PLIANT_HAVE_CUDA
/* Room for n pairs' lists, meshes and overlaps in w; PL_OK or PL_EINTERNAL. */
static int fit_batch(coll_ws *w, int n)
{
    if (n <= w->cap_batch) return PL_OK;
    coll_cand_list *c = realloc(w->cand, (size_t)(3 * n) * sizeof *c);
    if (c) {
        memset(c + 3 * w->cap_batch, 0, (size_t)(3 * (n - w->cap_batch)) * sizeof *c);
        w->cand = c;
    }
    const pl_coll_mesh **a = realloc(w->batch_a, (size_t)n * sizeof *a);
    if (a) w->batch_a = a;
    const pl_coll_mesh **b = realloc(w->batch_b, (size_t)n * sizeof *b);
    if (b) w->batch_b = b;
    long long *o = realloc(w->batch_overlaps, (size_t)n * sizeof *o);
    if (o) w->batch_overlaps = o;
    if (!c || !a || !b || !o) return PL_EINTERNAL;
    w->cap_batch = n;
    return PL_OK;
}

/* The pairs over the device's candidates; 1 when the device failed (the
 * host does them), else PL_OK or PL_EINTERNAL. */
static int device_pairs(const collision_pipeline *p, coll_ws *w, int n, const int *kl,
                        const pl_detect_params *prm, pl_error *err)
{
    if (fit_batch(w, n)) return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
    for (int i = 0; i < n; ++i) {
        w->batch_a[i] = &w->models[kl[2 * i]].mesh;
        w->batch_b[i] = &w->models[kl[2 * i + 1]].mesh;
    }
    pl_error e;
    double ms = 0.0;
    if (coll_dev_batch(w->dev, n, w->batch_a, w->batch_b, prm, w->cand, w->batch_overlaps, &ms,
                       &e)) {
        pl_log_warn("CollisionPipeline '%s': detection goes back to the host: %s",
                    p->base.name, e.msg);
        coll_dev_close(w->dev);
        w->dev = NULL;
        w->dev_state = DEV_NEVER;
        return 1;
    }
    w->cand_ms += ms;
    w->dev_step = 1;
    for (int i = 0; i < n; ++i) {
        long long before = prm->counts ? prm->counts->candidates : 0;
        if (detect_pair_given(w->batch_a[i], kl[2 * i], w->batch_b[i], kl[2 * i + 1], prm,
                              &w->cand[3 * i], &w->prox))
            return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
        /* the statistic counts the broad phase's pairs, as detect_pair's */
        if (prm->counts) prm->counts->candidates = before + w->batch_overlaps[i];
    }
    return PL_OK;
}
#endif

int coll_detect_pairs(const collision_pipeline *p, coll_ws *w, int n, const int *kl,
                      const pl_detect_params *prm, pl_error *err)
{
    double t0 = pl_now();
    int st = choose(p, w), rc = 1;
    if (st == DEV_BAD)
        return pl_component_fail(&p->base, err, PL_EINPUT,
                                 "PLIANT_DETECT='%s' is not host, cuda or auto",
                                 getenv("PLIANT_DETECT"));
#ifdef PLIANT_HAVE_CUDA
    if (n > 0 && (st == DEV_ALWAYS || (st == DEV_AUTO && w->last_overlaps >= COLL_DEV_MIN_OVERLAPS)))
        rc = device_pairs(p, w, n, kl, prm, err);
#endif
    if (rc == 1) rc = host_pairs(p, w, n, kl, prm, err);
    w->pairs_ms += 1e3 * (pl_now() - t0);
    return rc;
}

int coll_detect_models(const collision_pipeline *p, coll_ws *w, int k, int l,
                       const pl_detect_params *prm, pl_error *err)
{
    int kl[2] = {k, l};
    return coll_detect_pairs(p, w, 1, kl, prm, err);
}

void coll_detect_ws_free(coll_ws *w)
{
#ifdef PLIANT_HAVE_CUDA
    coll_dev_close(w->dev);
#endif
    w->dev = NULL;
    w->dev_state = 0;
    for (int k = 0; k < 3 * w->cap_batch; ++k) coll_cand_list_free(&w->cand[k]);
    free(w->cand);
    free(w->batch_a);
    free(w->batch_b);
    free(w->batch_overlaps);
    free(w->pairs);
    w->cand = NULL;
    w->batch_a = w->batch_b = NULL;
    w->batch_overlaps = NULL;
    w->pairs = NULL;
    w->cap_batch = w->cap_pairs = 0;
}
