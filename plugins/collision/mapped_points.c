/* mapped_points.c - MappedPoints: points that only follow a body (SOFA's
 * mapped MechanicalObject: a collision node's sphere centres under a
 * BarycentricMapping, a surface's points under an IdentityMapping).  They
 * have no mass and take no part in the solve: after every step each point
 * is sum_k w_k x_k over the corners of the tetrahedron that contained it at
 * rest (the nearest one, weights extrapolated, when it was outside; the
 * location is tet_map.c's, as for MappedSurfaceCollisionModel), or the
 * body's vertex itself without points (identity).  `pliant regress` records
 * them as SOFA's WriteState records mapped states (mapped 1). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "models.h"

typedef struct mapped_points {
    pl_component base;
    pl_doubles position;  /* field: rest points (none: identity) */
    char *filename;       /* field: a SOFA .sph file: its sphere centres */
    pl_link volume;
    /* model */
    pl_component *state;
    int n;                /* points */
    double *rest;         /* n x 3 rest points (barycentric) */
    int *local;           /* n x 4 vertices of the state (identity: NULL) */
    double *weight;       /* n x 4 weights */
    int slot_x, slot_v;
} mapped_points;

static const pl_field FIELDS[] = {
    PL_FIELD(mapped_points, position, "position", PL_F_DOUBLES, NULL,
             "rest points [m], x y z each, mapped into the tetrahedra containing them (none and "
             "no filename: the body's own vertices, SOFA's IdentityMapping)",
             0),
    PL_FIELD(mapped_points, filename, "filename", PL_F_STRING, NULL,
             "a SOFA sphere file (.sph, SphereLoader): the sphere centres are the rest points", 0),
    PL_FIELD(mapped_points, volume, "tetrahedra", PL_F_LINK, NULL,
             "the body's tetrahedral mesh (default: the mesh of the state's node)", 0),
};

/* The centres of a .sph file ("sphe index x y z radius" lines). */
static int read_sph(mapped_points *m, pl_component *c, pl_ctx *ctx)
{
    char path[4096], tried[2048];
    if (pl_util_data_file(c->node->file, m->filename, path, sizeof path, tried, sizeof tried))
        return pl_component_error(c, ctx, PL_EINPUT, "filename: '%s' not found (tried %s)",
                                  m->filename, tried);
    FILE *f = fopen(path, "r");
    if (!f) return pl_component_error(c, ctx, PL_EINPUT, "filename: cannot open '%s'", path);
    char line[512];
    int ln = 0, rc = PL_OK, cap = 0;
    while (rc == PL_OK && fgets(line, sizeof line, f)) {
        ++ln;
        if (strncmp(line, "sphe", 4) || (line[4] != ' ' && line[4] != '\t')) continue;
        double p[3], r;
        int idx;
        if (sscanf(line + 4, "%d %lf %lf %lf %lf", &idx, &p[0], &p[1], &p[2], &r) != 5 ||
            !isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            rc = pl_component_error(c, ctx, PL_EINPUT,
                                    "%s:%d: expected 'sphe index x y z radius'", path, ln);
            break;
        }
        if (m->n == cap) {
            double *y = realloc(m->rest, (size_t)(cap = cap ? 2 * cap : 64) * 3 * sizeof *y);
            if (!y) {
                rc = pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
                break;
            }
            m->rest = y;
        }
        memcpy(&m->rest[3 * m->n++], p, sizeof p);
    }
    fclose(f);
    if (rc == PL_OK && m->n == 0)
        rc = pl_component_error(c, ctx, PL_EINPUT, "%s: no sphere ('sphe' line)", path);
    return rc;
}

static void free_map(mapped_points *m)
{
    free(m->local);
    free(m->weight);
    m->local = NULL;
    m->weight = NULL;
}

static int mp_init(pl_component *c, pl_ctx *ctx)
{
    mapped_points *m = (mapped_points *)c;
    m->state = pl_node_find_role_up(c->node, PL_ROLE_STATE);
    if (!m->state)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "no state (MechanicalObject) in this node or above it to follow");
    if (m->filename && m->position.n)
        return pl_component_error(c, ctx, PL_EINPUT, "give position or filename, not both");
    if (m->position.n % 3)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "position: expected 3 numbers per point, found %d numbers",
                                  m->position.n);
    if (m->filename) {
        int rc = read_sph(m, c, ctx);
        if (rc) return rc;
    } else if (m->position.n) {
        m->n = m->position.n / 3;
        m->rest = malloc((size_t)m->position.n * sizeof *m->rest);
        if (!m->rest) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
        memcpy(m->rest, m->position.v, (size_t)m->position.n * sizeof *m->rest);
    } else {
        const pl_state_ops *so = pl_component_role(m->state, PL_ROLE_STATE);
        m->n = so->count(m->state);
    }
    size_t bytes = (size_t)m->n * 3 * sizeof(double);
    m->slot_x = pl_model_add_slot(ctx->build, c, "position", bytes);
    m->slot_v = pl_model_add_slot(ctx->build, c, "velocity", bytes);
    if (m->slot_x < 0 || m->slot_v < 0)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_model_set_slot_check(ctx->build, m->slot_x, pl_slot_check_finite);
    pl_model_set_slot_check(ctx->build, m->slot_v, pl_slot_check_finite);
    return PL_OK;
}

