/* test_ncp_contact_parts.c - the scene side of Algorithm 4 without a scene:
 * rows of a step over the unknowns (active rows, merged entries, offsets),
 * the Delassus operator W = H A^-1 H^T against a dense reference (explicit
 * Y^T Y, matrix-free products, the exact diagonal by its three routes, the
 * mass diagonal), and the warm-start matching rule.  The global solver is a
 * fake component holding a dense A: solve = A^-1 b, rows = L^-1 H^T. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact.h"
#include "ncp_test_util.h"
#include "pliant/plugin.h"

/* ---- a dense global solver ------------------------------------------------ */
typedef struct fake_solver {
    pl_component base;
    int n;
    double *L;                /* n x n lower Cholesky factor of A */
    double *Ainv;             /* n x n */
} fake_solver;

static int fake_solve(const pl_component *c, const pl_buffer *b, pl_buffer *x, pl_error *err)
{
    const fake_solver *f = (const fake_solver *)c;
    int n = f->n, k = (int)b->cols;
    const double *bd = b->data;
    double *out = malloc(sizeof(double) * (size_t)n * (size_t)k);
    (void)err;
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < k; ++a) {
            double s = 0.0;
            for (int j = 0; j < n; ++j) s += f->Ainv[i * n + j] * bd[j * k + a];
            out[i * k + a] = s;
        }
    memcpy(x->data, out, sizeof(double) * (size_t)n * (size_t)k);
    free(out);
    return PL_OK;
}

/* Y = L^-1 H^T, dense columns stored as CSC (zeros kept). */
static int fake_rows(const pl_component *c, const pl_csr *H, pl_csc *Y, pl_error *err)
{
    const fake_solver *f = (const fake_solver *)c;
    int n = f->n, m = H->nrows;
    (void)err;
    Y->nrows = n;
    Y->ncols = m;
    Y->p = malloc(sizeof(int) * (size_t)(m + 1));
    Y->i = malloc(sizeof(int) * (size_t)(n * m + 1));
    Y->x = malloc(sizeof(double) * (size_t)(n * m + 1));
    double *h = malloc(sizeof(double) * (size_t)n);
    for (int r = 0; r < m; ++r) {
        memset(h, 0, sizeof(double) * (size_t)n);
        for (int q = H->p[r]; q < H->p[r + 1]; ++q) h[H->j[q]] += H->x[q];
        Y->p[r] = r * n;
        for (int i = 0; i < n; ++i) {
            double s = h[i];
            for (int k = 0; k < i; ++k) s -= f->L[i * n + k] * Y->x[r * n + k];
            Y->x[r * n + i] = s / f->L[i * n + i];
            Y->i[r * n + i] = i;
        }
    }
    Y->p[m] = m * n;
    free(h);
    return PL_OK;
}

static int fake_diag(const pl_component *c, double *d, pl_error *err)
{
    const fake_solver *f = (const fake_solver *)c;
    (void)err;
    for (int i = 0; i < f->n; ++i) d[i] = f->Ainv[i * f->n + i];
    return PL_OK;
}

static pl_global_solver_ops fake_ops = {.version = PL_GLOBAL_SOLVER_OPS_VERSION,
                                        .solve = fake_solve,
                                        .apply_inverse_to_rows = fake_rows,
                                        .inverse_diagonal = fake_diag};
static const pl_type fake_type = {.abi_version = PL_ABI_VERSION, .name = "FakeSolver",
                                  .roles = {[PL_ROLE_GLOBAL_SOLVER] = &fake_ops}};

