/* constant_force_field.c - ConstantForceField: fixed forces on vertices.
 *
 * It plays the local-term role with G = 0: nothing enters the matrix, and
 * every local step adds h^2 f to the right-hand side (the same as putting
 * h^2 M^-1 f into the predicted state).  Its energy is -f . q, so the
 * Newton reference sees the same load. */
#include <stdlib.h>
#include <string.h>

#include "base/component_util.h"
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

static void cf_destroy(pl_component *c)
{
    constant_force_field *f = (constant_force_field *)c;
    free(f->sel);
    free(f->f);
}

static pl_component *cf_state(const pl_component *c)
{
    return ((const constant_force_field *)c)->state;
}

static int cf_add_matrix(pl_component *c, int offset, double h2, pl_triplets *A, pl_error *err)
{
    return PL_OK;
}

static int cf_project(pl_component *c, pl_data *d, int offset, double h2, const pl_buffer *q,
                      pl_buffer *rhs, pl_error *err)
{
    const constant_force_field *f = (const constant_force_field *)c;
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

static const pl_local_term_ops OPS = {
    .version = PL_LOCAL_TERM_OPS_VERSION,
    .state = cf_state,
    .add_matrix = cf_add_matrix,
    .project = cf_project,
    .energy = cf_energy,
    .add_gradient = cf_gradient,
    .add_hessian = cf_hessian,
};

const pl_type pl_constant_force_field_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "ConstantForceField",
    .help = "Constant forces on selected vertices (a tip load, a pull).",
    .size = sizeof(constant_force_field),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = cf_bind, .destroy = cf_destroy},
    .roles = {[PL_ROLE_LOCAL_TERM] = &OPS},
};
