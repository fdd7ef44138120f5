/* surface_pressure_surface.c - the cavity surface of a
 * SurfacePressureConstraint: built from what the scene gives (triangles of
 * the state's vertices, points mapped into its tetrahedra as SOFA's
 * BarycentricMapping does, a surface loader's mesh, or the boundary faces
 * of the tetrahedra inside `box`), then checked closed and oriented. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "surface_pressure.h"
#include "pliant/util.h"

/* Maps the points p (np x 3) into the body's tetrahedra (SOFA's
 * BarycentricMapping, weights from the rest positions x). */
static int map_points(surface_pressure *sp, pl_ctx *ctx, const double *x, int n, const double *p,
                      int np, const char *what)
{
    pl_component *c = &sp->base;
    const pl_mesh *m = pl_util_topology(c, &sp->src, ctx, 1);
    if (!m) return PL_EINPUT;
    if (m->ntets == 0 || m->nverts != n)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "%s: mapped points need a tetrahedral mesh with the state's %d "
                                  "vertices (the mesh has %d vertices, %d tetrahedra)",
                                  what, n, m->nverts, m->ntets);
    int outside_count = 0;
    double worst = 0.0;
    for (int i = 0; i < np; ++i) {
        double out;
        if (cable_locate(x, m->tets, m->ntets, p + 3 * i, sp->surf.vert + 4 * i,
                         sp->surf.weight + 4 * i, &out) < 0)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "%s: the mesh has no tetrahedron of positive volume", what);
        if (out > 1e-6) ++outside_count, worst = out > worst ? out : worst;
    }
    if (outside_count)
        pl_component_warn(c, ctx,
                          "%s: %d of the %d cavity points lie outside the body's tetrahedra; they "
                          "follow the nearest one with extrapolated weights (smallest weight %g)",
                          what, outside_count, np, -worst);
    return PL_OK;
}

/* Triangles (and quads split in two) over np points into surf.tris. */
static int take_triangles(surface_pressure *sp, pl_ctx *ctx, const int *tris, int ntris,
                          const int *quads, int nquads, int np, const char *what)
{
    int *t = sp->surf.tris;
    for (int k = 0; k < 3 * ntris; ++k) t[k] = tris[k];
    for (int q = 0; q < nquads; ++q) {
        const int *v = quads + 4 * q;
        int *a = t + 3 * (ntris + 2 * q);
        a[0] = v[0], a[1] = v[1], a[2] = v[2];
        a[3] = v[0], a[4] = v[2], a[5] = v[3];
    }
    for (int k = 0; k < 3 * (ntris + 2 * nquads); ++k)
        if (t[k] < 0 || t[k] >= np)
            return pl_component_error(&sp->base, ctx, PL_EINPUT,
                                      "%s: index %d (%s %d) is out of range: there are %d points",
                                      what, t[k], k < 3 * ntris ? "triangle" : "quad",
                                      k < 3 * ntris ? k / 3 : (k / 3 - ntris) / 2, np);
    return PL_OK;
}

/* The points as the state's own vertices (weight 1 each). */
static void identity_points(cavity_surface *s)
{
    for (int i = 0; i < s->npoints; ++i) {
        s->vert[4 * i] = i;
        s->weight[4 * i] = 1.0;
    }
}

