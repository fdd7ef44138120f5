/* fem_term.c - the FEM local term shared by ARAP, Corotational and
 * NeoHookean: finds its mesh (init) and state (bind), builds the element
 * set from the state's rest positions (reinit, again whenever a field
 * changes), and plays PL_ROLE_LOCAL_TERM through hyperelastic_core.
 * ADMM-PD duals (3 x d per element) live in the pl_data slot "dual".
 * project() on device buffers (CUDA builds) goes to fem_term_device.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"
#include "fem_term.h"

const char *const hyper_fem_element_choices[] = {"auto", "tetrahedra", "triangles", NULL};
const char *const hyper_fem_rotation_choices[] = {"polar", "edges", NULL};

double *hyper_term_block(const pl_component *c, const pl_buffer *b, int offset, int nverts,
                         const char *what, pl_error *err)
{
    double *x = pl_buffer_f64(b);
    if (!x || b->cols != 3)
        pl_component_fail(c, err, PL_EINTERNAL, "%s: expected host float64 n x 3 data", what);
    else if (offset < 0 || b->rows < (size_t)offset + (size_t)nverts)
        pl_component_fail(c, err, PL_EINTERNAL, "%s: %zu rows, but its vertices are %d .. %d",
                          what, b->rows, offset, offset + nverts - 1);
    else
        return x;
    return NULL;
}

int hyper_fem_init(pl_component *c, pl_ctx *ctx, pl_hyper_material material)
{
    hyper_fem *f = (hyper_fem *)c;
    f->material = material;
    f->dual_slot = -1;
    f->mesh = pl_util_topology(c, &f->src, ctx, 1);
    if (!f->mesh) return PL_EINPUT;
    const pl_mesh *m = f->mesh;
    if (f->elements == 1 || (f->elements == 0 && m->ntets > 0)) {
        if (m->ntets == 0)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "elements=\"tetrahedra\" but the mesh has none");
        f->k = 4;
        f->nelem = m->ntets;
    } else {
        if (m->ntris == 0)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "the mesh has neither tetrahedra nor triangles");
        f->k = 3;
        f->nelem = m->ntris;
    }
    if (f->young.n != 1 && f->young.n != f->nelem)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "youngModulus: expected 1 value or one per element (%d), got %d",
                                  f->nelem, f->young.n);
    if (f->poisson.n != 1 && f->poisson.n != f->nelem)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "poissonRatio: expected 1 value or one per element (%d), got %d",
                                  f->nelem, f->poisson.n);
    for (int i = 0; i < f->nelem; ++i) {
        double mu, la;
        pl_error e;
        int rc = hyper_lame(f->young.v[f->young.n == 1 ? 0 : i],
                               f->poisson.v[f->poisson.n == 1 ? 0 : i], 0, &mu, &la, &e);
        if (rc != PL_OK && f->young.n == 1 && f->poisson.n == 1)
            return pl_component_error(c, ctx, rc, "%s", e.msg);
        if (rc != PL_OK) return pl_component_error(c, ctx, rc, "element %d: %s", i, e.msg);
        if (f->young.n == 1 && f->poisson.n == 1) break;
    }
    if (!(f->admm_weight > 0.0 && isfinite(f->admm_weight)))
        return pl_component_error(c, ctx, PL_EINPUT, "admmWeight must be positive, got %g",
                                  f->admm_weight);
    if (!(f->admm_relaxation > 0.0 && f->admm_relaxation < 2.0))
        return pl_component_error(c, ctx, PL_EINPUT, "admmRelaxation must be in (0, 2), got %g",
                                  f->admm_relaxation);
    if (material == PL_HYPER_ARAP && f->admm_relaxation != 1.0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "admmRelaxation relaxes the ADMM-PD of Corotational and "
                                  "NeoHookean; ARAP's local step is a projection (no dual)");
    if (material == PL_HYPER_ARAP && f->admm_weight != 1.0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "admmWeight is the ADMM-PD penalty of Corotational and "
                                  "NeoHookean; ARAP's weight is its stiffness (2 mu V)");
    if (f->k == 3 && !(f->thickness > 0.0))
        return pl_component_error(c, ctx, PL_EINPUT, "thickness must be positive [m], got %g",
                                  f->thickness);
    if (material != PL_HYPER_ARAP) {
        size_t bytes = (size_t)f->nelem * 3 * (f->k - 1) * sizeof(double);
        f->dual_slot = pl_model_add_slot(ctx->build, c, "dual", bytes);
        if (f->dual_slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
        pl_model_set_slot_check(ctx->build, f->dual_slot, pl_slot_check_finite);
    }
    return PL_OK;
}

int hyper_fem_bind(pl_component *c, pl_ctx *ctx)
{
    hyper_fem *f = (hyper_fem *)c;
    f->state = pl_util_state(c, ctx, 1);
    return f->state ? PL_OK : PL_EINPUT;
}

int hyper_fem_reinit(pl_component *c, pl_ctx *ctx)
{
    hyper_fem *f = (hyper_fem *)c;
    hyper_elements_free(&f->el); /* workspaces (device copies) are remade after a reinit */
    if (!f->state || !f->mesh) return PL_EINPUT; /* init or bind already reported why */
    int nrest;
    const double *rest = pl_util_rest(f->state, &nrest);
    if (!rest) return pl_component_error(c, ctx, PL_EINPUT, "its state has no rest positions");
    pl_error err;
    const int *cells = f->k == 4 ? f->mesh->tets : f->mesh->tris;
    int rc = hyper_elements_build(&f->el, f->material, f->k, cells, f->nelem, rest, nrest,
                                     f->young.v, f->young.n, f->poisson.v, f->poisson.n,
                                     f->thickness, &err);
    if (rc != PL_OK) return pl_component_error(c, ctx, rc, "%s", err.msg);
    if (f->rotation && f->k != 4)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "rotation=\"edges\" (SOFA's 'large') needs tetrahedra");
    f->el.edge_rotation = f->rotation;
    /* the penalty scales the weights everywhere they appear: the system
     * matrix, the local prox and the right-hand side (ARAP: 1, init) */
    f->el.weight_scale = f->admm_weight;
    double wsum = 0.0;
    for (int i = 0; i < f->el.n; ++i) wsum += f->el.w[i] *= f->admm_weight;
    char law[64];
    if (f->material == PL_HYPER_ARAP)
        snprintf(law, sizeof law, "PD (w = 2 mu V)");
    else if (f->admm_weight == 1.0)
        snprintf(law, sizeof law, "ADMM-PD (w = (2 mu + lambda) V)");
    else
        snprintf(law, sizeof law, "ADMM-PD (w = %g (2 mu + lambda) V)", f->admm_weight);
    pl_log_info("%s: %d %s, %s, mean weight w = %g N m", c->name, f->el.n,
                f->k == 4 ? "tetrahedra" : "triangles", law, f->el.n ? wsum / f->el.n : 0.0);
    return PL_OK;
}

