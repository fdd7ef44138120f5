/* cable_constraint.c - CableConstraint: a cable through a body, pulled from a
 * fixed point, with SoftRobots' field names and meanings.  Its length L
 * (cable.h) is driven to cableInitialLength - value (valueType displacement)
 * or pulled with the tension value (valueType force).  Once per step it
 * emits rows of H linearised at the start of the step:
 *     H = -dL/dx (at q_t),   delta = H q - d = L_target - L_lin(q),
 *     L_lin(q) = L(q_t) + dL/dx . (q - q_t)
 * so lambda > 0 is a tension [N] (the cable pulls, shortening itself).
 *   displacement, no force bounds:  a BILATERAL row (compliance, 0 = hard);
 *   displacement with minForce / maxForce: a BOUNDED row, lambda in
 *     [minForce, maxForce]: with minForce = 0 the cable pulls but never
 *     pushes (it goes slack, L < L_target, lambda = 0);
 *   force: a BOUNDED row with lo = hi = value (the tension is imposed, the
 *     row's delta is free); with a displacement limit the row targets the
 *     limit instead and its bounds become [minForce, value] (maxPositiveDisp:
 *     the tension drops where it would pull further) or [value, maxForce]
 *     (maxNegativeDisp); with both, the limit nearer to the displacement at
 *     the start of the step (only one can be reached at a time).
 * Why a row and not an external load for the force mode: the tension acts
 * along H, which moves with the body; as a row it enters the constrained
 * global step implicitly (q = A^-1 (b + h^2 H^T lambda) in every iteration),
 * its multiplier is reported like the displacement mode's, and a
 * displacement limit only changes the row's target and bounds.  The SDK
 * has no role for configuration-dependent external loads.
 * Outputs (lifecycle `get`, from the state): cableLength [m], displacement =
 * cableInitialLength - cableLength [m] (> 0 when pulled), force [N] (the
 * multipliers of the last step, kept in the pl_data slot "force").
 * value, valueIndex, valueType and pullPoint are input fields: their values
 * live in each pl_data (input.h), so two simulations of one scene can pull
 * differently; the row's scratch is the data's workspace. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable.h"
#include "cable_area.h"
#include "pliant/util.h"

enum { MODE_DISPLACEMENT = 0, MODE_FORCE = 1 };

typedef struct cable_constraint {
    pl_component base;
    /* fields */
    pl_ints indices;
    pl_doubles position;          /* points mapped into the tetrahedra */
    pl_doubles centers;           /* points snapped to the nearest vertex */
    double pull_point[3];
    int has_pull_point;
    pl_doubles initial_length;    /* cableInitialLength: empty = from the rest positions */
    pl_doubles value;
    int value_index;
    int value_type;
    pl_doubles min_force, max_force, max_positive_disp, max_negative_disp, max_disp_variation;
    double compliance;
    pl_link src;
    int method;                   /* CABLE_AREA_*: point, or pulled areas around centers */
    pl_doubles radii;
    pl_link surface;              /* the triangle surface the areas lie on */
    double out_length, out_displacement, out_force;
    /* model */
    pl_component *state;
    pl_cable_path path;
    double L0;                    /* cable length that displacement 0 means [m] */
    int slot;                     /* "force": the tension of the last step [N] */
} cable_constraint;

/* Per data (pl_data_workspace): the step's scratch. */
typedef struct cable_ws {
    double *g;                    /* npoints x 3: dL/dP_i */
    int *row_vert;                /* nslot npoints: merged row entries */
    double *row_coef;
} cable_ws;

/* The input fields' current values (in a data, or the scene's). */
typedef struct cable_inputs {
    pl_doubles value;
    int index, type;
    const double *pull;
} cable_inputs;

static cable_inputs inputs_of(const cable_constraint *cc, const pl_data *d)
{
    const pl_component *c = &cc->base;
    cable_inputs in = {pl_input_doubles(d, c, &cc->value), pl_input_int(d, c, &cc->value_index),
                       pl_input_int(d, c, &cc->value_type), pl_input_vec3(d, c, cc->pull_point)};
    return in;
}

static const char *const VALUE_TYPES[] = {"displacement", "force", NULL};
static const char *const METHODS[] = {"point", "sphere", "geodesic", NULL};

