/* gen_util.c - allocation and orientation helpers of the generators. */
#include "gen_util.h"

#include <limits.h>
#include <stdlib.h>

int pl_gen_alloc(pl_mesh *out, long long nverts, long long ntets, long long ntris,
                 pl_error *err)
{
    pl_mesh_init(out);
    if (nverts > INT_MAX / 4 || ntets > INT_MAX / 4 || ntris > INT_MAX / 4)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "generated mesh too large: %lld vertices, %lld tetrahedra, %lld "
                            "triangles (at most %d each)",
                            nverts, ntets, ntris, INT_MAX / 4);
    out->verts = malloc((size_t)nverts * 3 * sizeof(double) + 1);
    out->tets = ntets ? malloc((size_t)ntets * 4 * sizeof(int)) : NULL;
    out->tris = ntris ? malloc((size_t)ntris * 3 * sizeof(int)) : NULL;
    if (!out->verts || (ntets && !out->tets) || (ntris && !out->tris)) {
        pl_mesh_free(out);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory generating a mesh");
    }
    out->nverts = (int)nverts;
    out->ntets = (int)ntets;
    out->ntris = (int)ntris;
    return PL_OK;
}
