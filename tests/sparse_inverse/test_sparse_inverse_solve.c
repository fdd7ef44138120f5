/* test_sparse_inverse_solve.c - the global step P^T S^T S P b equals an
 * independent CHOLMOD solve of A x = b; S is exactly L^-1 with the profile
 * structure of a postordered etree; direct and sparse modes agree; results
 * do not depend on the thread count; bad input is refused. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparse_inverse.h"
#include "spinv_test_util.h"
#include "spinv_testmat.h"

#define TOL 1e-10

/* Sparse-mode solve of A x = b on n x 3 (in place too) against CHOLMOD. */
static void check_solve(const pl_csc *A, pl_spinv_ordering ord, pl_spinv_mode mode)
{
    int n = A->ncols;
    pl_spinv_options opt = {ord, mode, 0};
    pl_sparse_inverse *s = sparse_inverse_create(&opt);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s, A, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_size(s), n);
    double *b = spinv_random_block(n, 3, 11u + (unsigned)ord), *x = malloc(3 * (size_t)n * sizeof *x);
    double *ref = malloc(3 * (size_t)n * sizeof *ref);
    ck_assert_int_eq(spinv_ref_solve(A, b, ref, 3), 0);
    ck_assert_int_eq(sparse_inverse_solve(s, b, x, 3, &err), PL_OK);
    double d = spinv_rel_diff(x, ref, 3 * (size_t)n);
    ck_assert_msg(d < TOL, "%s/%s n=%d: relative difference %g", spinv_ordering_name(ord),
                  spinv_mode_name(mode), n, d);
    /* x may equal b */
    ck_assert_int_eq(sparse_inverse_solve(s, b, b, 3, &err), PL_OK);
    ck_assert_msg(spinv_rel_diff(b, ref, 3 * (size_t)n) < TOL, "in-place solve differs");
    /* a single right-hand side goes through the general-k path */
    double *b1 = spinv_random_block(n, 1, 5u), *x1 = malloc((size_t)n * sizeof *x1);
    double *r1 = malloc((size_t)n * sizeof *r1);
    ck_assert_int_eq(spinv_ref_solve(A, b1, r1, 1), 0);
    ck_assert_int_eq(sparse_inverse_solve(s, b1, x1, 1, &err), PL_OK);
    ck_assert_msg(spinv_rel_diff(x1, r1, (size_t)n) < TOL, "k = 1 solve differs");
    free(b1), free(x1), free(r1);
    free(b), free(x), free(ref);
    sparse_inverse_destroy(s);
}

static const int grids[][3] = {{4, 3, 3}, {8, 5, 4}, {12, 7, 6}, {20, 6, 6}};

static void check_orderings_on_grids(pl_spinv_mode mode)
{
    for (int g = 0; g < 4; ++g) {
        pl_csc A;
        ck_assert_int_eq(spinv_grid_matrix(grids[g][0], grids[g][1], grids[g][2], 10.0, &A), 0);
        check_solve(&A, PL_SPINV_METIS, mode);
        check_solve(&A, PL_SPINV_NESDIS, mode);
        check_solve(&A, PL_SPINV_AMD, mode);
        if (A.ncols <= 200) check_solve(&A, PL_SPINV_NATURAL, mode);
        pl_csc_free(&A);
    }
}

START_TEST(test_sparse_solve_equals_cholmod_on_tet_grids)
{
    check_orderings_on_grids(PL_SPINV_SPARSE);
}
END_TEST

START_TEST(test_direct_solve_equals_cholmod_on_tet_grids)
{
    check_orderings_on_grids(PL_SPINV_DIRECT);
}
END_TEST

START_TEST(test_sparse_solve_equals_cholmod_on_random_spd)
{
    pl_csc A;
    ck_assert_int_eq(spinv_random_spd(400, 3, 42u, &A), 0);
    for (int o = 0; o < 4; ++o) check_solve(&A, (pl_spinv_ordering)o, PL_SPINV_SPARSE);
    pl_csc_free(&A);
}
END_TEST

