/* shape_tets.c - ImplicitTetrahedra: a solid given as a union of simple
 * primitives (ellipsoids, capsules, boxes), optionally clipped by a box,
 * meshed on a regular grid: every cell whose centre is inside is kept and
 * split into 6 tetrahedra around its main diagonal (the Kuhn / Freudenthal
 * split, conforming across cells).  Generated at load time, so scenes need
 * no mesh files: the gingerbread man (an extruded cookie: a union clipped
 * to a slab) and the pulled body of pulling_through_gap are made this way. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "shape_tets.h"
#include "pliant/work_limits.h"



static const pl_field FIELDS[] = {
    PL_FIELD(shape_tets, ellipsoids, "ellipsoids", PL_F_DOUBLES, NULL,
             "ellipsoids of the union: cx cy cz rx ry rz each (axis-aligned radii) [m]", 0),
    PL_FIELD(shape_tets, capsules, "capsules", PL_F_DOUBLES, NULL,
             "capsules of the union: x0 y0 z0 x1 y1 z1 r each (segment and radius) [m]", 0),
    PL_FIELD(shape_tets, boxes, "boxes", PL_F_DOUBLES, NULL,
             "boxes of the union: xmin ymin zmin xmax ymax zmax each [m]", 0),
    PL_FIELD(shape_tets, clip, "clip", PL_F_DOUBLES, NULL,
             "keep only the part inside this box: xmin ymin zmin xmax ymax zmax [m] (e.g. a slab "
             "that makes a flat cookie)",
             0),
    PL_FIELD(shape_tets, cell, "cellSize", PL_F_DOUBLE, NULL,
             "edge of the grid's cubic cells [m]: the resolution", PL_FIELD_REQUIRED),
    PL_FIELD(shape_tets, smooth, "smooth", PL_F_BOOL, "1",
             "move the boundary vertices onto the shape's surface (no staircase; vertices move "
             "at most 0.45 cellSize and never invert a tetrahedron)",
             0),
    PL_FIELD(shape_tets, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "rotation of the generated mesh [deg about x, then y, then z]", 0),
    PL_FIELD(shape_tets, translation, "translation", PL_F_VEC3, "0 0 0",
             "translation after the rotation [m]", 0),
};

int coll_shape_inside(const shape_tets *s, const double p[3])
{
    if (s->clip.n == 6)
        for (int k = 0; k < 3; ++k)
            if (p[k] < s->clip.v[k] || p[k] > s->clip.v[3 + k]) return 0;
    for (int i = 0; i + 6 <= s->ellipsoids.n; i += 6) {
        const double *e = &s->ellipsoids.v[i];
        double r = 0;
        for (int k = 0; k < 3; ++k) r += (p[k] - e[k]) * (p[k] - e[k]) / (e[3 + k] * e[3 + k]);
        if (r <= 1.0) return 1;
    }
    for (int i = 0; i + 7 <= s->capsules.n; i += 7) {
        const double *c = &s->capsules.v[i];
        double d[3], w[3], dd = 0, t = 0, r2 = 0;
        for (int k = 0; k < 3; ++k) {
            d[k] = c[3 + k] - c[k];
            w[k] = p[k] - c[k];
            dd += d[k] * d[k];
            t += w[k] * d[k];
        }
        t = dd > 0 ? fmin(1.0, fmax(0.0, t / dd)) : 0.0;
        for (int k = 0; k < 3; ++k) r2 += (w[k] - t * d[k]) * (w[k] - t * d[k]);
        if (r2 <= c[6] * c[6]) return 1;
    }
    for (int i = 0; i + 6 <= s->boxes.n; i += 6) {
        const double *b = &s->boxes.v[i];
        if (p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] &&
            p[2] <= b[5])
            return 1;
    }
    return 0;
}

static int check_fields(shape_tets *s, pl_component *c, pl_ctx *ctx)
{
    if (s->ellipsoids.n % 6)
        return pl_component_error(c, ctx, PL_EINPUT, "ellipsoids: 6 numbers each, found %d",
                                  s->ellipsoids.n);
    if (s->capsules.n % 7)
        return pl_component_error(c, ctx, PL_EINPUT, "capsules: 7 numbers each, found %d",
                                  s->capsules.n);
    if (s->boxes.n % 6)
        return pl_component_error(c, ctx, PL_EINPUT, "boxes: 6 numbers each, found %d",
                                  s->boxes.n);
    if (s->clip.n != 0 && s->clip.n != 6)
        return pl_component_error(c, ctx, PL_EINPUT, "clip: 6 numbers (min max), found %d",
                                  s->clip.n);
    if (s->ellipsoids.n + s->capsules.n + s->boxes.n == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "no primitive: give ellipsoids, capsules or boxes");
    for (int i = 3; i < s->ellipsoids.n; i += (i % 6 == 5) ? 4 : 1)
        if (!(s->ellipsoids.v[i] > 0))
            return pl_component_error(c, ctx, PL_EINPUT, "ellipsoids: radii must be > 0 [m]");
    for (int i = 6; i < s->capsules.n; i += 7)
        if (!(s->capsules.v[i] > 0))
            return pl_component_error(c, ctx, PL_EINPUT, "capsules: radius must be > 0 [m]");
    if (!(s->cell > 0) || !isfinite(s->cell))
        return pl_component_error(c, ctx, PL_EINPUT, "cellSize must be > 0 [m], got %g", s->cell);
    return PL_OK;
}

/* Bounding box of the union (then of the clip). */
static void bounds(const shape_tets *s, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; ++k) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int i = 0; i + 6 <= s->ellipsoids.n; i += 6)
        for (int k = 0; k < 3; ++k) {
            const double *e = &s->ellipsoids.v[i];
            lo[k] = fmin(lo[k], e[k] - e[3 + k]);
            hi[k] = fmax(hi[k], e[k] + e[3 + k]);
        }
    for (int i = 0; i + 7 <= s->capsules.n; i += 7)
        for (int k = 0; k < 3; ++k) {
            const double *c = &s->capsules.v[i];
            lo[k] = fmin(lo[k], fmin(c[k], c[3 + k]) - c[6]);
            hi[k] = fmax(hi[k], fmax(c[k], c[3 + k]) + c[6]);
        }
    for (int i = 0; i + 6 <= s->boxes.n; i += 6)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], s->boxes.v[i + k]);
            hi[k] = fmax(hi[k], s->boxes.v[i + 3 + k]);
        }
    if (s->clip.n == 6)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmax(lo[k], s->clip.v[k]);
            hi[k] = fmin(hi[k], s->clip.v[3 + k]);
        }
}

