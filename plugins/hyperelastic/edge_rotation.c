/* edge_rotation.c - SOFA's 'large' corotational method (TetrahedronFEMForceField
 * and TetrahedralCorotationalFEMForceField, method="large"): the element's
 * rotation is not the polar one but comes from a frame built on its edges,
 * x along the edge v0 -> v1, z normal to the face (v0, v1, v2), y = z x x;
 * R = Rc^T R0 turns the rest frame R0 into the current one Rc.  The force is
 * linear elasticity in that rotated frame:
 *     P = R sigma,  sigma = 2 mu eps + lambda tr(eps) I,  eps = sym(R^T F) - I,
 * and its stiffness holds R fixed (SOFA's R K0 R^T):
 *     dP = R [mu (G + G^T) + lambda tr(G) I],  G = R^T dF.
 * Where R^T F is symmetric (no shear in the frame) this is the polar
 * Corotational's force; otherwise it is not the gradient of an energy, so
 * only LinearizedEulerSolver (forces and stiffness) uses it.
 * Edges come from F: the rest edges are the columns of Dm = G^-1 (G: rows 1
 * to 3 of the element's shape matrix), the current ones F Dm. */
#include <math.h>

#include "hyperelastic.h"
#include "small_matrix.h"

/* The frame's rows (x, y, z) from the edges e1 = v1 - v0, e2 = v2 - v0. */
static void edge_frame(const double *e1, const double *e2, double *r)
{
    double z[3], y[3];
    hm_cross(e1, e2, z);
    hm_cross(z, e1, y);
    double nx = hm_norm3(e1), ny = hm_norm3(y), nz = hm_norm3(z);
    for (int a = 0; a < 3; ++a) {
        r[a] = e1[a] / nx;
        r[3 + a] = y[a] / ny;
        r[6 + a] = z[a] / nz;
    }
}

/* R = Rc^T R0 for the element with deformation gradient F and shape
 * matrix D (4 x 3, row-major: F = sum_c x_c D_c^T). */
void hyper_edge_rotation(const double *F, const double *D, double *R)
{
    /* Dm = inverse of the 3 x 3 matrix of rows D_1, D_2, D_3: its columns are the rest edges */
    const double *G = D + 3;
    double det = hm_det3(G), Dm[9];
    Dm[0] = (G[4] * G[8] - G[5] * G[7]) / det;
    Dm[1] = (G[2] * G[7] - G[1] * G[8]) / det;
    Dm[2] = (G[1] * G[5] - G[2] * G[4]) / det;
    Dm[3] = (G[5] * G[6] - G[3] * G[8]) / det;
    Dm[4] = (G[0] * G[8] - G[2] * G[6]) / det;
    Dm[5] = (G[2] * G[3] - G[0] * G[5]) / det;
    Dm[6] = (G[3] * G[7] - G[4] * G[6]) / det;
    Dm[7] = (G[1] * G[6] - G[0] * G[7]) / det;
    Dm[8] = (G[0] * G[4] - G[1] * G[3]) / det;
    double r1[3], r2[3], c1[3], c2[3], R0[9], Rc[9];
    for (int a = 0; a < 3; ++a) {
        r1[a] = Dm[a * 3 + 0];
        r2[a] = Dm[a * 3 + 1];
    }
    for (int a = 0; a < 3; ++a) {
        c1[a] = F[a * 3 + 0] * r1[0] + F[a * 3 + 1] * r1[1] + F[a * 3 + 2] * r1[2];
        c2[a] = F[a * 3 + 0] * r2[0] + F[a * 3 + 1] * r2[1] + F[a * 3 + 2] * r2[2];
    }
    edge_frame(r1, r2, R0);
    edge_frame(c1, c2, Rc);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            R[a * 3 + b] = Rc[0 * 3 + a] * R0[0 * 3 + b] + Rc[1 * 3 + a] * R0[1 * 3 + b] +
                           Rc[2 * 3 + a] * R0[2 * 3 + b];
}

/* out = R [mu (G + G^T) + la tr(G) I] with G = R^T M (3 x 3). */
static void rotated_linear_stress(const double *R, double mu, double la, const double *M,
                                  double *out)
{
    double G[9], S[9];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            G[a * 3 + b] = R[0 * 3 + a] * M[0 * 3 + b] + R[1 * 3 + a] * M[1 * 3 + b] +
                           R[2 * 3 + a] * M[2 * 3 + b];
    double tr = G[0] + G[4] + G[8];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) S[a * 3 + b] = mu * (G[a * 3 + b] + G[b * 3 + a]) + (a == b ? la * tr : 0.0);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            out[a * 3 + b] = R[a * 3 + 0] * S[0 * 3 + b] + R[a * 3 + 1] * S[1 * 3 + b] +
                             R[a * 3 + 2] * S[2 * 3 + b];
}

void hyper_edge_piola(const pl_hyper_law *m, const double *F, const double *D, double *P)
{
    double R[9], M[9];
    hyper_edge_rotation(F, D, R);
    /* sigma(sym(R^T F) - I) = the linear stress of G = R^T (F - R) */
    for (int i = 0; i < 9; ++i) M[i] = F[i] - R[i];
    rotated_linear_stress(R, m->mu, m->material == PL_HYPER_COROTATIONAL ? m->lambda : 0.0, M, P);
}

void hyper_edge_dPdF(const pl_hyper_law *m, const double *F, const double *D, double *H)
{
    double R[9];
    hyper_edge_rotation(F, D, R);
    double la = m->material == PL_HYPER_COROTATIONAL ? m->lambda : 0.0;
    for (int j = 0; j < 9; ++j) { /* column j: dF = e_j */
        double E[9] = {0}, dP[9];
        E[j] = 1.0;
        rotated_linear_stress(R, m->mu, la, E, dP);
        for (int i = 0; i < 9; ++i) H[i * 9 + j] = dP[i];
    }
}
