/* lg_device_fakes.c - the test components of test_lg_device (see
 * lg_device_fakes.h): a device service whose "device memory" is host
 * memory, a spring term and a dense Cholesky solver that take buffers in
 * either place.  Every loop is serial, so results are bitwise repeatable. */
#include "lg_device_fakes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"

/* ---- HostDevice ------------------------------------------------------------ */

typedef struct host_device {
    pl_component base;
    int profile;
    int loops;  /* field: offer loop (PL_DEVICE_LOOPS) */
    long live;  /* allocations not freed */
    long calls; /* kernel calls */
    long rules; /* stopping rules applied by loop */
} host_device;

static int hd_flags(const pl_component *c)
{
    const host_device *d = (const host_device *)c;
    return d->profile ? PL_DEVICE_PROFILE : d->loops ? PL_DEVICE_LOOPS : 0;
}
static void *hd_stream(const pl_component *c)
{
    (void)c;
    return NULL;
}
static void *hd_alloc(pl_component *c, size_t bytes, pl_error *err)
{
    void *p = malloc(bytes ? bytes : 1);
    if (!p) pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    if (p) ((host_device *)c)->live++;
    return p;
}
static void hd_free(pl_component *c, void *p)
{
    if (p) ((host_device *)c)->live--;
    free(p);
}
static int hd_zero(pl_component *c, void *p, size_t bytes, pl_error *err)
{
    (void)c, (void)err;
    memset(p, 0, bytes);
    return PL_OK;
}
static int hd_copy(pl_component *c, void *dst, pl_location to, const void *src, pl_location from,
                   size_t bytes, pl_error *err)
{
    (void)c, (void)to, (void)from, (void)err;
    if (bytes) memcpy(dst, src, bytes);
    return PL_OK;
}
static int hd_pin(pl_component *c, void *host, size_t bytes, pl_error *err)
{
    (void)c, (void)host, (void)bytes, (void)err;
    return PL_OK;
}
static void hd_unpin(pl_component *c, void *host)
{
    (void)c, (void)host;
}
static int hd_sync(pl_component *c, pl_error *err)
{
    (void)c, (void)err;
    return PL_OK;
}
static int hd_scale_rows(pl_component *c, int n, const double *s, const double *x, double *y,
                         pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) y[3 * i + k] = s[i] * x[3 * i + k];
    return PL_OK;
}
static int hd_gather_rows(pl_component *c, int m, const int *map, const double *x, double *y,
                          pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int f = 0; f < m; ++f) memcpy(&y[3 * f], &x[3 * map[f]], 3 * sizeof(double));
    return PL_OK;
}
static int hd_scatter_rows(pl_component *c, int m, const int *map, const double *y, double *x,
                           double *change, pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int f = 0; f < m; ++f)
        for (int k = 0; k < 3; ++k) {
            double nv = y[3 * f + k], d = fabs(nv - x[3 * map[f] + k]);
            *change = isfinite(nv) ? fmax(*change, d) : INFINITY;
            x[3 * map[f] + k] = nv;
        }
    return PL_OK;
}
static int hd_sub_csr(pl_component *c, const pl_csr *A, const double *x, double *y, pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int r = 0; r < A->nrows; ++r)
        for (int p = A->p[r]; p < A->p[r + 1]; ++p)
            for (int k = 0; k < 3; ++k) y[3 * r + k] -= A->x[p] * x[3 * A->j[p] + k];
    return PL_OK;
}
/* gather_rows then sub_csr, one call */
static int hd_gather_sub_csr(pl_component *c, int m, const int *map, const double *x,
                             const pl_csr *A, const double *q, double *y, pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int f = 0; f < m; ++f) {
        memcpy(&y[3 * f], &x[3 * map[f]], 3 * sizeof(double));
        for (int p = A ? A->p[f] : 0; A && p < A->p[f + 1]; ++p)
            for (int k = 0; k < 3; ++k) y[3 * f + k] -= A->x[p] * q[3 * A->j[p] + k];
    }
    return PL_OK;
}
/* force_residual.c's expression, in its order: bitwise the CPU's value */
static int hd_residual_max(pl_component *c, int m, const int *map, const double *s, double h2,
                           const double *x, const double *y, const double *g, const double *t,
                           double *out, pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int f = 0; f < m; ++f) {
        int v = map[f];
        double r[3];
        for (int k = 0; k < 3; ++k) {
            r[k] = s[v] * (x[3 * v + k] - y[3 * v + k]) / h2 + g[3 * v + k];
            if (t) r[k] += t[3 * f + k] / h2;
        }
        double n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        *out = isfinite(n) ? fmax(*out, n) : INFINITY;
    }
    return PL_OK;
}
/* version 4: scale_rows with a zero, one call */
static int hd_scale_rows_zero(pl_component *c, int n, const double *s, const double *x, double *y,
                              void *z, size_t bytes, pl_error *err)
{
    memset(z, 0, bytes);
    return hd_scale_rows(c, n, s, x, y, err);
}
/* version 4: gather_sub_csr's t and residual_max with it, one call (t row
 * by row in a 3-vector: the same values) */
