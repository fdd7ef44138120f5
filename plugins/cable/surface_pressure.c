/* surface_pressure.c - SurfacePressureConstraint: SoftRobots' pneumatic
 * actuator.  A closed triangle surface bounds a cavity in the body; its
 * volume V (cavity.h) is driven to cavityInitialVolume + value (valueType
 * volumeGrowth) or inflated by the pressure value (valueType pressure).
 * Once per step it emits one row linearised at the start of the step:
 *     H = dV/dx (at q_t),   delta = H q - d = V_lin(q) - V_target,
 *     V_lin(q) = V(q_t) + dV/dx . (q - q_t)
 * so the multiplier lambda is the pressure [Pa] and H^T lambda = p dV/dx
 * the force it exerts on the vertices (for a closed surface, each
 * triangle's area normal times p, shared by its corners).
 *   pressure: a BOUNDED row with lo = hi = p (a known force; delta free);
 *     with minVolumeGrowth / maxVolumeGrowth the row targets the limit
 *     nearer to the growth at the start of the step, with bounds
 *     [minPressure, p] (max) or [p, maxPressure] (min): the pressure drops
 *     (rises) where it would take the volume past the limit;
 *   volumeGrowth: delta = 0 with the pressure solved, a BOUNDED row in
 *     [minPressure, maxPressure] (a BILATERAL one without bounds);
 *   eqPressure: the pressure is that value in both modes (its bounds).
 * The row moves with the body as the cable's does: it is linearised once
 * per time step, at q_t, so a step lags the surface's rotation and growth
 * by one step; at equilibrium (q_t = q) the force is p dV/dx exactly.
 * The surface's points follow the body's vertices: `triangles` indices of
 * the state's vertices, or points mapped into the tetrahedra (`position`
 * with `triangles` over those points, or the vertices and triangles of a
 * `surface` loader: SOFA's cavity node with a BarycentricMapping), or the
 * boundary faces of the body's tetrahedra inside `box` (a hole in the
 * mesh).  The surface must be closed and consistently oriented; an
 * inward-facing one (V < 0) is turned around with a warning.
 * Outputs: cavityVolume, volumeGrowth = cavityVolume - initialCavityVolume,
 * pressure (the multiplier of the last step, in the pl_data slot). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable.h"
#include "cavity.h"
#include "surface_pressure.h"
#include "pliant/util.h"

enum { MODE_PRESSURE = 0, MODE_GROWTH = 1 };


/* Per data: the step's scratch. */
typedef struct sp_ws {
    double *g;    /* npoints x 3 */
    double *acc;  /* state vertices x 3: the row, summed per vertex */
    int *mark;    /* state vertices: 1 when in the row */
    int *list;    /* the row's vertices */
} sp_ws;

static const char *const VALUE_TYPES[] = {"pressure", "volumeGrowth", NULL};

