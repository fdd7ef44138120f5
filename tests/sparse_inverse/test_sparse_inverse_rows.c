/* test_sparse_inverse_rows.c - Y = S P H^T gives H A^-1 H^T = Y^T Y, and
 * inverse_diagonal gives diag(A^-1), both against dense references built
 * from independent CHOLMOD solves, in sparse and direct modes. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparse_inverse.h"
#include "spinv_test_util.h"
#include "spinv_testmat.h"

/* m random rows over n unknowns: row r has r % 4 nonzeros (row 0 empty),
 * one row repeats a column (duplicates add up). */
static void random_rows(int n, int m, unsigned seed, pl_csr *H)
{
    H->nrows = m;
    H->ncols = n;
    H->p = malloc(((size_t)m + 1) * sizeof *H->p);
    H->j = malloc((size_t)(4 * m + 1) * sizeof *H->j);
    H->x = malloc((size_t)(4 * m + 1) * sizeof *H->x);
    double *v = spinv_random_block(4 * m + 1, 2, seed);
    int w = 0;
    for (int r = 0; r < m; ++r) {
        H->p[r] = w;
        for (int t = 0; t < r % 4; ++t) {
            H->j[w] = (int)((v[2 * w] + 1.0) * 0.5 * (n - 1));
            H->x[w] = v[2 * w + 1];
            w++;
        }
        if (r == 3) H->j[w - 1] = H->j[w - 2];
    }
    H->p[m] = w;
    free(v);
}

/* W_ref = H A^-1 H^T from X = A^-1 H^T (dense, m x m row-major). */
static double *reference_delassus(const pl_csc *A, const pl_csr *H)
{
    int n = A->ncols, m = H->nrows;
    double *Ht = calloc((size_t)n * m, sizeof *Ht), *X = malloc((size_t)n * m * sizeof *X);
    double *W = calloc((size_t)m * m, sizeof *W);
    for (int r = 0; r < m; ++r)
        for (int q = H->p[r]; q < H->p[r + 1]; ++q) Ht[(size_t)H->j[q] * m + r] += H->x[q];
    ck_assert_int_eq(spinv_ref_solve(A, Ht, X, m), 0);
    for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b)
            for (int q = H->p[a]; q < H->p[a + 1]; ++q)
                W[(size_t)a * m + b] += H->x[q] * X[(size_t)H->j[q] * m + b];
    free(Ht);
    free(X);
    return W;
}

static double *gram(const pl_csc *Y)
{
    int n = Y->nrows, m = Y->ncols;
    double *W = calloc((size_t)m * m, sizeof *W), *col = calloc((size_t)n, sizeof *col);
    for (int a = 0; a < m; ++a) {
        for (int q = Y->p[a]; q < Y->p[a + 1]; ++q) col[Y->i[q]] = Y->x[q];
        for (int b = 0; b < m; ++b)
            for (int q = Y->p[b]; q < Y->p[b + 1]; ++q) W[(size_t)a * m + b] += col[Y->i[q]] * Y->x[q];
        for (int q = Y->p[a]; q < Y->p[a + 1]; ++q) col[Y->i[q]] = 0.0;
    }
    free(col);
    return W;
}

static void check_rows(const pl_csc *A, pl_spinv_ordering ord, pl_spinv_mode mode, int m)
{
    pl_spinv_options opt = {ord, mode, 0};
    pl_sparse_inverse *s = sparse_inverse_create(&opt);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s, A, &err), PL_OK);
    pl_csr H;
    random_rows(A->ncols, m, 23u, &H);
    pl_csc Y;
    ck_assert_int_eq(sparse_inverse_apply_inverse_to_rows(s, &H, &Y, &err), PL_OK);
    ck_assert_int_eq(Y.nrows, A->ncols);
    ck_assert_int_eq(Y.ncols, m);
    ck_assert_int_eq(Y.p[1] - Y.p[0], 0); /* the empty row */
    for (int r = 0; r < m; ++r)
        for (int q = Y.p[r]; q < Y.p[r + 1]; ++q) {
            ck_assert(Y.i[q] >= 0 && Y.i[q] < A->ncols);
            if (q > Y.p[r]) ck_assert_int_lt(Y.i[q - 1], Y.i[q]);
        }
    double *W = gram(&Y), *Wref = reference_delassus(A, &H);
    double d = spinv_rel_diff(W, Wref, (size_t)m * m);
    ck_assert_msg(d < 1e-10, "%s/%s: Y^T Y differs from H A^-1 H^T by %g",
                  spinv_ordering_name(ord), spinv_mode_name(mode), d);
    free(W);
    free(Wref);
    pl_csc_free(&Y);
    pl_csr_free(&H);
    sparse_inverse_destroy(s);
}

START_TEST(test_rows_gram_equals_delassus_on_tet_grid)
{
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(7, 5, 4, 10.0, &A), 0);
    for (int o = 0; o < 4; ++o) {
        check_rows(&A, (pl_spinv_ordering)o, PL_SPINV_SPARSE, 13);
        check_rows(&A, (pl_spinv_ordering)o, PL_SPINV_DIRECT, 13);
    }
    pl_csc_free(&A);
}
END_TEST

START_TEST(test_rows_gram_equals_delassus_on_random_spd)
{
    pl_csc A;
    ck_assert_int_eq(spinv_random_spd(250, 3, 5u, &A), 0);
    check_rows(&A, PL_SPINV_METIS, PL_SPINV_SPARSE, 20);
    check_rows(&A, PL_SPINV_AMD, PL_SPINV_DIRECT, 20);
    pl_csc_free(&A);
}
END_TEST

