/* gen_cylinder.c - cylinder surface and solid cylinder, axis along y. */
#include "gen_util.h"

#include <math.h>
#include <stdlib.h>

static int check_cylinder(const double c[3], double radius, double height, const char *what,
                          pl_error *err)
{
    if (!(radius > 0) || !(height > 0) || !isfinite(radius) || !isfinite(height) ||
        !isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "%s: radius %g, height %g: expected finite positive values and a "
                            "finite centre", what, radius, height);
    return PL_OK;
}

int pl_generate_cylinder_surface(const double center[3], double radius, double height,
                                 int nsides, int nlayers, pl_mesh *out, pl_error *err)
{
    pl_mesh_init(out);
    if (check_cylinder(center, radius, height, "cylinder surface", err)) return PL_EINPUT;
    if (nsides < 3 || nlayers < 1 || nsides > 1 << 20 || nlayers > 1 << 20)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "cylinder surface: %d sides, %d layers: expected >= 3 sides and "
                            ">= 1 layer",
                            nsides, nlayers);
    long long nring = (long long)nsides * (nlayers + 1);
    int rc = pl_gen_alloc(out, nring + 2, 0, 2LL * nsides * (nlayers + 1), err);
    if (rc) return rc;
    const double two_pi = 8 * atan(1.0), y0 = center[1] - height / 2;
    for (int l = 0; l <= nlayers; ++l)
        for (int j = 0; j < nsides; ++j) {
            double *v = out->verts + 3 * ((size_t)l * nsides + j), a = two_pi * j / nsides;
            v[0] = center[0] + radius * cos(a);
            v[1] = l == nlayers ? y0 + height : y0 + height * l / nlayers;
            v[2] = center[2] + radius * sin(a);
        }
    int bottom = (int)nring, top = bottom + 1;
    double *vb = out->verts + 3 * (size_t)bottom, *vt = vb + 3;
    vb[0] = vt[0] = center[0];
    vb[1] = y0;
    vt[1] = y0 + height;
    vb[2] = vt[2] = center[2];
    int *f = out->tris;
    for (int l = 0; l < nlayers; ++l)
        for (int j = 0; j < nsides; ++j) {
            /* up x tangent points outward: (p, p+up, p+tangent) */
            int a = l * nsides + j, b = l * nsides + (j + 1) % nsides;
            int c = a + nsides, d = b + nsides;
            int quad[6] = {a, c, b, c, d, b};
            for (int q = 0; q < 6; ++q) *f++ = quad[q];
        }
    for (int j = 0; j < nsides; ++j) {
        int a = j, b = (j + 1) % nsides, off = nlayers * nsides;
        int cap[6] = {bottom, a, b, top, off + b, off + a};
        for (int q = 0; q < 6; ++q) *f++ = cap[q];
    }
    return PL_OK;
}

/* Disk of `rings` concentric rings in the xz plane (ring r: 6r points, the
 * centre is ring 0).  Writes 2D points (x, z) and 6 rings^2 triangles. */
static void disk(int rings, double radius, double *xz, int *tri)
{
    const double two_pi = 8 * atan(1.0);
    xz[0] = xz[1] = 0;
    int start = 1; /* first index of the current ring */
    for (int r = 1; r <= rings; ++r) {
        int n = 6 * r, m = 6 * (r - 1), inner = start - (r == 1 ? 1 : m);
        for (int j = 0; j < n; ++j) {
            xz[2 * (start + j)] = radius * r / rings * cos(two_pi * j / n);
            xz[2 * (start + j) + 1] = radius * r / rings * sin(two_pi * j / n);
        }
        /* zip the inner ring (m points, or the centre) and the outer ring by angle */
        int i = 0, j = 0;
        while (i < m || j < n) {
            int take_outer = i == m || (j < n && (double)(j + 1) / n <= (double)(i + 1) / m);
            int a = r == 1 ? 0 : inner + i % m;
            if (take_outer) {
                tri[0] = a, tri[1] = start + j, tri[2] = start + (j + 1) % n;
                j++;
            } else {
                tri[0] = a, tri[1] = start + j % n, tri[2] = inner + (i + 1) % m;
                i++;
            }
            tri += 3;
        }
        start += n;
    }
}

int pl_generate_cylinder_tets(const double center[3], double radius, double height, int rings,
                              int nlayers, pl_mesh *out, pl_error *err)
{
    pl_mesh_init(out);
    if (check_cylinder(center, radius, height, "cylinder volume", err)) return PL_EINPUT;
    if (rings < 1 || rings > 4096)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "cylinder volume: %d rings: expected 1..4096", rings);
    if (nlayers <= 0) nlayers = (int)fmax(1, lround(height * rings / radius));
    if (nlayers > 1 << 20)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "cylinder volume: %d layers: too many",
                            nlayers);
    int nd = 1 + 3 * rings * (rings + 1), nt2 = 6 * rings * rings;
    double *xz = malloc(2 * (size_t)nd * sizeof *xz);
    int *tri = malloc(3 * (size_t)nt2 * sizeof *tri);
    int rc = xz && tri ? pl_gen_alloc(out, (long long)nd * (nlayers + 1),
                                      3LL * nt2 * nlayers, 0, err)
                       : pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    if (rc == PL_OK) {
        disk(rings, radius, xz, tri);
        const double y0 = center[1] - height / 2;
        for (int l = 0; l <= nlayers; ++l)
            for (int p = 0; p < nd; ++p) {
                double *v = out->verts + 3 * ((size_t)l * nd + p);
                v[0] = center[0] + xz[2 * p];
                v[1] = l == nlayers ? y0 + height : y0 + height * l / nlayers;
                v[2] = center[2] + xz[2 * p + 1];
            }
        int *t = out->tets;
        for (int l = 0; l < nlayers; ++l)
            for (int f = 0; f < nt2; ++f) {
                /* sort the corners: the split of each side quad then joins the
                 * smaller bottom index to the larger top one, the same in both
                 * prisms that share it */
                int a = tri[3 * f], b = tri[3 * f + 1], c = tri[3 * f + 2], s;
                if (a > b) s = a, a = b, b = s;
                if (b > c) s = b, b = c, c = s;
                if (a > b) s = a, a = b, b = s;
                int lo = l * nd, hi = lo + nd;
                int prism[12] = {lo + a, lo + b, lo + c, hi + c, lo + a, lo + b,
                                 hi + b, hi + c, lo + a, hi + a, hi + b, hi + c};
                for (int q = 0; q < 12; ++q) *t++ = prism[q];
            }
        pl_mesh_fix_inverted(out); /* the sorted split fixes no orientation */
    }
    free(xz);
    free(tri);
    return rc;
}
