/* generator_components.c - scene components that generate meshes: a box of
 * tetrahedra (bars), a triangle grid (cloths), spheres and cylinders.  Each
 * provides its mesh through the topology role, like MeshLoader. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "generators/generators.h"
#include "loader.h"

/* ---- RegularGridTetrahedra ---------------------------------------------- */

typedef struct grid_tets {
    pl_component base;
    pl_mesh mesh;
    double min[3], max[3], rotation[3], translation[3];
    pl_ints n;
    pl_doubles holes;
} grid_tets;
_Static_assert(offsetof(grid_tets, mesh) == sizeof(pl_component), "mesh after base");

static const pl_field GRID_TETS_FIELDS[] = {
    PL_FIELD(grid_tets, min, "min", PL_F_VEC3, "0 0 0", "lower corner of the box [m]", 0),
    PL_FIELD(grid_tets, max, "max", PL_F_VEC3, "1 1 1", "upper corner of the box [m]", 0),
    PL_FIELD(grid_tets, n, "n", PL_F_INTS, NULL,
             "vertices along x, y and z (each >= 2); every cell is split into 6 tetrahedra",
             PL_FIELD_REQUIRED),
    PL_FIELD(grid_tets, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "rotation of the generated mesh [deg about x, then y, then z]", 0),
    PL_FIELD(grid_tets, translation, "translation", PL_F_VEC3, "0 0 0",
             "translation after the rotation [m]", 0),
    PL_FIELD(grid_tets, holes, "holes", PL_F_DOUBLES, NULL,
             "boxes (xmin ymin zmin xmax ymax zmax each, before the rotation) whose cells are "
             "left out: cavities (SurfacePressureConstraint box) or notches",
             0),
};

/* Leaves out the tetrahedra whose centroid lies in a hole box (all six of
 * a cell share its centre's side for boxes on cell boundaries), then the
 * vertices no tetrahedron uses. */
static int cut_holes(pl_mesh *m, const pl_doubles *holes)
{
    int kept = 0;
    for (int t = 0; t < m->ntets; ++t) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k)
            for (int a = 0; a < 3; ++a) c[a] += 0.25 * m->verts[3 * m->tets[4 * t + k] + a];
        int in = 0;
        for (int b = 0; b + 6 <= holes->n && !in; b += 6) {
            const double *h = holes->v + b;
            in = c[0] > h[0] && c[0] < h[3] && c[1] > h[1] && c[1] < h[4] && c[2] > h[2] &&
                 c[2] < h[5];
        }
        if (!in) memmove(m->tets + 4 * kept++, m->tets + 4 * t, 4 * sizeof *m->tets);
    }
    m->ntets = kept;
    m->ntris = 0; /* the generator writes none for a box */
    return pl_mesh_drop_unused(m);
}

static int finish(pl_component *c, pl_ctx *ctx, pl_mesh *m, int rc, pl_error *err,
                  const double rot[3], const double tr[3])
{
    static const double one[3] = {1, 1, 1};
    if (rc != PL_OK) return pl_component_error(c, ctx, rc, "%s", err->msg);
    pl_mesh_transform(m, one, rot, tr);
    pl_log_debug("%s %s: %d vertices, %d tetrahedra, %d triangles", c->type->name, c->name,
                 m->nverts, m->ntets, m->ntris);
    return PL_OK;
}

/* Refuses a mesh of `elements` (estimated before it is made) above the cap;
 * a NaN estimate (arguments the generator itself refuses) passes. */
static int check_size(pl_component *c, pl_ctx *ctx, double elements)
{
    if (!(elements >= 0)) return PL_OK;
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    return pl_work_limit_check(c, ctx, elements, lim.max_elements,
                               "the number of elements it would generate", "maxElements");
}

static int grid_tets_init(pl_component *c, pl_ctx *ctx)
{
    grid_tets *g = (grid_tets *)c;
    pl_error err;
    if (g->n.n != 3) return pl_component_error(c, ctx, PL_EINPUT, "n: expected 3 integers (nx ny nz)");
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= g->n.v[a] >= 2 ? g->n.v[a] - 1.0 : NAN;
    if (check_size(c, ctx, 6.0 * cells)) return PL_EINPUT;
    if (g->holes.n && pl_util_check_boxes(c, ctx, "holes", &g->holes)) return PL_EINPUT;
    int rc = pl_generate_box_tets(g->n.v, g->min, g->max, &g->mesh, &err);
    if (rc == PL_OK && g->holes.n && cut_holes(&g->mesh, &g->holes) < 0)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (rc == PL_OK && g->mesh.ntets == 0)
        return pl_component_error(c, ctx, PL_EINPUT, "holes: they leave no tetrahedron");
    return finish(c, ctx, &g->mesh, rc, &err, g->rotation, g->translation);
}

static void mesh_destroy(pl_component *c)
{
    pl_mesh_free((pl_mesh *)((char *)c + sizeof(pl_component)));
}