static int hd_residual_max_csr(pl_component *c, int m, const int *map, const double *s,
                               double h2, const double *x, const double *y, const double *g,
                               const double *b, const pl_csr *A, double *out, pl_error *err)
{
    for (int f = 0; f < m; ++f) {
        double t[3];
        memcpy(t, &b[3 * map[f]], sizeof t);
        for (int p = A ? A->p[f] : 0; A && p < A->p[f + 1]; ++p)
            for (int k = 0; k < 3; ++k) t[k] -= A->x[p] * x[3 * A->j[p] + k];
        int one[1] = {map[f]};
        int rc = hd_residual_max(c, 1, one, s, h2, x, y, g, t, out, err);
        if (rc) return rc;
    }
    return PL_OK;
}
/* version 6: a step's start and end (roles.h), in the host's order of
 * operations: pl_dynamics_begin's and pl_dynamics_scatter's values */
static int hd_step_begin(pl_component *c, int n3, double h, int first_order, int guess, double hv,
                         const double *x, const double *v, const double *g, double *q_t,
                         double *sn, double *q, pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int i = 0; i < n3; ++i) {
        double m = first_order ? x[i] + h * g[i] : x[i] + h * v[i] + h * h * g[i];
        q_t[i] = x[i], sn[i] = m;
        q[i] = guess ? x[i] + hv * v[i] : m;
    }
    return PL_OK;
}
static int hd_step_end(pl_component *c, int n3, double h, double scale, const double *q,
                       const double *q_t, double *x, double *v, int *bad, pl_error *err)
{
    (void)err;
    ((host_device *)c)->calls++;
    for (int i = 0; i < n3; ++i) {
        if (!isfinite(q[i])) *bad = 1;
        v[i] = scale * (q[i] - q_t[i]) / h;
        x[i] = q[i];
    }
    return PL_OK;
}
static int hd_no_graphs(pl_component *c, pl_error *err)
{
    return pl_component_fail(c, err, PL_EINTERNAL, "HostDevice records no graphs");
}
static int hd_capture_end(pl_component *c, void **graph, pl_error *err)
{
    *graph = NULL;
    return hd_no_graphs(c, err);
}
static int hd_replay(pl_component *c, void *graph, pl_error *err)
{
    (void)graph;
    return hd_no_graphs(c, err);
}
/* The loop as the contract writes it, one body call per iteration (it
 * records nothing: *graph stays NULL), with the shared rule. */
static int hd_loop(pl_component *c, int (*body)(void *arg, pl_error *err), void *arg,
                   pl_device_loop *state, const double *change, const double *residual,
                   void **graph, pl_error *err)
{
    host_device *d = (host_device *)c;
    *graph = NULL;
    for (;;) {
        d->rules++;
        if (!pl_device_loop_rule(state, change, residual)) return PL_OK;
        int rc = body(arg, err);
        if (rc) return rc;
    }
}
static void hd_graph_free(pl_component *c, void *graph)
{
    (void)c, (void)graph;
}

/* The members every version of the table has (3: loop, gather_sub_csr) */
#define HD_OPS_V3_MEMBERS                                                              \
    .flags = hd_flags, .stream = hd_stream, .alloc = hd_alloc, .free = hd_free,        \
    .zero = hd_zero, .copy = hd_copy, .pin = hd_pin, .unpin = hd_unpin, .sync = hd_sync, \
    .scale_rows = hd_scale_rows, .gather_rows = hd_gather_rows,                        \
    .scatter_rows = hd_scatter_rows, .sub_csr = hd_sub_csr,                            \
    .capture_begin = hd_no_graphs, .capture_end = hd_capture_end, .replay = hd_replay, \
    .graph_free = hd_graph_free, .residual_max = hd_residual_max, .loop = hd_loop,     \
    .gather_sub_csr = hd_gather_sub_csr