/* The cavity surface from whichever source the scene gave. */
int sp_build_surface(surface_pressure *sp, pl_ctx *ctx, const double *x, int n)
{
    pl_component *c = &sp->base;
    cavity_surface *s = &sp->surf;
    if (sp->box.n) {
        const pl_mesh *m = pl_util_topology(c, &sp->src, ctx, 1);
        if (!m) return PL_EINPUT;
        if (m->ntets == 0 || m->nverts != n)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "box: needs the node's tetrahedral mesh (%d vertices, "
                                      "%d tetrahedra; the state has %d vertices)",
                                      m->nverts, m->ntets, n);
        int *tris = NULL;
        int nt = cavity_faces_in_boxes(x, m->tets, m->ntets, sp->box.v, sp->box.n / 6, &tris);
        if (nt < 0 || cavity_alloc(s, n, nt)) {
            free(tris);
            return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
        }
        if (nt) memcpy(s->tris, tris, (size_t)nt * 3 * sizeof *tris);
        free(tris);
        if (!nt)
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "box: no boundary face of the mesh lies inside (the cavity "
                                      "must be a hole in the tetrahedra)");
        identity_points(s);
        return PL_OK;
    }
    if (sp->surface.path) {
        const pl_mesh *m = pl_util_topology(c, &sp->surface, ctx, 1);
        if (!m) return PL_EINPUT;
        if (m->ntris == 0)
            return pl_component_error(c, ctx, PL_EINPUT, "surface: '%s' has no triangles",
                                      sp->surface.path);
        if (cavity_alloc(s, m->nverts, m->ntris))
            return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
        memcpy(s->tris, m->tris, (size_t)m->ntris * 3 * sizeof *m->tris);
        return map_points(sp, ctx, x, n, m->verts, m->nverts, "surface");
    }
    int np = sp->position.n ? sp->position.n / 3 : n;
    if (cavity_alloc(s, np, sp->triangles.n / 3 + 2 * (sp->quads.n / 4)))
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    int rc = take_triangles(sp, ctx, sp->triangles.v, sp->triangles.n / 3, sp->quads.v,
                            sp->quads.n / 4, np, sp->position.n ? "triangles (of position)"
                                                                : "triangles");
    if (rc) return rc;
    if (!sp->position.n) {
        identity_points(s);
        return PL_OK;
    }
    return map_points(sp, ctx, x, n, sp->position.v, np, "position");
}

static void reverse_triangles(cavity_surface *s)
{
    for (int t = 0; t < s->ntris; ++t) {
        int k = s->tris[3 * t + 1];
        s->tris[3 * t + 1] = s->tris[3 * t + 2];
        s->tris[3 * t + 2] = k;
    }
}

/* Closed, manifold, consistently oriented, facing out of the cavity. */
int sp_check_surface(surface_pressure *sp, pl_ctx *ctx, const double *x)
{
    pl_component *c = &sp->base;
    cavity_surface *s = &sp->surf;
    int a = -1, b = -1;
    int bad = cavity_check_closed(s->tris, s->ntris, s->npoints, &a, &b);
    static const char *const why[] = {
        NULL,
        "is not closed: the edge %d-%d belongs to one triangle only (a cavity's volume needs a "
        "closed surface; SoftRobots computes a meaningless one)",
        "is not a manifold: the edge %d-%d belongs to more than two triangles",
        "is not consistently oriented: the two triangles at the edge %d-%d face opposite ways",
        "has a degenerate triangle (a point repeated: %d-%d)"};
    if (bad < 0) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (bad) {
        char msg[256];
        snprintf(msg, sizeof msg, why[bad], a, b);
        return pl_component_error(c, ctx, PL_EINPUT, "the cavity surface (%d triangles) %s",
                                  s->ntris, msg);
    }
    if (sp->flip) reverse_triangles(s);
    double V = cavity_volume(s, x);
    if (!isfinite(V)) return pl_component_error(c, ctx, PL_EINPUT, "the cavity volume is not finite");
    double scale = 0.0; /* the surface's extent cubed: what "no volume" means */
    for (int i = 0; i < s->npoints; ++i) {
        double p[3];
        cavity_point(s, x, i, p);
        for (int k = 0; k < 3; ++k) scale = fmax(scale, fabs(p[k] - x[3 * s->vert[0] + k]));
    }
    if (!(fabs(V) > 1e-9 * scale * scale * scale))
        return pl_component_error(c, ctx, PL_EINPUT, "the cavity surface encloses no volume (%g)",
                                  V);
    if (V < 0) {
        reverse_triangles(s);
        pl_component_warn(c, ctx,
                          "the cavity's triangles face into it (signed volume %g): turned "
                          "around so that a positive pressure inflates it (SoftRobots would "
                          "deflate it unless flipNormal is set)",
                          V);
    }
    return PL_OK;
}
