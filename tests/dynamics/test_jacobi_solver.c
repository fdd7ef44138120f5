/* test_jacobi_solver.c - the JacobiSolver baseline (issue 14 item 5): one
 * Jacobi sweep per call from the given iterate, converging to the direct
 * solution (faster with Chebyshev); inside a LocalGlobalSolver it reaches the
 * same implicit-Euler step as the exact global solver; constraint rows and
 * bad fields are refused. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dyn_test_util.h"

/* A = M + h^2 k L on an nx x ny x nz grid graph (scalar, as the loop's A):
 * lumped masses m, springs k; returned as CSC with both triangles. */
static void grid_system(int nx, int ny, int nz, double m, double h2k, pl_csc *A, double *dense)
{
    int n = nx * ny * nz;
    pl_triplets t;
    ck_assert_int_eq(pl_triplets_init(&t, n, n, 16 * n), PL_OK);
    memset(dense, 0, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < n; ++i) {
        pl_triplets_add(&t, i, i, m);
        dense[i * n + i] += m;
    }
    for (int x = 0; x < nx; ++x)
        for (int y = 0; y < ny; ++y)
            for (int z = 0; z < nz; ++z) {
                int i = (x * ny + y) * nz + z, nb[3] = {x + 1 < nx ? i + ny * nz : -1,
                                                         y + 1 < ny ? i + nz : -1, z + 1 < nz ? i + 1 : -1};
                for (int d = 0; d < 3; ++d) {
                    int j = nb[d];
                    if (j < 0) continue;
                    pl_triplets_add(&t, i, i, h2k);
                    pl_triplets_add(&t, j, j, h2k);
                    pl_triplets_add(&t, i, j, -h2k);
                    pl_triplets_add(&t, j, i, -h2k);
                    dense[i * n + i] += h2k, dense[j * n + j] += h2k;
                    dense[i * n + j] -= h2k, dense[j * n + i] -= h2k;
                }
            }
    ck_assert_int_eq(pl_triplets_to_csc(&t, A), 0);
    pl_triplets_free(&t);
}

/* x = A^-1 b (dense Cholesky, n x 3 right-hand sides). */
static void dense_solve(const double *A, int n, const double *b, double *x)
{
    double *L = calloc((size_t)(n * n), sizeof(double));
    for (int j = 0; j < n; ++j) {
        double s = A[j * n + j];
        for (int k = 0; k < j; ++k) s -= L[j * n + k] * L[j * n + k];
        L[j * n + j] = sqrt(s);
        for (int i = j + 1; i < n; ++i) {
            double v = A[i * n + j];
            for (int k = 0; k < j; ++k) v -= L[i * n + k] * L[j * n + k];
            L[i * n + j] = v / L[j * n + j];
        }
    }
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i < n; ++i) {
            double s = b[3 * i + c];
            for (int k = 0; k < i; ++k) s -= L[i * n + k] * x[3 * k + c];
            x[3 * i + c] = s / L[i * n + i];
        }
        for (int i = n - 1; i >= 0; --i) {
            double s = x[3 * i + c];
            for (int k = i + 1; k < n; ++k) s -= L[k * n + i] * x[3 * k + c];
            x[3 * i + c] = s / L[i * n + i];
        }
    }
    free(L);
}

/* A scene holding only a JacobiSolver named "jacobi" with the given fields. */
static pl_sim *jacobi_scene(const char *fields)
{
    char xml[512];
    snprintf(xml, sizeof xml, "<Node name=\"root\" dt=\"0.01\"><JacobiSolver name=\"jacobi\" %s/></Node>",
             fields);
    return dyn_load(xml);
}

/* Calls (sweeps) until max |x - x*| <= tol * max |x*|, at most max_calls; -1 if never. */
static int sweeps_to(pl_sim *s, const pl_csc *A, const double *b, const double *xstar, int n,
                     double tol, int max_calls)
{
    pl_component *c = pl_sim_component(s, "jacobi");
    ck_assert_ptr_nonnull(c);
    const pl_global_solver_ops *ops = pl_component_role(c, PL_ROLE_GLOBAL_SOLVER);
    ck_assert_int_ge(ops->version, 4);
    ck_assert_ptr_nonnull(ops->solve_from);
    pl_error err;
    ck_assert_int_eq(ops->factor(c, A, NULL, &err), PL_OK);
    double *x = calloc((size_t)(3 * n), sizeof(double)), scale = 0;
    for (int i = 0; i < 3 * n; ++i) scale = fmax(scale, fabs(xstar[i]));
    pl_buffer bb = pl_buffer_host_f64((double *)b, (size_t)n, 3), xb = pl_buffer_host_f64(x, (size_t)n, 3);
    int found = -1;
    for (int k = 0; k < max_calls && found < 0; ++k) {
        ck_assert_int_eq(ops->solve_from(c, &bb, &xb, k, &err), PL_OK);
        double e = 0;
        for (int i = 0; i < 3 * n; ++i) e = fmax(e, fabs(x[i] - xstar[i]));
        if (e <= tol * scale) found = k + 1;
    }
    free(x);
    return found;
}