#define SP surface_pressure
static const pl_field FIELDS[] = {
    PL_FIELD(SP, triangles, "triangles", PL_F_INTS, NULL,
             "cavity triangles, 3 indices each: of the state's vertices, or of the points of "
             "`position`; facing out of the cavity",
             0),
    PL_FIELD(SP, quads, "quads", PL_F_INTS, NULL,
             "cavity quads, 4 indices each (split into two triangles)", 0),
    PL_FIELD(SP, position, "position", PL_F_DOUBLES, NULL,
             "cavity points [m], x y z each, that `triangles` index: each follows the "
             "tetrahedron containing it (barycentric mapping)",
             0),
    PL_FIELD(SP, surface, "surface", PL_F_LINK, NULL,
             "a loader or generator whose triangles are the cavity; its vertices follow the "
             "tetrahedra containing them (SOFA's mapped cavity node)",
             0),
    PL_FIELD(SP, box, "box", PL_F_DOUBLES, NULL,
             "boxes (xmin ymin zmin xmax ymax zmax each): the cavity is the boundary of the "
             "node's tetrahedra whose faces lie inside (a hole in the mesh)",
             0),
    PL_FIELD(SP, src, "src", PL_F_LINK, NULL,
             "tetrahedral mesh carrying mapped points and `box` (default: the node's first "
             "loader or generator)",
             0),
    PL_FIELD(SP, flip, "flipNormal", PL_F_BOOL, "0",
             "1: the triangles face into the cavity (reverse them)", 0),
    PL_FIELD(SP, value, "value", PL_F_DOUBLES, "0",
             "pressure [Pa] or volume growth [m^3] to impose; a list, value[valueIndex] is used",
             PL_FIELD_INPUT),
    PL_FIELD(SP, value_index, "valueIndex", PL_F_INT, "0", "index of the entry of value to impose",
             PL_FIELD_INPUT),
    PL_FIELD_ENUM(SP, value_type, "valueType", VALUE_TYPES, "pressure",
                  "pressure: inflate with the pressure value; volumeGrowth: drive the cavity "
                  "volume to initialCavityVolume + value (the pressure is solved)",
                  PL_FIELD_INPUT),
    PL_FIELD(SP, min_p, "minPressure", PL_F_DOUBLES, NULL, "lowest pressure [Pa] (empty = none)",
             PL_FIELD_RUNTIME),
    PL_FIELD(SP, max_p, "maxPressure", PL_F_DOUBLES, NULL, "highest pressure [Pa] (empty = none)",
             PL_FIELD_RUNTIME),
    PL_FIELD(SP, eq_p, "eqPressure", PL_F_DOUBLES, NULL,
             "the pressure is this value [Pa] in both modes (empty = none; not with "
             "minPressure/maxPressure)",
             PL_FIELD_RUNTIME),
    PL_FIELD(SP, max_dp, "maxPressureVariation", PL_F_DOUBLES, NULL,
             "pressure mode: largest change of the imposed pressure in one step [Pa]",
             PL_FIELD_RUNTIME),
    PL_FIELD(SP, min_g, "minVolumeGrowth", PL_F_DOUBLES, NULL,
             "lowest volume growth [m^3] (empty = none)", PL_FIELD_RUNTIME),
    PL_FIELD(SP, max_g, "maxVolumeGrowth", PL_F_DOUBLES, NULL,
             "highest volume growth [m^3] (empty = none)", PL_FIELD_RUNTIME),
    PL_FIELD(SP, max_dg, "maxVolumeGrowthVariation", PL_F_DOUBLES, NULL,
             "volumeGrowth mode: largest change of the imposed growth in one step [m^3]",
             PL_FIELD_RUNTIME),
    PL_FIELD(SP, out_pressure, "pressure", PL_F_DOUBLE, "0",
             "pressure of the last step [Pa]: the row's multiplier", PL_FIELD_OUTPUT),
    PL_FIELD(SP, out_growth, "volumeGrowth", PL_F_DOUBLE, "0",
             "cavityVolume - initialCavityVolume [m^3]", PL_FIELD_OUTPUT),
    PL_FIELD(SP, out_volume, "cavityVolume", PL_F_DOUBLE, "0", "current cavity volume [m^3]",
             PL_FIELD_OUTPUT),
    PL_FIELD(SP, out_v0, "initialCavityVolume", PL_F_DOUBLE, "0",
             "cavity volume at the rest positions [m^3]", PL_FIELD_OUTPUT),
};
#undef SP

static int opt_set(const pl_doubles *d) { return d->n > 0; }

/* Checks the bounds (they may change while running) and the value. */
static int check_values(const surface_pressure *sp, pl_doubles value, int index, char *msg,
                        size_t size)
{
    const struct {
        const pl_doubles *d;
        const char *name;
    } opts[] = {{&sp->min_p, "minPressure"},     {&sp->max_p, "maxPressure"},
                {&sp->eq_p, "eqPressure"},       {&sp->max_dp, "maxPressureVariation"},
                {&sp->min_g, "minVolumeGrowth"}, {&sp->max_g, "maxVolumeGrowth"},
                {&sp->max_dg, "maxVolumeGrowthVariation"}};
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; ++k) {
        if (opts[k].d->n > 1) {
            snprintf(msg, size, "%s: expected one number (or nothing), found %d", opts[k].name,
                     opts[k].d->n);
            return PL_EINPUT;
        }
        if (opts[k].d->n && !isfinite(opts[k].d->v[0])) {
            snprintf(msg, size, "%s: %g is not a finite number", opts[k].name, opts[k].d->v[0]);
            return PL_EINPUT;
        }
    }
    if (value.n < 1 || index < 0 || index >= value.n) {
        snprintf(msg, size, "valueIndex: %d is out of range (value has %d entries)", index,
                 value.n);
        return PL_EINPUT;
    }
    if (!isfinite(value.v[index])) {
        snprintf(msg, size, "value: %g is not a finite number", value.v[index]);
        return PL_EINPUT;
    }
    if (opt_set(&sp->min_p) && opt_set(&sp->max_p) && sp->min_p.v[0] > sp->max_p.v[0]) {
        snprintf(msg, size, "minPressure (%g Pa) is above maxPressure (%g Pa)", sp->min_p.v[0],
                 sp->max_p.v[0]);
        return PL_EINPUT;
    }
    if (opt_set(&sp->min_g) && opt_set(&sp->max_g) && sp->min_g.v[0] > sp->max_g.v[0]) {
        snprintf(msg, size, "minVolumeGrowth (%g) is above maxVolumeGrowth (%g)", sp->min_g.v[0],
                 sp->max_g.v[0]);
        return PL_EINPUT;
    }
    if (opt_set(&sp->eq_p) && (opt_set(&sp->min_p) || opt_set(&sp->max_p))) {
        snprintf(msg, size, "eqPressure fixes the pressure: give it without minPressure and "
                            "maxPressure");
        return PL_EINPUT;
    }
    if ((opt_set(&sp->max_dp) && !(sp->max_dp.v[0] >= 0)) ||
        (opt_set(&sp->max_dg) && !(sp->max_dg.v[0] >= 0))) {
        snprintf(msg, size, "the variation limits must be >= 0");
        return PL_EINPUT;
    }
    return PL_OK;
}