#define CC cable_constraint
static const pl_field FIELDS[] = {
    PL_FIELD(CC, indices, "indices", PL_F_INTS, NULL,
             "cable points: vertices of the node's MechanicalObject, in order from the pull "
             "point to the end of the cable",
             0),
    PL_FIELD_ALIAS(CC, position, "position", PL_F_DOUBLES, NULL,
                   "cable points [m], x y z each, in order from the pull point: each follows "
                   "the tetrahedron containing it (barycentric mapping, weights computed at "
                   "load from the rest positions)",
                   0, "positions"),
    PL_FIELD(CC, centers, "centers", PL_F_DOUBLES, NULL,
             "cable points [m], x y z each: each is replaced by the nearest vertex (as "
             "SoftRobots' centers); with method sphere / geodesic the centers of the pulled "
             "areas",
             0),
    PL_FIELD(CC, pull_point, "pullPoint", PL_F_VEC3, "0 0 0",
             "fixed point the cable is pulled from [m]", PL_FIELD_INPUT),
    PL_FIELD(CC, has_pull_point, "hasPullPoint", PL_F_BOOL, "1",
             "0: no fixed pull point, the cable starts at its first point (needs two points)", 0),
    PL_FIELD(CC, initial_length, "cableInitialLength", PL_F_DOUBLES, NULL,
             "length that displacement 0 refers to [m] (one number; default: the length at "
             "the rest positions)",
             0),
    PL_FIELD(CC, value, "value", PL_F_DOUBLES, "0",
             "displacement [m] (shortening, > 0 pulls) or tension [N] to impose; a list, "
             "value[valueIndex] is used",
             PL_FIELD_INPUT),
    PL_FIELD(CC, value_index, "valueIndex", PL_F_INT, "0", "index of the entry of value to impose",
             PL_FIELD_INPUT),
    PL_FIELD_ENUM(CC, value_type, "valueType", VALUE_TYPES, "displacement",
                  "displacement: drive the length to cableInitialLength - value; force: pull "
                  "with the tension value",
                  PL_FIELD_INPUT),
    PL_FIELD(CC, min_force, "minForce", PL_F_DOUBLES, NULL,
             "lowest tension [N] (one number, empty = none): 0 makes a cable that pulls but "
             "never pushes",
             PL_FIELD_RUNTIME),
    PL_FIELD(CC, max_force, "maxForce", PL_F_DOUBLES, NULL,
             "highest tension [N] (one number, empty = none)", PL_FIELD_RUNTIME),
    PL_FIELD(CC, max_positive_disp, "maxPositiveDisp", PL_F_DOUBLES, NULL,
             "largest displacement [m] (one number, empty = none): clamps the commanded "
             "displacement, or limits the displacement in force mode",
             PL_FIELD_RUNTIME),
    PL_FIELD(CC, max_negative_disp, "maxNegativeDisp", PL_F_DOUBLES, NULL,
             "largest displacement in the negative direction [m] (one number, empty = none): "
             "displacement >= -maxNegativeDisp",
             PL_FIELD_RUNTIME),
    PL_FIELD(CC, max_disp_variation, "maxDispVariation", PL_F_DOUBLES, NULL,
             "largest change of the commanded displacement in one step from the current "
             "displacement [m] (one number, empty = none)",
             PL_FIELD_RUNTIME),
    PL_FIELD(CC, compliance, "compliance", PL_F_DOUBLE, "0",
             "compliance of the displacement row [m/N] (0 = hard; used when no force bound "
             "is given)",
             PL_FIELD_RUNTIME),
    PL_FIELD(CC, src, "src", PL_F_LINK, NULL,
             "mesh whose tetrahedra carry the points of `position` (default: the node's first "
             "loader or generator)",
             0),
    PL_FIELD_ENUM(CC, method, "method", METHODS, "point",
                  "point: the cable ends at its points; sphere / geodesic: each of `centers` is "
                  "an area of `surface`, its points within radii of the center (straight / "
                  "along the surface's edges) weighted by radius - distance, normalised "
                  "(cable_area.c)",
                  0),
    PL_FIELD(CC, radii, "radii", PL_F_DOUBLES, NULL,
             "radius [m] of each center's area (one for all; default 1)", 0),
    PL_FIELD(CC, surface, "surface", PL_F_LINK, NULL,
             "mesh (loader) whose triangles carry the areas; its points follow the "
             "tetrahedra of `src` (SoftRobots' surfaceTopology in a mapped node)",
             0),
    PL_FIELD(CC, out_length, "cableLength", PL_F_DOUBLE, "0", "current cable length [m]",
             PL_FIELD_OUTPUT),
    PL_FIELD(CC, out_displacement, "displacement", PL_F_DOUBLE, "0",
             "current displacement cableInitialLength - cableLength [m]", PL_FIELD_OUTPUT),
    PL_FIELD(CC, out_force, "force", PL_F_DOUBLE, "0",
             "tension of the last step [N] (> 0 pulls): the cable rows' multipliers",
             PL_FIELD_OUTPUT),
};
#undef CC

