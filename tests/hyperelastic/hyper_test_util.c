/* hyper_test_util.c - see hyper_test_util.h. */
#include "hyper_test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double ht_rand(unsigned long long *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) / (double)(1ULL << 53) * 2.0 - 1.0;
}

void ht_random_rotation(unsigned long long *state, double R[9])
{
    /* unit quaternion from 4 normal-ish numbers */
    double q[4], l = 0.0;
    for (int i = 0; i < 4; ++i) {
        q[i] = ht_rand(state);
        l += q[i] * q[i];
    }
    l = sqrt(l);
    double w = q[0] / l, x = q[1] / l, y = q[2] / l, z = q[3] / l;
    double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                   2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
    memcpy(R, M, sizeof M);
}

static double det_tet(const double *v, const int *t)
{
    double e[3][3];
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) e[c][r] = v[3 * t[c + 1] + r] - v[3 * t[0] + r];
    return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
           e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
           e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

int ht_tet_grid(int nx, int ny, int nz, double h, double **verts, int **tets, int *ntets)
{
    int nv = nx * ny * nz, nc = (nx - 1) * (ny - 1) * (nz - 1);
    double *v = malloc((size_t)nv * 3 * sizeof *v);
    int *t = malloc((size_t)nc * 24 * sizeof *t);
    if (!v || !t) abort();
#define VID(i, j, k) ((i) + nx * ((j) + ny * (k)))
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                double *p = v + 3 * VID(i, j, k);
                p[0] = i * h;
                p[1] = j * h;
                p[2] = k * h;
            }
    static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    int n = 0;
    for (int k = 0; k < nz - 1; ++k)
        for (int j = 0; j < ny - 1; ++j)
            for (int i = 0; i < nx - 1; ++i)
                for (int p = 0; p < 6; ++p) {
                    int c[3] = {0, 0, 0}, *tt = t + 4 * n;
                    tt[0] = VID(i, j, k);
                    for (int s = 0; s < 3; ++s) {
                        c[perm[p][s]] = 1;
                        tt[s + 1] = VID(i + c[0], j + c[1], k + c[2]);
                    }
                    if (det_tet(v, tt) < 0) {
                        int tmp = tt[2];
                        tt[2] = tt[3];
                        tt[3] = tmp;
                    }
                    ++n;
                }
#undef VID
    *verts = v;
    *tets = t;
    *ntets = n;
    return nv;
}

int ht_tri_grid(int nx, int ny, double h, double **verts, int **tris, int *ntris)
{
    int nv = nx * ny, n = 0;
    double *v = malloc((size_t)nv * 3 * sizeof *v);
    int *t = malloc((size_t)(nx - 1) * (ny - 1) * 6 * sizeof *t);
    if (!v || !t) abort();
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            v[3 * (i + nx * j) + 0] = i * h;
            v[3 * (i + nx * j) + 1] = j * h;
            v[3 * (i + nx * j) + 2] = 0.0;
        }
    for (int j = 0; j < ny - 1; ++j)
        for (int i = 0; i < nx - 1; ++i) {
            int a = i + nx * j, b = a + 1, c = a + nx, d = c + 1;
            int q[6] = {a, b, d, a, d, c};
            memcpy(t + 3 * n, q, sizeof q);
            n += 2;
        }
    *verts = v;
    *tris = t;
    *ntris = n;
    return nv;
}

void ht_triplets_to_dense(const pl_triplets *t, double *A, int n)
{
    for (int k = 0; k < t->nnz; ++k) A[(size_t)t->i[k] * n + t->j[k]] += t->x[k];
}

int ht_cholesky(int n, double *A)
{
    for (int j = 0; j < n; ++j) {
        double d = A[j * n + j];
        for (int k = 0; k < j; ++k) d -= A[j * n + k] * A[j * n + k];
        if (!(d > 0.0)) return -1;
        d = sqrt(d);
        A[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = A[i * n + j];
            for (int k = 0; k < j; ++k) s -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = s / d;
        }
    }
    return 0;
}

void ht_cholesky_solve(int n, const double *L, int k, double *b)
{
    for (int c = 0; c < k; ++c) {
        for (int i = 0; i < n; ++i) {
            double s = b[i * k + c];
            for (int j = 0; j < i; ++j) s -= L[i * n + j] * b[j * k + c];
            b[i * k + c] = s / L[i * n + i];
        }
        for (int i = n - 1; i >= 0; --i) {
            double s = b[i * k + c];
            for (int j = i + 1; j < n; ++j) s -= L[j * n + i] * b[j * k + c];
            b[i * k + c] = s / L[i * n + i];
        }
    }
}