static void fake_make(fake_solver *f, int n, test_rng *g)
{
    memset(f, 0, sizeof *f);
    f->base.type = &fake_type;
    f->n = n;
    double *A = malloc(sizeof(double) * (size_t)(n * n));
    random_spd(g, n, 0.5, A);
    f->L = calloc((size_t)(n * n), sizeof(double));
    for (int j = 0; j < n; ++j) {
        double s = A[j * n + j];
        for (int k = 0; k < j; ++k) s -= f->L[j * n + k] * f->L[j * n + k];
        f->L[j * n + j] = sqrt(s);
        for (int i = j + 1; i < n; ++i) {
            double t = A[i * n + j];
            for (int k = 0; k < j; ++k) t -= f->L[i * n + k] * f->L[j * n + k];
            f->L[i * n + j] = t / f->L[j * n + j];
        }
    }
    f->Ainv = malloc(sizeof(double) * (size_t)(n * n));
    double *e = calloc((size_t)n, sizeof(double));
    for (int j = 0; j < n; ++j) {
        e[j] = 1.0;
        dense_cholesky_solve(n, A, e, f->Ainv + j * n); /* symmetric: column = row */
        e[j] = 0.0;
    }
    free(e);
    free(A);
}

static void fake_free(fake_solver *f)
{
    free(f->L);
    free(f->Ainv);
}

/* ---- a system of 15 vertices, 3 of them prescribed ------------------------ */
enum { NV = 15, NF = 12 };
static const int PRESCRIBED[3] = {2, 7, 11};

typedef struct problem {
    fake_solver solver;
    int free_index[NV], free_vertex[NF];
    double mass[NV];
    pl_system sys;
    pl_rows rows;
    double qt[3 * NV];
} problem;

static int add_row(pl_rows *r, pl_row_kind kind, int nv, const int *v, const double *c, double d)
{
    int k = pl_rows_begin(r, kind, NULL);
    for (int a = 0; a < nv; ++a) pl_rows_add(r, v[a], c[3 * a], c[3 * a + 1], c[3 * a + 2]);
    r->d[k] = d;
    return k;
}

static void problem_make(problem *p, unsigned seed)
{
    test_rng g = {seed};
    fake_make(&p->solver, NF, &g);
    for (int v = 0, f = 0; v < NV; ++v) {
        int pre = v == PRESCRIBED[0] || v == PRESCRIBED[1] || v == PRESCRIBED[2];
        p->free_index[v] = pre ? -1 : f;
        if (!pre) p->free_vertex[f++] = v;
        p->mass[v] = rng_range(&g, 0.5, 2.0);
        for (int k = 0; k < 3; ++k) p->qt[3 * v + k] = rng_range(&g, -1, 1);
    }
    p->sys = (pl_system){NV, NF, p->free_index, p->free_vertex, 0.01, &p->solver.base, p->mass};
    pl_rows_init(&p->rows);
    pl_rows *r = &p->rows;
    /* 0: normal on one vertex, with two friction rows (1, 2) */
    int n0 = add_row(r, PL_ROW_NORMAL, 1, (int[]){0}, (double[]){0, 1, 0}, 0.1);
    r->mu[n0] = 0.4;
    for (int t = 0; t < 2; ++t) {
        int f = add_row(r, PL_ROW_FRICTION, 1, (int[]){0}, t ? (double[]){0, 0, 1} : (double[]){1, 0, 0}, 0.3);
        r->pair[f] = n0;
    }
    r->pair[n0] = 1;
    /* 3: two-body normal (c on 3, -c on 5), one friction row (4) */
    double c[3] = {0.6, 0.0, 0.8};
    int n3 = add_row(r, PL_ROW_NORMAL, 2, (int[]){3, 5}, (double[]){c[0], c[1], c[2], -c[0], -c[1], -c[2]}, -0.2);
    r->mu[n3] = 0.2;
    int f4 = add_row(r, PL_ROW_FRICTION, 2, (int[]){3, 5}, (double[]){0.8, 0, -0.6, -0.8, 0, 0.6}, 0.0);
    r->pair[f4] = n3;
    /* 5: a triangle point with a prescribed vertex and a repeated vertex */
    add_row(r, PL_ROW_BILATERAL, 4, (int[]){6, 7, 8, 6},
            (double[]){0.2, 0.1, 0.3, 0.3, 0.3, 0.3, 0.5, -0.2, 0.1, 0.1, 0.4, 0.0}, 0.05);
    r->compliance[5] = 1e-3;
    /* 6: bounded on prescribed vertices only: inactive */
    add_row(r, PL_ROW_BOUNDED, 2, (int[]){2, 11}, (double[]){0, 1, 0, 0, -1, 0}, 0.0);
    /* 7: normal on a prescribed vertex with its friction row 8: both inactive */
    int n7 = add_row(r, PL_ROW_NORMAL, 1, (int[]){7}, (double[]){1, 0, 0}, 0.0);
    int f8 = add_row(r, PL_ROW_FRICTION, 1, (int[]){7}, (double[]){0, 1, 0}, 0.0);
    r->pair[f8] = n7;
    /* 9: bounded on two free vertices and a prescribed one */
    int b9 = add_row(r, PL_ROW_BOUNDED, 3, (int[]){9, 10, 11}, (double[]){0, 0, 1, 0, 0, 1, 0, 0, -1}, 0.0);
    r->lo[b9] = 0.0;
    r->hi[b9] = 2.0;
    /* 10: entries that cancel on vertex 12 (it drops out), one left on 13 */
    add_row(r, PL_ROW_BILATERAL, 3, (int[]){12, 13, 12}, (double[]){1, 0, 0, 0, 1, 0, -1, 0, 0}, 0.0);
}

