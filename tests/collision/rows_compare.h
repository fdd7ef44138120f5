/* rows_compare.h - two sets of constraint rows compared array by array, with
 * Check's assertions (tests of the rows' emission). */
#ifndef PLIANT_TESTS_ROWS_COMPARE_H
#define PLIANT_TESTS_ROWS_COMPARE_H

#include <check.h>
#include <string.h>

#include "pliant/rows.h"

/* owners: also the emitting components (not across two simulations, whose
 * components are other objects). */
static inline void same_rows(const pl_rows *a, const pl_rows *b, int owners)
{
    ck_assert_int_eq(a->n, b->n);
    ck_assert_int_eq(a->nent, b->nent);
    ck_assert(!memcmp(a->start, b->start, sizeof(int) * (size_t)(a->n + 1)));
    ck_assert(!memcmp(a->vertex, b->vertex, sizeof(int) * (size_t)a->nent));
    ck_assert(!memcmp(a->coef, b->coef, 3 * sizeof(double) * (size_t)a->nent));
    for (int r = 0; r < a->n; ++r) {
        ck_assert_int_eq(a->kind[r], b->kind[r]);
        ck_assert_int_eq(a->pair[r], b->pair[r]);
        ck_assert(!owners || a->owner[r] == b->owner[r]);
        ck_assert(a->d[r] == b->d[r] && a->mu[r] == b->mu[r]);
        ck_assert(a->compliance[r] == b->compliance[r]);
        ck_assert(a->lo[r] == b->lo[r] && a->hi[r] == b->hi[r]);
    }
}

#endif
