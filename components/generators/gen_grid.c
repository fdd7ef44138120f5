/* gen_grid.c - structured generators: the Kuhn box of tetrahedra and the
 * triangle grid (cloth). */
#include "gen_util.h"

#include <math.h>
#include <stdlib.h>

/* The six Kuhn tetrahedra of a cube are the monotone lattice paths from
 * corner 000 to 111; corner bits are x = 1, y = 2, z = 4.  Paths of odd
 * permutations have negative orientation and get two vertices swapped. */
static const int kuhn_axes[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                    {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};

void pl_gen_kuhn_cell(const int corner[8], int mirror, int *tets)
{
    /* Mirroring the cell about `mirror` axes (bit mask) keeps the
     * decomposition conforming across grid planes; each mirror flips the
     * orientation once. */
    int parity = ((mirror & 1) + ((mirror >> 1) & 1) + ((mirror >> 2) & 1)) & 1;
    for (int p = 0; p < 6; ++p) {
        int bits = 0, v[4];
        v[0] = corner[mirror];
        for (int s = 0; s < 3; ++s) {
            bits |= 1 << kuhn_axes[p][s];
            v[s + 1] = corner[bits ^ mirror];
        }
        int odd = (p >= 3) ^ parity;
        int *t = tets + 4 * p;
        t[0] = v[0];
        t[1] = odd ? v[2] : v[1];
        t[2] = odd ? v[1] : v[2];
        t[3] = v[3];
    }
}

int pl_generate_box_tets(const int n[3], const double lo[3], const double hi[3], pl_mesh *out,
                         pl_error *err)
{
    pl_mesh_init(out);
    for (int a = 0; a < 3; ++a) {
        if (n[a] < 2)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "box: n[%d] = %d vertices: expected at least 2", a, n[a]);
        if (!(hi[a] > lo[a]) || !isfinite(lo[a]) || !isfinite(hi[a]))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "box: axis %d spans [%g, %g]: expected finite lo < hi", a, lo[a],
                                hi[a]);
    }
    long long nv = (long long)n[0] * n[1] * n[2];
    long long nt = 6LL * (n[0] - 1) * (n[1] - 1) * (n[2] - 1);
    int rc = pl_gen_alloc(out, nv, nt, 0, err);
    if (rc) return rc;
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                double *v = out->verts + 3 * (size_t)(i + n[0] * (j + (size_t)n[1] * k));
                int idx[3] = {i, j, k};
                for (int a = 0; a < 3; ++a) /* exact end points, no accumulated rounding */
                    v[a] = idx[a] == n[a] - 1 ? hi[a]
                                              : lo[a] + (hi[a] - lo[a]) * idx[a] / (n[a] - 1);
            }
    int *t = out->tets;
    for (int k = 0; k + 1 < n[2]; ++k)
        for (int j = 0; j + 1 < n[1]; ++j)
            for (int i = 0; i + 1 < n[0]; ++i) {
                int c[8];
                for (int b = 0; b < 8; ++b)
                    c[b] = (i + (b & 1)) + n[0] * ((j + ((b >> 1) & 1)) + n[1] * (k + (b >> 2)));
                pl_gen_kuhn_cell(c, 0, t);
                t += 24;
            }
    return PL_OK;
}

/* Grid of triangles; `flip` reverses the winding of every triangle. */
static int triangle_grid(int nu, int nv, const double o[3], const double eu[3],
                         const double ev[3], int flip, pl_mesh *out, pl_error *err)
{
    pl_mesh_init(out);
    if (nu < 2 || nv < 2)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "triangle grid: %d x %d vertices: expected at least 2 x 2", nu, nv);
    double cr[3] = {eu[1] * ev[2] - eu[2] * ev[1], eu[2] * ev[0] - eu[0] * ev[2],
                    eu[0] * ev[1] - eu[1] * ev[0]};
    double area = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    if (!(area > 0) || !isfinite(area))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "triangle grid: the edge vectors are parallel or degenerate: "
                            "expected a parallelogram of positive area");
    int rc = pl_gen_alloc(out, (long long)nu * nv, 0, 2LL * (nu - 1) * (nv - 1), err);
    if (rc) return rc;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double s = (double)i / (nu - 1), t = (double)j / (nv - 1);
            double *v = out->verts + 3 * ((size_t)i + (size_t)nu * j);
            for (int a = 0; a < 3; ++a) v[a] = o[a] + s * eu[a] + t * ev[a];
        }
    int *f = out->tris;
    for (int j = 0; j + 1 < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            int a = i + nu * j, b = a + 1, c = a + nu + 1, d = a + nu;
            /* counter-clockwise in (u, v): (a b c)(a c d) or, on odd cells, (a b d)(b c d) */
            int tri[2][3] = {{a, b, c}, {a, c, d}};
            if ((i + j) & 1) {
                int alt[2][3] = {{a, b, d}, {b, c, d}};
                for (int r = 0; r < 2; ++r)
                    for (int q = 0; q < 3; ++q) tri[r][q] = alt[r][q];
            }
            for (int r = 0; r < 2; ++r, f += 3) {
                f[0] = tri[r][0];
                f[1] = flip ? tri[r][2] : tri[r][1];
                f[2] = flip ? tri[r][1] : tri[r][2];
            }
        }
    return PL_OK;
}

int pl_generate_triangle_grid(int nu, int nv, const double origin[3], const double edge_u[3],
                              const double edge_v[3], pl_mesh *out, pl_error *err)
{
    return triangle_grid(nu, nv, origin, edge_u, edge_v, 0, out, err);
}

int pl_generate_cloth_xz(int nx, int nz, double x0, double x1, double z0, double z1, double y0,
                         pl_mesh *out, pl_error *err)
{
    double o[3] = {x0, y0, z0}, eu[3] = {x1 - x0, 0, 0}, ev[3] = {0, 0, z1 - z0};
    /* x cross z is -y: flip so the normals point up when x1 > x0, z1 > z0 */
    int flip = (x1 - x0) * (z1 - z0) > 0;
    return triangle_grid(nx, nz, o, eu, ev, flip, out, err);
}