static void problem_free(problem *p)
{
    pl_rows_free(&p->rows);
    fake_free(&p->solver);
}

/* Dense W over the active rows: H_f A^-1 H_f^T summed over coordinates. */
static double *dense_w(const problem *p, const pl_ncpc_rows *r)
{
    int m = r->m;
    double *H = calloc((size_t)(3 * m * NF), sizeof(double)), *W = calloc((size_t)(m * m), sizeof(double));
    for (int j = 0; j < m; ++j) {
        int i = r->full[j];
        for (int e = p->rows.start[i]; e < p->rows.start[i + 1]; ++e) {
            int f = p->free_index[p->rows.vertex[e]];
            if (f < 0) continue;
            for (int k = 0; k < 3; ++k) H[(k * m + j) * NF + f] += p->rows.coef[3 * e + k];
        }
    }
    const double *Ai = p->solver.Ainv;
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < m; ++a)
            for (int b = 0; b < m; ++b) {
                double s = 0.0;
                for (int u = 0; u < NF; ++u)
                    for (int v = 0; v < NF; ++v) s += H[(k * m + a) * NF + u] * Ai[u * NF + v] * H[(k * m + b) * NF + v];
                W[a * m + b] += s;
            }
    free(H);
    return W;
}

START_TEST(active_rows_offsets_and_values)
{
    problem p;
    problem_make(&p, 11);
    pl_ncpc_rows r;
    pl_error err;
    ncpc_rows_init(&r);
    ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_OK);
    /* rows 6 (prescribed only), 7 (prescribed only) and 8 (its normal is out) are left out */
    ck_assert_int_eq(r.nall, 11);
    ck_assert_int_eq(r.m, 8);
    int expect_full[8] = {0, 1, 2, 3, 4, 5, 9, 10};
    for (int j = 0; j < 8; ++j) ck_assert_int_eq(r.full[j], expect_full[j]);
    ck_assert_int_eq(r.sub[6], -1);
    ck_assert_int_eq(r.sub[8], -1);
    ck_assert_int_eq(r.pair[1], 0);
    ck_assert_int_eq(r.pair[4], 3);
    /* vertex 6 appears twice in row 5: merged into one free entry */
    ck_assert_int_eq(r.fstart[6] - r.fstart[5], 2);
    ck_assert_int_eq(r.pstart[6] - r.pstart[5], 1);
    /* row 10: the entries on vertex 12 cancel */
    ck_assert_int_eq(r.fstart[8] - r.fstart[7], 1);
    ck_assert_int_eq(r.fcol[r.fstart[7]], p.free_index[13]);
    /* friction offsets: H_f q_t + h d_f */
    ck_assert_double_eq_tol(r.offset[1], p.qt[0] + 0.01 * 0.3, 1e-15);
    ck_assert_double_eq(r.offset[0], 0.1);
    /* delta over the unknowns + prescribed, and over all vertices */
    double q[3 * NV], x[3 * NF], d1[8], d2[8];
    test_rng g = {5};
    for (int i = 0; i < 3 * NV; ++i) q[i] = rng_range(&g, -1, 1);
    for (int f = 0; f < NF; ++f)
        for (int k = 0; k < 3; ++k) x[3 * f + k] = q[3 * p.free_vertex[f] + k];
    ncpc_rows_delta(&r, x, q, d1);
    ncpc_rows_delta_all(&r, p.free_vertex, q, d2);
    for (int j = 0; j < 8; ++j) {
        double ref = pl_rows_dot(&p.rows, r.full[j], q) - r.offset[j];
        ck_assert_double_eq_tol(d1[j], ref, 1e-14);
        ck_assert_double_eq_tol(d2[j], ref, 1e-14);
    }
    ncpc_rows_free(&r);
    problem_free(&p);
}
END_TEST

