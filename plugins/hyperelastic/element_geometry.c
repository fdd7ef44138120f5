/* element_geometry.c - the constant shape matrices D with F = X D.
 *
 * Tetrahedron: Ds = [x1-x0, x2-x0, x3-x0] = X E with E = [-1 -1 -1; I3], so
 * F = Ds Dm^-1 = X (E Dm^-1) and D = E Dm^-1 (4 x 3): row 0 is minus the sum
 * of the rows of Dm^-1.  Triangle: the same in the rest triangle's own 2D
 * frame (t1 along edge 01, t2 = n x t1), giving a 3 x 2 F. */
#include <math.h>

#include "hyperelastic.h"
#include "small_matrix.h"

/* Relative size under which an element counts as degenerate. */
#define PL_HYPER_DEGENERATE 1e-12

int hyper_tet_shape(const double x[12], double D[12], double *volume)
{
    double e[3][3]; /* e[c] = x_{c+1} - x0 */
    double lmax = 0.0;
    for (int c = 0; c < 3; ++c) {
        hm_sub3(x + 3 * (c + 1), x, e[c]);
        lmax = fmax(lmax, hm_norm3(e[c]));
    }
    /* Dm has the edges as columns */
    double Dm[9] = {e[0][0], e[1][0], e[2][0], e[0][1], e[1][1], e[2][1],
                    e[0][2], e[1][2], e[2][2]};
    double det = hm_det3(Dm);
    if (!(fabs(det) > PL_HYPER_DEGENERATE * lmax * lmax * lmax)) return PL_EINPUT;
    double inv[9];
    inv[0] = (Dm[4] * Dm[8] - Dm[5] * Dm[7]) / det;
    inv[1] = (Dm[2] * Dm[7] - Dm[1] * Dm[8]) / det;
    inv[2] = (Dm[1] * Dm[5] - Dm[2] * Dm[4]) / det;
    inv[3] = (Dm[5] * Dm[6] - Dm[3] * Dm[8]) / det;
    inv[4] = (Dm[0] * Dm[8] - Dm[2] * Dm[6]) / det;
    inv[5] = (Dm[2] * Dm[3] - Dm[0] * Dm[5]) / det;
    inv[6] = (Dm[3] * Dm[7] - Dm[4] * Dm[6]) / det;
    inv[7] = (Dm[1] * Dm[6] - Dm[0] * Dm[7]) / det;
    inv[8] = (Dm[0] * Dm[4] - Dm[1] * Dm[3]) / det;
    for (int b = 0; b < 3; ++b) {
        D[0 * 3 + b] = -(inv[0 * 3 + b] + inv[1 * 3 + b] + inv[2 * 3 + b]);
        for (int r = 0; r < 3; ++r) D[(r + 1) * 3 + b] = inv[r * 3 + b];
    }
    *volume = fabs(det) / 6.0;
    return PL_OK;
}

int hyper_tri_shape(const double x[9], double D[6], double *area)
{
    double e1[3], e2[3], n[3], t1[3], t2[3];
    hm_sub3(x + 3, x, e1);
    hm_sub3(x + 6, x, e2);
    hm_cross(e1, e2, n);
    double l1 = hm_norm3(e1), ln = hm_norm3(n);
    double lmax = fmax(l1, hm_norm3(e2));
    if (!(ln > PL_HYPER_DEGENERATE * lmax * lmax)) return PL_EINPUT;
    for (int r = 0; r < 3; ++r) {
        t1[r] = e1[r] / l1;
        n[r] /= ln;
    }
    hm_cross(n, t1, t2);
    /* Dm = [[l1, e2.t1], [0, e2.t2]] is upper triangular */
    double a = l1, b = hm_dot3(e2, t1), c = hm_dot3(e2, t2);
    double inv[4] = {1.0 / a, -b / (a * c), 0.0, 1.0 / c};
    for (int j = 0; j < 2; ++j) {
        D[0 * 2 + j] = -(inv[0 * 2 + j] + inv[1 * 2 + j]);
        D[1 * 2 + j] = inv[0 * 2 + j];
        D[2 * 2 + j] = inv[1 * 2 + j];
    }
    *area = 0.5 * ln;
    return PL_OK;
}
