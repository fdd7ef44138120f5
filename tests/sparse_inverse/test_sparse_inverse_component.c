/* test_sparse_inverse_component.c - the SparseInverseSolver component
 * loaded from the plugin: its fields, the global solver role (factor logs
 * and records its statistics, solve equals an independent CHOLMOD solve in
 * both modes, bad buffers are refused), and its lifecycle. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/component.h"
#include "pliant/log.h"
#include "pliant/registry.h"
#include "pliant/roles.h"
#include "pliant/timer.h"
#include "sparse_inverse.h"
#include "spinv_test_util.h"
#include "spinv_testmat.h"

#define PLUGIN PL_BINARY_DIR "/plugins/libpliant_sparse_inverse.so"

static pl_registry *reg;
static char logged[4096];

static void capture(pl_log_level level, const char *msg, void *user)
{
    (void)level;
    (void)user;
    strncat(logged, msg, sizeof logged - strlen(logged) - 1);
}

/* A component of type t with its fields at their defaults. */
static pl_component *make_component(const pl_type *t)
{
    pl_component *c = calloc(1, t->size);
    ck_assert_ptr_nonnull(c);
    c->type = t;
    c->name = strdup("solver");
    pl_error err;
    for (int k = 0; k < t->nfields; ++k)
        if (t->fields[k].def)
            ck_assert_int_eq(pl_field_parse(&t->fields[k], c, t->fields[k].def, &err), PL_OK);
    return c;
}

static void free_component(pl_component *c)
{
    const pl_type *t = c->type;
    if (t->ops.destroy) t->ops.destroy(c);
    for (int k = 0; k < t->nfields; ++k) pl_field_release(&t->fields[k], c);
    free(c->name);
    free(c);
}

static void set_field(pl_component *c, const char *name, const char *value)
{
    pl_error err;
    const pl_field *f = pl_component_field(c, name);
    ck_assert_ptr_nonnull(f);
    ck_assert_int_eq(pl_field_parse(f, c, value, &err), PL_OK);
}

static void setup(void)
{
    pl_error err;
    reg = pl_registry_create();
    ck_assert_int_eq(pl_registry_load_plugin(reg, PLUGIN, &err), PL_OK);
}

static void teardown(void)
{
    pl_registry_free(reg);
    pl_log_set_sink(NULL, NULL);
}

START_TEST(test_type_declares_fields_and_global_solver_role)
{
    const pl_type *t = pl_registry_find(reg, "SparseInverseSolver");
    ck_assert_ptr_nonnull(t);
    const char *names[] = {"ordering", "mode", "threads"};
    for (int k = 0; k < 3; ++k) {
        int found = 0;
        for (int f = 0; f < t->nfields; ++f)
            if (!strcmp(t->fields[f].name, names[k])) {
                found = 1;
                ck_assert(t->fields[f].help && strlen(t->fields[f].help) > 10);
            }
        ck_assert_msg(found, "field %s missing", names[k]);
    }
    const pl_global_solver_ops *ops = t->roles[PL_ROLE_GLOBAL_SOLVER];
    ck_assert_ptr_nonnull(ops);
    ck_assert_int_ge(ops->version, PL_GLOBAL_SOLVER_OPS_VERSION);
    ck_assert(ops->factor && ops->solve && ops->apply_inverse_to_rows && ops->inverse_diagonal &&
              ops->size);
    /* defaults: metis, sparse, 0 threads; a negative thread count is refused */
    pl_component *c = make_component(t);
    char buf[64];
    ck_assert_int_eq(pl_field_format(pl_component_field(c, "ordering"), c, buf, sizeof buf), PL_OK);
    ck_assert_str_eq(buf, "metis");
    pl_diag diag;
    pl_diag_init(&diag);
    pl_ctx ctx = {0};
    ctx.diag = &diag;
    ck_assert_int_eq(t->ops.init(c, &ctx), PL_OK);
    set_field(c, "threads", "-2");
    ck_assert_int_eq(t->ops.init(c, &ctx), PL_EINPUT);
    ck_assert_int_eq(diag.nerrors, 1);
    pl_diag_free(&diag);
    free_component(c);
}
END_TEST