START_TEST(delassus_matches_the_dense_reference)
{
    for (unsigned seed = 1; seed <= 5; ++seed) {
        problem p;
        problem_make(&p, seed);
        pl_ncpc_rows r;
        pl_error err;
        ncpc_rows_init(&r);
        ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_OK);
        int m = r.m;
        double *Wref = dense_w(&p, &r), scale = 0.0;
        for (int i = 0; i < m * m; ++i) scale = fmax(scale, fabs(Wref[i]));
        /* explicit: Y^T Y, bitwise symmetric */
        pl_ncpc_delassus D;
        ncpc_delassus_init(&D);
        ck_assert_int_eq(ncpc_delassus_explicit(&D, &p.sys, &r, &err), PL_OK);
        for (int a = 0; a < m; ++a)
            for (int b = 0; b < m; ++b) {
                ck_assert_double_le(fabs(D.W[a * m + b] - Wref[a * m + b]), 1e-12 * scale);
                ck_assert(D.W[a * m + b] == D.W[b * m + a]);
            }
        /* matrix-free: products and the diagonal by each route */
        double inv[NF];
        fake_diag(&p.solver.base, inv, &err);
        for (int route = 0; route < 3; ++route) {
            fake_ops.apply_inverse_to_rows = route == 2 ? NULL : fake_rows;
            pl_ncpc_delassus M;
            ncpc_delassus_init(&M);
            ck_assert_int_eq(ncpc_delassus_matrix_free(&M, &p.sys, &r, route == 1 ? NULL : inv, &err), PL_OK);
            for (int j = 0; j < m; ++j) ck_assert_double_le(fabs(M.diag[j] - Wref[j * m + j]), 1e-12 * scale);
            double xv[16], y[16];
            test_rng g = {seed + 100};
            for (int j = 0; j < m; ++j) xv[j] = rng_range(&g, -1, 1);
            pl_ncp_operator op = ncpc_delassus_operator(&M);
            ck_assert_ptr_null(op.dense);
            ck_assert_int_eq(ncp_operator_apply(&op, xv, y), PL_OK);
            for (int a = 0; a < m; ++a) {
                double s = 0.0;
                for (int b = 0; b < m; ++b) s += Wref[a * m + b] * xv[b];
                ck_assert_double_le(fabs(y[a] - s), 1e-12 * scale * m);
            }
            ncpc_delassus_free(&M);
        }
        fake_ops.apply_inverse_to_rows = fake_rows;
        /* mass diagonal: sum |c_a|^2 / m_a over the merged free entries */
        double dm[16];
        ck_assert_int_eq(ncpc_mass_diagonal(&r, &p.sys, dm, &err), PL_OK);
        /* row 0: (0 1 0) on vertex 0; row 5: merged vertex 6 = (0.3 0.5 0.3) and vertex 8 */
        ck_assert_double_eq_tol(dm[0], 1.0 / p.mass[0], 1e-15);
        double c6[3] = {0.3, 0.5, 0.3}, c8[3] = {0.5, -0.2, 0.1};
        double ref5 = (c6[0] * c6[0] + c6[1] * c6[1] + c6[2] * c6[2]) / p.mass[6] +
                      (c8[0] * c8[0] + c8[1] * c8[1] + c8[2] * c8[2]) / p.mass[8];
        ck_assert_double_eq_tol(dm[5], ref5, 1e-15);
        free(Wref);
        ncpc_delassus_free(&D);
        ncpc_rows_free(&r);
        problem_free(&p);
    }
}
END_TEST