static int sp_init(pl_component *c, pl_ctx *ctx)
{
    surface_pressure *sp = (surface_pressure *)c;
    char msg[256];
    sp->slot = -1;
    int sources = (sp->triangles.n || sp->quads.n) + (sp->surface.path != NULL) + (sp->box.n > 0);
    if (sources == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "no cavity: give its surface as triangles (and quads), a "
                                  "surface loader, or box");
    if (sources > 1)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "give the cavity once: triangles/quads, surface or box");
    if (sp->triangles.n % 3 || sp->quads.n % 4)
        return pl_component_error(c, ctx, PL_EINPUT, "%s: expected %d indices each, found %d",
                                  sp->triangles.n % 3 ? "triangles" : "quads",
                                  sp->triangles.n % 3 ? 3 : 4,
                                  sp->triangles.n % 3 ? sp->triangles.n : sp->quads.n);
    if (sp->position.n % 3)
        return pl_component_error(c, ctx, PL_EINPUT, "position: expected x y z per point, found "
                                  "%d numbers", sp->position.n);
    if (sp->position.n && !sp->triangles.n && !sp->quads.n)
        return pl_component_error(c, ctx, PL_EINPUT, "position needs triangles over its points");
    for (int i = 0; i < sp->position.n; ++i)
        if (!isfinite(sp->position.v[i]))
            return pl_component_error(c, ctx, PL_EINPUT, "position: number %d is not finite", i);
    if (sp->box.n && pl_util_check_boxes(c, ctx, "box", &sp->box)) return PL_EINPUT;
    pl_doubles value = pl_input_doubles(NULL, c, &sp->value);
    int index = pl_input_int(NULL, c, &sp->value_index);
    if (check_values(sp, value, index, msg, sizeof msg) != PL_OK)
        return pl_component_error(c, ctx, PL_EINPUT, "%s", msg);
    sp->slot = pl_model_add_slot(ctx->build, c, "pressure", sizeof(double));
    if (sp->slot < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, sp->slot, pl_slot_check_finite);
    return PL_OK;
}

static int sp_bind(pl_component *c, pl_ctx *ctx)
{
    surface_pressure *sp = (surface_pressure *)c;
    if (!(sp->state = pl_util_state(c, ctx, 1))) return PL_EINPUT;
    int n;
    const double *x = pl_util_rest(sp->state, &n);
    if (!x) return pl_component_error(c, ctx, PL_EINPUT, "its state has no rest positions");
    int rc = sp_build_surface(sp, ctx, x, n);
    if (!rc) rc = sp_check_surface(sp, ctx, x);
    if (rc) return rc;
    sp->V0 = cavity_volume(&sp->surf, x);
    sp->out_v0 = sp->V0;
    const pl_state_ops *sops = pl_component_role(sp->state, PL_ROLE_STATE);
    pl_buffer xb = sops->positions(sp->state, ctx->data);
    sp->out_volume = cavity_volume(&sp->surf, pl_buffer_f64(&xb));
    sp->out_growth = sp->out_volume - sp->V0;
    *(double *)pl_data_slot(ctx->data, sp->slot) = 0.0;
    pl_log_debug("SurfacePressureConstraint %s: %d triangles, %d points, volume %g", c->name,
                 sp->surf.ntris, sp->surf.npoints, sp->V0);
    return PL_OK;
}

static void sp_destroy(pl_component *c) { cavity_free(&((surface_pressure *)c)->surf); }