/* An optional scalar given as a list: empty = unset. */
static int opt_set(const pl_doubles *d) { return d->n > 0; }

/* Checks the fields that may change while running (the inputs as in);
 * fills msg. */
static int check_values(const cable_constraint *cc, const cable_inputs *in, char *msg, size_t size)
{
    const struct {
        const pl_doubles *d;
        const char *name;
    } opts[] = {{&cc->min_force, "minForce"},
                {&cc->max_force, "maxForce"},
                {&cc->max_positive_disp, "maxPositiveDisp"},
                {&cc->max_negative_disp, "maxNegativeDisp"},
                {&cc->max_disp_variation, "maxDispVariation"}};
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; ++k)
        if (opts[k].d->n > 1) {
            snprintf(msg, size, "%s: expected one number (or nothing), found %d", opts[k].name,
                     opts[k].d->n);
            return PL_EINPUT;
        }
    if (in->value.n < 1) {
        snprintf(msg, size, "value: expected at least one number");
        return PL_EINPUT;
    }
    if (in->index < 0 || in->index >= in->value.n) {
        snprintf(msg, size, "valueIndex: %d is out of range (value has %d entries)", in->index,
                 in->value.n);
        return PL_EINPUT;
    }
    if (opt_set(&cc->min_force) && opt_set(&cc->max_force) &&
        cc->min_force.v[0] > cc->max_force.v[0]) {
        snprintf(msg, size, "minForce (%g N) is above maxForce (%g N)", cc->min_force.v[0],
                 cc->max_force.v[0]);
        return PL_EINPUT;
    }
    if (opt_set(&cc->max_disp_variation) && !(cc->max_disp_variation.v[0] >= 0.0)) {
        snprintf(msg, size, "maxDispVariation must be >= 0 [m], got %g",
                 cc->max_disp_variation.v[0]);
        return PL_EINPUT;
    }
    if (!(cc->compliance >= 0.0)) {
        snprintf(msg, size, "compliance must be >= 0 [m/N], got %g", cc->compliance);
        return PL_EINPUT;
    }
    return PL_OK;
}

static int cc_init(pl_component *c, pl_ctx *ctx)
{
    cable_constraint *cc = (cable_constraint *)c;
    char msg[256];
    cc->slot = -1;
    int sources = (cc->indices.n > 0) + (cc->position.n > 0) + (cc->centers.n > 0);
    if (sources == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the cable is empty: give its points as indices, position or "
                                  "centers");
    if (sources > 1)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "give the cable points once: indices, position or centers, "
                                  "not several of them");
    if (cc->position.n % 3 || cc->centers.n % 3)
        return pl_component_error(c, ctx, PL_EINPUT, "%s: expected x y z per point, found %d numbers",
                                  cc->position.n ? "position" : "centers",
                                  cc->position.n ? cc->position.n : cc->centers.n);
    int npoints = cc->indices.n ? cc->indices.n : (cc->position.n + cc->centers.n) / 3;
    if (cc->method != CABLE_AREA_POINT && (!cc->centers.n || !cc->surface.path))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "method=\"%s\" needs centers and a surface (a loader of "
                                  "triangles) to take the pulled areas from",
                                  METHODS[cc->method]);
    if (cc->method == CABLE_AREA_POINT && (cc->radii.n || cc->surface.path))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "radii and surface mean pulled areas: set method=\"geodesic\" "
                                  "or \"sphere\"");
    if (cc->radii.n > 1 && cc->radii.n != npoints)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "radii: %d values for %d centers (give one, or one per center)",
                                  cc->radii.n, npoints);
    for (int i = 0; i < cc->radii.n; ++i)
        if (!(cc->radii.v[i] > 0))
            return pl_component_error(c, ctx, PL_EINPUT, "radii: entry %d is not a positive "
                                                         "radius [m]", i);
    if (!cc->has_pull_point && npoints < 2)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "without a pull point (hasPullPoint=0) the cable needs at least "
                                  "two points, found %d",
                                  npoints);
    if (cc->initial_length.n > 1 || (cc->initial_length.n == 1 && !(cc->initial_length.v[0] > 0)))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "cableInitialLength: expected one positive length [m]");
    cable_inputs in = inputs_of(cc, NULL); /* the scene's values */
    if (check_values(cc, &in, msg, sizeof msg) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", msg);
    cc->slot = pl_model_add_slot(ctx->build, c, "force", sizeof(double));
    if (cc->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, cc->slot, pl_slot_check_finite);
    return PL_OK;
}

