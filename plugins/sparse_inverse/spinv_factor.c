/* spinv_factor.c - the solver object and CHOLMOD's simplicial LL^T with a
 * chosen ordering and a postordered elimination tree. */
#include "spinv_internal.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

static const char *const ordering_names[] = {"metis", "nesdis", "amd", "natural"};
static const char *const mode_names[] = {"sparse", "direct"};

const char *spinv_ordering_name(pl_spinv_ordering o)
{
    return ((unsigned)o < 4) ? ordering_names[o] : "?";
}

const char *spinv_mode_name(pl_spinv_mode m)
{
    return ((unsigned)m < 2) ? mode_names[m] : "?";
}

pl_sparse_inverse *sparse_inverse_create(const pl_spinv_options *opt)
{
    pl_sparse_inverse *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    pl_spinv_options defaults = {PL_SPINV_METIS, PL_SPINV_SPARSE, 0};
    s->opt = opt ? *opt : defaults;
    s->nthreads = s->opt.threads > 0 ? s->opt.threads : omp_get_max_threads();
    /* never more threads than the cores this process may use (its affinity):
     * the extra ones would only wait at every barrier */
    if (s->nthreads > omp_get_num_procs()) s->nthreads = omp_get_num_procs();
    if (s->nthreads < 1) s->nthreads = 1;
    if (!cholmod_start(&s->cc)) {
        free(s);
        return NULL;
    }
    s->cc_started = 1;
    return s;
}

void spinv_clear(pl_sparse_inverse *s)
{
    if (s->L) cholmod_free_factor(&s->L, &s->cc);
    cholmod_free_dense(&s->B, &s->cc);
    cholmod_free_dense(&s->X, &s->cc);
    cholmod_free_dense(&s->Y, &s->cc);
    cholmod_free_dense(&s->E, &s->cc);
    free(s->perm);
    free(s->pinv);
    free(s->parent);
    free(s->first);
    free(s->S_bounds);
    free(s->ST_bounds);
    free(s->work_a);
    free(s->work_b);
    s->perm = s->pinv = s->parent = s->first = s->S_bounds = s->ST_bounds = NULL;
    s->work_a = s->work_b = NULL;
    s->work_cap = 0;
    spinv_profile_free(&s->S);
    spinv_runs_free(&s->ST);
    s->n = 0;
    memset(&s->stats, 0, sizeof s->stats);
}

void sparse_inverse_destroy(pl_sparse_inverse *s)
{
    if (!s) return;
    spinv_clear(s);
    if (s->cc_started) cholmod_finish(&s->cc);
    free(s);
}

/* Square, monotone column pointers, row indices in range; counts the
 * nonzeros of the symmetric matrix from its lower triangle and says whether
 * rows are sorted within columns. */
static int check_input(const pl_csc *A, int64_t *nnz_full, int *sorted, pl_error *err)
{
    if (!A || !A->p || A->nrows != A->ncols || A->ncols < 1)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse: expected a square non-empty CSC matrix, got %d x %d",
                            A ? A->nrows : 0, A ? A->ncols : 0);
    int n = A->ncols;
    if (A->p[0] != 0 || (A->p[n] > 0 && (!A->i || !A->x)))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse: malformed CSC matrix");
    int64_t lower = 0, diag = 0;
    *sorted = 1;
    for (int j = 0; j < n; ++j) {
        if (A->p[j + 1] < A->p[j])
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "sparse inverse: column pointers decrease at column %d", j);
        for (int q = A->p[j]; q < A->p[j + 1]; ++q) {
            int i = A->i[q];
            if (i < 0 || i >= n)
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "sparse inverse: row index %d out of range 0..%d in column %d",
                                    i, n - 1, j);
            if (q > A->p[j] && A->i[q - 1] >= i) *sorted = 0;
            if (i >= j) lower++;
            if (i == j) diag++;
        }
    }
    *nnz_full = 2 * lower - diag;
    return PL_OK;
}

