/* constant_force_field.c - ConstantForceField: fixed forces on vertices.
 *
 * It plays the local-term role with G = 0: nothing enters the matrix, and
 * every local step adds h^2 f to the right-hand side (the same as putting
 * h^2 M^-1 f into the predicted state).  Its energy is -f . q, so the
 * Newton reference sees the same load.
 *
 * On device buffers (LocalGlobalSolver device="cuda") it needs no kernel of
 * its own: through the scene's device service (pl_device_ops) it keeps a
 * CSR R over its state's vertices with R(sel[k], k) = -1 and the block
 * h^2 f on the device, and sub_csr (rhs -= R (h^2 f)) adds h^2 f to the
 * selected rows of rhs, in selection order, with the CPU's rounding.  Those
 * device copies are made per pl_data, in its workspace. */
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"
#include "force.h"

typedef struct constant_force_field {
    pl_component base;
    pl_ints indices;
    pl_doubles box;
    pl_doubles forces;
    double total_force[3];
    pl_component *state;
    int *sel;
    int nsel;
    double *f;   /* nsel x 3 [N] */
} constant_force_field;

/* Per data (pl_data_workspace): the device copies, made on the first device
 * project with that data. */
typedef struct cf_ws {
    pl_component *dev;
    const pl_device_ops *dops;
    pl_csr R;    /* device arrays: rows = selected vertices' range, R(sel[k], k) = -1 */
    double *hf;  /* device nsel x 3: h2 f */
    double *hf_host;
    double h2;   /* the h2 of hf (0: not uploaded yet) */
} cf_ws;

static const pl_field FIELDS[] = {
    PL_FIELD(constant_force_field, indices, "indices", PL_F_INTS, NULL,
             "loaded vertices (0-based)", 0),
    PL_FIELD(constant_force_field, box, "box", PL_F_DOUBLES, NULL,
             "boxes selecting loaded vertices by rest position [m]: xmin ymin zmin xmax ymax zmax "
             "each",
             0),
    PL_FIELD(constant_force_field, forces, "forces", PL_F_DOUBLES, NULL,
             "force on each selected vertex [N]: one x y z for all, or x y z per vertex", 0),
    PL_FIELD(constant_force_field, total_force, "totalForce", PL_F_VEC3, "0 0 0",
             "force shared equally by the selected vertices [N] (used when forces is empty)", 0),
};