/* The lower triangle alone gives the same factor and the same answer. */
START_TEST(test_lower_triangle_input_gives_same_result)
{
    pl_csc A, Lo;
    ck_assert_int_eq(spinv_grid_matrix(7, 5, 4, 10.0, &A), 0);
    ck_assert_int_eq(spinv_lower(&A, &Lo), 0);
    pl_sparse_inverse *s1 = sparse_inverse_create(NULL), *s2 = sparse_inverse_create(NULL);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s1, &A, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_factor(s2, &Lo, &err), PL_OK);
    const pl_spinv_stats *t1 = sparse_inverse_stats(s1), *t2 = sparse_inverse_stats(s2);
    ck_assert_int_eq(t1->nnz_A, A.p[A.ncols]);
    ck_assert_int_eq(t1->nnz_A, t2->nnz_A);
    ck_assert_int_eq(t1->nnz_S, t2->nnz_S);
    int n = A.ncols;
    double *b = spinv_random_block(n, 3, 3u), *x1 = malloc(3 * (size_t)n * sizeof *x1);
    double *x2 = malloc(3 * (size_t)n * sizeof *x2);
    ck_assert_int_eq(sparse_inverse_solve(s1, b, x1, 3, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_solve(s2, b, x2, 3, &err), PL_OK);
    ck_assert(spinv_rel_diff(x2, x1, 3 * (size_t)n) < 1e-14);
    free(b), free(x1), free(x2);
    sparse_inverse_destroy(s1);
    sparse_inverse_destroy(s2);
    pl_csc_free(&A);
    pl_csc_free(&Lo);
}
END_TEST

/* Row i of S holds exactly the descendants of i (first[i]..i): every
 * ancestor k of every j has first[k] <= j, and the counts agree.  S^T holds
 * the same values.  S (P A P^T) S^T = I with S lower triangular and a
 * positive diagonal, which makes S the inverse Cholesky factor. */
static void check_profile(const pl_csc *A, pl_spinv_ordering ord)
{
    pl_spinv_options opt = {ord, PL_SPINV_SPARSE, 0};
    pl_sparse_inverse *s = sparse_inverse_create(&opt);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s, A, &err), PL_OK);
    const pl_spinv_profile *S = pl_sparse_inverse_S(s);
    const pl_spinv_runs *ST = pl_sparse_inverse_ST(s);
    const int *parent = sparse_inverse_parent(s), *perm = sparse_inverse_perm(s);
    int n = A->ncols;
    ck_assert_ptr_nonnull(S);
    ck_assert_ptr_nonnull(ST);
    int64_t pairs = 0;
    for (int j = 0; j < n; ++j) {
        int64_t q = ST->start[j], r = ST->run_ptr[j];
        int in_run = 0;
        for (int k = j; k != -1; k = parent[k], ++pairs, ++q) {
            ck_assert_int_gt(k, -1);
            ck_assert_int_le(S->first[k], j);
            ck_assert(S->start[k + 1] - S->start[k] == k - S->first[k] + 1);
            /* the run structure of row j of S^T names this k */
            ck_assert_int_lt(r, ST->run_ptr[j + 1]);
            ck_assert_int_eq(ST->run_col[r] + in_run, k);
            if (++in_run == ST->run_len[r]) r++, in_run = 0;
            ck_assert(ST->val[q] == S->val[S->start[k] + (j - S->first[k])]);
        }
        ck_assert_int_eq(q, ST->start[j + 1]);
        ck_assert_int_eq(r, ST->run_ptr[j + 1]);
    }
    ck_assert_int_eq(pairs, S->start[n]);
    ck_assert_int_eq(pairs, sparse_inverse_stats(s)->nnz_S);
    if (n <= 400) {
        double *D = spinv_dense(A), *Sd = calloc((size_t)n * n, sizeof *Sd);
        double *T = calloc((size_t)n * n, sizeof *T);
        for (int i = 0; i < n; ++i) {
            ck_assert(S->val[S->start[i + 1] - 1] > 0.0); /* diagonal, last in the row */
            for (int j = S->first[i]; j <= i; ++j)
                Sd[(size_t)i * n + j] = S->val[S->start[i] + j - S->first[i]]; /* row-major */
        }
        /* T = S Ap with Ap(a, b) = A(perm a, perm b) */
        for (int i = 0; i < n; ++i)
            for (int b = 0; b < n; ++b) {
                double sum = 0.0;
                for (int a = S->first[i]; a <= i; ++a)
                    sum += Sd[(size_t)i * n + a] * D[(size_t)perm[b] * n + perm[a]];
                T[(size_t)i * n + b] = sum;
            }
        double worst = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double sum = 0.0;
                for (int b = S->first[j]; b <= j; ++b) sum += T[(size_t)i * n + b] * Sd[(size_t)j * n + b];
                worst = fmax(worst, fabs(sum - (i == j ? 1.0 : 0.0)));
            }
        ck_assert_msg(worst < 1e-11, "S Ap S^T differs from I by %g", worst);
        free(D), free(Sd), free(T);
    }
    sparse_inverse_destroy(s);
}