static const pl_device_ops HD_OPS = {
    .version = PL_DEVICE_OPS_VERSION,
    HD_OPS_V3_MEMBERS,
    .scale_rows_zero = hd_scale_rows_zero,
    .residual_max_csr = hd_residual_max_csr,
    .step_begin = hd_step_begin,
    .step_end = hd_step_end,
};

/* The same service as a version 3 table (without the version 4 members):
 * the solver's other path */
static const pl_device_ops HD_OPS_V3 = {.version = 3, HD_OPS_V3_MEMBERS};

static const pl_field HD_FIELDS[] = {
    PL_FIELD(host_device, profile, "profile", PL_F_BOOL, "0", "sync after each phase", 0),
    PL_FIELD(host_device, loops, "loops", PL_F_BOOL, "1", "offer loop (device ops version 3)", 0),
};

static void hd_destroy(pl_component *c)
{
    host_device *d = (host_device *)c;
    if (d->live) fake_device_leaks += d->live;
}

long fake_device_leaks;

const pl_type fake_host_device_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "HostDevice",
    .help = "test device service in host memory",
    .size = sizeof(host_device),
    .fields = HD_FIELDS,
    .nfields = 2,
    .ops = {.destroy = hd_destroy},
    .roles = {[PL_ROLE_DEVICE] = &HD_OPS},
};

const pl_type fake_host_device_v3_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "HostDeviceV3",
    .help = "test device service in host memory, device ops version 3",
    .size = sizeof(host_device),
    .fields = HD_FIELDS,
    .nfields = 2,
    .ops = {.destroy = hd_destroy},
    .roles = {[PL_ROLE_DEVICE] = &HD_OPS_V3},
};

long fake_device_calls(const pl_component *c)
{
    return ((const host_device *)c)->calls;
}

long fake_device_rules(const pl_component *c)
{
    return ((const host_device *)c)->rules;
}

/* ---- TestSprings: w/2 (|x_a - x_b| - L)^2 on the edges of the tetrahedra -- */

typedef struct springs {
    pl_component base;
    double stiffness;
    int device_ok; /* field: accept device buffers */
    int device_gradient; /* field: add_gradient takes device buffers */
    int nan_call; /* field: the project call (1-based) that writes NaN (0: none) */
    pl_component *state;
    int nedges, *edges;
    double *rest;
    int nverts;
} springs;

/* project calls since the last init (for nanCall; the tests run one
 * simulation at a time per process) */
static long sp_project_calls;