const pl_type pl_grid_tetrahedra_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "RegularGridTetrahedra",
    .help = "A box of tetrahedra: n[0] x n[1] x n[2] vertices, 6 tetrahedra per cell (bars).",
    .size = sizeof(grid_tets),
    .fields = GRID_TETS_FIELDS,
    .nfields = sizeof GRID_TETS_FIELDS / sizeof GRID_TETS_FIELDS[0],
    .ops = {.init = grid_tets_init, .destroy = mesh_destroy},
    .roles = {[PL_ROLE_TOPOLOGY] = &pl_mesh_provider_ops},
};

/* ---- RegularGridTriangles ----------------------------------------------- */

static const pl_field GRID_TRIS_FIELDS[] = {
    PL_FIELD(grid_tets, min, "min", PL_F_VEC3, "0 0 0", "lower corner [m]", 0),
    PL_FIELD(grid_tets, max, "max", PL_F_VEC3, "1 0 1",
             "upper corner [m]; the axis whose n is 1 is the cloth's normal", 0),
    PL_FIELD(grid_tets, n, "n", PL_F_INTS, NULL,
             "vertices along x, y and z: exactly one of them 1 (the flat axis), the others >= 2",
             PL_FIELD_REQUIRED),
    PL_FIELD(grid_tets, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "rotation of the generated mesh [deg about x, then y, then z]", 0),
    PL_FIELD(grid_tets, translation, "translation", PL_F_VEC3, "0 0 0",
             "translation after the rotation [m]", 0),
};

static int grid_tris_init(pl_component *c, pl_ctx *ctx)
{
    grid_tets *g = (grid_tets *)c;
    pl_error err;
    if (g->n.n != 3) return pl_component_error(c, ctx, PL_EINPUT, "n: expected 3 integers (nx ny nz)");
    int flat = -1;
    for (int a = 0; a < 3; ++a)
        if (g->n.v[a] == 1) flat = flat < 0 ? a : 3;
    if (flat < 0 || flat == 3)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "n: exactly one axis must have 1 vertex (the flat one), found "
                                  "%d %d %d",
                                  g->n.v[0], g->n.v[1], g->n.v[2]);
    int u = (flat + 1) % 3, v = (flat + 2) % 3;
    double eu[3] = {0, 0, 0}, ev[3] = {0, 0, 0};
    eu[u] = g->max[u] - g->min[u];
    ev[v] = g->max[v] - g->min[v];
    if (g->n.v[u] >= 2 && g->n.v[v] >= 2 &&
        check_size(c, ctx, 2.0 * (g->n.v[u] - 1.0) * (g->n.v[v] - 1.0)))
        return PL_EINPUT;
    int rc = pl_generate_triangle_grid(g->n.v[u], g->n.v[v], g->min, eu, ev, &g->mesh, &err);
    return finish(c, ctx, &g->mesh, rc, &err, g->rotation, g->translation);
}

const pl_type pl_grid_triangles_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "RegularGridTriangles",
    .help = "A flat rectangle of triangles (cloth) between min and max; n gives the vertices per "
            "axis, 1 on the flat axis.",
    .size = sizeof(grid_tets),
    .fields = GRID_TRIS_FIELDS,
    .nfields = sizeof GRID_TRIS_FIELDS / sizeof GRID_TRIS_FIELDS[0],
    .ops = {.init = grid_tris_init, .destroy = mesh_destroy},
    .roles = {[PL_ROLE_TOPOLOGY] = &pl_mesh_provider_ops},
};

/* ---- SphereMesh and CylinderMesh ---------------------------------------- */

typedef struct shape_mesh {
    pl_component base;
    pl_mesh mesh;
    double center[3], radius, height, inner;
    int volume, level, vertices, rings, layers, sides;
} shape_mesh;
_Static_assert(offsetof(shape_mesh, mesh) == sizeof(pl_component), "mesh after base");

static const pl_field SPHERE_FIELDS[] = {
    PL_FIELD(shape_mesh, center, "center", PL_F_VEC3, "0 0 0", "centre [m]", 0),
    PL_FIELD(shape_mesh, radius, "radius", PL_F_DOUBLE, "1", "radius [m]", 0),
    PL_FIELD(shape_mesh, volume, "volume", PL_F_BOOL, "1",
             "1: a solid ball of tetrahedra; 0: an icosphere surface of triangles", 0),
    PL_FIELD(shape_mesh, vertices, "vertices", PL_F_INT, "1000",
             "solid ball: about this many vertices", 0),
    PL_FIELD(shape_mesh, level, "level", PL_F_INT, "3",
             "surface and hollow sphere: icosahedron subdivisions (10*4^level + 2 vertices)", 0),
    PL_FIELD(shape_mesh, inner, "innerRadius", PL_F_DOUBLE, "0",
             "> 0: a hollow sphere (thick-walled shell) of tetrahedra between innerRadius and "
             "radius [m], the icosphere of `level` on layers + 1 spheres; its triangles are "
             "both boundary spheres",
             0),
    PL_FIELD(shape_mesh, layers, "layers", PL_F_INT, "0",
             "hollow sphere: layers of prisms through the wall (0: about as thick as the inner "
             "sphere's edges)",
             0),
};