int hyper_fem_begin_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    const hyper_fem *f = (const hyper_fem *)c;
    (void)err;
    if (f->dual_slot >= 0 && !f->warm_start)
        memset(pl_data_slot(ctx->data, f->dual_slot), 0, pl_data_slot_bytes(ctx->data, f->dual_slot));
    /* the prox's warm start is within a step only: each step starts cold,
     * so that it depends on the slots alone (restore, clone: bitwise) */
    hyper_term_ws *w = pl_data_workspace(ctx->data, c);
    if (w && w->warm) memset(w->warm, 0, w->nwarm * sizeof *w->warm);
    if (w) w->relax_ready = 0; /* over-relaxation from the step's second iteration on */
#ifdef PLIANT_HAVE_CUDA
    hyper_fem_device_begin_step(f, ctx->data);
#endif
    return PL_OK;
}

/* t's statistic `name` += v (summed over the steps and over the terms of
 * one type). */
static void stat_add(pl_timers *t, const char *type, const char *what, double v)
{
    char name[96];
    double old = 0.0;
    snprintf(name, sizeof name, "%s: local %s", type, what);
    if (pl_stat_get(t, name, &old) != 0) old = 0.0;
    pl_stat_set(t, name, old + v);
}

/* The step's local-solve counts into the timers' statistics ("NeoHookean:
 * local solves", "... newton", "... halvings", "... capped", "... its=k",
 * "... seconds"; pliant run --timings prints them), then zeroed. */
