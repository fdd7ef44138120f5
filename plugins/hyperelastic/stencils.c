/* stencils.c - constant-matrix PD terms w/2 ||g x - p||^2 with a scalar
 * stencil row g: cloth bending and position targets.  The row acts on x, y
 * and z alike, so the term adds h2 w g g^T to the scalar system and
 * h2 w g^T p to the right-hand side. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hyperelastic.h"
#include "incidence.h"
#include "keep_norm.h"
#include "small_matrix.h"
#include "stencils_internal.h"

void hyper_stencils_free(pl_hyper_stencils *s)
{
    if (!s) return;
    free(s->ptr);
    free(s->vert);
    free(s->coef);
    free(s->w);
    free(s->rest);
    free(s->vptr);
    free(s->vinc);
    memset(s, 0, sizeof *s);
}

/* y = g_r x for global positions q. */
static void apply_row(const pl_hyper_stencils *s, int r, int offset, const double *q, double *y)
{
    y[0] = y[1] = y[2] = 0.0;
    for (int k = s->ptr[r]; k < s->ptr[r + 1]; ++k) {
        const double *x = q + 3 * ((size_t)offset + s->vert[k]);
        for (int a = 0; a < 3; ++a) y[a] += s->coef[k] * x[a];
    }
}

/* The projection p_r for y = g_r x. */
static void target_of(const pl_hyper_stencils *s, int r, const double *y, const double *targets,
                      double *p)
{
    if (s->kind == PL_HYPER_STENCIL_FIXED) {
        for (int a = 0; a < 3; ++a) p[a] = targets ? targets[3 * r + a] : 0.0;
        return;
    }
    hm_keep_norm_target(s->rest + 3 * r, y, p);
}

int hyper_stencils_add_matrix(const pl_hyper_stencils *s, int offset, double h2,
                                 pl_triplets *A, pl_error *err)
{
    for (int r = 0; r < s->n; ++r)
        for (int a = s->ptr[r]; a < s->ptr[r + 1]; ++a)
            for (int b = s->ptr[r]; b < s->ptr[r + 1]; ++b)
                if (pl_triplets_add(A, offset + s->vert[a], offset + s->vert[b],
                                    h2 * s->w[r] * s->coef[a] * s->coef[b]) != PL_OK)
                    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                        "out of memory assembling the system matrix");
    return PL_OK;
}

size_t hyper_stencils_work_size(const pl_hyper_stencils *s)
{
    size_t nz = s->ptr ? (size_t)s->ptr[s->n] : 0;
    return 3 * (nz > 0 ? nz : 1);
}

int hyper_stencils_project(const pl_hyper_stencils *s, int offset, double h2, const double *q,
                              const double *targets, double *work, double *rhs, pl_error *err)
{
    (void)err;
#pragma omp parallel for schedule(static)
    for (int r = 0; r < s->n; ++r) {
        double y[3], p[3];
        apply_row(s, r, offset, q, y);
        target_of(s, r, y, targets, p);
        for (int k = s->ptr[r]; k < s->ptr[r + 1]; ++k)
            for (int a = 0; a < 3; ++a) work[3 * (size_t)k + a] = h2 * s->w[r] * s->coef[k] * p[a];
    }
    hyper_incidence_gather(s->nverts, s->vptr, s->vinc, work, offset, rhs);
    return PL_OK;
}

double hyper_stencils_energy(const pl_hyper_stencils *s, int offset, const double *q,
                                const double *targets)
{
    double sum = 0.0; /* sequential: fixed order, and cheap next to the elements */
    for (int r = 0; r < s->n; ++r) {
        double y[3], p[3], e = 0.0;
        apply_row(s, r, offset, q, y);
        target_of(s, r, y, targets, p);
        for (int a = 0; a < 3; ++a) e += (y[a] - p[a]) * (y[a] - p[a]);
        sum += 0.5 * s->w[r] * e;
    }
    return sum;
}

int hyper_stencils_add_gradient(const pl_hyper_stencils *s, int offset, const double *q,
                                   const double *targets, double *grad, pl_error *err)
{
    (void)err;
    /* sequential scatter: this is the Newton reference path */
    for (int r = 0; r < s->n; ++r) {
        double y[3], p[3];
        apply_row(s, r, offset, q, y);
        target_of(s, r, y, targets, p); /* envelope theorem: p is a minimiser */
        for (int k = s->ptr[r]; k < s->ptr[r + 1]; ++k)
            for (int a = 0; a < 3; ++a)
                grad[3 * ((size_t)offset + s->vert[k]) + a] += s->w[r] * s->coef[k] * (y[a] - p[a]);
    }
    return PL_OK;
}

