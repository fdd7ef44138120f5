/* contact_test_component.c - see contact_test_component.h. */
#include "contact_test_component.h"

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MODE_PLANE, MODE_PIN, MODE_BOUNDED };
static const char *const MODES[] = {"plane", "pin", "bounded", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD_ENUM(test_constraint, mode, "mode", MODES, "plane", "plane, pin or bounded", 0),
    PL_FIELD(test_constraint, alarm, "alarm", PL_F_DOUBLE, "0.005", "plane: contact height [m]", PL_FIELD_RUNTIME),
    PL_FIELD(test_constraint, mu, "mu", PL_F_DOUBLE, "0", "plane: friction coefficient", PL_FIELD_RUNTIME),
    PL_FIELD(test_constraint, height, "height", PL_F_DOUBLE, "0", "pin: target y [m]", PL_FIELD_RUNTIME),
    PL_FIELD(test_constraint, compliance, "compliance", PL_F_DOUBLE, "0", "pin: compliance [m/N]",
             PL_FIELD_RUNTIME),
    PL_FIELD(test_constraint, lo, "lo", PL_F_DOUBLE, "-1e300", "bounded: lower bound [N]", PL_FIELD_RUNTIME),
    PL_FIELD(test_constraint, hi, "hi", PL_F_DOUBLE, "1e300", "bounded: upper bound [N]", PL_FIELD_RUNTIME),
    PL_FIELD(test_constraint, vertices, "vertices", PL_F_INTS, NULL, "global vertices", 0),
    PL_FIELD(test_constraint, above, "above", PL_F_DOUBLE, "1e300",
             "pin/bounded without vertices: the vertices with y >= above at the first step [m]", 0),
    PL_FIELD(test_constraint, pairs, "pairs", PL_F_BOOL, "0", "pin/bounded: rows on midpoints of pairs", 0),
};

static int row(pl_rows *rows, pl_row_kind kind, const pl_component *c, pl_error *err)
{
    int r = pl_rows_begin(rows, kind, c);
    if (r < 0) pl_error_set(err, PL_EINTERNAL, NULL, 0, "TestConstraint", "out of memory");
    return r;
}

static int add(pl_rows *rows, int v, double x, double y, double z, pl_error *err)
{
    if (pl_rows_add(rows, v, x, y, z) != 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, "TestConstraint", "out of memory");
    return PL_OK;
}

static int build_rows(const pl_component *c, pl_ctx *ctx, const pl_system *sys, const pl_buffer *q,
                      pl_rows *rows, pl_error *err)
{
    const test_constraint *t = (const test_constraint *)c;
    test_probe *p = pl_data_workspace(ctx->data, c);
    const double *x = pl_buffer_f64(q);
    if (!p) return pl_error_set(err, PL_EINTERNAL, NULL, 0, "TestConstraint", "out of memory");
    p->total_mass = 0.0;
    for (int v = 0; v < sys->nverts; ++v) p->total_mass += sys->mass ? sys->mass[v] : 0.0;
    if (t->mode == MODE_PLANE) {
        for (int v = 0; v < sys->nverts; ++v) {
            if (!(x[3 * v + 1] < t->alarm)) continue;
            int n = row(rows, PL_ROW_NORMAL, c, err);
            if (n < 0 || add(rows, v, 0, 1, 0, err)) return PL_EINTERNAL;
            rows->mu[n] = t->mu;
            for (int k = 0; k < 2; ++k) {
                int f = row(rows, PL_ROW_FRICTION, c, err);
                if (f < 0 || add(rows, v, k == 0, 0, k == 1, err)) return PL_EINTERNAL;
                rows->pair[f] = n;
                if (k == 0) rows->pair[n] = f;
            }
        }
        return PL_OK;
    }
    if (t->vertices.n == 0 && !p->selected) /* first step: select by height */
        for (int v = 0; v < sys->nverts; ++v)
            if (x[3 * v + 1] >= t->above) {
                int *nv = realloc(p->selected, sizeof(int) * (size_t)(p->nselected + 1));
                if (!nv) return pl_error_set(err, PL_EINTERNAL, NULL, 0, "TestConstraint", "out of memory");
                p->selected = nv;
                p->selected[p->nselected++] = v;
            }
    const int *verts = t->vertices.n ? t->vertices.v : p->selected;
    int nverts = t->vertices.n ? t->vertices.n : p->nselected;
    int step = t->pairs ? 2 : 1;
    for (int i = 0; i + step - 1 < nverts; i += step) {
        int r = row(rows, t->mode == MODE_BOUNDED ? PL_ROW_BOUNDED : PL_ROW_BILATERAL, c, err);
        if (r < 0) return PL_EINTERNAL;
        rows->d[r] = t->height;
        if (t->mode == MODE_BOUNDED) {
            rows->lo[r] = t->lo;
            rows->hi[r] = t->hi;
        } else {
            rows->compliance[r] = t->compliance;
        }
        for (int s = 0; s < step; ++s)
            if (add(rows, verts[i + s], 0, 1.0 / step, 0, err)) return PL_EINTERNAL;
    }
    return PL_OK;
}

