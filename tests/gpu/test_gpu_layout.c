/* test_gpu_layout.c - the CUDA backend's device layout of S, checked on the
 * CPU: the kernels' work lists are replayed here lane by lane, with the same
 * index arithmetic and masks as spinv_cuda_kernels.cu, and must
 *  - visit every padded value of S exactly once in y = S a, and every
 *    stored value of a column j < n exactly once in z = S^T y;
 *  - reproduce spinv_profile_mult / spinv_runs_mult (1e-13).
 * Runs without a GPU (the GPU checks are tests/gpu/gpu_check). */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparse_inverse.h"
#include "spinv_testmat.h"
#include "../../plugins/sparse_inverse/cuda/spinv_cuda_layout.h"

typedef struct fixture {
    pl_csc A;
    pl_sparse_inverse *s;
    const pl_spinv_profile *S;
    const pl_spinv_runs *ST;
} fixture;

static void fixture_grid(fixture *f, int nx, int ny, int nz)
{
    ck_assert_int_eq(spinv_grid_matrix(nx, ny, nz, 50.0, &f->A), PL_OK);
    pl_spinv_options o = {PL_SPINV_METIS, PL_SPINV_SPARSE, 1};
    f->s = sparse_inverse_create(&o);
    pl_error err;
    ck_assert_ptr_nonnull(f->s);
    ck_assert_int_eq(sparse_inverse_factor(f->s, &f->A, &err), PL_OK);
    f->S = pl_sparse_inverse_S(f->s);
    f->ST = pl_sparse_inverse_ST(f->s);
}

static void fixture_free(fixture *f)
{
    sparse_inverse_destroy(f->s);
    pl_csc_free(&f->A);
}

/* y4 (n x 4) = S a (a: npad x 3) as k_mult_S computes it; visits counts
 * the reads of each padded value. */
static void replay_S(const pl_spinv_cuda_layout *L, const double *val, const double *a, double *y4,
                     int *visits)
{
    const int VC = L->vc, GPB = PL_SPINV_CUDA_BLOCK / VC, G = L->group;
    double *part = calloc((size_t)(L->nparts_S > 0 ? L->nparts_S : 1) * G * 3, sizeof *part);
    ck_assert_ptr_nonnull(part);
    for (int w = 0; w < L->nitems_S; ++w) {
        const pl_spinv_cuda_item *it = &L->items_S[w];
        if (it->kind == PL_SPINV_ITEM_SHORT) {
            for (int lane = 0; lane < it->lo; ++lane) {
                int row = L->short_rows[it->idx + lane];
                const pl_spinv_cuda_rowmeta *m = &L->meta[row];
                double s[3] = {0, 0, 0};
                for (int col = m->f0; col <= m->e; ++col) {
                    visits[m->vbase + col]++;
                    for (int c = 0; c < 3; ++c) s[c] += val[m->vbase + col] * a[3 * (size_t)col + c];
                }
                memcpy(y4 + 4 * (size_t)row, s, sizeof s);
            }
            continue;
        }
        ck_assert_int_eq(it->kind, PL_SPINV_ITEM_ROWS);
        ck_assert(it->pad >= 1 && it->pad <= G);
        const int row0 = it->idx, f0 = L->meta[row0].f0;
        double acc[PL_SPINV_CUDA_GROUP_MAX][3] = {{0}};
        for (int r = 0; r < it->pad; ++r) ck_assert_int_eq(L->meta[row0 + r].f0, f0);
        for (int lane = 0; lane < 32; ++lane)
            for (int g = it->lo * GPB + lane; g < it->hi * GPB; g += 32) {
                int col0 = f0 + g * VC;
                for (int r = 0; r < it->pad; ++r) {
                    const pl_spinv_cuda_rowmeta *m = &L->meta[row0 + r];
                    if (col0 > m->e) continue;
                    for (int k = 0; k < VC; ++k) {
                        int64_t q = m->vbase + col0 + k;
                        visits[q]++;
                        for (int c = 0; c < 3; ++c) acc[r][c] += val[q] * a[3 * (size_t)(col0 + k) + c];
                    }
                }
            }
        for (int r = 0; r < it->pad; ++r)
            memcpy(it->part >= 0 ? part + 3 * ((size_t)it->part * G + r) : y4 + 4 * (size_t)(row0 + r),
                   acc[r], sizeof acc[r]);
    }
    /* the last warp of a split group sums its parts in order */
    for (int w = 0; w < L->nitems_S; ++w) {
        const pl_spinv_cuda_item *it = &L->items_S[w];
        if (it->kind != PL_SPINV_ITEM_ROWS || it->part < 0 || it->part != it->part0) continue;
        for (int r = 0; r < it->pad; ++r) {
            double *y = y4 + 4 * (size_t)(it->idx + r);
            y[0] = y[1] = y[2] = 0.0;
            for (int q = 0; q < it->nparts; ++q)
                for (int c = 0; c < 3; ++c) y[c] += part[3 * ((size_t)(it->part0 + q) * G + r) + c];
        }
    }
    free(part);
}