static const int cholmod_ordering[] = {CHOLMOD_METIS, CHOLMOD_NESDIS, CHOLMOD_AMD,
                                       CHOLMOD_NATURAL};

/* Ordering, symbolic and numeric factorisation of P A P^T = L L^T. */
static int factor_cholmod(pl_sparse_inverse *s, const pl_csc *A, int sorted, pl_error *err)
{
    cholmod_common *cc = &s->cc;
    cholmod_sparse Aw;
    memset(&Aw, 0, sizeof Aw);
    Aw.nrow = Aw.ncol = (size_t)A->ncols;
    Aw.nzmax = (size_t)A->p[A->ncols];
    Aw.p = A->p;
    Aw.i = A->i;
    Aw.x = A->x;
    Aw.stype = -1; /* lower triangle used, upper ignored */
    Aw.itype = CHOLMOD_INT;
    Aw.xtype = CHOLMOD_REAL;
    Aw.dtype = CHOLMOD_DOUBLE;
    Aw.sorted = sorted;
    Aw.packed = 1;
    if ((unsigned)s->opt.ordering >= 4)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse: unknown ordering %d",
                            (int)s->opt.ordering);
    cc->nmethods = 1;
    cc->method[0].ordering = cholmod_ordering[s->opt.ordering];
    cc->postorder = 1;
    cc->supernodal = CHOLMOD_SIMPLICIAL;
    cc->final_ll = 1;
    cc->print = 0; /* errors are reported through err */
    s->L = cholmod_analyze(&Aw, cc);
    if (!s->L)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "sparse inverse: CHOLMOD analysis (%s ordering) failed, status %d",
                            spinv_ordering_name(s->opt.ordering), cc->status);
    if (!cholmod_factorize(&Aw, s->L, cc) && cc->status != CHOLMOD_NOT_POSDEF)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "sparse inverse: CHOLMOD factorisation failed, status %d", cc->status);
    if (cc->status == CHOLMOD_NOT_POSDEF || s->L->minor < s->L->n)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "sparse inverse: the matrix is not positive definite (pivot %d of %d "
                            "in the permuted order)",
                            (int)s->L->minor, A->ncols);
    if (s->L->is_super || !s->L->is_ll || s->L->xtype != CHOLMOD_REAL)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "sparse inverse: CHOLMOD did not return a simplicial LL^T factor");
    return PL_OK;
}

/* Permutation, its inverse and the etree from L's pattern: the parent of k
 * is the first off-diagonal row of column k (the diagonal comes first). */
static int read_factor(pl_sparse_inverse *s, pl_error *err)
{
    int n = s->n;
    const cholmod_factor *L = s->L;
    const int *Lp = L->p, *Li = L->i, *Lnz = L->nz, *P = L->Perm;
    s->perm = malloc((size_t)n * sizeof *s->perm);
    s->pinv = malloc((size_t)n * sizeof *s->pinv);
    s->parent = malloc((size_t)n * sizeof *s->parent);
    s->first = malloc((size_t)n * sizeof *s->first);
    if (!s->perm || !s->pinv || !s->parent || !s->first)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "sparse inverse: out of memory");
    int64_t nnz_L = 0;
    for (int k = 0; k < n; ++k) {
        s->perm[k] = P ? P[k] : k;
        s->pinv[s->perm[k]] = k;
        if (Lnz[k] < 1 || Li[Lp[k]] != k)
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                "sparse inverse: column %d of L does not start on its diagonal", k);
        int par = -1;
        for (int q = Lp[k] + 1; q < Lp[k] + Lnz[k]; ++q)
            if (par < 0 || Li[q] < par) par = Li[q];
        s->parent[k] = par;
        nnz_L += Lnz[k];
    }
    s->stats.nnz_L = nnz_L;
    return PL_OK;
}