/* Each rest point's tetrahedron and weights. */
static int locate(mapped_points *m, pl_component *c, pl_ctx *ctx)
{
    int n;
    const double *rest = pl_util_rest(m->state, &n);
    pl_component *t = m->volume.target ? m->volume.target
                                       : pl_node_find_role(m->state->node, PL_ROLE_TOPOLOGY);
    const pl_topology_ops *ops = t ? pl_component_role(t, PL_ROLE_TOPOLOGY) : NULL;
    const pl_mesh *vol = ops ? ops->mesh(t) : NULL;
    if (!vol || vol->ntets == 0 || vol->nverts != n || !rest)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "tetrahedra: the points are mapped into the tetrahedra of the "
                                  "state '%s' (%d vertices), which %s",
                                  m->state->name, n,
                                  vol ? "this mesh does not match" : "has no mesh here");
    size_t cnt = (size_t)m->n;
    int *tet_of = malloc(cnt * sizeof *tet_of);
    m->local = malloc(cnt * 4 * sizeof *m->local);
    m->weight = malloc(cnt * 4 * sizeof *m->weight);
    if (!tet_of || !m->local || !m->weight) {
        free(tet_of);
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    }
    pl_error err;
    int outside = 0;
    int rc = barycentric_map(rest, n, vol->tets, vol->ntets, m->rest, m->n, tet_of, m->weight,
                             &outside, &err);
    if (rc == PL_OK)
        for (int i = 0; i < m->n; ++i)
            for (int k = 0; k < 4; ++k) m->local[4 * i + k] = vol->tets[4 * tet_of[i] + k];
    free(tet_of);
    if (rc) return pl_component_error(c, ctx, rc, "%s", err.msg);
    if (outside)
        pl_component_warn(c, ctx, "%d of %d points lie outside the body's tetrahedra: they "
                                  "follow the nearest one (extrapolated weights)",
                          outside, m->n);
    return PL_OK;
}

/* Positions and velocities from the state's in d. */
static void follow(const mapped_points *m, pl_data *d)
{
    const pl_state_ops *so = pl_component_role(m->state, PL_ROLE_STATE);
    pl_buffer xb = so->positions(m->state, d), vb = so->velocities(m->state, d);
    const double *xs = pl_buffer_f64(&xb), *vs = pl_buffer_f64(&vb);
    double *x = pl_data_slot(d, m->slot_x), *v = pl_data_slot(d, m->slot_v);
    if (!m->local) {
        memcpy(x, xs, (size_t)m->n * 3 * sizeof *x);
        memcpy(v, vs, (size_t)m->n * 3 * sizeof *v);
        return;
    }
    for (int i = 0; i < m->n; ++i)
        for (int j = 0; j < 3; ++j) {
            double px = 0.0, pv = 0.0;
            for (int k = 0; k < 4; ++k) {
                int l = m->local[4 * i + k];
                px += m->weight[4 * i + k] * xs[3 * l + j];
                pv += m->weight[4 * i + k] * vs[3 * l + j];
            }
            x[3 * i + j] = px;
            v[3 * i + j] = pv;
        }
}

static int mp_bind(pl_component *c, pl_ctx *ctx)
{
    mapped_points *m = (mapped_points *)c;
    free_map(m);
    if (m->rest) {
        int rc = locate(m, c, ctx);
        if (rc) return rc;
    }
    follow(m, ctx->data);
    return PL_OK;
}

static int mp_end_step(const pl_component *c, pl_ctx *ctx, pl_error *err)
{
    (void)err;
    follow((const mapped_points *)c, ctx->data);
    return PL_OK;
}

static void mp_destroy(pl_component *c)
{
    mapped_points *m = (mapped_points *)c;
    free_map(m);
    free(m->rest);
}

static int format_block(const double *x, int n, char *buf, size_t size)
{
    size_t w = 0;
    buf[0] = '\0';
    for (int i = 0; i < 3 * n; ++i) {
        int k = snprintf(buf + w, size - w, i ? " %.17g" : "%.17g", x[i]);
        if (k < 0 || (size_t)k >= size - w) return PL_EINTERNAL;
        w += (size_t)k;
    }
    return PL_OK;
}

static int mp_get(const pl_component *c, const pl_data *d, const char *field, char *buf,
                  size_t size)
{
    const mapped_points *m = (const mapped_points *)c;
    if (!strcmp(field, "position")) return format_block(pl_data_slot(d, m->slot_x), m->n, buf, size);
    if (!strcmp(field, "velocity")) return format_block(pl_data_slot(d, m->slot_v), m->n, buf, size);
    return PL_EINPUT;
}

const pl_type coll_mapped_points_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "MappedPoints",
    .help = "Points that follow a body without mass or forces (SOFA's mapped MechanicalObject): "
            "barycentric in its tetrahedra, or its own vertices; recorded by pliant regress "
            "(mapped 1).",
    .size = sizeof(mapped_points),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = mp_init,
            .bind = mp_bind,
            .end_step = mp_end_step,
            .destroy = mp_destroy,
            .get = mp_get},
};
