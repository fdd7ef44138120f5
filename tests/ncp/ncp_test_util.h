/* ncp_test_util.h - small helpers shared by the ncp tests: a deterministic
 * random generator, random SPD matrices, a dense Cholesky solve. */
#ifndef NCP_TEST_UTIL_H
#define NCP_TEST_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

typedef struct test_rng {
    uint64_t s;
} test_rng;

/* uniform in [0, 1) (splitmix64: deterministic on every platform) */
static inline double rng_uniform(test_rng *g)
{
    uint64_t z = (g->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static inline double rng_range(test_rng *g, double a, double b) { return a + (b - a) * rng_uniform(g); }

static inline double rng_normal(test_rng *g)
{
    double u1 = rng_uniform(g), u2 = rng_uniform(g);
    if (u1 < 1e-300)
        u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* W = B B^T / n + eps I, n x n row-major (B n x n standard normal). */
static inline void random_spd(test_rng *g, int n, double eps, double *W)
{
    double *B = malloc(sizeof(double) * (size_t)n * (size_t)n);
    for (int i = 0; i < n * n; ++i)
        B[i] = rng_normal(g);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j <= i; ++j) {
            double s = 0.0;
            for (int k = 0; k < n; ++k)
                s += B[i * n + k] * B[j * n + k];
            s /= n;
            if (i == j)
                s += eps;
            W[i * n + j] = W[j * n + i] = s;
        }
    free(B);
}

/* Solves A x = b (A SPD, n x n row-major) by Cholesky; 0 on success. */
static inline int dense_cholesky_solve(int n, const double *A, const double *b, double *x)
{
    double *L = calloc((size_t)n * (size_t)n, sizeof(double));
    int ok = 0;
    for (int j = 0; j < n && !ok; ++j) {
        double s = A[j * n + j];
        for (int k = 0; k < j; ++k)
            s -= L[j * n + k] * L[j * n + k];
        if (!(s > 0.0)) {
            ok = 1;
            break;
        }
        L[j * n + j] = sqrt(s);
        for (int i = j + 1; i < n; ++i) {
            double t = A[i * n + j];
            for (int k = 0; k < j; ++k)
                t -= L[i * n + k] * L[j * n + k];
            L[i * n + j] = t / L[j * n + j];
        }
    }
    if (!ok) {
        for (int i = 0; i < n; ++i) {
            double t = b[i];
            for (int k = 0; k < i; ++k)
                t -= L[i * n + k] * x[k];
            x[i] = t / L[i * n + i];
        }
        for (int i = n - 1; i >= 0; --i) {
            double t = x[i];
            for (int k = i + 1; k < n; ++k)
                t -= L[k * n + i] * x[k];
            x[i] = t / L[i * n + i];
        }
    }
    free(L);
    return ok;
}

#endif