START_TEST(test_inverse_rows_are_contiguous_descendant_ranges)
{
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(6, 5, 4, 10.0, &A), 0);
    for (int o = 0; o < 4; ++o) check_profile(&A, (pl_spinv_ordering)o);
    pl_csc_free(&A);
    ck_assert_int_eq(spinv_grid_matrix(16, 8, 8, 10.0, &A), 0);
    check_profile(&A, PL_SPINV_METIS);
    pl_csc_free(&A);
    ck_assert_int_eq(spinv_random_spd(300, 2, 9u, &A), 0);
    check_profile(&A, PL_SPINV_AMD);
    pl_csc_free(&A);
}
END_TEST

START_TEST(test_postorder_check_accepts_postorder_and_refuses_others)
{
    int first[5];
    pl_error err;
    const int post[] = {1, 4, 3, 4, -1}; /* 0 < 1, 2 < 3, both under 4 */
    ck_assert_int_eq(spinv_check_postorder(5, post, first, &err), PL_OK);
    ck_assert_int_eq(first[1], 0);
    ck_assert_int_eq(first[3], 2);
    ck_assert_int_eq(first[4], 0);
    const int mixed[] = {2, 3, 3, -1}; /* 2's descendants {0, 2} skip 1 */
    ck_assert_int_eq(spinv_check_postorder(4, mixed, first, &err), PL_EINTERNAL);
    ck_assert_ptr_nonnull(strstr(err.msg, "postorder"));
    const int down[] = {-1, 0}; /* a parent below its child */
    ck_assert_int_eq(spinv_check_postorder(2, down, first, &err), PL_EINTERNAL);
}
END_TEST

/* One thread and two threads give bitwise the same S and x. */
START_TEST(test_results_do_not_depend_on_thread_count)
{
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(12, 8, 6, 10.0, &A), 0);
    pl_spinv_options o1 = {PL_SPINV_METIS, PL_SPINV_SPARSE, 1}, o2 = {PL_SPINV_METIS, PL_SPINV_SPARSE, 2};
    pl_sparse_inverse *s1 = sparse_inverse_create(&o1), *s2 = sparse_inverse_create(&o2);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s1, &A, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_factor(s2, &A, &err), PL_OK);
    const pl_spinv_profile *S1 = pl_sparse_inverse_S(s1), *S2 = pl_sparse_inverse_S(s2);
    int n = A.ncols;
    ck_assert_int_eq(S1->start[n], S2->start[n]);
    ck_assert_int_eq(memcmp(S1->val, S2->val, (size_t)S1->start[n] * sizeof(double)), 0);
    double *b = spinv_random_block(n, 3, 17u), *x1 = malloc(3 * (size_t)n * sizeof *x1);
    double *x2 = malloc(3 * (size_t)n * sizeof *x2);
    ck_assert_int_eq(sparse_inverse_solve(s1, b, x1, 3, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_solve(s2, b, x2, 3, &err), PL_OK);
    ck_assert_int_eq(memcmp(x1, x2, 3 * (size_t)n * sizeof *x1), 0);
    free(b), free(x1), free(x2);
    sparse_inverse_destroy(s1);
    sparse_inverse_destroy(s2);
    pl_csc_free(&A);
}
END_TEST

