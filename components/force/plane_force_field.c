/* plane_force_field.c - PlaneForceField: SOFA's penalty plane.
 *
 * Every vertex of the node's state with d = n . x - D < 0 (below the plane;
 * any d with bilateral) is pushed back by f = -k d n: the energy
 * psi = k/2 d^2, with n as given (SOFA does not normalise it either, so k
 * is per unit of |n|^2).  SOFA adds a damping force damping * d * v on those
 * vertices (depth-weighted, along the whole velocity) and gives it no
 * matrix: it is explicit in SOFA's linearised step.  Here it is the same
 * explicit force: evaluated at begin_step from the step's start (x_t, v_t)
 * and held constant during the step, like a ConstantForceField.
 *
 * What each solver sees:
 *  - LocalGlobalSolver (Projective Dynamics): per vertex the projection p
 *    of q onto the half-space n . x >= D (onto the plane with bilateral),
 *    with weight w = k |n|^2, so that w/2 |q - p|^2 = k/2 d^2 exactly; the
 *    matrix gets w on every vertex (constant: PD's price is slower
 *    convergence where nothing touches, not a different answer);
 *  - NewtonSolver and LinearizedEulerSolver: the gradient k d n and the
 *    Hessian k n n^T of the vertices below (PSD as it stands). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"
#include "force.h"

typedef struct plane_force_field {
    pl_component base;
    double normal[3];
    double d;         /* plane offset D: n . x = D on the plane */
    double stiffness; /* k [N/m per |n|^2] */
    double damping;   /* [N s/m^2]: SOFA's depth-weighted velocity damping */
    int bilateral;
    pl_component *state;
    int n;            /* vertices of the state */
} plane_force_field;

/* Per data: the damping force of the step being taken (n x 3) [N]. */
typedef struct pf_ws {
    double *fd;
    int n;
} pf_ws;

static const pl_field FIELDS[] = {
    PL_FIELD(plane_force_field, normal, "normal", PL_F_VEC3, "0 1 0",
             "plane normal, pointing to the free side (not normalised: the force is "
             "stiffness * depth * normal, as in SOFA)",
             0),
    PL_FIELD(plane_force_field, d, "d", PL_F_DOUBLE, "0",
             "plane offset: the plane is normal . x = d [m]", 0),
    PL_FIELD(plane_force_field, stiffness, "stiffness", PL_F_DOUBLE, "500",
             "penalty stiffness [N/m]: energy stiffness/2 (normal . x - d)^2 below the plane", 0),
    PL_FIELD(plane_force_field, damping, "damping", PL_F_DOUBLE, "5",
             "SOFA's damping: force damping * (normal . x - d) * v on the vertices below the "
             "plane [N s/m^2], evaluated at the start of each step (explicit, as in SOFA)",
             0),
    PL_FIELD(plane_force_field, bilateral, "bilateral", PL_F_BOOL, "0",
             "push on both sides (keeps the vertices on the plane)", 0),
};

static double norm2(const double *n) { return n[0] * n[0] + n[1] * n[1] + n[2] * n[2]; }

static int pf_init(pl_component *c, pl_ctx *ctx)
{
    plane_force_field *p = (plane_force_field *)c;
    if (!(norm2(p->normal) > 0) || !isfinite(norm2(p->normal)))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "normal (%g %g %g): a plane needs a non-zero, finite normal",
                                  p->normal[0], p->normal[1], p->normal[2]);
    if (!(p->stiffness >= 0) || !isfinite(p->stiffness))
        return pl_component_error(c, ctx, PL_EINPUT, "stiffness must be >= 0 [N/m], got %g",
                                  p->stiffness);
    if (!(p->damping >= 0) || !isfinite(p->damping))
        return pl_component_error(c, ctx, PL_EINPUT, "damping must be >= 0, got %g", p->damping);
    if (!isfinite(p->d)) return pl_component_error(c, ctx, PL_EINPUT, "d must be finite");
    return PL_OK;
}

static int pf_bind(pl_component *c, pl_ctx *ctx)
{
    plane_force_field *p = (plane_force_field *)c;
    if (!(p->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    const pl_state_ops *so = pl_component_role(p->state, PL_ROLE_STATE);
    p->n = so->count(p->state);
    return PL_OK;
}

/* Signed depth of x: n . x - D (< 0 below). */
static double depth(const plane_force_field *p, const double *x)
{
    return p->normal[0] * x[0] + p->normal[1] * x[1] + p->normal[2] * x[2] - p->d;
}

static int pushed(const plane_force_field *p, double dist) { return p->bilateral || dist < 0; }

/* The damping force at the step's start, into the data's workspace. */
static int pf_begin_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    const plane_force_field *p = (const plane_force_field *)c;
    pf_ws *w = pl_data_workspace(ctx->data, c);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    if (!w->fd) {
        w->fd = calloc((size_t)p->n * 3, sizeof *w->fd);
        if (!w->fd) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
        w->n = p->n;
    }
    memset(w->fd, 0, (size_t)p->n * 3 * sizeof *w->fd);
    if (p->damping == 0) return PL_OK;
    const pl_state_ops *so = pl_component_role(p->state, PL_ROLE_STATE);
    pl_buffer xb = so->positions(p->state, ctx->data), vb = so->velocities(p->state, ctx->data);
    const double *x = pl_buffer_f64(&xb), *v = pl_buffer_f64(&vb);
    if (!x || !v)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "damping needs the state's positions and velocities on the host");
    for (int i = 0; i < p->n; ++i) {
        double dist = depth(p, x + 3 * i);
        if (pushed(p, dist))
            for (int j = 0; j < 3; ++j) w->fd[3 * i + j] = p->damping * dist * v[3 * i + j];
    }
    return PL_OK;
}