double coll_tet_volume(const double *v, const int *t)
{
    const double *a = &v[3 * t[0]];
    double u[3], w[3], x[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = v[3 * t[1] + k] - a[k];
        w[k] = v[3 * t[2] + k] - a[k];
        x[k] = v[3 * t[3] + k] - a[k];
    }
    return (u[0] * (w[1] * x[2] - w[2] * x[1]) - u[1] * (w[0] * x[2] - w[2] * x[0]) +
            u[2] * (w[0] * x[1] - w[1] * x[0])) /
           6.0;
}

static int generate(shape_tets *s)
{
    double lo[3], hi[3];
    bounds(s, lo, hi);
    int n[3];
    for (int k = 0; k < 3; ++k) {
        double ext = hi[k] - lo[k];
        if (!(ext > 0)) return PL_EINPUT;
        n[k] = (int)ceil(ext / s->cell - 1e-9);
        lo[k] = 0.5 * (lo[k] + hi[k]) - 0.5 * n[k] * s->cell; /* centred grid */
        if (n[k] > 2000) return PL_EINPUT;
    }
    int m[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
    size_t nvert = (size_t)m[0] * m[1] * m[2], ncell = (size_t)n[0] * n[1] * n[2];
    int *id = malloc(nvert * sizeof *id);
    unsigned char *keep = malloc(ncell ? ncell : 1);
    if (!id || !keep) {
        free(id);
        free(keep);
        return PL_EINTERNAL;
    }
    for (size_t v = 0; v < nvert; ++v) id[v] = -1;
    size_t nkeep = 0;
    for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y)
            for (int x = 0; x < n[0]; ++x) {
                double p[3] = {lo[0] + (x + 0.5) * s->cell, lo[1] + (y + 0.5) * s->cell,
                               lo[2] + (z + 0.5) * s->cell};
                size_t c = (size_t)x + (size_t)n[0] * ((size_t)y + (size_t)n[1] * z);
                keep[c] = (unsigned char)coll_shape_inside(s, p);
                if (!keep[c]) continue;
                nkeep++;
                for (int b = 0; b < 8; ++b)
                    id[(size_t)(x + (b & 1)) +
                       (size_t)m[0] * ((size_t)(y + ((b >> 1) & 1)) + (size_t)m[1] * (z + (b >> 2)))] = 0;
            }
    int nv = 0;
    for (size_t v = 0; v < nvert; ++v)
        if (id[v] == 0) id[v] = nv++;
    pl_mesh *out = &s->mesh;
    out->verts = malloc((size_t)(nv ? nv : 1) * 3 * sizeof *out->verts);
    out->tets = malloc((nkeep ? nkeep : 1) * 24 * sizeof *out->tets);
    if (!out->verts || !out->tets) {
        free(id);
        free(keep);
        return PL_EINTERNAL;
    }
    for (int z = 0; z < m[2]; ++z)
        for (int y = 0; y < m[1]; ++y)
            for (int x = 0; x < m[0]; ++x) {
                int v = id[(size_t)x + (size_t)m[0] * ((size_t)y + (size_t)m[1] * z)];
                if (v < 0) continue;
                out->verts[3 * v] = lo[0] + x * s->cell;
                out->verts[3 * v + 1] = lo[1] + y * s->cell;
                out->verts[3 * v + 2] = lo[2] + z * s->cell;
            }
    /* the 6 monotone paths from corner 0 to corner 7 */
    static const int path[6][2] = {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}};
    int nt = 0;
    for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y)
            for (int x = 0; x < n[0]; ++x) {
                if (!keep[(size_t)x + (size_t)n[0] * ((size_t)y + (size_t)n[1] * z)]) continue;
                int c[8];
                for (int b = 0; b < 8; ++b)
                    c[b] = id[(size_t)(x + (b & 1)) +
                              (size_t)m[0] * ((size_t)(y + ((b >> 1) & 1)) +
                                              (size_t)m[1] * (z + (b >> 2)))];
                for (int p = 0; p < 6; ++p) {
                    int *t = &out->tets[4 * nt++];
                    t[0] = c[0];
                    t[1] = c[path[p][0]];
                    t[2] = c[path[p][0] | path[p][1]];
                    t[3] = c[7];
                    if (coll_tet_volume(out->verts, t) < 0) { /* positively oriented */
                        int tmp = t[1];
                        t[1] = t[2];
                        t[2] = tmp;
                    }
                }
            }
    out->nverts = nv;
    out->ntets = nt;
    int rc = PL_OK;
    if (s->smooth) {
        /* a vertex is on the boundary when one of its 8 cells is not kept */
        unsigned char *boundary = calloc((size_t)(nv ? nv : 1), 1);
        if (!boundary) rc = PL_EINTERNAL;
        for (int z = 0; z < m[2] && rc == PL_OK; ++z)
            for (int y = 0; y < m[1]; ++y)
                for (int x = 0; x < m[0]; ++x) {
                    int v = id[(size_t)x + (size_t)m[0] * ((size_t)y + (size_t)m[1] * z)];
                    if (v < 0) continue;
                    for (int b = 0; b < 8; ++b) {
                        int cx = x - (b & 1), cy = y - ((b >> 1) & 1), cz = z - (b >> 2);
                        if (cx < 0 || cy < 0 || cz < 0 || cx >= n[0] || cy >= n[1] || cz >= n[2] ||
                            !keep[(size_t)cx + (size_t)n[0] * ((size_t)cy + (size_t)n[1] * cz)])
                            boundary[v] = 1;
                    }
                }
        if (rc == PL_OK) rc = coll_shape_snap(s, out, boundary);
        free(boundary);
    }
    free(id);
    free(keep);
    return rc;
}

