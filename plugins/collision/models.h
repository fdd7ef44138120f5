/* models.h - what the mesh-based collision components share (plugin-
 * internal): where a surface comes from (a file, a link to a loader or
 * generator, or vertices and triangles written in the scene) with its
 * placement, and the per-type queries the CollisionPipeline makes. */
#ifndef PLIANT_COLLISION_MODELS_H
#define PLIANT_COLLISION_MODELS_H

#include "detect.h"
#include "pliant/pliant.h"
#include "pliant/util.h"

/* The source of a surface: exactly one of filename, src, position. */
typedef struct coll_mesh_source {
    pl_link src;
    char *filename;
    pl_doubles position;   /* inline vertices, x y z each [m] */
    pl_ints triangles;     /* inline triangles, 3 indices each */
    double scale3d[3], rotation[3], translation[3];
} coll_mesh_source;

/* Field table entries of a coll_mesh_source member `m` of struct S. */
#define COLL_MESH_SOURCE_FIELDS(S, m, what)                                                      \
    PL_FIELD(S, m.src, "src", PL_F_LINK, NULL,                                                    \
             "the " what " from a loader or generator (default: the first one in this node; "    \
             "a volume mesh gives its boundary surface)",                                         \
             0),                                                                                  \
    PL_FIELD(S, m.filename, "filename", PL_F_STRING, NULL,                                        \
             "the " what " from a file (OBJ, STL, VTK, VTU, Gmsh), relative to the scene's "     \
             "folder; instead of src",                                                            \
             0),                                                                                  \
    PL_FIELD(S, m.position, "position", PL_F_DOUBLES, NULL,                                       \
             "the " what "'s vertices written in the scene, x y z each [m] (with triangles); "   \
             "instead of src",                                                                    \
             0),                                                                                  \
    PL_FIELD(S, m.triangles, "triangles", PL_F_INTS, NULL,                                        \
             "the triangles of position, 3 vertex indices each", 0),                              \
    PL_FIELD(S, m.scale3d, "scale3d", PL_F_VEC3, "1 1 1",                                         \
             "scale applied to the " what " (0.001 0.001 0.001: millimetres to metres)", 0),     \
    PL_FIELD(S, m.rotation, "rotation", PL_F_VEC3, "0 0 0",                                       \
             "rotation after scaling [deg about x, then y, then z]", 0),                          \
    PL_FIELD(S, m.translation, "translation", PL_F_VEC3, "0 0 0",                                 \
             "translation after rotation [m]", 0)

/* Reads the surface into out (vertices and triangles; a volume mesh gives its
 * boundary, oriented outward; vertices no triangle uses are dropped), placed
 * by scale3d, rotation, translation.  Errors are recorded against c. */
int coll_mesh_source_load(pl_component *c, pl_ctx *ctx, coll_mesh_source *s, pl_mesh *out);


/* The sides setting of a collision model of this plugin: MeshObstacle's
 * field; one for the boundary of a tetrahedral body (a solid, whatever
 * non-manifold edges its boundary has where parts of it touch); auto for
 * the others. */
pl_mesh_sides coll_model_sides(const pl_component *c);
/* Whether c is a SurfaceCollisionModel of a tetrahedral body. */
int coll_surface_model_solid(const pl_component *c);

/* A collision model's geometry of one step, in the data being stepped
 * (model_ws.c; the type's workspace_size is sizeof(coll_geom_ws)). */
typedef struct coll_geom_ws {
    double *x, *v;        /* n x 3 positions [m] and velocities [m/s] */
    int *vertex;          /* n x 4 global vertices, or NULL */
} coll_geom_ws;

/* c's workspace in d, with room for n points (and their vertices when
 * with_vertex); NULL when memory runs out.  The model is remade (and the
 * workspace with it) whenever n could change. */
coll_geom_ws *coll_geom_ws_get(const pl_component *c, pl_data *d, int n, int with_vertex);
/* The types' workspace_free. */
void coll_geom_ws_free(const pl_component *c, void *ws);

extern const pl_type coll_mesh_obstacle_type;
extern const pl_type coll_mapped_model_type;

#endif