START_TEST(test_bad_input_is_refused)
{
    pl_sparse_inverse *s = sparse_inverse_create(NULL);
    pl_error err;
    double b[6] = {1, 2, 3, 4, 5, 6}, x[6];
    ck_assert_int_eq(sparse_inverse_solve(s, b, x, 3, &err), PL_EINPUT);
    /* indefinite: diag(1, -1) */
    int p[] = {0, 1, 2}, i[] = {0, 1};
    double v[] = {1.0, -1.0};
    pl_csc A = {2, 2, p, i, v};
    ck_assert_int_eq(sparse_inverse_factor(s, &A, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "positive definite"));
    ck_assert_int_eq(sparse_inverse_size(s), 0);
    /* not square, and a row index out of range */
    pl_csc R = {3, 2, p, i, v};
    ck_assert_int_eq(sparse_inverse_factor(s, &R, &err), PL_EINPUT);
    int bad_i[] = {0, 5};
    pl_csc B = {2, 2, p, bad_i, v};
    ck_assert_int_eq(sparse_inverse_factor(s, &B, &err), PL_EINPUT);
    /* a good matrix after bad ones works */
    double good[] = {2.0, 4.0};
    pl_csc G = {2, 2, p, i, good};
    ck_assert_int_eq(sparse_inverse_factor(s, &G, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_solve(s, b, x, 3, &err), PL_OK);
    ck_assert(fabs(x[0] - 0.5) < 1e-15 && fabs(x[5] - 1.5) < 1e-15);
    ck_assert_int_eq(sparse_inverse_solve(s, b, x, 0, &err), PL_EINPUT);
    sparse_inverse_destroy(s);
}
END_TEST

/* The grid generator: a Kuhn triangulation has 7 edge directions, so
 * nnz(A) = n + 2 E with E counted per direction. */
START_TEST(test_grid_matrix_has_freudenthal_edges)
{
    int nx = 5, ny = 4, nz = 3, nt = 0;
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(nx, ny, nz, 1.0, &A), 0);
    int E = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1) +
            (nx - 1) * (ny - 1) * nz + (nx - 1) * ny * (nz - 1) + nx * (ny - 1) * (nz - 1) +
            (nx - 1) * (ny - 1) * (nz - 1);
    ck_assert_int_eq(A.p[A.ncols], nx * ny * nz + 2 * E);
    int *t = spinv_grid_tets(nx, ny, nz, &nt);
    ck_assert_int_eq(nt, 6 * 4 * 3 * 2);
    free(t);
    pl_csc_free(&A);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sparse_inverse_solve");
    TCase *tc = tcase_create("solve");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_sparse_solve_equals_cholmod_on_tet_grids);
    tcase_add_test(tc, test_direct_solve_equals_cholmod_on_tet_grids);
    tcase_add_test(tc, test_sparse_solve_equals_cholmod_on_random_spd);
    tcase_add_test(tc, test_lower_triangle_input_gives_same_result);
    tcase_add_test(tc, test_inverse_rows_are_contiguous_descendant_ranges);
    tcase_add_test(tc, test_postorder_check_accepts_postorder_and_refuses_others);
    tcase_add_test(tc, test_results_do_not_depend_on_thread_count);
    tcase_add_test(tc, test_bad_input_is_refused);
    tcase_add_test(tc, test_grid_matrix_has_freudenthal_edges);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