/* z (n x 3) = S^T y as k_mult_ST computes it. */
static void replay_ST(const pl_spinv_cuda_layout *L, const double *val, const double *y4, double *z,
                      int *visits)
{
    const int VC = L->vc, NV = 3 * VC, n = L->n;
    double *part = calloc((size_t)(L->nparts_ST > 0 ? L->nparts_ST : 1) * 32 * NV, sizeof *part);
    double *tile = calloc((size_t)L->ntiles * 32 * NV, sizeof *tile);
    ck_assert_ptr_nonnull(part);
    ck_assert_ptr_nonnull(tile);
    for (int w = 0; w < L->nitems_ST; ++w) {
        const pl_spinv_cuda_item *it = &L->items_ST[w];
        ck_assert_int_eq(it->kind, PL_SPINV_ITEM_TILE);
        for (int lane = 0; lane < 32; ++lane) {
            int col0 = it->idx * 32 * VC + lane * VC;
            double acc[12] = {0};
            for (int p = it->lo; p < it->hi; ++p) {
                const pl_spinv_cuda_tilerow *m = &L->rowlist[p];
                int i = m->row;
                ck_assert(m->vbase == L->meta[i].vbase && m->f0 == L->meta[i].f0);
                if (!(col0 >= m->f0 && col0 <= (i | (PL_SPINV_CUDA_BLOCK - 1)))) continue;
                for (int k = 0; k < VC; ++k) {
                    int64_t q = m->vbase + col0 + k;
                    if (col0 + k < n) visits[q]++;
                    for (int c = 0; c < 3; ++c) acc[3 * k + c] += val[q] * y4[4 * (size_t)i + c];
                }
            }
            double *dst = it->part >= 0 ? part + ((size_t)it->part * 32 + lane) * NV
                                        : tile + ((size_t)it->idx * 32 + lane) * NV;
            memcpy(dst, acc, (size_t)NV * sizeof *dst);
        }
    }
    for (int w = 0; w < L->nitems_ST; ++w) {
        const pl_spinv_cuda_item *it = &L->items_ST[w];
        if (it->part < 0 || it->part != it->part0) continue;
        for (int lane = 0; lane < 32; ++lane) {
            double *dst = tile + ((size_t)it->idx * 32 + lane) * NV;
            for (int q = 0; q < it->nparts; ++q)
                for (int k = 0; k < NV; ++k)
                    dst[k] += part[((size_t)(it->part0 + q) * 32 + lane) * NV + k];
        }
    }
    for (int t = 0; t < L->ntiles; ++t)
        for (int lane = 0; lane < 32; ++lane)
            for (int k = 0; k < VC; ++k) {
                int j = t * 32 * VC + lane * VC + k;
                if (j >= n) continue;
                for (int c = 0; c < 3; ++c)
                    z[3 * (size_t)j + c] = tile[((size_t)t * 32 + lane) * NV + 3 * k + c];
            }
    free(part);
    free(tile);
}

static double rel_diff(const double *a, const double *b, size_t m)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < m; ++i) num += (a[i] - b[i]) * (a[i] - b[i]), den += b[i] * b[i];
    return sqrt(num / den);
}

/* Replays both kernels for one element size and row grouping and
 * compares with the CPU. */
static void check_layout(const fixture *f, int elem_size, int group, int item_blocks)
{
    pl_spinv_cuda_layout L;
    pl_error err;
    ck_assert_int_eq(
        spinv_cuda_layout_build(f->S, f->ST, elem_size, group, item_blocks, &L, &err), PL_OK);
    int n = L.n;
    ck_assert_int_eq(L.vc, 16 / elem_size);
    ck_assert_int_eq(L.npad % PL_SPINV_CUDA_BLOCK, 0);
    double *val = malloc((size_t)L.nval * sizeof *val);
    int *visits = calloc((size_t)L.nval, sizeof *visits);
    double *a = calloc((size_t)L.npad * 3, sizeof *a), *y4 = calloc((size_t)n * 4, sizeof *y4);
    double *y = malloc((size_t)n * 3 * sizeof *y), *z = malloc((size_t)n * 3 * sizeof *z);
    double *yref = malloc((size_t)n * 3 * sizeof *yref), *zref = malloc((size_t)n * 3 * sizeof *zref);
    int bounds[2] = {0, n};
    ck_assert(val && visits && a && y4 && y && z && yref && zref);
    spinv_cuda_layout_fill_f64(&L, f->S, val);
    srand(7);
    for (int i = 0; i < 3 * n; ++i) a[i] = rand() / (double)RAND_MAX - 0.5;
    replay_S(&L, val, a, y4, visits);
    for (int64_t q = 0; q < L.nval; ++q) ck_assert_int_eq(visits[q], 1);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) y[3 * i + c] = y4[4 * i + c];
    spinv_profile_mult(f->S, a, yref, 3, bounds, 1, 1);
    ck_assert_double_lt(rel_diff(y, yref, (size_t)3 * n), 1e-13);

    /* S^T on y: each stored value of a real column once */
    memset(visits, 0, (size_t)L.nval * sizeof *visits);
    replay_ST(&L, val, y4, z, visits);
    for (int i = 0; i < n; ++i)
        for (int j = L.meta[i].f0; j <= L.meta[i].e && j < n; ++j)
            ck_assert_int_eq(visits[L.meta[i].vbase + j], 1);
    spinv_runs_mult(f->ST, y, zref, 3, bounds, 1, 1);
    ck_assert_double_lt(rel_diff(z, zref, (size_t)3 * n), 1e-13);
    free(val), free(visits), free(a), free(y4), free(y), free(z), free(yref), free(zref);
    spinv_cuda_layout_free(&L);
}

