/* bending_boundary.c - Laplace-Beltrami rows at the boundary of a flat rest
 * state.
 *
 * At a boundary vertex the cotangent row does not vanish on a flat sheet:
 * it returns an in-plane vector b (the missing half of the one-ring).
 * Keeping |L x| = |b| then gives no stiffness against bending at all: an
 * out-of-plane curvature c changes |L x| = sqrt(b^2 + c^2) only at second
 * order.  For such rows (boundary vertex, flat one-ring) the row g is
 * replaced by the nearest row g' that annihilates every affine function of
 * the rest ring (g' = g - P^T (P P^T)^-1 P g, P = [1; u; v] over the ring's
 * 2D rest coordinates), scaled so that it returns 2H = 2 on the paraboloid
 * (u^2 + v^2)/2 as an interior row does; its rest value is then zero, so
 * the row is quadratic like the interior ones. */
#include <math.h>
#include <stdlib.h>

#include "hyperelastic.h"
#include "small_matrix.h"
#include "stencils_internal.h"

/* Solves the 3x3 system M y = b (Cramer); returns -1 if M is singular. */
static int solve3(const double *M, const double *b, double *y)
{
    double det = hm_det3(M);
    double scale = fabs(M[0]) + fabs(M[4]) + fabs(M[8]);
    if (!(fabs(det) > 1e-14 * scale * scale * scale)) return -1;
    for (int c = 0; c < 3; ++c) {
        double Mc[9];
        for (int i = 0; i < 9; ++i) Mc[i] = (i % 3 == c) ? b[i / 3] : M[i];
        y[c] = hm_det3(Mc) / det;
    }
    return 0;
}

/* Row r's ring in 2D rest coordinates (uv: 2 per entry), or -1 if the ring
 * is not flat.  The row's first entry is its own vertex (u = v = 0). */
static int flat_ring(const pl_hyper_stencils *s, int r, const double *rest, double *uv)
{
    const double *xi = rest + 3 * (size_t)s->vert[s->ptr[r]];
    double C[9] = {0}, size = 0.0, lam[3], Q[9];
    for (int k = s->ptr[r]; k < s->ptr[r + 1]; ++k) {
        double d[3];
        hm_sub3(rest + 3 * (size_t)s->vert[k], xi, d);
        size = fmax(size, hm_norm3(d));
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) C[a * 3 + b] += d[a] * d[b];
    }
    /* the plane through x_i spanned by the two largest principal directions */
    hyper_sym_eigen(3, C, lam, Q);
    double t1[3] = {Q[2], Q[5], Q[8]}, t2[3] = {Q[1], Q[4], Q[7]}, n[3] = {Q[0], Q[3], Q[6]};
    for (int k = s->ptr[r]; k < s->ptr[r + 1]; ++k) {
        double d[3];
        hm_sub3(rest + 3 * (size_t)s->vert[k], xi, d);
        if (fabs(hm_dot3(d, n)) > 1e-8 * size) return -1;
        uv[2 * (k - s->ptr[r])] = hm_dot3(d, t1);
        uv[2 * (k - s->ptr[r]) + 1] = hm_dot3(d, t2);
    }
    return 0;
}

int hyper_lb_fix_flat_boundary(pl_hyper_stencils *s, const double *rest,
                               const unsigned char *boundary)
{
    int maxlen = 0;
    for (int r = 0; r < s->n; ++r)
        if (s->ptr[r + 1] - s->ptr[r] > maxlen) maxlen = s->ptr[r + 1] - s->ptr[r];
    double *uv = malloc(sizeof(double) * 2 * (size_t)(maxlen > 0 ? maxlen : 1));
    if (!uv) return -1;
    for (int r = 0; r < s->n; ++r) {
        int b = s->ptr[r], m = s->ptr[r + 1] - b;
        if (!boundary[s->vert[b]] || flat_ring(s, r, rest, uv) != 0) continue;
        /* P g and P P^T with P rows 1, u, v */
        double Pg[3] = {0}, PPt[9] = {0}, y[3], gnorm = 0.0, size2 = 0.0;
        for (int k = 0; k < m; ++k) {
            gnorm += fabs(s->coef[b + k]);
            size2 = fmax(size2, uv[2 * k] * uv[2 * k] + uv[2 * k + 1] * uv[2 * k + 1]);
        }
        for (int k = 0; k < m; ++k) {
            double p[3] = {1.0, uv[2 * k], uv[2 * k + 1]};
            for (int a = 0; a < 3; ++a) {
                Pg[a] += p[a] * s->coef[b + k];
                for (int c = 0; c < 3; ++c) PPt[a * 3 + c] += p[a] * p[c];
            }
        }
        double curv = 0.0;
        if (solve3(PPt, Pg, y) == 0) {
            for (int k = 0; k < m; ++k) {
                s->coef[b + k] -= y[0] + y[1] * uv[2 * k] + y[2] * uv[2 * k + 1];
                curv += s->coef[b + k] * 0.5 * (uv[2 * k] * uv[2 * k] + uv[2 * k + 1] * uv[2 * k + 1]);
            }
        }
        /* calibrate to 2H = 2 on the unit paraboloid; a ring too small to
         * measure curvature (three points) keeps no row */
        double scale = curv > 1e-6 * gnorm * size2 ? 2.0 / curv : 0.0;
        for (int k = 0; k < m; ++k) s->coef[b + k] *= scale;
        s->rest[3 * r] = s->rest[3 * r + 1] = s->rest[3 * r + 2] = 0.0;
    }
    free(uv);
    return 0;
}