static void publish_prox(const pl_component *c, pl_ctx *ctx)
{
    hyper_term_ws *w = pl_data_workspace(ctx->data, c);
    if (!w || !ctx->timers || w->prox.solves == 0) return;
    const char *type = c->type->name;
    const hyper_prox_stats *p = &w->prox;
    stat_add(ctx->timers, type, "solves", (double)p->solves);
    stat_add(ctx->timers, type, "newton", (double)p->newton);
    stat_add(ctx->timers, type, "halvings", (double)p->halvings);
    stat_add(ctx->timers, type, "capped", (double)p->capped);
    stat_add(ctx->timers, type, "seconds", w->prox_seconds);
    for (int b = 0; b < HYPER_PROX_HIST; ++b) {
        char bin[16];
        snprintf(bin, sizeof bin, b < HYPER_PROX_HIST - 1 ? "its=%d" : "its>=%d", b);
        if (p->hist[b]) stat_add(ctx->timers, type, bin, (double)p->hist[b]);
    }
    char name[96];
    snprintf(name, sizeof name, "%s: local max iterations", type);
    pl_stat_max(ctx->timers, name, p->max_iterations);
    memset(&w->prox, 0, sizeof w->prox);
    w->prox_seconds = 0.0;
}

int hyper_fem_end_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    int rc = PL_OK;
#ifdef PLIANT_HAVE_CUDA
    rc = hyper_fem_device_end_step((const hyper_fem *)c, ctx->data, err);
#else
    (void)err;
#endif
    publish_prox(c, ctx);
    return rc;
}

void hyper_fem_destroy(pl_component *c)
{
    hyper_elements_free(&((hyper_fem *)c)->el);
}

/* ---- PL_ROLE_LOCAL_TERM --------------------------------------------------- */

static pl_component *fem_state(const pl_component *c)
{
    return ((const hyper_fem *)c)->state;
}

static int fem_add_matrix(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err)
{
    hyper_fem *f = (hyper_fem *)c;
    pl_error e;
    if (hyper_elements_add_matrix(&f->el, offset, h2, A, &e) != PL_OK)
        return pl_component_fail(c, err, e.code, "%s", e.msg);
    return PL_OK;
}

static int fem_project(const pl_component *c, pl_data *d, int offset, double h2, const pl_buffer *q,
                       pl_buffer *rhs, pl_error *err)
{
    const hyper_fem *f = (const hyper_fem *)c;
    if (f->el.edge_rotation) /* its force is not the gradient of an energy */
        return pl_component_fail(c, err, PL_EINPUT,
                                 "rotation=\"edges\" (SOFA's 'large' method) has no energy to "
                                 "project on: only LinearizedEulerSolver (forces and stiffness) "
                                 "uses it; with this solver use rotation=\"polar\"");
    if (q->location == PL_DEVICE || rhs->location == PL_DEVICE) {
#ifdef PLIANT_HAVE_CUDA
        return hyper_fem_project_device(f, d, offset, h2, q, rhs, err);
#else
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: device buffers, but this build has no CUDA");
#endif
    }
    const double *x = hyper_term_block(c, q, offset, f->el.nverts, "positions", err);
    double *b = x ? hyper_term_block(c, rhs, offset, f->el.nverts, "right-hand side", err) : NULL;
    if (!b) return PL_EINTERNAL;
    double *dual = NULL;
    if (f->dual_slot >= 0) {
        size_t bytes = (size_t)f->el.n * hyper_elements_dual_size(&f->el) * sizeof(double);
        /* a pl_data made before the model knew its size gets zero duals */
        if (pl_data_slot_bytes(d, f->dual_slot) != bytes &&
            pl_data_resize_slot(d, f->dual_slot, bytes) != 0)
            return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (duals)");
        dual = pl_data_slot(d, f->dual_slot);
    }
    double *work = hyper_term_work(c, d, hyper_elements_work_size(&f->el), err);
    if (!work) return err->code;
    hyper_term_ws *w = pl_data_workspace(d, c); /* not NULL: hyper_term_work made it */
    double *warm = NULL;
    if (!(warm = hyper_term_warm(c, d, (size_t)f->el.n * HM_WARM_LEN(f->el.d), err)))
        return err->code;
    double *prev = NULL, alpha = 1.0;
    if (dual && f->admm_relaxation != 1.0) {
        if (!(prev = hyper_term_prev(c, d, (size_t)f->el.n * hyper_elements_dual_size(&f->el), err)))
            return err->code;
        alpha = w->relax_ready ? f->admm_relaxation : 1.0;
        w->relax_ready = 1;
    }
    pl_error e;
    long long capped = w->prox.capped;
    double t0 = pl_now();
    if (hyper_elements_project_relaxed(&f->el, offset, h2, x, dual, warm, alpha, prev, work, b,
                                       &w->prox, &e) != PL_OK)
        return pl_component_fail(c, err, e.code, "%s", e.msg);
    w->prox_seconds += pl_now() - t0;
    if (w->prox.capped > capped)
        pl_log_debug("%s: %lld local solves stopped before their tolerance", c->name,
                     w->prox.capped - capped);
    return PL_OK;
}

