/* gen_shell.c - a thick-walled hollow sphere (spherical shell) of
 * tetrahedra: the icosphere of `level` on `layers` + 1 concentric spheres
 * between the inner and outer radius, each triangle times each layer a
 * prism cut into 3 tetrahedra.  With the triangle's corners sorted by
 * index (s0 < s1 < s2), the prism's side quad between s_i < s_j is cut
 * along the diagonal from s_i's lower copy to s_j's upper one: the two
 * prisms sharing the quad cut it alike, so the mesh is conforming.  Lame's
 * thick sphere under internal pressure is the test it was made for. */
#include "gen_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double orient(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = d[k] - a[k];
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

int pl_generate_sphere_shell(const double center[3], double inner, double outer, int level,
                             int layers, pl_mesh *out, pl_error *err)
{
    pl_mesh_init(out);
    if (!(inner > 0) || !(outer > inner) || !isfinite(outer))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "hollow sphere: radii %g (inner) and %g (outer): expected 0 < inner "
                            "< outer",
                            inner, outer);
    if (layers < 1 || layers > 1000)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "hollow sphere: %d layers: expected 1..1000", layers);
    pl_mesh s;
    static const double zero[3] = {0, 0, 0};
    int rc = pl_generate_sphere_surface(zero, 1.0, level, &s, err);
    if (rc) return rc;
    long long ns = s.nverts, nf = s.ntris;
    rc = pl_gen_alloc(out, ns * (layers + 1), 3 * nf * layers, 2 * nf, err);
    if (rc) {
        pl_mesh_free(&s);
        return rc;
    }
    for (int l = 0; l <= layers; ++l) {
        double r = inner + (outer - inner) * l / layers;
        for (long long i = 0; i < ns; ++i)
            for (int c = 0; c < 3; ++c)
                out->verts[3 * (l * ns + i) + c] = center[c] + r * s.verts[3 * i + c];
    }
    int *t = out->tets;
    for (long long f = 0; f < nf; ++f) {
        int v[3];
        memcpy(v, s.tris + 3 * f, sizeof v);
        for (int i = 0; i < 2; ++i) /* sort the corners */
            for (int j = 0; j < 2 - i; ++j)
                if (v[j] > v[j + 1]) {
                    int k = v[j];
                    v[j] = v[j + 1];
                    v[j + 1] = k;
                }
        for (int l = 0; l < layers; ++l) {
            int B[3], T[3];
            for (int k = 0; k < 3; ++k) B[k] = (int)(l * ns + v[k]), T[k] = (int)((l + 1) * ns + v[k]);
            int tet[3][4] = {{B[0], B[1], B[2], T[2]}, {B[0], B[1], T[1], T[2]},
                             {B[0], T[0], T[1], T[2]}};
            for (int k = 0; k < 3; ++k, t += 4) {
                memcpy(t, tet[k], sizeof tet[k]);
                const double *x = out->verts;
                if (orient(x + 3 * t[0], x + 3 * t[1], x + 3 * t[2], x + 3 * t[3]) < 0) {
                    int w = t[2];
                    t[2] = t[3];
                    t[3] = w;
                }
            }
        }
    }
    /* the boundary, facing out of the material: the outer sphere as the
     * icosphere faces, the inner one turned towards the centre */
    for (long long f = 0; f < nf; ++f) {
        const int *a = s.tris + 3 * f;
        int *o = out->tris + 3 * f, *in = out->tris + 3 * (nf + f);
        for (int k = 0; k < 3; ++k) o[k] = (int)(layers * ns + a[k]);
        in[0] = a[0], in[1] = a[2], in[2] = a[1];
    }
    pl_mesh_free(&s);
    return PL_OK;
}