/* delassus=auto on the host counts the exact work of W = Y^T Y (the sum
 * over the rows of Y of nnz^2, here from the fake solver's Y) and builds W
 * only within its budget: at the budget W is the explicit one bitwise, one
 * below it the operator is matrix-free with the diagonal of
 * ncpc_delassus_matrix_free bitwise (issue 16 item 5: the estimate from
 * the average column of S let W cost 2-3x the matrix-free step). */
START_TEST(delassus_auto_counts_its_work)
{
    for (unsigned seed = 1; seed <= 5; ++seed) {
        problem p;
        problem_make(&p, seed);
        pl_ncpc_rows r;
        pl_error err;
        ncpc_rows_init(&r);
        ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_OK);
        int m = r.m;
        pl_csr H;
        pl_csc Y;
        ck_assert_int_eq(ncpc_rows_scalar_csr(&r, NF, NULL, m, &H, &err), PL_OK);
        ck_assert_int_eq(fake_rows(&p.solver.base, &H, &Y, &err), PL_OK);
        double work = 0.0;
        for (int k = 0; k < 3; ++k)
            for (int row = 0; row < NF; ++row) {
                int c = 0;
                for (int j = 0; j < m; ++j)
                    for (int q = Y.p[k * m + j]; q < Y.p[k * m + j + 1]; ++q) c += Y.i[q] == row;
                work += (double)c * c;
            }
        ck_assert_double_gt(work, 0.0);
        pl_ncpc_delassus E, A, M, F;
        ncpc_delassus_init(&E);
        ncpc_delassus_init(&A);
        ncpc_delassus_init(&M);
        ncpc_delassus_init(&F);
        double inv[NF];
        fake_diag(&p.solver.base, inv, &err);
        ck_assert_int_eq(ncpc_delassus_explicit(&E, &p.sys, &r, &err), PL_OK);
        ck_assert_double_eq(E.work, work);
        ck_assert_int_eq(ncpc_delassus_auto(&A, &p.sys, &r, work, inv, &err), PL_OK);
        ck_assert_double_eq(A.work, work);
        ck_assert_ptr_nonnull(ncpc_delassus_operator(&A).dense);
        ck_assert_int_eq(memcmp(A.W, E.W, sizeof(double) * (size_t)m * (size_t)m), 0);
        ck_assert_int_eq(ncpc_delassus_matrix_free(&M, &p.sys, &r, inv, &err), PL_OK);
        ck_assert_int_eq(ncpc_delassus_auto(&F, &p.sys, &r, work - 1.0, inv, &err), PL_OK);
        ck_assert_double_eq(F.work, work);
        ck_assert_ptr_null(ncpc_delassus_operator(&F).dense);
        ck_assert_int_eq(memcmp(F.diag, M.diag, sizeof(double) * (size_t)m), 0);
        ncpc_delassus_free(&E);
        ncpc_delassus_free(&A);
        ncpc_delassus_free(&M);
        ncpc_delassus_free(&F);
        pl_csr_free(&H);
        pl_csc_free(&Y);
        ncpc_rows_free(&r);
        problem_free(&p);
    }
}
END_TEST