static double fem_energy(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q)
{
    const hyper_fem *f = (const hyper_fem *)c;
    (void)d;
    const double *x = pl_buffer_f64(q);
    if (!x || q->rows < (size_t)offset + (size_t)f->el.nverts) return NAN;
    if (f->el.edge_rotation) return NAN; /* no energy (edge_rotation.c) */
    return hyper_elements_energy(&f->el, offset, x);
}

static int fem_add_gradient(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                            pl_buffer *grad, pl_error *err)
{
    const hyper_fem *f = (const hyper_fem *)c;
    if (q->location == PL_DEVICE || grad->location == PL_DEVICE) {
#ifdef PLIANT_HAVE_CUDA
        /* the data's workspace holds the device copy (per-data scratch) */
        return hyper_fem_gradient_device(f, (pl_data *)d, offset, q, grad, err);
#else
        return pl_component_fail(c, err, PL_EINPUT,
                                 "add_gradient: device buffers, but this build has no CUDA");
#endif
    }
    (void)d;
    const double *x = hyper_term_block(c, q, offset, f->el.nverts, "positions", err);
    double *g = x ? hyper_term_block(c, grad, offset, f->el.nverts, "gradient", err) : NULL;
    if (!g) return PL_EINTERNAL;
    pl_error e;
    if (hyper_elements_add_gradient(&f->el, offset, x, g, &e) != PL_OK)
        return pl_component_fail(c, err, e.code, "%s", e.msg);
    return PL_OK;
}

static int fem_add_hessian(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                           int psd, pl_triplets *H, pl_error *err)
{
    const hyper_fem *f = (const hyper_fem *)c;
    (void)d;
    const double *x = hyper_term_block(c, q, offset, f->el.nverts, "positions", err);
    if (!x) return PL_EINTERNAL;
    pl_error e;
    if (hyper_elements_add_hessian(&f->el, offset, x, psd, H, &e) != PL_OK)
        return pl_component_fail(c, err, e.code, "%s", e.msg);
    return PL_OK;
}

/* Host float64 always; device float64 (tetrahedra and triangles) in CUDA
 * builds, for project() and (PL_ACCEPTS_GRADIENT) add_gradient, which the
 * edge rotation does not have. */
static int fem_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    const hyper_fem *f = (const hyper_fem *)c;
    if ((int)prec == (PL_F64 | PL_ACCEPTS_GRADIENT)) {
        if (f->el.edge_rotation) return 0;
        prec = PL_F64;
    }
    if (prec != PL_F64) return 0;
    if (where == PL_HOST) return 1;
#ifdef PLIANT_HAVE_CUDA
    return 1;
#else
    return 0;
#endif
}

const pl_local_term_ops hyper_fem_local_term_ops = {
    .version = PL_LOCAL_TERM_OPS_VERSION,
    .state = fem_state,
    .add_matrix = fem_add_matrix,
    .project = fem_project,
    .energy = fem_energy,
    .add_gradient = fem_add_gradient,
    .add_hessian = fem_add_hessian,
    .matrix_changed = NULL,
    .accepts = fem_accepts,
};
