/* mesh_source.c - where a collision surface comes from: a file read with
 * pl_mesh_load, a link to a loader or generator, or vertices and triangles
 * written in the scene; then scaled, rotated and translated.  Volume meshes
 * give their boundary triangles (oriented outward). */
#include <stdlib.h>
#include <string.h>

#include "models.h"

static int from_file(pl_component *c, pl_ctx *ctx, const char *name, pl_mesh *out)
{
    char path[1024], tried[2048];
    if (pl_util_data_file(c->file, name, path, sizeof path, tried, sizeof tried) != 0)
        return pl_component_error(c, ctx, PL_EINPUT, "filename: cannot find '%s' (tried %s)", name,
                                  tried);
    pl_diag diag;
    pl_diag_init(&diag);
    int rc = pl_mesh_load(path, NULL, out, &diag);
    for (int k = 0; k < diag.count; ++k) pl_diag_add(ctx->diag, &diag.items[k]);
    pl_diag_free(&diag);
    if (rc != PL_OK)
        return pl_component_error(c, ctx, rc, "could not load '%s' (see the message above)", path);
    return PL_OK;
}

static int from_inline(pl_component *c, pl_ctx *ctx, const coll_mesh_source *s, pl_mesh *out)
{
    if (s->position.n % 3 != 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "position: expected x y z per vertex, found %d numbers",
                                  s->position.n);
    if (s->triangles.n == 0 || s->triangles.n % 3 != 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "triangles: expected 3 indices per triangle, found %d",
                                  s->triangles.n);
    int nv = s->position.n / 3;
    for (int k = 0; k < s->triangles.n; ++k)
        if (s->triangles.v[k] < 0 || s->triangles.v[k] >= nv)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "triangles: index %d (entry %d) is outside the %d vertices "
                                      "of position",
                                      s->triangles.v[k], k, nv);
    out->verts = malloc((size_t)s->position.n * sizeof *out->verts);
    out->tris = malloc((size_t)s->triangles.n * sizeof *out->tris);
    if (!out->verts || !out->tris) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    memcpy(out->verts, s->position.v, (size_t)s->position.n * sizeof *out->verts);
    memcpy(out->tris, s->triangles.v, (size_t)s->triangles.n * sizeof *out->tris);
    out->nverts = nv;
    out->ntris = s->triangles.n / 3;
    return PL_OK;
}

/* Replaces a volume mesh's triangles by its boundary. */
static int boundary_of_volume(pl_component *c, pl_ctx *ctx, pl_mesh *m)
{
    if (m->ntets == 0) return PL_OK;
    int *tris = NULL, ntris = 0;
    int rc = pl_mesh_boundary_triangles(m, &tris, &ntris);
    if (rc != PL_OK) {
        free(tris);
        return pl_component_error(c, ctx, rc,
                                  rc == PL_EINPUT ? "the volume mesh is not a manifold: no "
                                                    "boundary surface"
                                                  : "out of memory");
    }
    free(m->tris);
    m->tris = tris;
    m->ntris = ntris;
    free(m->tets);
    m->tets = NULL;
    m->ntets = 0;
    return PL_OK;
}

int coll_mesh_source_load(pl_component *c, pl_ctx *ctx, coll_mesh_source *s, pl_mesh *out)
{
    pl_mesh_free(out);
    pl_mesh_init(out);
    int given = (s->filename && *s->filename) + (s->position.n > 0) + (s->src.path != NULL);
    if (given > 1)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "give one source of the surface: filename, src or "
                                  "position/triangles (found %d)",
                                  given);
    if (s->triangles.n > 0 && s->position.n == 0)
        return pl_component_error(c, ctx, PL_EINPUT, "triangles given without position");
    int rc;
    if (s->filename && *s->filename) {
        rc = from_file(c, ctx, s->filename, out);
    } else if (s->position.n > 0) {
        rc = from_inline(c, ctx, s, out);
    } else {
        const pl_mesh *m = pl_util_topology(c, &s->src, ctx, 1);
        if (!m) return PL_EINPUT;
        rc = pl_mesh_copy(out, m) ? pl_component_error(c, ctx, PL_EINTERNAL, "out of memory")
                                  : PL_OK;
    }
    if (rc) return rc;
    if ((rc = boundary_of_volume(c, ctx, out))) return rc;
    if (out->ntris == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the surface has no triangles (a point cloud cannot collide "
                                  "as a surface)");
    /* interior vertices of a volume mesh would only cost detection time */
    if (pl_mesh_drop_unused(out) < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    pl_mesh_transform(out, s->scale3d, s->rotation, s->translation);
    return PL_OK;
}