/* Pulled areas (method sphere / geodesic): one weighted point per center. */
static int build_area_path(cable_constraint *cc, pl_ctx *ctx, const double *x, int n)
{
    pl_component *c = &cc->base;
    const pl_mesh *sm = pl_util_topology(c, &cc->surface, ctx, 1);
    if (!sm) return PL_EINPUT;
    if (sm->ntris == 0)
        return pl_component_error(c, ctx, PL_EINPUT, "surface: '%s' has no triangles",
                                  cc->surface.path);
    const pl_mesh *m = pl_util_topology(c, &cc->src, ctx, 1);
    if (!m) return PL_EINPUT;
    if (m->ntets == 0 || m->nverts != n)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "surface: its points need a tetrahedral mesh with the state's "
                                  "%d vertices (the mesh has %d vertices, %d tetrahedra)",
                                  n, m->nverts, m->ntets);
    cable_surface s = {sm->verts, sm->nverts, sm->tris, sm->ntris};
    int bad, outside;
    int rc = cable_area_path(&cc->path, &s, cc->centers.v, cc->centers.n / 3, cc->radii.v,
                             cc->radii.n, cc->method, x, m->tets, m->ntets, &bad, &outside);
    if (rc == PL_EINTERNAL) return pl_component_error(c, ctx, rc, "out of memory");
    if (rc != PL_OK && bad >= 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "centers: no point of the surface '%s' lies within the radius "
                                  "of center %d (%g %g %g)",
                                  cc->surface.path, bad, cc->centers.v[3 * bad],
                                  cc->centers.v[3 * bad + 1], cc->centers.v[3 * bad + 2]);
    if (rc != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the mesh has no tetrahedron of positive volume");
    if (outside)
        pl_component_warn(c, ctx,
                          "surface: %d area points lie outside the body's tetrahedra; they follow "
                          "the nearest one with extrapolated weights",
                          outside);
    cc->path.has_pull = cc->has_pull_point;
    memcpy(cc->path.pull, cc->pull_point, sizeof cc->path.pull);
    return PL_OK;
}