static pl_ncpc_key key(uint64_t owner, pl_row_kind kind, int vertex, int pair, double x, double y, double z,
                       double lambda)
{
    pl_ncpc_key k;
    memset(&k, 0, sizeof k);
    double n = sqrt(x * x + y * y + z * z);
    k.owner = owner;
    k.kind = (int32_t)kind;
    k.vertex = vertex;
    k.pair = pair;
    k.dir[0] = x / n;
    k.dir[1] = y / n;
    k.dir[2] = z / n;
    k.lambda = lambda;
    return k;
}

START_TEST(warm_start_matching_rule)
{
    const double deg = 3.14159265358979323846 / 180, d20 = 20 * deg, d40 = 40 * deg;
    /* the old step: a contact on vertex 4 (normal 0, friction 1 and 2 along
     * x and z), pins x and y on vertex 9, a bounded row on vertex 3, a
     * normal of another owner on vertex 4 */
    pl_ncpc_key old[7] = {
        key(7, PL_ROW_NORMAL, 4, -1, 0, 1, 0, 5.0),
        key(7, PL_ROW_FRICTION, 4, 0, 1, 0, 0, 1.0),
        key(7, PL_ROW_FRICTION, 4, 0, 0, 0, 1, -2.0),
        key(7, PL_ROW_BILATERAL, 9, -1, 1, 0, 0, 3.0),
        key(7, PL_ROW_BILATERAL, 9, -1, 0, 1, 0, 4.0),
        key(7, PL_ROW_BOUNDED, 3, -1, 0, 0, 1, 6.0),
        key(8, PL_ROW_NORMAL, 4, -1, 0, 1, 0, 9.0),
    };
    /* the new step, in another order: the contact's normal turned by 20
     * degrees, its tangents by 90 degrees about y; the pins swapped; the
     * bounded row turned by 40 degrees (no match); a new contact */
    pl_ncpc_key now[9] = {
        key(7, PL_ROW_BILATERAL, 9, -1, 0, 1, 0, 0),
        key(7, PL_ROW_BILATERAL, 9, -1, 1, 0, 0, 0),
        key(7, PL_ROW_BOUNDED, 3, -1, 0, sin(d40), cos(d40), 0),
        key(7, PL_ROW_FRICTION, 4, 4, 0, 0, 1, 0),
        key(7, PL_ROW_NORMAL, 4, -1, sin(d20), cos(d20), 0, 0),
        key(7, PL_ROW_FRICTION, 4, 4, -1, 0, 0, 0),
        key(7, PL_ROW_NORMAL, 5, -1, 0, 1, 0, 0),
        key(7, PL_ROW_FRICTION, 5, 6, 1, 0, 0, 0),
        key(8, PL_ROW_NORMAL, 4, -1, 0, 1, 0, 0),
    };
    double lambda[9];
    pl_error err;
    int got = ncpc_warm_start(now, 9, old, 7, lambda, &err);
    ck_assert_int_eq(got, 6);
    ck_assert_double_eq(lambda[0], 4.0);
    ck_assert_double_eq(lambda[1], 3.0);
    ck_assert_double_eq(lambda[2], 0.0);
    /* old friction force (1, 0, -2): on z -> -2, on -x -> -1 */
    ck_assert_double_eq_tol(lambda[3], -2.0, 1e-15);
    ck_assert_double_eq(lambda[4], 5.0);
    ck_assert_double_eq_tol(lambda[5], -1.0, 1e-15);
    ck_assert_double_eq(lambda[6], 0.0);
    ck_assert_double_eq(lambda[7], 0.0);
    ck_assert_double_eq(lambda[8], 9.0);
    /* nothing old: all zero */
    ck_assert_int_eq(ncpc_warm_start(now, 9, old, 0, lambda, &err), 0);
    for (int j = 0; j < 9; ++j) ck_assert_double_eq(lambda[j], 0.0);
}
END_TEST

/* The rule by brute force: each row in turn scans every old record in the
 * old order (the matcher's hash chains must meet the same candidates in
 * the same order, whatever the buckets). */
