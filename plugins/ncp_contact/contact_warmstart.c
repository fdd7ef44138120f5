/* contact_warmstart.c - lambda of the rows that persist from one step to
 * the next (a resting contact keeps nearly the same force).
 *
 * Matching rule.  Each active row of a step leaves a record: its owner
 * (a hash of the emitting component's path, stable across runs and saved
 * states), kind, the global vertex of its first entry and the direction of
 * that entry's coefficient (normalised), with its final lambda.  At the
 * next step:
 *   - a bilateral, normal or bounded row takes the lambda of an unused old
 *     record with the same owner, kind and first vertex whose direction is
 *     within 30 degrees of its own (cos >= 0.866); among several, the one
 *     with the closest direction, then the first in the old order (rows
 *     that differ only in direction, like the x/y/z rows pinning one
 *     vertex, keep their own lambda);
 *   - a friction row whose normal row was matched gets the old friction
 *     force of that contact projected on its own direction,
 *     lambda_t = (sum_old lambda_t' dir_t') . dir_t, so a contact whose
 *     tangent basis turned keeps its friction force vector;
 *   - every other row starts from 0.
 * The records live in a pl_data slot (see contact_solver.c), so that
 * save/restore, reset and several states over one model stay exact. */
#include "contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WARM_COS_MIN 0.8660254037844386 /* cos 30 deg */

static uint64_t fnv1a(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; ++s) {
        h ^= (unsigned char)*s;
        h *= 1099511628211ull;
    }
    return h;
}

int ncpc_keys_build(const pl_ncpc_rows *r, const pl_rows *rows, pl_ncpc_key *keys, pl_error *err)
{
    const pl_component *last = NULL;
    uint64_t hash = 0;
    (void)err;
    for (int j = 0; j < r->m; ++j) {
        int i = r->full[j];
        pl_ncpc_key *k = &keys[j];
        const pl_component *owner = rows->owner ? rows->owner[i] : NULL;
        if (j == 0 || owner != last) {
            char path[512];
            hash = owner ? fnv1a(pl_component_path(owner, path, sizeof path)) : 0;
            last = owner;
        }
        memset(k, 0, sizeof *k);
        k->owner = hash;
        k->kind = (int32_t)r->kind[j];
        k->pair = r->kind[j] == PL_ROW_FRICTION ? r->pair[j] : -1;
        int e = rows->start[i];
        k->vertex = rows->vertex[e];
        const double *c = &rows->coef[3 * e];
        double n = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (int a = 0; a < 3; ++a) k->dir[a] = n > 0.0 ? c[a] / n : 0.0;
    }
    return PL_OK;
}

int ncpc_keys_check(const pl_component *owner, const void *data, size_t bytes, pl_error *err)
{
    const pl_ncpc_key *k = data;
    size_t n = bytes / sizeof *k;
    for (size_t j = 0; j < n; ++j) {
        int bad = k[j].kind < PL_ROW_BILATERAL || k[j].kind > PL_ROW_BOUNDED ||
                  k[j].pair < -1 || (k[j].pair >= 0 && (size_t)k[j].pair >= n) ||
                  !isfinite(k[j].lambda);
        for (int a = 0; a < 3 && !bad; ++a) bad = !isfinite(k[j].dir[a]);
        if (bad)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "warm-start record %zu is corrupt "
                                "(kind %d, pair %d of %zu, or a non-finite value)", j,
                                (int)k[j].kind, (int)k[j].pair, n);
    }
    return PL_OK;
}

static int same_key(const pl_ncpc_key *a, const pl_ncpc_key *b)
{
    return a->owner == b->owner && a->kind == b->kind && a->vertex == b->vertex;
}

static uint64_t key_hash(const pl_ncpc_key *k)
{
    uint64_t h = k->owner ^ ((uint64_t)(uint32_t)k->kind << 32) ^ (uint64_t)(uint32_t)k->vertex;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull; /* a 64-bit finaliser (MurmurHash3's) */
    h ^= h >> 33;
    return h;
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The old records of each key in a hash table of chains (head, next), each
 * chain in increasing old index: a row's candidates are met in the old
 * order, as the rule's tie break wants.  Linear in the rows: the sharp
 * corner 10.2k's 9.5k contacts took a sort of about a millisecond a step. */
int ncpc_warm_start(const pl_ncpc_key *keys, int m, const pl_ncpc_key *old, int nold,
                       double *lambda, pl_error *err)
{
    for (int j = 0; j < m; ++j) lambda[j] = 0.0;
    if (m == 0 || nold == 0) return 0;
    size_t no = (size_t)nold, nh = 16;
    while (nh < 2 * no) nh *= 2;
    int *head = malloc(sizeof(int) * nh), *next = malloc(sizeof(int) * no);
    int *used = calloc(no, sizeof(int));
    int *fric = malloc(sizeof(int) * 2 * no), *match = malloc(sizeof(int) * (size_t)m);
    if (!head || !next || !used || !fric || !match) {
        free(head);
        free(next);
        free(used);
        free(fric);
        free(match);
        return -pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "out of memory");
    }
    /* old friction rows of each old normal record (at most two) */
    for (size_t a = 0; a < 2 * no; ++a) fric[a] = -1;
    for (size_t b = 0; b < nh; ++b) head[b] = -1;
    for (int a = 0; a < nold; ++a) {
        if (old[a].kind != PL_ROW_FRICTION) continue;
        int n = old[a].pair;
        if (n < 0 || n >= nold) continue;
        if (fric[2 * n] < 0) fric[2 * n] = a;
        else if (fric[2 * n + 1] < 0) fric[2 * n + 1] = a;
    }
    for (int a = nold - 1; a >= 0; --a) { /* pushed last first: chains in old order */
        if (old[a].kind == PL_ROW_FRICTION) continue;
        size_t b = (size_t)(key_hash(&old[a]) & (nh - 1));
        next[a] = head[b];
        head[b] = a;
    }
    int matched = 0;
    for (int j = 0; j < m; ++j) {
        match[j] = -1;
        if (keys[j].kind == PL_ROW_FRICTION) continue;
        int best = -1;
        double best_dot = WARM_COS_MIN;
        for (int a = head[key_hash(&keys[j]) & (nh - 1)]; a >= 0; a = next[a]) {
            if (!same_key(&old[a], &keys[j])) continue;
            double d = dot3(old[a].dir, keys[j].dir);
            if (!used[a] && (d > best_dot || (best < 0 && d >= best_dot))) {
                best = a;
                best_dot = d;
            }
        }
        if (best >= 0) {
            used[best] = 1;
            match[j] = best;
            lambda[j] = old[best].lambda;
            ++matched;
        }
    }
    for (int j = 0; j < m; ++j) {
        if (keys[j].kind != PL_ROW_FRICTION) continue;
        int n = keys[j].pair, J = n >= 0 && n < m ? match[n] : -1;
        if (J < 0) continue;
        double F[3] = {0.0, 0.0, 0.0};
        for (int s = 0; s < 2; ++s) {
            int a = fric[2 * J + s];
            if (a < 0) continue;
            for (int c = 0; c < 3; ++c) F[c] += old[a].lambda * old[a].dir[c];
        }
        lambda[j] = dot3(F, keys[j].dir);
        ++matched;
    }
    free(head);
    free(next);
    free(used);
    free(fric);
    free(match);
    return matched;
}