/* The points as weighted vertices of the state (rest positions x, n). */
static int build_path(cable_constraint *cc, pl_ctx *ctx, const double *x, int n)
{
    pl_component *c = &cc->base;
    pl_cable_path *p = &cc->path;
    int npoints = cc->indices.n ? cc->indices.n : (cc->position.n + cc->centers.n) / 3;
    if (cc->method != CABLE_AREA_POINT) return build_area_path(cc, ctx, x, n);
    if (cable_path_alloc(p, npoints) != PL_OK)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    p->has_pull = cc->has_pull_point;
    memcpy(p->pull, cc->pull_point, sizeof p->pull);
    if (cc->indices.n) {
        for (int i = 0; i < npoints; ++i) {
            int v = cc->indices.v[i];
            if (v < 0 || v >= n)
                return pl_component_error(c, ctx, PL_EINPUT,
                                          "indices: %d (entry %d) is out of range: the "
                                          "MechanicalObject has %d vertices",
                                          v, i, n);
            p->vert[4 * i] = v;
            p->weight[4 * i] = 1.0;
        }
    } else if (cc->centers.n) {
        for (int i = 0; i < npoints; ++i) {
            p->vert[4 * i] = cable_nearest(x, n, cc->centers.v + 3 * i);
            p->weight[4 * i] = 1.0;
        }
    } else {
        const pl_mesh *m = pl_util_topology(c, &cc->src, ctx, 1);
        if (!m) return PL_EINPUT;
        if (m->ntets == 0 || m->nverts != n)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "position: needs a tetrahedral mesh with the state's %d "
                                      "vertices (the mesh has %d vertices, %d tetrahedra)",
                                      n, m->nverts, m->ntets);
        for (int i = 0; i < npoints; ++i) {
            const double *pt = cc->position.v + 3 * i;
            double outside;
            if (cable_locate(x, m->tets, m->ntets, pt, p->vert + 4 * i, p->weight + 4 * i,
                                &outside) < 0)
                return pl_component_error(c, ctx, PL_EINPUT,
                                          "position: the mesh has no tetrahedron of positive "
                                          "volume");
            if (outside > 1e-9)
                pl_component_warn(c, ctx,
                                  "position: point %d (%g %g %g) lies outside the mesh; it "
                                  "follows the nearest tetrahedron with extrapolated weights "
                                  "(smallest weight %g)",
                                  i, pt[0], pt[1], pt[2], -outside);
        }
    }
    return PL_OK;
}