static int sphere_init(pl_component *c, pl_ctx *ctx)
{
    shape_mesh *s = (shape_mesh *)c;
    pl_error err;
    static const double zero[3] = {0, 0, 0};
    /* a ball of about `vertices` vertices has 6 tetrahedra per vertex at most;
     * an icosphere of level L has 20 4^L triangles */
    if (s->inner != 0) {
        /* the inner icosphere's edge is about 1.1 innerRadius / 2^level */
        int layers = s->layers > 0 ? s->layers
                     : (int)fmax(1.0, ceil((s->radius - s->inner) /
                                           (1.1 * s->inner / pow(2, s->level))));
        if (!s->volume)
            return pl_component_error(c, ctx, PL_EINPUT, "innerRadius needs volume=\"1\"");
        if (check_size(c, ctx, 60.0 * pow(4, s->level) * layers)) return PL_EINPUT;
        int rc = pl_generate_sphere_shell(s->center, s->inner, s->radius, s->level, layers,
                                          &s->mesh, &err);
        return finish(c, ctx, &s->mesh, rc, &err, zero, zero);
    }
    if (check_size(c, ctx, s->volume ? 6.0 * s->vertices : 20.0 * pow(4, s->level)))
        return PL_EINPUT;
    int rc = s->volume ? pl_generate_sphere_tets(s->center, s->radius, s->vertices, &s->mesh, &err)
                       : pl_generate_sphere_surface(s->center, s->radius, s->level, &s->mesh, &err);
    return finish(c, ctx, &s->mesh, rc, &err, zero, zero);
}

const pl_type pl_sphere_mesh_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "SphereMesh",
    .help = "A ball of tetrahedra, a hollow sphere (innerRadius > 0) or a sphere surface of "
            "triangles.",
    .size = sizeof(shape_mesh),
    .fields = SPHERE_FIELDS,
    .nfields = sizeof SPHERE_FIELDS / sizeof SPHERE_FIELDS[0],
    .ops = {.init = sphere_init, .destroy = mesh_destroy},
    .roles = {[PL_ROLE_TOPOLOGY] = &pl_mesh_provider_ops},
};

static const pl_field CYLINDER_FIELDS[] = {
    PL_FIELD(shape_mesh, center, "center", PL_F_VEC3, "0 0 0", "centre [m] (axis along y)", 0),
    PL_FIELD(shape_mesh, radius, "radius", PL_F_DOUBLE, "1", "radius [m]", 0),
    PL_FIELD(shape_mesh, height, "height", PL_F_DOUBLE, "1", "length along y [m]", 0),
    PL_FIELD(shape_mesh, volume, "volume", PL_F_BOOL, "1",
             "1: solid tetrahedra; 0: a closed surface of triangles", 0),
    PL_FIELD(shape_mesh, rings, "rings", PL_F_INT, "4", "solid: concentric rings of the disk", 0),
    PL_FIELD(shape_mesh, layers, "layers", PL_F_INT, "0",
             "layers along the axis (solid: 0 picks about ring-thick layers)", 0),
    PL_FIELD(shape_mesh, sides, "sides", PL_F_INT, "24", "surface: vertices around", 0),
};

static int cylinder_init(pl_component *c, pl_ctx *ctx)
{
    shape_mesh *s = (shape_mesh *)c;
    pl_error err;
    static const double zero[3] = {0, 0, 0};
    /* solid: 3 tetrahedra per disk triangle (6 rings^2) per layer (0 layers:
     * about height rings / radius); surface: 2 triangles per side quad per
     * layer plus the caps */
    double layers = s->layers > 0 ? s->layers
                    : s->radius > 0 ? fmax(1.0, s->height * s->rings / s->radius) : NAN;
    if (check_size(c, ctx, s->volume ? 18.0 * s->rings * s->rings * layers
                                     : 2.0 * s->sides * (layers + 1)))
        return PL_EINPUT;
    int rc = s->volume ? pl_generate_cylinder_tets(s->center, s->radius, s->height, s->rings,
                                                   s->layers, &s->mesh, &err)
                       : pl_generate_cylinder_surface(s->center, s->radius, s->height, s->sides,
                                                      s->layers > 0 ? s->layers : 1, &s->mesh,
                                                      &err);
    return finish(c, ctx, &s->mesh, rc, &err, zero, zero);
}

const pl_type pl_cylinder_mesh_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "CylinderMesh",
    .help = "A solid cylinder of tetrahedra or a closed cylinder surface (axis along y).",
    .size = sizeof(shape_mesh),
    .fields = CYLINDER_FIELDS,
    .nfields = sizeof CYLINDER_FIELDS / sizeof CYLINDER_FIELDS[0],
    .ops = {.init = cylinder_init, .destroy = mesh_destroy},
    .roles = {[PL_ROLE_TOPOLOGY] = &pl_mesh_provider_ops},
};
