/* rows.c - growable constraint rows and contact lists. */
#include "pliant/rows.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pl_rows_init(pl_rows *r)
{
    memset(r, 0, sizeof *r);
}

void pl_rows_free(pl_rows *r)
{
    free(r->start);
    free(r->vertex);
    free(r->coef);
    free(r->kind);
    free(r->d);
    free(r->compliance);
    free(r->lo);
    free(r->hi);
    free(r->pair);
    free(r->mu);
    free(r->owner);
    memset(r, 0, sizeof *r);
}

void pl_rows_clear(pl_rows *r)
{
    r->n = 0;
    r->nent = 0;
    if (r->start) r->start[0] = 0;
}

#define GROW(ptr, count) \
    do { void *p_ = realloc((ptr), (size_t)(count) * sizeof *(ptr)); if (!p_) return -1; (ptr) = p_; } while (0)

/* Room for at least `need` rows: the capacity doubled until it holds them,
 * in one reallocation of each array. */
static int grow_rows(pl_rows *r, int need)
{
    int cap = r->cap ? 2 * r->cap : 64;
    while (cap < need) cap *= 2;
    GROW(r->start, cap + 1);
    GROW(r->kind, cap);
    GROW(r->d, cap);
    GROW(r->compliance, cap);
    GROW(r->lo, cap);
    GROW(r->hi, cap);
    GROW(r->pair, cap);
    GROW(r->mu, cap);
    GROW(r->owner, cap);
    if (r->cap == 0) r->start[0] = 0;
    r->cap = cap;
    return 0;
}

void pl_rows_put(pl_rows *r, int k, pl_row_kind kind, const pl_component *owner, int first)
{
    r->start[k] = first;
    r->kind[k] = kind;
    r->d[k] = 0.0;
    r->compliance[k] = 0.0;
    r->lo[k] = -INFINITY;
    r->hi[k] = INFINITY;
    r->pair[k] = -1;
    r->mu[k] = 0.0;
    r->owner[k] = owner;
}

int pl_rows_begin(pl_rows *r, pl_row_kind kind, const pl_component *owner)
{
    if (r->n == r->cap && grow_rows(r, r->n + 1) != 0) return -1;
    int k = r->n++;
    pl_rows_put(r, k, kind, owner, r->nent);
    r->start[k + 1] = r->nent;
    return k;
}

static int grow_entries(pl_rows *r, int need)
{
    int cap = r->cap_ent ? 2 * r->cap_ent : 256;
    while (cap < need) cap *= 2;
    GROW(r->vertex, cap);
    GROW(r->coef, 3 * cap);
    r->cap_ent = cap;
    return 0;
}

int pl_rows_reserve(pl_rows *r, int rows, int entries)
{
    if (r->cap < r->n + rows && grow_rows(r, r->n + rows) != 0) return -1;
    if (r->nent + entries > r->cap_ent && grow_entries(r, r->nent + entries) != 0) return -1;
    return 0;
}

int pl_rows_add(pl_rows *r, int vertex, double cx, double cy, double cz)
{
    if (r->n == 0) return -1;
    if (r->nent == r->cap_ent && grow_entries(r, r->nent + 1) != 0) return -1;
    int e = r->nent++;
    r->vertex[e] = vertex;
    r->coef[3 * e] = cx;
    r->coef[3 * e + 1] = cy;
    r->coef[3 * e + 2] = cz;
    r->start[r->n] = r->nent;
    return 0;
}

double pl_rows_dot(const pl_rows *r, int row, const double *q)
{
    double s = 0.0;
    for (int e = r->start[row]; e < r->start[row + 1]; ++e) {
        const double *c = &r->coef[3 * e], *x = &q[3 * r->vertex[e]];
        s += c[0] * x[0] + c[1] * x[1] + c[2] * x[2];
    }
    return s;
}

void pl_rows_add_transpose(const pl_rows *r, const double *lambda, double alpha, double *y)
{
    for (int row = 0; row < r->n; ++row) {
        double l = alpha * lambda[row];
        if (l == 0.0) continue;
        for (int e = r->start[row]; e < r->start[row + 1]; ++e) {
            const double *c = &r->coef[3 * e];
            double *x = &y[3 * r->vertex[e]];
            x[0] += l * c[0];
            x[1] += l * c[1];
            x[2] += l * c[2];
        }
    }
}