/* factor + solve through the role, in the given mode and ordering. */
static void check_role(const char *mode, const char *ordering)
{
    const pl_type *t = pl_registry_find(reg, "SparseInverseSolver");
    const pl_global_solver_ops *ops = t->roles[PL_ROLE_GLOBAL_SOLVER];
    pl_component *c = make_component(t);
    set_field(c, "mode", mode);
    set_field(c, "ordering", ordering);
    pl_csc A;
    ck_assert_int_eq(spinv_grid_matrix(9, 5, 4, 10.0, &A), 0);
    int n = A.ncols;
    pl_error err;
    double *b = spinv_random_block(n, 3, 2u), *x = malloc(3 * (size_t)n * sizeof *x);
    pl_buffer bb = pl_buffer_host_f64(b, (size_t)n, 3), xb = pl_buffer_host_f64(x, (size_t)n, 3);
    ck_assert_int_eq(ops->size(c), 0);
    ck_assert_int_eq(ops->solve(c, &bb, &xb, &err), PL_EINPUT); /* before factor */
    pl_timers *timers = pl_timers_create();
    logged[0] = '\0';
    pl_log_set_level(PL_LOG_INFO);
    pl_log_set_sink(capture, NULL);
    ck_assert_int_eq(ops->factor(c, &A, timers, &err), PL_OK);
    ck_assert_ptr_nonnull(strstr(logged, "nnz(S)"));
    ck_assert_int_eq(ops->size(c), n);
    /* the recorded statistics are the numeric core's */
    pl_spinv_options opt = {!strcmp(ordering, "amd") ? PL_SPINV_AMD : PL_SPINV_METIS,
                            !strcmp(mode, "direct") ? PL_SPINV_DIRECT : PL_SPINV_SPARSE, 0};
    pl_sparse_inverse *core = sparse_inverse_create(&opt);
    ck_assert_int_eq(sparse_inverse_factor(core, &A, &err), PL_OK);
    double v = 0;
    ck_assert_int_eq(pl_stat_get(timers, "nnz(S)", &v), 0);
    ck_assert(v == (double)sparse_inverse_stats(core)->nnz_S);
    ck_assert_int_eq(pl_stat_get(timers, "nnz(A)", &v), 0);
    ck_assert(v == (double)A.p[n]);
    ck_assert_int_eq(pl_stat_get(timers, "nnz(L)", &v), 0);
    ck_assert(v == (double)sparse_inverse_stats(core)->nnz_L);
    sparse_inverse_destroy(core);
    /* solve against the reference */
    double *ref = malloc(3 * (size_t)n * sizeof *ref);
    ck_assert_int_eq(spinv_ref_solve(&A, b, ref, 3), 0);
    ck_assert_int_eq(ops->solve(c, &bb, &xb, &err), PL_OK);
    ck_assert(spinv_rel_diff(x, ref, 3 * (size_t)n) < 1e-10);
    /* wrong sizes and float32 are refused */
    pl_buffer small = pl_buffer_host_f64(x, (size_t)n - 1, 3);
    ck_assert_int_eq(ops->solve(c, &bb, &small, &err), PL_EINPUT);
    pl_buffer f32 = bb;
    f32.precision = PL_F32;
    ck_assert_int_eq(ops->solve(c, &f32, &xb, &err), PL_EINPUT);
    /* the diagonal of A^-1: e_0^T A^-1 e_0 */
    double *diag = malloc((size_t)n * sizeof *diag), *e0 = calloc((size_t)n, sizeof *e0);
    double *col = malloc((size_t)n * sizeof *col);
    e0[0] = 1.0;
    ck_assert_int_eq(spinv_ref_solve(&A, e0, col, 1), 0);
    ck_assert_int_eq(ops->inverse_diagonal(c, diag, &err), PL_OK);
    ck_assert(fabs(diag[0] - col[0]) < 1e-12 * fabs(col[0]));
    /* one row e_0: Y^T Y = [A^-1]_00 */
    int hp[] = {0, 1}, hj[] = {0};
    double hx[] = {1.0};
    pl_csr H = {1, n, hp, hj, hx};
    pl_csc Y;
    ck_assert_int_eq(ops->apply_inverse_to_rows(c, &H, &Y, &err), PL_OK);
    double yy = 0.0;
    for (int q = 0; q < Y.p[1]; ++q) yy += Y.x[q] * Y.x[q];
    ck_assert(fabs(yy - col[0]) < 1e-12 * fabs(col[0]));
    pl_csc_free(&Y);
    /* refactoring replaces the old factor without leaking */
    ck_assert_int_eq(ops->factor(c, &A, NULL, &err), PL_OK);
    pl_log_set_sink(NULL, NULL);
    free(diag), free(e0), free(col), free(ref), free(b), free(x);
    pl_timers_free(timers);
    pl_csc_free(&A);
    free_component(c);
}

START_TEST(test_role_sparse_mode_solves_and_records_statistics)
{
    check_role("sparse", "metis");
    check_role("sparse", "amd");
}
END_TEST

START_TEST(test_role_direct_mode_solves_and_records_statistics)
{
    check_role("direct", "metis");
}
END_TEST

START_TEST(test_role_factor_refuses_indefinite_matrix)
{
    const pl_type *t = pl_registry_find(reg, "SparseInverseSolver");
    const pl_global_solver_ops *ops = t->roles[PL_ROLE_GLOBAL_SOLVER];
    pl_component *c = make_component(t);
    int p[] = {0, 1, 2}, i[] = {0, 1};
    double v[] = {1.0, -3.0};
    pl_csc A = {2, 2, p, i, v};
    pl_error err;
    pl_log_set_sink(capture, NULL);
    ck_assert_int_eq(ops->factor(c, &A, NULL, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.where, "solver"));
    ck_assert_int_eq(ops->size(c), 0);
    free_component(c);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("sparse_inverse_component");
    TCase *tc = tcase_create("component");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_type_declares_fields_and_global_solver_role);
    tcase_add_test(tc, test_role_sparse_mode_solves_and_records_statistics);
    tcase_add_test(tc, test_role_direct_mode_solves_and_records_statistics);
    tcase_add_test(tc, test_role_factor_refuses_indefinite_matrix);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