static int cf_bind(pl_component *c, pl_ctx *ctx)
{
    constant_force_field *f = (constant_force_field *)c;
    if (!(f->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    f->nsel = pl_util_select_checked(c, ctx, f->state, &f->box, &f->indices, &f->sel);
    if (f->nsel < 0) return PL_EINPUT;
    if (f->nsel == 0) return pl_component_error(c, ctx, PL_EINPUT, "selects no vertex");
    if (f->forces.n && f->forces.n != 3 && f->forces.n != 3 * f->nsel)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "forces: expected 3 numbers or 3 per selected vertex (%d), "
                                  "found %d",
                                  3 * f->nsel, f->forces.n);
    f->f = malloc((size_t)f->nsel * 3 * sizeof *f->f);
    if (!f->f) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    for (int k = 0; k < f->nsel; ++k)
        for (int j = 0; j < 3; ++j)
            f->f[3 * k + j] = f->forces.n ? f->forces.v[f->forces.n == 3 ? j : 3 * k + j]
                                          : f->total_force[j] / f->nsel;
    return PL_OK;
}

static void cf_device_free(cf_ws *f)
{
    if (f->dev) {
        pl_error err;
        f->dops->sync(f->dev, &err); /* nothing may still read them */
        f->dops->free(f->dev, f->R.p);
        f->dops->free(f->dev, f->R.j);
        f->dops->free(f->dev, f->R.x);
        f->dops->free(f->dev, f->hf);
    }
    free(f->hf_host);
    f->dev = NULL, f->dops = NULL, f->hf = NULL, f->hf_host = NULL, f->h2 = 0.0;
    memset(&f->R, 0, sizeof f->R);
}

static void cf_destroy(pl_component *c)
{
    constant_force_field *f = (constant_force_field *)c;
    free(f->sel);
    free(f->f);
}

static void cf_workspace_free(const pl_component *c, void *ws)
{
    (void)c;
    cf_device_free(ws);
}

static pl_component *cf_state(const pl_component *c)
{
    return ((const constant_force_field *)c)->state;
}

static int cf_add_matrix(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err)
{
    return PL_OK;
}

/* The scene's device service (this node or above), or NULL. */
static const pl_device_ops *find_device(const pl_component *c, pl_component **dev)
{
    *dev = pl_util_device(c);
    const pl_device_ops *ops = *dev ? pl_component_role(*dev, PL_ROLE_DEVICE) : NULL;
    return ops && ops->version >= 1 && ops->sub_csr && ops->alloc && ops->copy ? ops : NULL;
}

/* R and the device block in w, from the selection (once per data). */
static int device_prepare(const constant_force_field *f, cf_ws *w, pl_error *err)
{
    const pl_component *c = &f->base;
    if (w->dev) return PL_OK;
    pl_component *dev;
    const pl_device_ops *o = find_device(c, &dev);
    if (!o)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: device buffers, but no device service in this node "
                                 "or above");
    /* components of a node are destroyed in reverse order: the device must
     * outlive this force field, which frees its memory through it */
    if (dev->node == c->node)
        for (int k = 0; k < c->node->ncomponents && c->node->components[k] != dev; ++k)
            if (c->node->components[k] == c)
                return pl_component_fail(c, err, PL_EINPUT,
                                         "%s must come before this force field in the scene",
                                         dev->name);
    int rows = 0;
    for (int k = 0; k < f->nsel; ++k)
        if (f->sel[k] + 1 > rows) rows = f->sel[k] + 1;
    int *p = calloc((size_t)rows + 1, sizeof *p), *j = malloc((size_t)f->nsel * sizeof *j);
    double *x = malloc((size_t)f->nsel * sizeof *x);
    w->hf_host = malloc((size_t)f->nsel * 3 * sizeof *w->hf_host);
    int rc = p && j && x && w->hf_host ? PL_OK
                                       : pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    if (!rc) {
        /* row v lists the k with sel[k] = v in increasing k: the CPU's order */
        for (int k = 0; k < f->nsel; ++k) p[f->sel[k] + 1]++;
        for (int v = 0; v < rows; ++v) p[v + 1] += p[v];
        int *next = malloc(((size_t)rows + 1) * sizeof *next);
        if (!next) rc = pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        for (int v = 0; !rc && v < rows; ++v) next[v] = p[v];
        for (int k = 0; !rc && k < f->nsel; ++k) {
            int at = next[f->sel[k]]++;
            j[at] = k;
            x[at] = -1.0;
        }
        free(next);
    }
    w->dev = dev, w->dops = o;
    w->R.nrows = rows, w->R.ncols = f->nsel;
    size_t ip = ((size_t)rows + 1) * sizeof(int), ij = (size_t)f->nsel * sizeof(int);
    size_t ix = (size_t)f->nsel * sizeof(double);
    if (!rc && (!(w->R.p = o->alloc(dev, ip, err)) || !(w->R.j = o->alloc(dev, ij, err)) ||
                !(w->R.x = o->alloc(dev, ix, err)) || !(w->hf = o->alloc(dev, 3 * ix, err))))
        rc = err->code ? err->code : PL_EINTERNAL;
    if (!rc) rc = o->copy(dev, w->R.p, PL_DEVICE, p, PL_HOST, ip, err);
    if (!rc) rc = o->copy(dev, w->R.j, PL_DEVICE, j, PL_HOST, ij, err);
    if (!rc) rc = o->copy(dev, w->R.x, PL_DEVICE, x, PL_HOST, ix, err);
    if (!rc) rc = o->sync(dev, err); /* p, j, x go below */
    free(p), free(j), free(x);
    if (rc) cf_device_free(w);
    return rc;
}