static int brute_match(const pl_ncpc_key *now, int m, const pl_ncpc_key *old, int nold, double *lambda)
{
    int used[512] = {0}, matched = 0;
    for (int j = 0; j < m; ++j) {
        int best = -1;
        double best_dot = 0.8660254037844386;
        lambda[j] = 0.0;
        for (int a = 0; a < nold; ++a) {
            if (old[a].owner != now[j].owner || old[a].kind != now[j].kind || old[a].vertex != now[j].vertex ||
                used[a])
                continue;
            double d = old[a].dir[0] * now[j].dir[0] + old[a].dir[1] * now[j].dir[1] + old[a].dir[2] * now[j].dir[2];
            if (d > best_dot || (best < 0 && d >= best_dot)) best = a, best_dot = d;
        }
        if (best >= 0) used[best] = 1, lambda[j] = old[best].lambda, ++matched;
    }
    return matched;
}

START_TEST(warm_start_many_rows_as_brute_force)
{
    /* 500 old and 400 new rows over 2 owners, 2 kinds, 40 vertices and 3
     * directions (one within 30 degrees of another): many rows share a key,
     * many tie on the direction */
    enum { NOLD = 500, NNEW = 400 };
    static pl_ncpc_key old[NOLD], now[NNEW];
    const double dirs[3][3] = {{0, 0, 1}, {0, 0.5, 0.8660254037844386}, {1, 0, 0}};
    unsigned st = 12345;
    for (int r = 0; r < NOLD + NNEW; ++r) {
        unsigned v[4];
        for (int t = 0; t < 4; ++t) st = st * 1103515245u + 12345u, v[t] = (st >> 16) & 0x7fff;
        const double *d = dirs[v[3] % 3];
        pl_ncpc_key k = key(v[0] % 2 ? 7 : 8, v[1] % 2 ? PL_ROW_NORMAL : PL_ROW_BILATERAL, (int)(v[2] % 40), -1,
                            d[0], d[1], d[2], r < NOLD ? 1.0 + r : 0.0);
        if (r < NOLD) old[r] = k;
        else now[r - NOLD] = k;
    }
    double got[NNEW], want[NNEW];
    pl_error err;
    int n_got = ncpc_warm_start(now, NNEW, old, NOLD, got, &err);
    int n_want = brute_match(now, NNEW, old, NOLD, want);
    ck_assert_int_gt(n_want, 100);
    ck_assert_int_eq(n_got, n_want);
    for (int j = 0; j < NNEW; ++j) ck_assert_double_eq(got[j], want[j]);
}
END_TEST

START_TEST(bad_rows_are_refused)
{
    problem p;
    problem_make(&p, 3);
    pl_ncpc_rows r;
    pl_error err;
    ncpc_rows_init(&r);
    p.rows.vertex[0] = NV; /* out of range */
    ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "vertex 15"));
    p.rows.vertex[0] = 0;
    p.rows.pair[1] = 5; /* friction paired with a bilateral row */
    ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "friction row 1"));
    p.rows.pair[1] = 0;
    p.rows.coef[0] = NAN;
    ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_EINPUT);
    p.rows.coef[0] = 0.0;
    int s4 = p.rows.start[4];
    p.rows.start[4] = p.rows.start[5] + 1; /* row 3 longer, row 4 ends before it starts */
    ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "row 4: its entries end"));
    p.rows.start[4] = s4;
    ck_assert_int_eq(ncpc_rows_build(&r, &p.sys, &p.rows, p.qt, &err), PL_OK);
    ncpc_rows_free(&r);
    problem_free(&p);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("ncp_contact_parts");
    TCase *tc = tcase_create("parts");
    tcase_add_test(tc, active_rows_offsets_and_values);
    tcase_add_test(tc, delassus_matches_the_dense_reference);
    tcase_add_test(tc, delassus_auto_counts_its_work);
    tcase_add_test(tc, warm_start_matching_rule);
    tcase_add_test(tc, warm_start_many_rows_as_brute_force);
    tcase_add_test(tc, bad_rows_are_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf ? 1 : 0;
}