START_TEST(one_call_is_one_jacobi_sweep_from_the_given_iterate)
{
    int n = 4 * 3 * 3;
    double *dense = malloc(sizeof(double) * (size_t)(n * n)), b[3 * 36], x0[3 * 36], x[3 * 36];
    pl_csc A;
    grid_system(4, 3, 3, 0.5, 2.0, &A, dense);
    for (int i = 0; i < 3 * n; ++i) b[i] = sin(0.7 * i), x0[i] = cos(1.3 * i);
    memcpy(x, x0, sizeof x);
    pl_sim *s = jacobi_scene("");
    pl_component *c = pl_sim_component(s, "jacobi");
    const pl_global_solver_ops *ops = pl_component_role(c, PL_ROLE_GLOBAL_SOLVER);
    pl_error err;
    ck_assert_int_eq(ops->factor(c, &A, NULL, &err), PL_OK);
    pl_buffer bb = pl_buffer_host_f64(b, (size_t)n, 3), xb = pl_buffer_host_f64(x, (size_t)n, 3);
    ck_assert_int_eq(ops->solve_from(c, &bb, &xb, 0, &err), PL_OK);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double r = b[3 * i + k];
            for (int j = 0; j < n; ++j) r -= dense[i * n + j] * x0[3 * j + k];
            ck_assert_double_eq_tol(x[3 * i + k], x0[3 * i + k] + r / dense[i * n + i], 1e-13);
        }
    /* no exact solve, and it says so */
    ck_assert_int_eq(ops->solve(c, &bb, &xb, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "solve_from"));
    ck_assert(ops->approximate && ops->approximate(c));
    pl_sim_free(s);
    pl_csc_free(&A);
    free(dense);
}
END_TEST

START_TEST(sweeps_converge_to_the_direct_solution_and_chebyshev_is_faster)
{
    int n = 8 * 4 * 4;
    double *dense = malloc(sizeof(double) * (size_t)(n * n));
    double *b = malloc(sizeof(double) * 3 * (size_t)n), *xstar = malloc(sizeof(double) * 3 * (size_t)n);
    pl_csc A;
    /* h^2 k / m = 4: a stiff-ish system (spectral radius of Jacobi near 0.99) */
    grid_system(8, 4, 4, 0.01, 0.04, &A, dense);
    for (int i = 0; i < 3 * n; ++i) b[i] = 0.01 * (1.0 + sin(0.37 * i));
    dense_solve(dense, n, b, xstar);
    pl_sim *plain = jacobi_scene(""), *cheb = jacobi_scene("chebyshev=\"1\" delay=\"1\"");
    int k_plain = sweeps_to(plain, &A, b, xstar, n, 1e-10, 20000);
    int k_cheb = sweeps_to(cheb, &A, b, xstar, n, 1e-10, 20000);
    fprintf(stderr, "Jacobi sweeps to 1e-10 of the direct solution: %d plain, %d Chebyshev\n", k_plain,
            k_cheb);
    ck_assert_int_gt(k_plain, 0);
    ck_assert_int_gt(k_cheb, 0);
    ck_assert_int_lt(3 * k_cheb, k_plain); /* the 1 - rho against 1 - sqrt(1 - rho^2) rate */
    pl_sim_free(plain);
    pl_sim_free(cheb);
    pl_csc_free(&A);
    free(dense);
    free(b);
    free(xstar);
}
END_TEST

/* A small bar hanging from its left end, one step with the given global solver. */
static pl_sim *hanging_bar(const char *global, int iterations)
{
    static char xml[4096];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
             "  <RequiredPlugin name=\"hyperelastic\"/>\n"
             "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"%d\"/>\n"
             "  %s\n"
             "  <Node name=\"bar\">\n"
             "    <RegularGridTetrahedra name=\"grid\" min=\"0 0 0\" max=\"0.4 0.1 0.1\" n=\"9 3 3\"/>\n"
             "    <MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
             "    <DiagonalMass massDensity=\"1000\"/>\n"
             "    <ARAP youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
             "    <FixedConstraint box=\"-0.001 -1 -1 0.001 1 1\"/>\n"
             "  </Node>\n"
             "</Node>\n",
             iterations, global);
    return dyn_load(xml);
}