static void sp_workspace_free(const pl_component *c, void *ws)
{
    sp_ws *w = ws;
    (void)c;
    free(w->g);
    free(w->acc);
    free(w->mark);
    free(w->list);
}

static sp_ws *workspace(const surface_pressure *sp, pl_data *d, int n)
{
    sp_ws *w = pl_data_workspace(d, &sp->base);
    if (w && !w->g) {
        w->g = malloc((size_t)sp->surf.npoints * 3 * sizeof *w->g + 1);
        w->acc = calloc((size_t)n * 3 + 1, sizeof *w->acc);
        w->mark = calloc((size_t)n + 1, sizeof *w->mark);
        w->list = malloc((size_t)n * sizeof *w->list + 1);
    }
    return w && w->g && w->acc && w->mark && w->list ? w : NULL;
}

static int sp_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    const surface_pressure *sp = (const surface_pressure *)c;
    if (!sp->state || !sp->surf.ntris) return PL_EINPUT;
    double v;
    if (!strcmp(field, "pressure")) {
        v = *(const double *)pl_data_slot(d, sp->slot);
    } else if (!strcmp(field, "initialCavityVolume")) {
        v = sp->V0;
    } else if (!strcmp(field, "cavityVolume") || !strcmp(field, "volumeGrowth")) {
        const pl_state_ops *sops = pl_component_role(sp->state, PL_ROLE_STATE);
        pl_buffer xb = sops->positions(sp->state, d);
        v = cavity_volume(&sp->surf, pl_buffer_f64(&xb));
        if (field[0] == 'v') v -= sp->V0;
    } else {
        return PL_EINPUT;
    }
    int k = snprintf(buf, size, "%.17g", v);
    return (k < 0 || (size_t)k >= size) ? PL_EINTERNAL : PL_OK;
}

/* ---- PL_ROLE_CONSTRAINT ---------------------------------------------------- */

/* Appends the row H = dV/dx (w->acc over w->list) with delta = V_lin(q) -
 * target, i.e. d = target - V(q_t) + H q_t. */
static int emit_row(const surface_pressure *sp, const sp_ws *w, int nlist, pl_rows *rows,
                    int offset, const double *x, double V, pl_row_kind kind, double target,
                    double lo, double hi)
{
    int r = pl_rows_begin(rows, kind, &sp->base);
    if (r < 0) return PL_EINTERNAL;
    double Hx = 0.0;
    for (int k = 0; k < nlist; ++k) {
        int v = w->list[k];
        const double *cf = w->acc + 3 * v;
        Hx += cf[0] * x[3 * v] + cf[1] * x[3 * v + 1] + cf[2] * x[3 * v + 2];
        if (pl_rows_add(rows, offset + v, cf[0], cf[1], cf[2]) != PL_OK) return PL_EINTERNAL;
    }
    rows->d[r] = target - V + Hx;
    if (kind == PL_ROW_BOUNDED) {
        rows->lo[r] = lo;
        rows->hi[r] = hi;
    }
    return PL_OK;
}

/* The row's entries: the point gradients spread onto their vertices,
 * summed per vertex, in increasing vertex order. */
