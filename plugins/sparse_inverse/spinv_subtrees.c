/* spinv_subtrees.c - splits an elimination tree into a top part and
 * independent subtrees of similar work, for computing S = L^-1 in parallel
 * with the locality of a sequential sweep: each subtree (the contiguous
 * range first[r]..r of a postorder) is swept by one thread from its root
 * down, after the top nodes, which are ancestors of everything below. */
#include "spinv_internal.h"

#include <stdlib.h>

typedef struct weighted_root {
    double w;
    int r;
} weighted_root;

/* Heaviest first; ties by index, so the split is deterministic. */
static int cmp_weight_desc(const void *a, const void *b)
{
    const weighted_root *x = a, *y = b;
    if (x->w != y->w) return (x->w < y->w) - (x->w > y->w);
    return (x->r < y->r) - (x->r > y->r);
}

static int cmp_desc_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x < y) - (x > y);
}

static int heaviest(const int *roots, int nroots, const double *W)
{
    int best = 0;
    for (int q = 1; q < nroots; ++q)
        if (W[roots[q]] > W[roots[best]]) best = q;
    return best;
}

/* Moves the heaviest subtree root to the top (its children become roots)
 * until every subtree has at most total / target work, or there would be
 * more than `cap` subtrees. */
static void split_heavy(pl_spinv_split *split, const double *W, const int *head,
                        const int *next, double light, int cap)
{
    while (split->nroots > 0) {
        int q = heaviest(split->roots, split->nroots, W), r = split->roots[q];
        int nchild = 0;
        for (int c = head[r]; c >= 0; c = next[c]) nchild++;
        if (W[r] <= light || split->nroots - 1 + nchild > cap) break;
        split->top[split->ntop++] = r;
        split->roots[q] = split->roots[--split->nroots];
        for (int c = head[r]; c >= 0; c = next[c]) split->roots[split->nroots++] = c;
    }
}

int spinv_subtrees(int n, const int *parent, const double *work, int target,
                      pl_spinv_split *split)
{
    double *W = malloc((size_t)n * sizeof *W);
    int *head = malloc((size_t)n * sizeof *head), *next = malloc((size_t)n * sizeof *next);
    weighted_root *wr = malloc((size_t)n * sizeof *wr);
    split->roots = malloc((size_t)n * sizeof *split->roots);
    split->top = malloc((size_t)n * sizeof *split->top);
    split->nroots = split->ntop = 0;
    int status = PL_OK;
    if (!W || !head || !next || !wr || !split->roots || !split->top) {
        spinv_split_free(split);
        status = PL_EINTERNAL;
        goto done;
    }
    double total = 0.0;
    for (int k = 0; k < n; ++k) {
        W[k] = work[k];
        head[k] = -1;
    }
    for (int k = 0; k < n; ++k) { /* children before parents */
        if (parent[k] >= 0) W[parent[k]] += W[k];
        else total += W[k];
    }
    for (int k = n - 1; k >= 0; --k) {
        if (parent[k] < 0) {
            split->roots[split->nroots++] = k;
        } else {
            next[k] = head[parent[k]];
            head[parent[k]] = k;
        }
    }
    if (target < 1) target = 1;
    split_heavy(split, W, head, next, total / target, 4 * target);
    /* the top in descending order (parents first); subtrees heaviest first */
    qsort(split->top, (size_t)split->ntop, sizeof *split->top, cmp_desc_int);
    for (int q = 0; q < split->nroots; ++q) {
        wr[q].w = W[split->roots[q]];
        wr[q].r = split->roots[q];
    }
    qsort(wr, (size_t)split->nroots, sizeof *wr, cmp_weight_desc);
    for (int q = 0; q < split->nroots; ++q) split->roots[q] = wr[q].r;
done:
    free(W);
    free(head);
    free(next);
    free(wr);
    return status;
}

void spinv_split_free(pl_spinv_split *split)
{
    free(split->roots);
    free(split->top);
    split->roots = split->top = NULL;
    split->nroots = split->ntop = 0;
}
