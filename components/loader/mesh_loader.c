/* mesh_loader.c - MeshLoader: reads a mesh file (any supported format,
 * detected from the content) and provides it to the node. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/mesh_subdivide.h"
#include "loader.h"
#include "pliant/work_limits.h"

typedef struct mesh_loader {
    pl_component base;
    pl_mesh mesh;          /* first after base: see pl_mesh_provider_ops */
    char *filename;
    double scale3d[3], rotation[3], translation[3];
    int only_attached;
    int keep_inverted;
    int subdivide;
    char *resolved;
} mesh_loader;

_Static_assert(offsetof(mesh_loader, mesh) == sizeof(pl_component),
               "pl_mesh_provider_ops expects the mesh right after the pl_component");

static const pl_field FIELDS[] = {
    PL_FIELD(mesh_loader, filename, "filename", PL_F_STRING, NULL,
             "mesh file: VTK legacy, VTU, Gmsh .msh v1/v2/v4, OBJ or STL (format read from the "
             "content); relative to the scene's folder",
             PL_FIELD_REQUIRED),
    PL_FIELD(mesh_loader, scale3d, "scale3d", PL_F_VEC3, "1 1 1",
             "scale applied to the vertices (0.001 0.001 0.001 turns millimetres into metres)", 0),
    PL_FIELD(mesh_loader, rotation, "rotation", PL_F_VEC3, "0 0 0",
             "rotation after scaling [deg about x, then y, then z]", 0),
    PL_FIELD(mesh_loader, translation, "translation", PL_F_VEC3, "0 0 0",
             "translation after rotation [m]", 0),
    PL_FIELD(mesh_loader, only_attached, "onlyAttachedPoints", PL_F_BOOL, "0",
             "drop vertices that no element uses (they would have no mass)", 0),
    PL_FIELD(mesh_loader, keep_inverted, "keepInverted", PL_F_BOOL, "0",
             "keep negatively oriented tetrahedra as they are (default: flip them, with a warning)",
             0),
    PL_FIELD(mesh_loader, subdivide, "subdivide", PL_F_INT, "0",
             "rounds of 1-to-8 tetrahedral subdivision (edge midpoints; each round multiplies "
             "the tetrahedra by 8)",
             0),
};

static int ml_init(pl_component *c, pl_ctx *ctx)
{
    mesh_loader *l = (mesh_loader *)c;
    char path[1024], tried[2048];
    if (!l->filename || !l->filename[0])
        return pl_component_error(c, ctx, PL_EINPUT, "filename is empty");
    if (pl_util_data_file(c->file, l->filename, path, sizeof path, tried, sizeof tried) != 0)
        return pl_component_error(c, ctx, PL_EINPUT, "filename: cannot find '%s' (tried %s)",
                                  l->filename, tried);
    if (!(l->resolved = strdup(path))) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_mesh_load_options opt = {.drop_unused = l->only_attached,
                                .keep_inverted = l->keep_inverted};
    pl_diag diag;
    pl_diag_init(&diag);
    int rc = pl_mesh_load(path, &opt, &l->mesh, &diag);
    /* the loader's messages name the mesh file and line; add which component read it */
    char where[192], p[160];
    snprintf(where, sizeof where, "MeshLoader %.170s", pl_component_path(c, p, sizeof p));
    for (int k = 0; k < diag.count; ++k) {
        pl_error e = diag.items[k];
        memcpy(e.where, where, sizeof e.where);
        pl_diag_add(ctx->diag, &e);
    }
    pl_diag_free(&diag);
    if (rc != PL_OK) {
        pl_component_error(c, ctx, rc, "could not load '%s' (see the message above)", path);
        return rc;
    }
    pl_mesh_transform(&l->mesh, l->scale3d, l->rotation, l->translation);
    if (l->subdivide < 0)
        return pl_component_error(c, ctx, PL_EINPUT, "subdivide must be >= 0, got %d",
                                  l->subdivide);
    /* each round multiplies the tetrahedra by 8, the triangles by 4: refuse
     * before making the first one what the last one could not hold */
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    double elements = l->mesh.ntets * pow(8, l->subdivide) + l->mesh.ntris * pow(4, l->subdivide);
    char what[96];
    snprintf(what, sizeof what, "the element count after subdivide=\"%d\" (of %d tetrahedra and "
             "%d triangles)", l->subdivide, l->mesh.ntets, l->mesh.ntris);
    if (pl_work_limit_check(c, ctx, elements, lim.max_elements, what, "maxElements"))
        return PL_EINPUT;
    pl_error se;
    if ((rc = pl_mesh_subdivide(&l->mesh, l->subdivide, &se)) != PL_OK)
        return pl_component_error(c, ctx, rc, "subdivide: %s", se.msg);
    pl_log_debug("MeshLoader %s: %s: %d vertices, %d tetrahedra, %d triangles", c->name, path,
                 l->mesh.nverts, l->mesh.ntets, l->mesh.ntris);
    return PL_OK;
}

static void ml_destroy(pl_component *c)
{
    mesh_loader *l = (mesh_loader *)c;
    pl_mesh_free(&l->mesh);
    free(l->resolved);
}

static const pl_mesh *provider_mesh(const pl_component *c)
{
    /* every mesh provider stores its pl_mesh right after the pl_component */
    return (const pl_mesh *)((const char *)c + sizeof(pl_component));
}

const pl_topology_ops pl_mesh_provider_ops = {.version = PL_TOPOLOGY_OPS_VERSION,
                                              .mesh = provider_mesh};

const pl_type pl_mesh_loader_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "MeshLoader",
    .help = "Loads a tetrahedral or triangle mesh from a file (VTK, VTU, Gmsh, OBJ, STL).",
    .size = sizeof(mesh_loader),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = ml_init, .destroy = ml_destroy},
    .roles = {[PL_ROLE_TOPOLOGY] = &pl_mesh_provider_ops},
};