/* M (3x3): the Hessian of the row's energy with respect to y, over w. */
static void row_curvature(const pl_hyper_stencils *s, int r, const double *y, int psd, double *M)
{
    for (int i = 0; i < 9; ++i) M[i] = (i % 4 == 0) ? 1.0 : 0.0;
    if (s->kind == PL_HYPER_STENCIL_FIXED) return;
    const double *y0 = s->rest + 3 * r;
    double r0 = hm_norm3(y0), ny = hm_norm3(y), yh[3];
    if (r0 == 0.0) return;
    /* (|y| - r0)^2 / 2: curvature 1 along y, 1 - r0/|y| across it */
    double across;
    if (ny > 1e-300) {
        for (int a = 0; a < 3; ++a) yh[a] = y[a] / ny;
        across = 1.0 - r0 / ny;
    } else {
        for (int a = 0; a < 3; ++a) yh[a] = y0[a] / r0;
        across = 0.0;
    }
    if (psd && across < 0.0) across = 0.0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            M[a * 3 + b] = yh[a] * yh[b] + across * ((a == b) - yh[a] * yh[b]);
}

int hyper_stencils_add_hessian(const pl_hyper_stencils *s, int offset, const double *q,
                                  int psd, pl_triplets *H, pl_error *err)
{
    for (int r = 0; r < s->n; ++r) {
        double y[3], M[9];
        apply_row(s, r, offset, q, y);
        row_curvature(s, r, y, psd, M);
        for (int i = s->ptr[r]; i < s->ptr[r + 1]; ++i)
            for (int j = s->ptr[r]; j < s->ptr[r + 1]; ++j) {
                double c = s->w[r] * s->coef[i] * s->coef[j];
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        if (pl_triplets_add(H, 3 * (offset + s->vert[i]) + a,
                                            3 * (offset + s->vert[j]) + b, c * M[a * 3 + b]) != PL_OK)
                            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                                "out of memory assembling the Hessian");
            }
    }
    return PL_OK;
}

int hyper_stencils_alloc(pl_hyper_stencils *s, pl_hyper_stencil_kind kind, int n, int nnz,
                         int nverts)
{
    memset(s, 0, sizeof *s);
    s->kind = kind;
    s->n = n;
    s->nverts = nverts;
    size_t nn = (size_t)(n > 0 ? n : 1), nz = (size_t)(nnz > 0 ? nnz : 1);
    s->ptr = calloc(nn + 1, sizeof *s->ptr);
    s->vert = malloc(nz * sizeof *s->vert);
    s->coef = malloc(nz * sizeof *s->coef);
    s->w = malloc(nn * sizeof *s->w);
    if (kind == PL_HYPER_STENCIL_KEEP_NORM) s->rest = malloc(3 * nn * sizeof *s->rest);
    if (!s->ptr || !s->vert || !s->coef || !s->w ||
        (kind == PL_HYPER_STENCIL_KEEP_NORM && !s->rest)) {
        hyper_stencils_free(s);
        return -1;
    }
    return 0;
}

int hyper_stencils_finish(pl_hyper_stencils *s, const double *rest_positions)
{
    if (hyper_incidence_build(s->nverts, s->ptr[s->n], s->vert, &s->vptr, &s->vinc) != 0) {
        hyper_stencils_free(s);
        return -1;
    }
    if (s->kind == PL_HYPER_STENCIL_KEEP_NORM)
        for (int r = 0; r < s->n; ++r) {
            double *y0 = s->rest + 3 * r, scale = 0.0;
            apply_row(s, r, 0, rest_positions, y0);
            /* a rest value at round-off level is a flat rest: make it exactly
             * zero, or the norm projection would see a spurious direction */
            const double *x0 = rest_positions + 3 * (size_t)s->vert[s->ptr[r]];
            for (int k = s->ptr[r]; k < s->ptr[r + 1]; ++k) {
                double d[3];
                hm_sub3(rest_positions + 3 * (size_t)s->vert[k], x0, d);
                scale += fabs(s->coef[k]) * hm_norm3(d);
            }
            if (hm_norm3(y0) <= 1e-10 * scale) y0[0] = y0[1] = y0[2] = 0.0;
        }
    return 0;
}