static int cf_project_device(const constant_force_field *f, pl_data *d, int offset, double h2,
                             pl_buffer *rhs, pl_error *err)
{
    const pl_component *c = &f->base;
    const pl_state_ops *so = pl_component_role(f->state, PL_ROLE_STATE);
    int n = so->count(f->state);
    if (rhs->location != PL_DEVICE || rhs->precision != PL_F64 || rhs->cols != 3 || offset < 0 ||
        rhs->rows < (size_t)offset + (size_t)n)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "project: expected a device float64 block of at least %d x 3",
                                 offset + n);
    cf_ws *w = pl_data_workspace(d, c);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    int rc = device_prepare(f, w, err);
    if (rc) return rc;
    if (h2 != w->h2) {
        /* h2 f as the CPU forms it; only when h2 changes (not while a graph
         * is being recorded: h2 is the same in every iteration) */
        for (int k = 0; k < 3 * f->nsel; ++k) w->hf_host[k] = h2 * f->f[k];
        rc = w->dops->copy(w->dev, w->hf, PL_DEVICE, w->hf_host, PL_HOST,
                           (size_t)f->nsel * 3 * sizeof(double), err);
        if (!rc) rc = w->dops->sync(w->dev, err);
        if (rc) return rc;
        w->h2 = h2;
    }
    return w->dops->sub_csr(w->dev, &w->R, w->hf, (double *)rhs->data + 3 * (size_t)offset, err);
}

static int cf_project(const pl_component *c, pl_data *d, int offset, double h2, const pl_buffer *q,
                      pl_buffer *rhs, pl_error *err)
{
    const constant_force_field *f = (const constant_force_field *)c;
    (void)q;
    if (rhs->location == PL_DEVICE) return cf_project_device(f, d, offset, h2, rhs, err);
    double *r = pl_buffer_f64(rhs);
    if (!r) return pl_component_fail(c, err, PL_EINTERNAL, "needs a host float64 buffer");
    for (int k = 0; k < f->nsel; ++k)
        for (int j = 0; j < 3; ++j) r[3 * (offset + f->sel[k]) + j] += h2 * f->f[3 * k + j];
    return PL_OK;
}

static double cf_energy(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q)
{
    const constant_force_field *f = (const constant_force_field *)c;
    const double *x = q->data;
    double e = 0.0;
    for (int k = 0; k < f->nsel; ++k)
        for (int j = 0; j < 3; ++j) e -= f->f[3 * k + j] * x[3 * (offset + f->sel[k]) + j];
    return e;
}

static int cf_gradient(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                       pl_buffer *grad, pl_error *err)
{
    const constant_force_field *f = (const constant_force_field *)c;
    double *g = pl_buffer_f64(grad);
    if (!g) return pl_component_fail(c, err, PL_EINTERNAL, "needs a host float64 buffer");
    for (int k = 0; k < f->nsel; ++k)
        for (int j = 0; j < 3; ++j) g[3 * (offset + f->sel[k]) + j] -= f->f[3 * k + j];
    return PL_OK;
}

static int cf_hessian(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                      int psd, pl_triplets *H, pl_error *err)
{
    return PL_OK; /* a constant force has no stiffness */
}

/* Host float64; device float64 with a device service in this node or above. */
static int cf_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    pl_component *dev;
    if (prec != PL_F64) return 0;
    return where == PL_HOST || (where == PL_DEVICE && find_device(c, &dev) != NULL);
}

static const pl_local_term_ops OPS = {
    .version = PL_LOCAL_TERM_OPS_VERSION,
    .state = cf_state,
    .add_matrix = cf_add_matrix,
    .project = cf_project,
    .energy = cf_energy,
    .add_gradient = cf_gradient,
    .add_hessian = cf_hessian,
    .accepts = cf_accepts,
};

const pl_type pl_constant_force_field_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "ConstantForceField",
    .help = "Constant forces on selected vertices (a tip load, a pull).",
    .size = sizeof(constant_force_field),
    .workspace_size = sizeof(cf_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = cf_bind, .destroy = cf_destroy, .workspace_free = cf_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &OPS},
};
