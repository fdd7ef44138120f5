/* fixed_constraint.c - FixedConstraint: vertices held at their rest
 * positions.  They are eliminated from the unknowns by the solver (never
 * held by stiff springs, which would ruin the conditioning of A). */
#include <stdlib.h>

#include "pliant/util.h"
#include "prescribed.h"

typedef struct fixed_constraint {
    pl_component base;
    pl_ints indices;
    pl_doubles box;
    int fix_all;
    pl_component *state;
    int *sel;
    int nsel;
} fixed_constraint;

static const pl_field FIELDS[] = {
    PL_FIELD(fixed_constraint, indices, "indices", PL_F_INTS, NULL,
             "vertices to fix (0-based indices into the MechanicalObject)", 0),
    PL_FIELD(fixed_constraint, box, "box", PL_F_DOUBLES, NULL,
             "boxes selecting vertices by rest position [m]: xmin ymin zmin xmax ymax zmax each", 0),
    PL_FIELD(fixed_constraint, fix_all, "fixAll", PL_F_BOOL, "0", "fix every vertex", 0),
};

static int fc_bind(pl_component *c, pl_ctx *ctx)
{
    fixed_constraint *f = (fixed_constraint *)c;
    if (!(f->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    if (f->fix_all) {
        int n;
        pl_util_rest(f->state, &n);
        f->sel = malloc((size_t)n * sizeof *f->sel);
        if (!f->sel) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
        for (int i = 0; i < n; ++i) f->sel[i] = i;
        f->nsel = n;
    } else {
        f->nsel = pl_util_select_checked(c, ctx, f->state, &f->box, &f->indices, &f->sel);
        if (f->nsel < 0) return PL_EINPUT;
    }
    if (f->nsel == 0)
        pl_component_warn(c, ctx, "selects no vertex (check indices and box)");
    return PL_OK;
}

static void fc_destroy(pl_component *c) { free(((fixed_constraint *)c)->sel); }

static pl_component *fc_state(const pl_component *c)
{
    return ((const fixed_constraint *)c)->state;
}

static int fc_indices(const pl_component *c, const int **idx)
{
    const fixed_constraint *f = (const fixed_constraint *)c;
    *idx = f->sel;
    return f->nsel;
}

static int fc_positions(const pl_component *c, const pl_data *d, double t, double *out,
                        pl_error *err)
{
    const fixed_constraint *f = (const fixed_constraint *)c;
    int n;
    const double *x = pl_util_rest(f->state, &n);
    for (int k = 0; k < f->nsel; ++k)
        for (int j = 0; j < 3; ++j) out[3 * k + j] = x[3 * f->sel[k] + j];
    return PL_OK;
}

static const pl_prescribed_ops OPS = {.version = PL_PRESCRIBED_OPS_VERSION,
                                      .state = fc_state,
                                      .indices = fc_indices,
                                      .positions_at = fc_positions};

const pl_type pl_fixed_constraint_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "FixedConstraint",
    .help = "Holds vertices (by indices or boxes) at their rest positions; they are removed from "
            "the unknowns.",
    .size = sizeof(fixed_constraint),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = fc_bind, .destroy = fc_destroy},
    .roles = {[PL_ROLE_PRESCRIBED] = &OPS},
};