static int gather_row(const surface_pressure *sp, sp_ws *w)
{
    const cavity_surface *s = &sp->surf;
    int nlist = 0;
    for (int i = 0; i < s->npoints; ++i)
        for (int k = 0; k < 4; ++k) {
            int v = s->vert[4 * i + k];
            if (v < 0) continue;
            double wt = s->weight[4 * i + k];
            if (!w->mark[v]) w->mark[v] = 1, w->list[nlist++] = v;
            for (int c = 0; c < 3; ++c) w->acc[3 * v + c] += wt * w->g[3 * i + c];
        }
    return nlist;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static int sp_build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys,
                         const pl_buffer *q, pl_rows *rows, pl_error *err)
{
    const surface_pressure *sp = (const surface_pressure *)c;
    char msg[256];
    pl_doubles value = pl_input_doubles(ctx->data, c, &sp->value);
    int index = pl_input_int(ctx->data, c, &sp->value_index);
    int type = pl_input_int(ctx->data, c, &sp->value_type);
    if (check_values(sp, value, index, msg, sizeof msg) != PL_OK)
        return pl_component_fail(c, err, PL_EINPUT, "%s", msg);
    const pl_state_ops *sops = pl_component_role(sp->state, PL_ROLE_STATE);
    int offset = sops->offset(sp->state), n = sops->count(sp->state);
    const double *qa = pl_buffer_f64(q);
    if (!qa || offset < 0 || (size_t)(offset + n) > q->rows)
        return pl_component_fail(c, err, PL_EINTERNAL, "positions do not cover its state");
    sp_ws *w = workspace(sp, ctx->data, n);
    if (!w) return pl_component_fail(c, err, PL_EINTERNAL, "out of memory");
    const double *x = qa + 3 * (size_t)offset;
    double V = cavity_gradient(&sp->surf, x, w->g);
    if (!isfinite(V))
        return pl_component_fail(c, err, PL_EINPUT, "the cavity volume became %g at step %ld", V,
                                 ctx->data->step + 1);
    int nlist = gather_row(sp, w);
    qsort(w->list, (size_t)nlist, sizeof *w->list, cmp_int);
    double v = value.v[index], growth = V - sp->V0;
    double lo = opt_set(&sp->min_p) ? sp->min_p.v[0] : -INFINITY;
    double hi = opt_set(&sp->max_p) ? sp->max_p.v[0] : INFINITY;
    if (opt_set(&sp->eq_p)) lo = hi = sp->eq_p.v[0];
    int rc;
    if (type == MODE_GROWTH) {
        /* SoftRobots' order: the variation limit, then the absolute ones */
        if (opt_set(&sp->max_dg)) v = fmin(fmax(v, growth - sp->max_dg.v[0]), growth + sp->max_dg.v[0]);
        if (opt_set(&sp->max_g)) v = fmin(v, sp->max_g.v[0]);
        if (opt_set(&sp->min_g)) v = fmax(v, sp->min_g.v[0]);
        int bounded = isfinite(lo) || isfinite(hi);
        rc = emit_row(sp, w, nlist, rows, offset, x, V, bounded ? PL_ROW_BOUNDED : PL_ROW_BILATERAL,
                      sp->V0 + v, lo, hi);
    } else {
        if (opt_set(&sp->max_dp)) {
            double now = *(const double *)pl_data_slot(ctx->data, sp->slot);
            v = fmin(fmax(v, now - sp->max_dp.v[0]), now + sp->max_dp.v[0]);
        }
        v = fmax(fmin(v, hi), lo);
        int pos = opt_set(&sp->max_g), neg = opt_set(&sp->min_g);
        if (pos && neg) pos = growth >= 0.5 * (sp->max_g.v[0] + sp->min_g.v[0]);
        if (pos)
            rc = emit_row(sp, w, nlist, rows, offset, x, V, PL_ROW_BOUNDED, sp->V0 + sp->max_g.v[0],
                          lo, v);
        else if (neg)
            rc = emit_row(sp, w, nlist, rows, offset, x, V, PL_ROW_BOUNDED, sp->V0 + sp->min_g.v[0],
                          v, hi);
        else
            rc = emit_row(sp, w, nlist, rows, offset, x, V, PL_ROW_BOUNDED, V, v, v);
    }
    for (int k = 0; k < nlist; ++k) { /* leave the scratch clean for the next step */
        int vv = w->list[k];
        w->mark[vv] = 0;
        w->acc[3 * vv] = w->acc[3 * vv + 1] = w->acc[3 * vv + 2] = 0.0;
    }
    (void)sys;
    return rc ? pl_component_fail(c, err, PL_EINTERNAL, "out of memory") : PL_OK;
}

static void sp_accept(const pl_component *c, pl_data *d, const pl_rows *rows,
                      const double *lambda, int first, int count)
{
    const surface_pressure *sp = (const surface_pressure *)c;
    (void)rows;
    if (count >= 1) *(double *)pl_data_slot(d, sp->slot) = lambda[first];
}

static const pl_constraint_ops CONSTRAINT = {.version = PL_CONSTRAINT_OPS_VERSION,
                                             .build_rows = sp_build_rows,
                                             .accept_multipliers = sp_accept};

const pl_type pl_surface_pressure_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "SurfacePressureConstraint",
    .help = "A pressurised cavity in the body (SoftRobots' SurfacePressureConstraint): imposes a "
            "pressure [Pa] or a volume growth [m^3] on a closed triangle surface; outputs "
            "pressure, volumeGrowth and cavityVolume.",
    .size = sizeof(surface_pressure),
    .workspace_size = sizeof(sp_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = sp_init,
            .bind = sp_bind,
            .destroy = sp_destroy,
            .get = sp_get,
            .workspace_free = sp_workspace_free},
    .roles = {[PL_ROLE_CONSTRAINT] = &CONSTRAINT},
};