static int sp_init(pl_component *c, pl_ctx *ctx)
{
    springs *s = (springs *)c;
    sp_project_calls = 0;
    const pl_mesh *m = pl_util_topology(c, NULL, ctx, 1);
    if (!m) return PL_EINPUT;
    static const int E[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    s->nedges = 6 * m->ntets;
    s->edges = malloc((size_t)s->nedges * 2 * sizeof(int));
    s->rest = malloc((size_t)s->nedges * sizeof(double));
    if (!s->edges || !s->rest) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    for (int t = 0; t < m->ntets; ++t)
        for (int e = 0; e < 6; ++e) {
            int a = m->tets[4 * t + E[e][0]], b = m->tets[4 * t + E[e][1]], k = 6 * t + e;
            s->edges[2 * k] = a, s->edges[2 * k + 1] = b;
            double d2 = 0;
            for (int i = 0; i < 3; ++i) {
                double d = m->verts[3 * a + i] - m->verts[3 * b + i];
                d2 += d * d;
            }
            s->rest[k] = sqrt(d2);
        }
    s->nverts = m->nverts;
    return PL_OK;
}
static int sp_bind(pl_component *c, pl_ctx *ctx)
{
    springs *s = (springs *)c;
    s->state = pl_util_state(c, ctx, 1);
    return s->state ? PL_OK : PL_EINPUT;
}
static void sp_destroy(pl_component *c)
{
    springs *s = (springs *)c;
    free(s->edges);
    free(s->rest);
}
static pl_component *sp_state(const pl_component *c)
{
    return ((const springs *)c)->state;
}
static int sp_add_matrix(pl_component *c, int off, double h2, pl_triplets *A, pl_error *err)
{
    springs *s = (springs *)c;
    double w = h2 * s->stiffness;
    for (int k = 0; k < s->nedges; ++k) {
        int a = off + s->edges[2 * k], b = off + s->edges[2 * k + 1];
        if (pl_triplets_add(A, a, a, w) || pl_triplets_add(A, b, b, w) ||
            pl_triplets_add(A, a, b, -w) || pl_triplets_add(A, b, a, -w))
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    return PL_OK;
}
static int sp_project(const pl_component *c, pl_data *d, int off, double h2, const pl_buffer *q,
                      pl_buffer *rhs, pl_error *err)
{
    const springs *s = (const springs *)c;
    (void)d;
    if (q->location == PL_DEVICE && !s->device_ok)
        return pl_component_fail(c, err, PL_EINPUT, "device buffers refused");
    const double *x = q->data;
    double *b = rhs->data, w = h2 * s->stiffness;
    if (++sp_project_calls == s->nan_call) b[3 * off + 3 * s->edges[1]] = NAN;
    for (int k = 0; k < s->nedges; ++k) {
        int a = off + s->edges[2 * k], e = off + s->edges[2 * k + 1];
        double v[3], len = 0;
        for (int i = 0; i < 3; ++i) v[i] = x[3 * a + i] - x[3 * e + i], len += v[i] * v[i];
        len = sqrt(len);
        for (int i = 0; i < 3; ++i) {
            double p = s->rest[k] * v[i] / len;
            b[3 * a + i] += w * p;
            b[3 * e + i] -= w * p;
        }
    }
    return PL_OK;
}
static double sp_energy(const pl_component *c, const pl_data *d, int off, const pl_buffer *q)
{
    const springs *s = (const springs *)c;
    const double *x = q->data;
    double e = 0;
    (void)d;
    for (int k = 0; k < s->nedges; ++k) {
        int a = off + s->edges[2 * k], b = off + s->edges[2 * k + 1];
        double len = 0;
        for (int i = 0; i < 3; ++i)
            len += (x[3 * a + i] - x[3 * b + i]) * (x[3 * a + i] - x[3 * b + i]);
        e += 0.5 * s->stiffness * (sqrt(len) - s->rest[k]) * (sqrt(len) - s->rest[k]);
    }
    return e;
}
/* grad += k (|v| - rest) v / |v| at a, minus that at b (v = x_a - x_b). */
static int sp_gradient(const pl_component *c, const pl_data *d, int off, const pl_buffer *q,
                       pl_buffer *grad, pl_error *err)
{
    const springs *s = (const springs *)c;
    (void)d;
    if ((q->location == PL_DEVICE || grad->location == PL_DEVICE) && !s->device_gradient)
        return pl_component_fail(c, err, PL_EINPUT, "device buffers refused (gradient)");
    const double *x = q->data;
    double *g = grad->data;
    for (int k = 0; k < s->nedges; ++k) {
        int a = off + s->edges[2 * k], e = off + s->edges[2 * k + 1];
        double v[3], len = 0;
        for (int i = 0; i < 3; ++i) v[i] = x[3 * a + i] - x[3 * e + i], len += v[i] * v[i];
        len = sqrt(len);
        double f = s->stiffness * (len - s->rest[k]) / len;
        for (int i = 0; i < 3; ++i) {
            g[3 * a + i] += f * v[i];
            g[3 * e + i] -= f * v[i];
        }
    }
    return PL_OK;
}
static int sp_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    const springs *s = (const springs *)c;
    if ((int)prec == (PL_F64 | PL_ACCEPTS_GRADIENT))
        return where == PL_HOST || (s->device_ok && s->device_gradient);
    return prec == PL_F64 && (where == PL_HOST || s->device_ok);
}

static const pl_local_term_ops SP_OPS = {.version = PL_LOCAL_TERM_OPS_VERSION,
                                         .state = sp_state,
                                         .add_matrix = sp_add_matrix,
                                         .project = sp_project,
                                         .energy = sp_energy,
                                         .add_gradient = sp_gradient,
                                         .accepts = sp_accepts};
static const pl_field SP_FIELDS[] = {
    PL_FIELD(springs, stiffness, "stiffness", PL_F_DOUBLE, "100", "[N/m]", 0),
    PL_FIELD(springs, device_ok, "deviceOk", PL_F_BOOL, "1", "take device buffers", 0),
    PL_FIELD(springs, device_gradient, "deviceGradient", PL_F_BOOL, "1",
             "add_gradient takes device buffers", 0),
    PL_FIELD(springs, nan_call, "nanCall", PL_F_INT, "0",
             "the project call (1-based, since init) that writes a NaN into rhs (0: none)", 0),
};
const pl_type fake_springs_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "TestSprings",
    .help = "test springs on tetrahedron edges",
    .size = sizeof(springs),
    .fields = SP_FIELDS,
    .nfields = 4,
    .ops = {.init = sp_init, .bind = sp_bind, .destroy = sp_destroy},
    .roles = {[PL_ROLE_LOCAL_TERM] = &SP_OPS},
};