int spinv_check_postorder(int n, const int *parent, int *first, pl_error *err)
{
    int *size = calloc((size_t)n, sizeof *size);
    if (!size) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    for (int k = 0; k < n; ++k) first[k] = k;
    int status = PL_OK;
    /* children precede parents, so one ascending sweep completes subtrees */
    for (int k = 0; k < n && status == PL_OK; ++k) {
        size[k] += 1;
        int p = parent[k];
        if (p != -1 && (p <= k || p >= n)) {
            status = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                  "sparse inverse: etree parent %d of %d is not above it", p, k);
            break;
        }
        /* descendants of k lie in first[k]..k; there are size[k] of them,
         * so they fill that range exactly when the counts agree */
        if (k - first[k] + 1 != size[k])
            status = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                  "sparse inverse: the elimination tree is not postordered "
                                  "(node %d has %d descendants spread over %d columns)",
                                  k, size[k], k - first[k] + 1);
        if (p != -1) {
            size[p] += size[k];
            if (first[k] < first[p]) first[p] = first[k];
        }
    }
    free(size);
    return status;
}

/* nnz(S) = sum of path lengths; runs of S^T: a path continues the run of
 * its parent's path exactly when the parent is the next index. */
static void count_inverse(pl_sparse_inverse *s)
{
    int n = s->n;
    int64_t nnz = 0, runs = 0;
    /* depth and runs of the path from k, computed from the root down */
    int *len = malloc((size_t)n * sizeof *len), *nr = malloc((size_t)n * sizeof *nr);
    if (len && nr) {
        for (int k = n - 1; k >= 0; --k) {
            int p = s->parent[k];
            len[k] = (p < 0) ? 1 : len[p] + 1;
            nr[k] = (p < 0) ? 1 : nr[p] + (p == k + 1 ? 0 : 1);
            nnz += len[k];
            runs += nr[k];
        }
    }
    free(len);
    free(nr);
    s->stats.nnz_S = nnz;
    s->stats.runs_ST = runs;
}

int sparse_inverse_factor(pl_sparse_inverse *s, const pl_csc *A, pl_error *err)
{
    if (!s) return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "sparse inverse: no solver");
    spinv_clear(s);
    int64_t nnz_full = 0;
    int sorted = 1;
    int status = check_input(A, &nnz_full, &sorted, err);
    if (status != PL_OK) return status;
    double t0 = omp_get_wtime();
    status = factor_cholmod(s, A, sorted, err);
    if (status == PL_OK) {
        s->n = A->ncols;
        status = read_factor(s, err);
    }
    if (status == PL_OK) status = spinv_check_postorder(s->n, s->parent, s->first, err);
    double t1 = omp_get_wtime();
    if (status == PL_OK) {
        s->stats.n = s->n;
        s->stats.nnz_A = nnz_full;
        s->stats.factor_s = t1 - t0;
        s->stats.ordering_used = s->L->ordering;
        count_inverse(s);
        if (s->opt.mode == PL_SPINV_SPARSE) {
            status = spinv_build_inverse(s, err);
            s->stats.inverse_s = omp_get_wtime() - t1;
        }
    }
    if (status != PL_OK) spinv_clear(s);
    return status;
}

int sparse_inverse_size(const pl_sparse_inverse *s) { return s ? s->n : 0; }

const pl_spinv_stats *sparse_inverse_stats(const pl_sparse_inverse *s)
{
    return s ? &s->stats : NULL;
}

const pl_spinv_profile *pl_sparse_inverse_S(const pl_sparse_inverse *s)
{
    return (s && s->S.val) ? &s->S : NULL;
}

const pl_spinv_runs *pl_sparse_inverse_ST(const pl_sparse_inverse *s)
{
    return (s && s->ST.val) ? &s->ST : NULL;
}

const int *sparse_inverse_perm(const pl_sparse_inverse *s) { return s ? s->perm : NULL; }
const int *sparse_inverse_parent(const pl_sparse_inverse *s) { return s ? s->parent : NULL; }
