/* spinv_test_util.c - references for the sparse inverse tests. */
#include "spinv_test_util.h"

#include <cholmod.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

double *spinv_random_block(int n, int k, unsigned seed)
{
    double *b = malloc((size_t)n * (size_t)k * sizeof *b);
    uint32_t s = seed ? seed : 7u;
    for (size_t i = 0; b && i < (size_t)n * (size_t)k; ++i) {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        b[i] = 2.0 * (s / 4294967296.0) - 1.0;
    }
    return b;
}

int spinv_ref_solve(const pl_csc *A, const double *b, double *x, int k)
{
    cholmod_common cc;
    cholmod_start(&cc);
    cc.print = 0;
    cholmod_sparse Aw;
    memset(&Aw, 0, sizeof Aw);
    Aw.nrow = Aw.ncol = (size_t)A->ncols;
    Aw.nzmax = (size_t)A->p[A->ncols];
    Aw.p = A->p;
    Aw.i = A->i;
    Aw.x = A->x;
    Aw.stype = -1;
    Aw.itype = CHOLMOD_INT;
    Aw.xtype = CHOLMOD_REAL;
    Aw.dtype = CHOLMOD_DOUBLE;
    Aw.sorted = 1;
    Aw.packed = 1;
    int ok = 0;
    size_t n = (size_t)A->ncols;
    cholmod_factor *L = cholmod_analyze(&Aw, &cc);
    cholmod_dense *B = cholmod_allocate_dense(n, (size_t)k, n, CHOLMOD_REAL, &cc), *X = NULL;
    if (L && B && cholmod_factorize(&Aw, L, &cc) && cc.status == CHOLMOD_OK) {
        double *Bx = B->x;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < k; ++c) Bx[(size_t)c * n + i] = b[i * k + c];
        X = cholmod_solve(CHOLMOD_A, L, B, &cc);
        if (X) {
            const double *Xx = X->x;
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < k; ++c) x[i * k + c] = Xx[(size_t)c * n + i];
            ok = 1;
        }
    }
    cholmod_free_dense(&X, &cc);
    cholmod_free_dense(&B, &cc);
    cholmod_free_factor(&L, &cc);
    cholmod_finish(&cc);
    return ok ? 0 : 1;
}

double spinv_rel_diff(const double *a, const double *b, size_t len)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < len; ++i) {
        num += (a[i] - b[i]) * (a[i] - b[i]);
        den += b[i] * b[i];
    }
    return den > 0 ? sqrt(num / den) : sqrt(num);
}

double *spinv_dense(const pl_csc *A)
{
    double *D = calloc((size_t)A->nrows * (size_t)A->ncols, sizeof *D);
    for (int j = 0; D && j < A->ncols; ++j)
        for (int q = A->p[j]; q < A->p[j + 1]; ++q)
            D[(size_t)j * A->nrows + A->i[q]] += A->x[q];
    return D;
}

int spinv_lower(const pl_csc *A, pl_csc *lower)
{
    int n = A->ncols, w = 0;
    memset(lower, 0, sizeof *lower);
    lower->p = malloc(((size_t)n + 1) * sizeof *lower->p);
    lower->i = malloc((size_t)(A->p[n] + 1) * sizeof *lower->i);
    lower->x = malloc((size_t)(A->p[n] + 1) * sizeof *lower->x);
    if (!lower->p || !lower->i || !lower->x) return 1;
    lower->nrows = A->nrows;
    lower->ncols = n;
    for (int j = 0; j < n; ++j) {
        lower->p[j] = w;
        for (int q = A->p[j]; q < A->p[j + 1]; ++q)
            if (A->i[q] >= j) {
                lower->i[w] = A->i[q];
                lower->x[w++] = A->x[q];
            }
    }
    lower->p[n] = w;
    return 0;
}