static int cc_bind(pl_component *c, pl_ctx *ctx)
{
    cable_constraint *cc = (cable_constraint *)c;
    if (!(cc->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    int n;
    const double *x = pl_util_rest(cc->state, &n);
    if (!x) return pl_component_error(c, ctx, PL_EINPUT, "its state has no rest positions");
    int rc = build_path(cc, ctx, x, n);
    if (rc) return rc;
    int np = cc->path.npoints;
    double Lrest = cable_path_length(&cc->path, x);
    cc->L0 = cc->initial_length.n ? cc->initial_length.v[0] : Lrest;
    if (!(cc->L0 > 0.0))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the cable has zero length at rest (its points coincide)");
    const pl_state_ops *sops = pl_component_role(cc->state, PL_ROLE_STATE);
    pl_buffer xb = sops->positions(cc->state, ctx->data);
    cc->out_length = cable_path_length(&cc->path, pl_buffer_f64(&xb));
    cc->out_displacement = cc->L0 - cc->out_length;
    *(double *)pl_data_slot(ctx->data, cc->slot) = 0.0;
    pl_log_debug("CableConstraint %s: %d points, rest length %g m", c->name, np, Lrest);
    return PL_OK;
}

static void cc_destroy(pl_component *c)
{
    cable_path_free(&((cable_constraint *)c)->path);
}

static void cc_workspace_free(const pl_component *c, void *ws)
{
    cable_ws *w = ws;
    (void)c;
    free(w->g);
    free(w->row_vert);
    free(w->row_coef);
}

/* The step's scratch in d, sized for the path; NULL when out of memory. */
static cable_ws *workspace(const cable_constraint *cc, pl_data *d)
{
    cable_ws *w = pl_data_workspace(d, &cc->base);
    size_t np = (size_t)cc->path.npoints;
    if (w && !w->g) {
        w->g = malloc(np * 3 * sizeof *w->g);
        size_t ns = (size_t)cc->path.nslot;
        w->row_vert = malloc(np * ns * sizeof *w->row_vert);
        w->row_coef = malloc(np * ns * 3 * sizeof *w->row_coef);
    }
    return w && w->g && w->row_vert && w->row_coef ? w : NULL;
}

static int cc_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    const cable_constraint *cc = (const cable_constraint *)c;
    if (!cc->state || !cc->path.npoints) return PL_EINPUT;
    double v;
    if (!strcmp(field, "force")) {
        v = *(const double *)pl_data_slot(d, cc->slot);
    } else if (!strcmp(field, "cableInitialLength")) {
        v = cc->L0;
    } else if (!strcmp(field, "cableLength") || !strcmp(field, "displacement")) {
        const pl_state_ops *sops = pl_component_role(cc->state, PL_ROLE_STATE);
        pl_buffer xb = sops->positions(cc->state, d);
        pl_cable_path p = cc->path; /* with the pull point as d's input says now */
        memcpy(p.pull, pl_input_vec3(d, c, cc->pull_point), sizeof p.pull);
        double L = cable_path_length(&p, pl_buffer_f64(&xb));
        v = field[0] == 'c' ? L : cc->L0 - L;
    } else {
        return PL_EINPUT;
    }
    int k = snprintf(buf, size, "%.17g", v);
    return (k < 0 || (size_t)k >= size) ? PL_EINTERNAL : PL_OK;
}

/* ---- PL_ROLE_CONSTRAINT ---------------------------------------------------- */

/* Appends one row H = -dL/dx (entries already in w->row_*), with
 * delta = L_target - L_lin(q). */
static int emit_row(const cable_constraint *cc, const cable_ws *w, pl_rows *rows, int offset,
                    int nent, const double *x, double L, pl_row_kind kind, double target,
                    double lo, double hi, double compliance)
{
    int r = pl_rows_begin(rows, kind, &cc->base);
    if (r < 0) return PL_EINTERNAL;
    double Hx = 0.0;
    for (int k = 0; k < nent; ++k) {
        const double *cf = w->row_coef + 3 * k;
        const double *xv = x + 3 * w->row_vert[k];
        Hx += cf[0] * xv[0] + cf[1] * xv[1] + cf[2] * xv[2];
        if (pl_rows_add(rows, offset + w->row_vert[k], cf[0], cf[1], cf[2]) != PL_OK)
            return PL_EINTERNAL;
    }
    /* delta = H q - d must be target - L_lin(q) = target - L(q_t) + H (q - q_t)
     * (H = -dL/dx), hence d = L(q_t) - target + H q_t */
    rows->d[r] = L - target + Hx;
    rows->compliance[r] = kind == PL_ROW_BILATERAL ? compliance : 0.0;
    if (kind == PL_ROW_BOUNDED) {
        rows->lo[r] = lo;
        rows->hi[r] = hi;
    }
    return PL_OK;
}

static int cc_build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                         const pl_buffer *q, pl_rows *rows, pl_error *err)
{
    const cable_constraint *cc = (const cable_constraint *)c;
    char msg[256];
    cable_inputs in = inputs_of(cc, ctx->data);
    if (check_values(cc, &in, msg, sizeof msg) != PL_OK)
        return pl_component_fail(c, err, PL_EINPUT, "%s", msg);
    cable_ws *w = workspace(cc, ctx->data);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    const pl_state_ops *sops = pl_component_role(cc->state, PL_ROLE_STATE);
    int offset = sops->offset(cc->state);
    const double *qa = pl_buffer_f64(q);
    if (!qa || offset < 0 || (size_t)(offset + sops->count(cc->state)) > q->rows)
        return pl_component_fail(c, err, PL_EINTERNAL, "positions do not cover its state");
    const double *x = qa + 3 * (size_t)offset;
    pl_cable_path path = cc->path; /* pullPoint is an input: this data's */
    memcpy(path.pull, in.pull, sizeof path.pull);
    double L = cable_gradient(&path, x, w->g);
    int nent = cable_row(&path, w->g, w->row_vert, w->row_coef);
    if (nent < 0) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    double v = in.value.v[in.index];
    double lo = opt_set(&cc->min_force) ? cc->min_force.v[0] : -INFINITY;
    double hi = opt_set(&cc->max_force) ? cc->max_force.v[0] : INFINITY;
    int rc;
    if (in.type == MODE_DISPLACEMENT) {
        /* SoftRobots' order: the variation limit first, then the absolute ones */
        if (opt_set(&cc->max_disp_variation)) {
            double now = cc->L0 - L, dv = cc->max_disp_variation.v[0];
            if (v > now + dv) v = now + dv;
            if (v < now - dv) v = now - dv;
        }
        if (opt_set(&cc->max_positive_disp) && v > cc->max_positive_disp.v[0])
            v = cc->max_positive_disp.v[0];
        if (opt_set(&cc->max_negative_disp) && v < -cc->max_negative_disp.v[0])
            v = -cc->max_negative_disp.v[0];
        int bounded = opt_set(&cc->min_force) || opt_set(&cc->max_force);
        rc = emit_row(cc, w, rows, offset, nent, x, L,
                      bounded ? PL_ROW_BOUNDED : PL_ROW_BILATERAL, cc->L0 - v, lo, hi,
                      cc->compliance);
    } else {
        if (v > hi) v = hi;
        if (v < lo) v = lo;
        /* one row: the tension v, or less (more) where it would take the
         * displacement past maxPositiveDisp (below -maxNegativeDisp); only
         * one limit can be reached at a time: the nearer one now */
        int pos = opt_set(&cc->max_positive_disp), neg = opt_set(&cc->max_negative_disp);
        double now = cc->L0 - L;
        if (pos && neg)
            pos = now >= 0.5 * (cc->max_positive_disp.v[0] - cc->max_negative_disp.v[0]);
        if (pos)
            rc = emit_row(cc, w, rows, offset, nent, x, L, PL_ROW_BOUNDED,
                          cc->L0 - cc->max_positive_disp.v[0], lo, v, 0.0);
        else if (neg)
            rc = emit_row(cc, w, rows, offset, nent, x, L, PL_ROW_BOUNDED,
                          cc->L0 + cc->max_negative_disp.v[0], v, hi, 0.0);
        else
            rc = emit_row(cc, w, rows, offset, nent, x, L, PL_ROW_BOUNDED, L, v, v, 0.0);
    }
    (void)sys;
    return rc ? pl_component_fail(c, err, PL_EINTERNAL, "out of memory") : PL_OK;
}