START_TEST(in_the_local_global_loop_it_reaches_the_exact_step)
{
    /* the converged local-global step does not depend on how the global step
     * was solved; 5 steps so that the bar bends */
    pl_sim *exact = hanging_bar("<SparseInverseSolver mode=\"direct\"/>", 200);
    pl_sim *jac = hanging_bar("<JacobiSolver/>", 3000);
    pl_sim *cheb = hanging_bar("<JacobiSolver chebyshev=\"1\"/>", 600);
    dyn_step(exact, 5);
    dyn_step(jac, 5);
    dyn_step(cheb, 5);
    int n;
    const double *xe = dyn_positions(exact, "bar/dofs", &n), *xj = dyn_positions(jac, "bar/dofs", &n),
                 *xc = dyn_positions(cheb, "bar/dofs", &n), *r = dyn_rest(exact, "bar/dofs", &n);
    double dj = 0, dc = 0, moved = 0;
    for (int i = 0; i < 3 * n; ++i) {
        dj = fmax(dj, fabs(xj[i] - xe[i]));
        dc = fmax(dc, fabs(xc[i] - xe[i]));
        moved = fmax(moved, fabs(xe[i] - r[i]));
    }
    fprintf(stderr, "hanging bar after 5 steps: moved %.3e m, Jacobi %.3e m, Chebyshev %.3e m away\n",
            moved, dj, dc);
    ck_assert(moved > 1e-3);
    ck_assert_msg(dj < 1e-9 && dc < 1e-9, "Jacobi %g, Chebyshev %g m from the exact step", dj, dc);
    pl_sim_free(exact);
    pl_sim_free(jac);
    pl_sim_free(cheb);
}
END_TEST

static void expect_load_error(const char *xml, const char *needle)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, PL_SOURCE_DIR "/scenes/test.xml", NULL, &diag);
    ck_assert_ptr_null(s);
    ck_assert_int_eq(pl_diag_status(&diag), PL_EINPUT);
    int found = 0;
    for (int k = 0; k < diag.count; ++k) found |= strstr(diag.items[k].msg, needle) != NULL;
    if (!found) pl_diag_print(&diag, stderr);
    ck_assert_msg(found, "no error saying \"%s\"", needle);
    pl_diag_free(&diag);
}

START_TEST(constraint_rows_and_bad_fields_are_refused)
{
    expect_load_error(
        "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
        "  <RequiredPlugin name=\"hyperelastic\"/>\n"
        "  <RequiredPlugin name=\"ncp_contact\"/>\n"
        "  <RequiredPlugin name=\"collision\"/>\n"
        "  <LocalGlobalSolver name=\"solver\"/>\n"
        "  <JacobiSolver name=\"global\"/>\n"
        "  <NonSmoothNewtonContactSolver name=\"contact\"/>\n"
        "  <PlaneObstacle name=\"floor\" point=\"0 0 0\" normal=\"0 1 0\"/>\n"
        "  <Node name=\"box\">\n"
        "    <RegularGridTetrahedra name=\"grid\" min=\"0 0.001 0\" max=\"0.1 0.101 0.1\" n=\"3 3 3\"/>\n"
        "    <MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
        "    <DiagonalMass massDensity=\"1000\"/>\n"
        "    <ARAP youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
        "    <SurfaceCollisionModel name=\"surface\"/>\n"
        "  </Node>\n"
        "</Node>\n",
        "only approximates A^-1 b");
    expect_load_error("<Node name=\"root\"><JacobiSolver rho=\"1.5\"/></Node>", "rho must be in [0, 1)");
    expect_load_error("<Node name=\"root\"><JacobiSolver relaxation=\"0\"/></Node>", "relaxation");
    expect_load_error("<Node name=\"root\"><JacobiSolver delay=\"-1\"/></Node>", "delay");
}
END_TEST

int main(void)
{
    Suite *s = suite_create("jacobi_solver");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, one_call_is_one_jacobi_sweep_from_the_given_iterate);
    tcase_add_test(tc, sweeps_converge_to_the_direct_solution_and_chebyshev_is_faster);
    tcase_add_test(tc, in_the_local_global_loop_it_reaches_the_exact_step);
    tcase_add_test(tc, constraint_rows_and_bad_fields_are_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