static void accept(const pl_component *c, pl_data *d, const pl_rows *rows, const double *lambda,
                   int first, int count)
{
    test_probe *t = pl_data_workspace(d, c);
    ck_assert_ptr_nonnull(t);
    free(t->lambda);
    t->lambda = malloc(sizeof(double) * (size_t)(count > 0 ? count : 1));
    ck_assert_ptr_nonnull(t->lambda);
    memcpy(t->lambda, lambda + first, sizeof(double) * (size_t)count);
    t->nrows = count;
    t->sum_normal = t->sum_rows = 0.0;
    t->sum_friction[0] = t->sum_friction[1] = t->sum_friction[2] = 0.0;
    t->cone_excess = -INFINITY;
    t->min_normal = INFINITY;
    t->ncontacts = 0;
    for (int r = first; r < first + count; ++r) {
        if (rows->kind[r] == PL_ROW_BILATERAL || rows->kind[r] == PL_ROW_BOUNDED) t->sum_rows += lambda[r];
        if (rows->kind[r] == PL_ROW_FRICTION) {
            const double *cf = &rows->coef[3 * rows->start[r]];
            for (int k = 0; k < 3; ++k) t->sum_friction[k] += lambda[r] * cf[k];
        }
        if (rows->kind[r] != PL_ROW_NORMAL) continue;
        t->ncontacts++;
        t->sum_normal += lambda[r];
        if (lambda[r] < t->min_normal) t->min_normal = lambda[r];
        double f2 = 0.0;
        for (int s = first; s < first + count; ++s)
            if (rows->kind[s] == PL_ROW_FRICTION && rows->pair[s] == r) f2 += lambda[s] * lambda[s];
        double excess = sqrt(f2) - rows->mu[r] * lambda[r] * (1 + 1e-6);
        if (excess > t->cone_excess) t->cone_excess = excess;
    }
}

static void probe_free(const pl_component *c, void *ws)
{
    test_probe *t = ws;
    (void)c;
    free(t->lambda);
    free(t->selected);
}

static const pl_constraint_ops OPS = {.version = PL_CONSTRAINT_OPS_VERSION, .build_rows = build_rows, .accept_multipliers = accept};

const pl_type test_constraint_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "TestConstraint",
    .help = "test rows: plane contacts, pins, bounded rows",
    .size = sizeof(test_constraint),
    .workspace_size = sizeof(test_probe),
    .fields = FIELDS,
    .nfields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .ops = {.workspace_free = probe_free},
    .roles = {[PL_ROLE_CONSTRAINT] = &OPS},
};

void ts_load(test_scene *t, const char *xml, const char *const *overrides, int noverrides)
{
    pl_error err;
    pl_diag diag;
    pl_diag_init(&diag);
    t->reg = pl_registry_create();
    ck_assert_ptr_nonnull(t->reg);
    ck_assert_int_eq(pl_register_builtin_components(t->reg, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(t->reg, &test_constraint_type, &err), PL_OK);
    pl_sim_options opt = {.registry = t->reg, .overrides = overrides, .noverrides = noverrides};
    t->sim = pl_sim_load_string(xml, PL_SOURCE_DIR "/scenes/inline.xml", &opt, &diag);
    if (!t->sim) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(t->sim);
}

void ts_free(test_scene *t)
{
    pl_sim_free(t->sim);
    pl_registry_free(t->reg);
    t->sim = NULL;
    t->reg = NULL;
}

void ts_step(test_scene *t, int n)
{
    pl_error err;
    int rc = pl_sim_step(t->sim, n, &err);
    if (rc) {
        char b[2048];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
}

static const pl_state_ops *state(test_scene *t, const char *path, pl_component **c)
{
    *c = pl_sim_component(t->sim, path);
    ck_assert_ptr_nonnull(*c);
    const pl_state_ops *ops = pl_component_role(*c, PL_ROLE_STATE);
    ck_assert_ptr_nonnull(ops);
    return ops;
}

const double *ts_positions(test_scene *t, const char *path, int *n)
{
    pl_component *c;
    pl_buffer b = state(t, path, &c)->positions(c, pl_sim_data(t->sim));
    *n = (int)b.rows;
    return b.data;
}

const double *ts_velocities(test_scene *t, const char *path, int *n)
{
    pl_component *c;
    pl_buffer b = state(t, path, &c)->velocities(c, pl_sim_data(t->sim));
    *n = (int)b.rows;
    return b.data;
}

test_probe *ts_constraint(test_scene *t, const char *path)
{
    pl_component *c = pl_sim_component(t->sim, path);
    ck_assert_ptr_nonnull(c);
    ck_assert_str_eq(c->type->name, test_constraint_type.name);
    test_probe *p = pl_data_workspace(pl_sim_data(t->sim), c);
    ck_assert_ptr_nonnull(p);
    return p;
}

double ts_min_y(test_scene *t, const char *path)
{
    int n;
    const double *x = ts_positions(t, path, &n);
    double m = INFINITY;
    for (int i = 0; i < n; ++i) m = fmin(m, x[3 * i + 1]);
    return m;
}

double *ts_masses(test_scene *t, const char *mass_path, int n)
{
    pl_component *m = pl_sim_component(t->sim, mass_path);
    ck_assert_ptr_nonnull(m);
    const pl_mass_ops *ops = pl_component_role(m, PL_ROLE_MASS);
    ck_assert_ptr_nonnull(ops);
    double *mass = calloc((size_t)n, sizeof *mass);
    pl_error err;
    ck_assert_int_eq(ops->add_vertex_masses(m, mass, n, &err), PL_OK);
    return mass;
}

double ts_mean_velocity(test_scene *t, const char *path, const double *mass, int k)
{
    int n;
    const double *v = ts_velocities(t, path, &n);
    double s = 0.0, w = 0.0;
    for (int i = 0; i < n; ++i) {
        double mi = mass ? mass[i] : 1.0;
        s += mi * v[3 * i + k];
        w += mi;
    }
    return s / w;
}