static void cc_accept(const pl_component *c, pl_data *d, const pl_rows *rows, const double *lambda,
                      int first, int count)
{
    const cable_constraint *cc = (const cable_constraint *)c;
    double f = 0.0;
    for (int k = 0; k < count; ++k) f += lambda[first + k];
    (void)rows;
    *(double *)pl_data_slot(d, cc->slot) = f;
}

static const pl_constraint_ops CONSTRAINT = {.version = PL_CONSTRAINT_OPS_VERSION,
                                             .build_rows = cc_build_rows,
                                             .accept_multipliers = cc_accept};

/* ---- PL_ROLE_VISUAL: the cable's path through the current positions ------ */

static int cc_draw(const pl_component *c, const pl_data *d, pl_drawing *dw, pl_error *err)
{
    const cable_constraint *cc = (const cable_constraint *)c;
    if (!cc->state || !cc->path.npoints) return PL_OK;
    const pl_state_ops *sops = pl_component_role(cc->state, PL_ROLE_STATE);
    pl_buffer xb = sops->positions(cc->state, d);
    const double *x = pl_buffer_f64(&xb);
    if (!x) return pl_component_fail(c, err, PL_EINTERNAL, "positions are not on the host");
    pl_draw_part *part = pl_drawing_add(dw, c, PL_DRAW_CABLE);
    int has_pull = cc->path.has_pull, n = cc->path.npoints + has_pull;
    double *pts = part ? malloc((size_t)n * 3 * sizeof *pts) : NULL;
    if (!pts) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    if (has_pull) memcpy(pts, pl_input_vec3(d, c, cc->pull_point), 3 * sizeof *pts);
    for (int i = 0; i < cc->path.npoints; ++i)
        cable_point(&cc->path, x, i, pts + 3 * (size_t)(i + has_pull));
    int rc = pl_draw_polyline(part, pts, n);
    free(pts);
    return rc ? pl_component_fail(c, err, rc, "cannot draw the cable") : PL_OK;
}

static const pl_visual_ops VISUAL = {.version = PL_VISUAL_OPS_VERSION, .draw = cc_draw};

const pl_type pl_cable_constraint_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "CableConstraint",
    .help = "A cable through the body pulled from a fixed point (SoftRobots' CableConstraint): "
            "imposes a displacement (shortening) [m] or a tension [N]; outputs cableLength, "
            "displacement and force.",
    .size = sizeof(cable_constraint),
    .workspace_size = sizeof(cable_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = cc_init,
            .bind = cc_bind,
            .destroy = cc_destroy,
            .get = cc_get,
            .workspace_free = cc_workspace_free},
    .roles = {[PL_ROLE_CONSTRAINT] = &CONSTRAINT, [PL_ROLE_VISUAL] = &VISUAL},
};
