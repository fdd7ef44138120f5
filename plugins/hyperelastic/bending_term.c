/* bending_term.c - the cloth bending local terms: a stencil per interior
 * edge (isometric) or per vertex (Laplace-Beltrami), rebuilt in reinit from
 * the state's rest positions; no state of their own.  project() on device
 * buffers (CUDA builds) goes to stencil_device.c. */
#include <math.h>

#include "pliant/util.h"
#include "bending_term.h"
#include "fem_term.h"
#ifdef PLIANT_HAVE_CUDA
#include "stencil_device.h"
#endif

int hyper_bending_init(pl_component *c, pl_ctx *ctx, hyper_bending_kind kind)
{
    hyper_bending *b = (hyper_bending *)c;
    b->kind = kind;
    b->mesh = pl_util_topology(c, &b->src, ctx, 1);
    if (!b->mesh) return PL_EINPUT;
    if (b->mesh->ntris == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "needs triangles: its mesh has %d tetrahedra and no triangle",
                                  b->mesh->ntets);
    if (!(b->stiffness >= 0.0) || !isfinite(b->stiffness))
        return pl_component_error(c, ctx, PL_EINPUT, "stiffness must be >= 0 [N m], got %g",
                                  b->stiffness);
    return PL_OK;
}

int hyper_bending_bind(pl_component *c, pl_ctx *ctx)
{
    hyper_bending *b = (hyper_bending *)c;
    b->state = pl_util_state(c, ctx, 1);
    return b->state ? PL_OK : PL_EINPUT;
}

int hyper_bending_reinit(pl_component *c, pl_ctx *ctx)
{
    hyper_bending *b = (hyper_bending *)c;
    hyper_stencils_free(&b->s); /* workspaces (device copies) are remade after a reinit */
    if (!b->state || !b->mesh) return PL_EINPUT;
    int n;
    const double *rest = pl_util_rest(b->state, &n);
    if (!rest) return pl_component_error(c, ctx, PL_EINPUT, "its state has no rest positions");
    pl_error err;
    int rc, skipped = 0;
    if (b->kind == HYPER_BENDING_ISOMETRIC)
        rc = hyper_isometric_bending_build(&b->s, b->mesh->tris, b->mesh->ntris, rest, n,
                                              b->stiffness, &skipped, &err);
    else
        rc = hyper_laplace_beltrami_build(&b->s, b->mesh->tris, b->mesh->ntris, rest, n,
                                             b->stiffness, &err);
    if (rc != PL_OK) return pl_component_error(c, ctx, rc, "%s", err.msg);
    if (skipped)
        pl_component_warn(c, ctx, "%d non-manifold edges (more than two triangles) carry no "
                                  "bending", skipped);
    if (b->kind == HYPER_BENDING_ISOMETRIC) {
        /* the quadratic model assumes a flat rest state: |K x| ~ |e| theta
         * estimates each edge's rest dihedral angle */
        double worst = 0.0;
        for (int r = 0; r < b->s.n; ++r) {
            double y[3] = {0, 0, 0}, e2 = 0.0;
            for (int k = b->s.ptr[r]; k < b->s.ptr[r + 1]; ++k)
                for (int a = 0; a < 3; ++a) y[a] += b->s.coef[k] * rest[3 * b->s.vert[k] + a];
            const double *x0 = rest + 3 * b->s.vert[b->s.ptr[r]];
            const double *x1 = rest + 3 * b->s.vert[b->s.ptr[r] + 1];
            for (int a = 0; a < 3; ++a) e2 += (x1[a] - x0[a]) * (x1[a] - x0[a]);
            worst = fmax(worst, sqrt((y[0] * y[0] + y[1] * y[1] + y[2] * y[2]) / e2));
        }
        if (worst > 1e-3)
            pl_component_warn(c, ctx, "the rest shape is not flat (dihedral angles up to about "
                                      "%.3g rad): isometric bending pulls it flat; "
                                      "LaplaceBeltramiBending keeps a curved rest shape", worst);
    }
    return PL_OK;
}

void hyper_bending_destroy(pl_component *c)
{
    hyper_stencils_free(&((hyper_bending *)c)->s);
}

static pl_component *bend_state(const pl_component *c)
{
    return ((const hyper_bending *)c)->state;
}

static int bend_add_matrix(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err)
{
    pl_error e;
    if (hyper_stencils_add_matrix(&((hyper_bending *)c)->s, offset, h2, A, &e) != PL_OK)
        return pl_component_fail(c, err, e.code, "%s", e.msg);
    return PL_OK;
}

static int bend_project(const pl_component *c, pl_data *d, int offset, double h2,
                        const pl_buffer *q, pl_buffer *rhs, pl_error *err)
{
    const hyper_bending *b = (const hyper_bending *)c;
    if (q->location == PL_DEVICE || rhs->location == PL_DEVICE) {
#ifdef PLIANT_HAVE_CUDA
        hyper_term_ws *w = pl_data_workspace(d, c);
        if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
        return hyper_stencil_project_device(c, &b->s, &w->stencil, d, NULL, offset, h2, q, rhs,
                                            err);
#else
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: device buffers, but this build has no CUDA");
#endif
    }
    const double *x = hyper_term_block(c, q, offset, b->s.nverts, "positions", err);
    double *r = x ? hyper_term_block(c, rhs, offset, b->s.nverts, "right-hand side", err) : NULL;
    if (!r) return PL_EINTERNAL;
    double *work = hyper_term_work(c, d, hyper_stencils_work_size(&b->s), err);
    if (!work) return err->code;
    return hyper_stencils_project(&b->s, offset, h2, x, NULL, work, r, err);
}

static double bend_energy(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q)
{
    const hyper_bending *b = (const hyper_bending *)c;
    (void)d;
    const double *x = pl_buffer_f64(q);
    if (!x || q->rows < (size_t)offset + (size_t)b->s.nverts) return NAN;
    return hyper_stencils_energy(&b->s, offset, x, NULL);
}

static int bend_add_gradient(const pl_component *c, const pl_data *d, int offset,
                             const pl_buffer *q, pl_buffer *grad, pl_error *err)
{
    const hyper_bending *b = (const hyper_bending *)c;
    (void)d;
    const double *x = hyper_term_block(c, q, offset, b->s.nverts, "positions", err);
    double *g = x ? hyper_term_block(c, grad, offset, b->s.nverts, "gradient", err) : NULL;
    if (!g) return PL_EINTERNAL;
    return hyper_stencils_add_gradient(&b->s, offset, x, NULL, g, err);
}

static int bend_add_hessian(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                            int psd, pl_triplets *H, pl_error *err)
{
    const hyper_bending *b = (const hyper_bending *)c;
    (void)d;
    const double *x = hyper_term_block(c, q, offset, b->s.nverts, "positions", err);
    if (!x) return PL_EINTERNAL;
    return hyper_stencils_add_hessian(&b->s, offset, x, psd, H, err);
}

/* Host float64 always; device float64 in CUDA builds. */
static int bend_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    (void)c;
    if (prec != PL_F64) return 0;
#ifdef PLIANT_HAVE_CUDA
    return where == PL_HOST || where == PL_DEVICE;
#else
    return where == PL_HOST;
#endif
}

const pl_local_term_ops hyper_bending_local_term_ops = {
    .version = PL_LOCAL_TERM_OPS_VERSION,
    .state = bend_state,
    .add_matrix = bend_add_matrix,
    .project = bend_project,
    .energy = bend_energy,
    .add_gradient = bend_add_gradient,
    .add_hessian = bend_add_hessian,
    .matrix_changed = NULL,
    .accepts = bend_accepts,
};