START_TEST(test_layout_replay_matches_cpu_products_small_bar)
{
    fixture f;
    fixture_grid(&f, 12, 5, 5);
    for (int group = 1; group <= 8; group *= 2) {
        check_layout(&f, 8, group, 0);
        check_layout(&f, 4, group, 0);
    }
    check_layout(&f, 4, 4, 8);
    fixture_free(&f);
}
END_TEST

/* 20x8x8: the root row of S spans all 1280 columns, so rows split into
 * several items and tile row lists into several parts. */
START_TEST(test_layout_replay_splits_long_rows_and_tiles)
{
    fixture f;
    fixture_grid(&f, 20, 8, 8);
    pl_spinv_cuda_layout L;
    pl_error err;
    ck_assert_int_eq(spinv_cuda_layout_build(f.S, f.ST, 4, 8, 0, &L, &err), PL_OK);
    ck_assert_int_gt(L.nparts_S, 0);
    ck_assert_int_gt(L.nparts_ST, 0);
    ck_assert_int_gt(L.nshort, 0);
    int grouped = 0; /* separators: chains of rows that share their first column */
    for (int w = 0; w < L.nitems_S; ++w) grouped += L.items_S[w].pad > 1;
    ck_assert_int_gt(grouped, 0);
    /* padding stays small: under 5% more values than nnz(S) */
    ck_assert_double_lt((double)L.nval, 1.05 * (double)f.S->start[f.S->n] + 16.0 * f.S->n);
    spinv_cuda_layout_free(&L);
    ck_assert_int_eq(spinv_cuda_layout_build(f.S, f.ST, 4, 3, 0, &L, &err), PL_EINPUT);
    check_layout(&f, 8, 0, 0);
    check_layout(&f, 4, 0, 0);
    check_layout(&f, 4, 8, 16);
    fixture_free(&f);
}
END_TEST

/* The single-block solve's threshold (spinv_cuda_small_fits): small n,
 * S's padded values within 64 KB, no split row, shared memory within the
 * device's limit (H100: 227 KB a block). */
START_TEST(test_small_solve_threshold)
{
    const int h100 = 232448;
    /* a, y and the tile sums: 12 KB a group of 8 warps, 4 groups */
    ck_assert_uint_eq(spinv_cuda_small_shmem(144, 8), 49152 + (3 * 144 + 4 * 144) * 8);
    ck_assert_uint_eq(spinv_cuda_small_shmem(138, 4), 49152 + (3 * 144 + 4 * 138) * 4);
    fixture f;
    fixture_grid(&f, 12, 4, 3); /* 144 unknowns, about the cable finger's 138 */
    pl_spinv_cuda_layout L;
    pl_error err;
    for (int es = 8; es >= 4; es -= 4) {
        ck_assert_int_eq(spinv_cuda_layout_build(f.S, f.ST, es, 0, 0, &L, &err), PL_OK);
        int bytes_ok = L.nval * es <= PL_SPINV_CUDA_SMALL_BYTES;
        ck_assert_int_eq(spinv_cuda_small_fits(L.n, L.nval, L.nparts_S, es, h100),
                         bytes_ok && L.nparts_S == 0);
        /* a device with too little shared memory a block keeps three launches */
        ck_assert_int_eq(spinv_cuda_small_fits(L.n, L.nval, L.nparts_S, es, 48 * 1024), 0);
        spinv_cuda_layout_free(&L);
    }
    fixture_free(&f);
    ck_assert_int_eq(spinv_cuda_small_fits(144, 5376, 0, 8, h100), 1);     /* 43 KB */
    ck_assert_int_eq(spinv_cuda_small_fits(256, 13712, 0, 8, h100), 0);    /* 110 KB */
    ck_assert_int_eq(spinv_cuda_small_fits(256, 13712, 0, 4, h100), 1);    /* 55 KB */
    ck_assert_int_eq(spinv_cuda_small_fits(144, 5376, 1, 8, h100), 0);     /* a split row */
    ck_assert_int_eq(spinv_cuda_small_fits(PL_SPINV_CUDA_SMALL_N + 1, 100, 0, 8, h100), 0);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("gpu_layout");
    TCase *tc = tcase_create("layout");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_layout_replay_matches_cpu_products_small_bar);
    tcase_add_test(tc, test_layout_replay_splits_long_rows_and_tiles);
    tcase_add_test(tc, test_small_solve_threshold);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