/* Sparse and direct modes give the same Y, entry by entry (same pattern). */
START_TEST(test_rows_sparse_and_direct_agree)
{
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(10, 6, 5, 10.0, &A), 0);
    pl_spinv_options os = {PL_SPINV_NESDIS, PL_SPINV_SPARSE, 0}, od = {PL_SPINV_NESDIS, PL_SPINV_DIRECT, 0};
    pl_sparse_inverse *s = sparse_inverse_create(&os), *d = sparse_inverse_create(&od);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s, &A, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_factor(d, &A, &err), PL_OK);
    pl_csr H;
    random_rows(A.ncols, 40, 99u, &H);
    pl_csc Ys, Yd;
    ck_assert_int_eq(sparse_inverse_apply_inverse_to_rows(s, &H, &Ys, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_apply_inverse_to_rows(d, &H, &Yd, &err), PL_OK);
    ck_assert_int_eq(Ys.p[40], Yd.p[40]);
    ck_assert_int_eq(memcmp(Ys.p, Yd.p, 41 * sizeof(int)), 0);
    ck_assert_int_eq(memcmp(Ys.i, Yd.i, (size_t)Ys.p[40] * sizeof(int)), 0);
    ck_assert(spinv_rel_diff(Ys.x, Yd.x, (size_t)Ys.p[40]) < 1e-12);
    /* and the global steps agree */
    int n = A.ncols;
    double *b = spinv_random_block(n, 3, 4u), *xs = malloc(3 * (size_t)n * sizeof *xs);
    double *xd = malloc(3 * (size_t)n * sizeof *xd);
    ck_assert_int_eq(sparse_inverse_solve(s, b, xs, 3, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_solve(d, b, xd, 3, &err), PL_OK);
    ck_assert(spinv_rel_diff(xs, xd, 3 * (size_t)n) < 1e-12);
    free(b), free(xs), free(xd);
    pl_csc_free(&Ys);
    pl_csc_free(&Yd);
    pl_csr_free(&H);
    sparse_inverse_destroy(s);
    sparse_inverse_destroy(d);
    pl_csc_free(&A);
}
END_TEST

START_TEST(test_rows_with_wrong_width_are_refused)
{
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(3, 3, 3, 1.0, &A), 0);
    pl_sparse_inverse *s = sparse_inverse_create(NULL);
    pl_error err;
    pl_csr H;
    random_rows(A.ncols + 1, 3, 1u, &H);
    pl_csc Y;
    ck_assert_int_eq(sparse_inverse_apply_inverse_to_rows(s, &H, &Y, &err), PL_EINPUT);
    ck_assert_int_eq(sparse_inverse_factor(s, &A, &err), PL_OK);
    ck_assert_int_eq(sparse_inverse_apply_inverse_to_rows(s, &H, &Y, &err), PL_EINPUT);
    ck_assert_ptr_null(Y.p);
    pl_csr_free(&H);
    sparse_inverse_destroy(s);
    pl_csc_free(&A);
}
END_TEST

/* diag[i] = e_i^T A^-1 e_i from n independent solves. */
static void check_diagonal(const pl_csc *A, pl_spinv_ordering ord, pl_spinv_mode mode)
{
    int n = A->ncols;
    pl_spinv_options opt = {ord, mode, 0};
    pl_sparse_inverse *s = sparse_inverse_create(&opt);
    pl_error err;
    ck_assert_int_eq(sparse_inverse_factor(s, A, &err), PL_OK);
    double *diag = malloc((size_t)n * sizeof *diag), *E = calloc((size_t)n * n, sizeof *E);
    double *X = malloc((size_t)n * n * sizeof *X), *ref = malloc((size_t)n * sizeof *ref);
    for (int i = 0; i < n; ++i) E[(size_t)i * n + i] = 1.0;
    ck_assert_int_eq(spinv_ref_solve(A, E, X, n), 0);
    for (int i = 0; i < n; ++i) ref[i] = X[(size_t)i * n + i];
    ck_assert_int_eq(sparse_inverse_inverse_diagonal(s, diag, &err), PL_OK);
    double d = spinv_rel_diff(diag, ref, (size_t)n);
    ck_assert_msg(d < 1e-12, "%s/%s: diag(A^-1) differs by %g", spinv_ordering_name(ord),
                  spinv_mode_name(mode), d);
    free(diag), free(E), free(X), free(ref);
    sparse_inverse_destroy(s);
}

START_TEST(test_inverse_diagonal_equals_solves)
{
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(8, 5, 4, 10.0, &A), 0);
    for (int o = 0; o < 4; ++o) {
        check_diagonal(&A, (pl_spinv_ordering)o, PL_SPINV_SPARSE);
        check_diagonal(&A, (pl_spinv_ordering)o, PL_SPINV_DIRECT);
    }
    pl_csc_free(&A);
    ck_assert_int_eq(spinv_random_spd(200, 3, 8u, &A), 0);
    check_diagonal(&A, PL_SPINV_METIS, PL_SPINV_SPARSE);
    pl_csc_free(&A);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sparse_inverse_rows");
    TCase *tc = tcase_create("rows");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_rows_gram_equals_delassus_on_tet_grid);
    tcase_add_test(tc, test_rows_gram_equals_delassus_on_random_spd);
    tcase_add_test(tc, test_rows_sparse_and_direct_agree);
    tcase_add_test(tc, test_rows_with_wrong_width_are_refused);
    tcase_add_test(tc, test_inverse_diagonal_equals_solves);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