static int st_init(pl_component *c, pl_ctx *ctx)
{
    shape_tets *s = (shape_tets *)c;
    pl_mesh_init(&s->mesh);
    int rc = check_fields(s, c, ctx);
    if (rc) return rc;
    /* the work (and at most 6 tetrahedra per cell) grows with the grid over
     * the bounding box: estimated before it is scanned */
    double lo[3], hi[3], cells = 1;
    bounds(s, lo, hi);
    for (int k = 0; k < 3; ++k) cells *= hi[k] > lo[k] ? ceil((hi[k] - lo[k]) / s->cell) : 1;
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    if (pl_work_limit_check(c, ctx, 6 * cells, lim.max_elements,
                            "the tetrahedra of its grid (6 per cell of the bounding box)",
                            "maxElements"))
        return PL_EINPUT;
    rc = generate(s);
    if (rc == PL_EINPUT)
        return pl_component_error(c, ctx, rc,
                                  "the shape is empty or too large for cellSize %g m (at most "
                                  "2000 cells per axis)",
                                  s->cell);
    if (rc) return pl_component_error(c, ctx, rc, "out of memory");
    if (s->mesh.ntets == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "no cell centre is inside the shape: make cellSize smaller");
    static const double one[3] = {1, 1, 1};
    pl_mesh_transform(&s->mesh, one, s->rotation, s->translation);
    pl_log_info("%s %s: %d vertices, %d tetrahedra", c->type->name, c->name, s->mesh.nverts,
                s->mesh.ntets);
    return PL_OK;
}

static void st_destroy(pl_component *c) { pl_mesh_free(&((shape_tets *)c)->mesh); }

static const pl_mesh *st_mesh(const pl_component *c) { return &((const shape_tets *)c)->mesh; }

static const pl_topology_ops TOPOLOGY = {.version = PL_TOPOLOGY_OPS_VERSION, .mesh = st_mesh};

const pl_type coll_shape_tets_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "ImplicitTetrahedra",
    .help = "A solid of tetrahedra generated from a union of ellipsoids, capsules and boxes "
            "(optionally clipped by a box) on a regular grid of cells, 6 tetrahedra per cell.",
    .size = sizeof(shape_tets),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = st_init, .destroy = st_destroy},
    .roles = {[PL_ROLE_TOPOLOGY] = &TOPOLOGY},
};
