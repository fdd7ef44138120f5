/* model_ws.c - the per-data workspace of the mesh-based collision models
 * (SurfaceCollisionModel, PointCollisionModel, MappedSurfaceCollisionModel,
 * MeshObstacle): the geometry their update() hands the pipeline each step
 * lives in the data being stepped, not in the component. */
#include <stdlib.h>

#include "models.h"

coll_geom_ws *coll_geom_ws_get(const pl_component *c, pl_data *d, int n, int with_vertex)
{
    coll_geom_ws *w = pl_data_workspace(d, c);
    if (!w) return NULL;
    if (!w->x) {
        size_t np = (size_t)(n > 0 ? n : 1);
        w->x = malloc(np * 3 * sizeof *w->x);
        w->v = malloc(np * 3 * sizeof *w->v);
        w->vertex = with_vertex ? malloc(np * 4 * sizeof *w->vertex) : NULL;
    }
    return w->x && w->v && (!with_vertex || w->vertex) ? w : NULL;
}

void coll_geom_ws_free(const pl_component *c, void *ws)
{
    coll_geom_ws *w = ws;
    (void)c;
    free(w->x);
    free(w->v);
    free(w->vertex);
}