static void pf_workspace_free(const pl_component *c, void *ws)
{
    (void)c;
    free(((pf_ws *)ws)->fd);
}

/* The step's damping force (NULL: none yet, e.g. before the first step). */
static const double *damping_force(const plane_force_field *p, const pl_data *d)
{
    if (p->damping == 0) return NULL;
    pf_ws *w = pl_data_workspace((pl_data *)d, &p->base);
    return w && w->fd && w->n == p->n ? w->fd : NULL;
}

/* ---- PL_ROLE_LOCAL_TERM --------------------------------------------------- */

static pl_component *pf_state(const pl_component *c) { return ((const plane_force_field *)c)->state; }

static int pf_add_matrix(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err)
{
    const plane_force_field *p = (const plane_force_field *)c;
    double w = h2 * p->stiffness * norm2(p->normal);
    for (int i = 0; i < p->n; ++i)
        if (pl_triplets_add(A, offset + i, offset + i, w) != PL_OK)
            return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    return PL_OK;
}

/* The host block of b for this term's vertices, or NULL (err set). */
static double *host_block(const plane_force_field *p, const pl_buffer *b, int offset, pl_error *err)
{
    double *x = pl_buffer_f64(b);
    if (!x || b->cols != 3 || offset < 0 || b->rows < (size_t)offset + (size_t)p->n) {
        pl_component_fail(&p->base, err, PL_EINPUT, "expected a host float64 block of %d x 3",
                          offset + p->n);
        return NULL;
    }
    return x + 3 * (size_t)offset;
}

static int pf_project(const pl_component *c, pl_data *d, int offset, double h2, const pl_buffer *q,
                      pl_buffer *rhs, pl_error *err)
{
    const plane_force_field *p = (const plane_force_field *)c;
    const double *x = host_block(p, q, offset, err);
    double *r = x ? host_block(p, rhs, offset, err) : NULL;
    if (!r) return err->code;
    const double *fd = damping_force(p, d), nn = norm2(p->normal);
    double w = h2 * p->stiffness * nn;
    for (int i = 0; i < p->n; ++i) {
        double dist = depth(p, x + 3 * i), s = pushed(p, dist) ? dist / nn : 0.0;
        for (int j = 0; j < 3; ++j) { /* p_i = x_i - s n: the half-space's closest point */
            r[3 * i + j] += w * (x[3 * i + j] - s * p->normal[j]);
            if (fd) r[3 * i + j] += h2 * fd[3 * i + j];
        }
    }
    return PL_OK;
}

static double pf_energy(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q)
{
    const plane_force_field *p = (const plane_force_field *)c;
    const double *x = pl_buffer_f64(q), *fd = damping_force(p, d);
    if (!x || q->rows < (size_t)offset + (size_t)p->n) return NAN;
    x += 3 * (size_t)offset;
    double e = 0.0;
    for (int i = 0; i < p->n; ++i) {
        double dist = depth(p, x + 3 * i);
        if (pushed(p, dist)) e += 0.5 * p->stiffness * dist * dist;
        if (fd) e -= fd[3 * i] * x[3 * i] + fd[3 * i + 1] * x[3 * i + 1] + fd[3 * i + 2] * x[3 * i + 2];
    }
    return e;
}

static int pf_gradient(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                       pl_buffer *grad, pl_error *err)
{
    const plane_force_field *p = (const plane_force_field *)c;
    const double *x = host_block(p, q, offset, err);
    double *g = x ? host_block(p, grad, offset, err) : NULL;
    if (!g) return err->code;
    const double *fd = damping_force(p, d);
    for (int i = 0; i < p->n; ++i) {
        double dist = depth(p, x + 3 * i);
        for (int j = 0; j < 3; ++j) {
            if (pushed(p, dist)) g[3 * i + j] += p->stiffness * dist * p->normal[j];
            if (fd) g[3 * i + j] -= fd[3 * i + j];
        }
    }
    return PL_OK;
}

static int pf_hessian(const pl_component *c, const pl_data *d, int offset, const pl_buffer *q,
                      int psd, pl_triplets *H, pl_error *err)
{
    const plane_force_field *p = (const plane_force_field *)c;
    (void)d, (void)psd; /* k n n^T is PSD as it stands */
    const double *x = host_block(p, q, offset, err);
    if (!x) return err->code;
    for (int i = 0; i < p->n; ++i) {
        if (!pushed(p, depth(p, x + 3 * i))) continue;
        int base = 3 * (offset + i);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (pl_triplets_add(H, base + a, base + b, p->stiffness * p->normal[a] * p->normal[b]))
                    return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    }
    return PL_OK;
}

static int pf_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    (void)c;
    return where == PL_HOST && prec == PL_F64;
}

static const pl_local_term_ops OPS = {
    .version = PL_LOCAL_TERM_OPS_VERSION,
    .state = pf_state,
    .add_matrix = pf_add_matrix,
    .project = pf_project,
    .energy = pf_energy,
    .add_gradient = pf_gradient,
    .add_hessian = pf_hessian,
    .accepts = pf_accepts,
};

const pl_type pl_plane_force_field_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "PlaneForceField",
    .help = "SOFA's penalty plane: vertices below normal . x = d are pushed back with "
            "stiffness * depth (energy stiffness/2 depth^2) and SOFA's explicit "
            "depth-weighted damping.",
    .size = sizeof(plane_force_field),
    .workspace_size = sizeof(pf_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = pf_init,
            .bind = pf_bind,
            .begin_step = pf_begin_step,
            .workspace_free = pf_workspace_free},
    .roles = {[PL_ROLE_LOCAL_TERM] = &OPS},
};