/* ---- TestDenseSolver: A = L L^T, dense ----------------------------------- */

typedef struct dense {
    pl_component base;
    int device_ok;
    int n;
    double *L;
} dense;

static int ds_factor(pl_component *c, const pl_csc *A, struct pl_timers *t, pl_error *err)
{
    dense *s = (dense *)c;
    (void)t;
    int n = A->ncols;
    free(s->L);
    s->n = n;
    s->L = calloc((size_t)n * (size_t)n, sizeof(double));
    if (!s->L) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int j = 0; j < n; ++j)
        for (int p = A->p[j]; p < A->p[j + 1]; ++p)
            if (A->i[p] >= j) s->L[A->i[p] * n + j] = A->x[p];
    for (int j = 0; j < n; ++j) {
        double *L = s->L;
        for (int k = 0; k < j; ++k) L[j * n + j] -= L[j * n + k] * L[j * n + k];
        if (!(L[j * n + j] > 0)) return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "not SPD");
        L[j * n + j] = sqrt(L[j * n + j]);
        for (int i = j + 1; i < n; ++i) {
            for (int k = 0; k < j; ++k) L[i * n + j] -= L[i * n + k] * L[j * n + k];
            L[i * n + j] /= L[j * n + j];
        }
    }
    return PL_OK;
}
static int ds_solve(const pl_component *c, const pl_buffer *b, pl_buffer *x, pl_error *err)
{
    const dense *s = (const dense *)c;
    if (b->location == PL_DEVICE && !s->device_ok)
        return pl_component_fail(c, err, PL_EINPUT, "device buffers refused");
    int n = s->n, k = (int)b->cols;
    const double *L = s->L, *bb = b->data;
    double *xx = x->data;
    if (xx != bb) memcpy(xx, bb, (size_t)n * (size_t)k * sizeof(double));
    for (int col = 0; col < k; ++col) {
        for (int i = 0; i < n; ++i) {
            double v = xx[i * k + col];
            for (int j = 0; j < i; ++j) v -= L[i * n + j] * xx[j * k + col];
            xx[i * k + col] = v / L[i * n + i];
        }
        for (int i = n - 1; i >= 0; --i) {
            double v = xx[i * k + col];
            for (int j = i + 1; j < n; ++j) v -= L[j * n + i] * xx[j * k + col];
            xx[i * k + col] = v / L[i * n + i];
        }
    }
    return PL_OK;
}
static int ds_size(const pl_component *c)
{
    return ((const dense *)c)->n;
}
static int ds_accepts(const pl_component *c, pl_location where, pl_precision prec)
{
    return prec == PL_F64 && (where == PL_HOST || ((const dense *)c)->device_ok);
}
static void ds_destroy(pl_component *c)
{
    free(((dense *)c)->L);
}
static const pl_global_solver_ops DS_OPS = {.version = PL_GLOBAL_SOLVER_OPS_VERSION,
                                            .factor = ds_factor,
                                            .solve = ds_solve,
                                            .size = ds_size,
                                            .accepts = ds_accepts};
static const pl_field DS_FIELDS[] = {
    PL_FIELD(dense, device_ok, "deviceOk", PL_F_BOOL, "1", "take device buffers", 0),
};
const pl_type fake_dense_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "TestDenseSolver",
    .help = "test dense Cholesky global solver",
    .size = sizeof(dense),
    .fields = DS_FIELDS,
    .nfields = 1,
    .ops = {.destroy = ds_destroy},
    .roles = {[PL_ROLE_GLOBAL_SOLVER] = &DS_OPS},
};
