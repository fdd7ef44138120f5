/* test_cable_area.c - the pulled area of a surface cable
 * (plugins/cable/cable_area.c; SoftRobots' CableConstraint with centers,
 * radii and method="sphere"|"geodesic"):
 *  - on a flat grid, the points within the radius of a center at a vertex
 *    are those of the disc (straight distance), and along the grid's axes
 *    the geodesic distance is the straight one;
 *  - on a folded sheet (two sheets 0.2 apart, joined at one end) a center
 *    on the lower sheet reaches the upper sheet with the straight distance
 *    but not along the surface;
 *  - the weights are (R - d) normalised to sum 1;
 *  - a center off the vertices starts the search at its projection on the
 *    nearest triangle;
 *  - an area with no point, or a broken surface, is refused;
 *  - a surface cable on a clamped bar, pulled by d, moves the weighted
 *    centroid of its area by d along the cable at equilibrium. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cable_area.h"
#include "test_tmp.h"
#include "cable_test_util.h"

/* A grid of (nx + 1) x (ny + 1) points with spacing h in the plane z = z0,
 * from x0, two triangles per cell; appends to p / tris at point offset off. */
static void grid(double *p, int *tris, int nx, int ny, double h, double x0, double z0, int off,
                 int *np, int *nt)
{
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            double *q = p + 3 * (off + j * (nx + 1) + i);
            q[0] = x0 + i * h, q[1] = j * h, q[2] = z0;
        }
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            int a = off + j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
            int *t = tris + 3 * *nt;
            t[0] = a, t[1] = b, t[2] = d, t[3] = a, t[4] = d, t[5] = c;
            *nt += 2;
        }
    *np += (nx + 1) * (ny + 1);
}

static int selected(const int *idx, int n, int v)
{
    for (int k = 0; k < n; ++k)
        if (idx[k] == v) return k;
    return -1;
}

START_TEST(flat_grid_disc_and_axes)
{
    enum { N = 10 };
    double p[3 * (N + 1) * (N + 1)], w[(N + 1) * (N + 1)], c[3] = {0.5, 0.5, 0.0};
    int tris[6 * N * N], idx[(N + 1) * (N + 1)], np = 0, nt = 0, ns;
    grid(p, tris, N, N, 0.1, 0.0, 0.0, 0, &np, &nt);
    double R = 0.25;
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, R, CABLE_AREA_SPHERE, idx, w, &ns), PL_OK);
    int expect = 0;
    for (int v = 0; v < np; ++v) {
        double dx = p[3 * v] - 0.5, dy = p[3 * v + 1] - 0.5, d = sqrt(dx * dx + dy * dy);
        int in = d < R;
        expect += in;
        ck_assert_int_eq(selected(idx, ns, v) >= 0, in);
    }
    ck_assert_int_eq(ns, expect); /* 21 points: the disc of radius 2.5 cells */
    ck_assert_int_eq(ns, 21);
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, R, CABLE_AREA_GEODESIC, idx, w, &ns), PL_OK);
    /* along the axes the edge path is straight: 0.1 and 0.2 away are in, with d exact */
    int centre = 5 * (N + 1) + 5, k0 = selected(idx, ns, centre);
    int kx2 = selected(idx, ns, centre + 2), ky2 = selected(idx, ns, centre + 2 * (N + 1));
    ck_assert(k0 >= 0 && kx2 >= 0 && ky2 >= 0);
    ck_assert_double_eq_tol(w[kx2] / w[k0], (R - 0.2) / R, 1e-12);
    ck_assert_double_eq_tol(w[ky2] / w[k0], (R - 0.2) / R, 1e-12);
    /* the geodesic area is within the disc (edge paths are never shorter) */
    for (int k = 0; k < ns; ++k) {
        const double *q = p + 3 * idx[k];
        ck_assert(hypot(q[0] - 0.5, q[1] - 0.5) < R);
    }
}
END_TEST

START_TEST(folded_sheet_geodesic_differs)
{
    /* lower sheet z = 0, x in [0, 1]; upper sheet z = 0.2, x in [0, 1]; joined
     * by a strip at x = 1 (the upper sheet's edge x = 1 shares nothing with the
     * lower one but a band of triangles) */
    enum { NX = 10, NY = 2, NP = 2 * (NX + 1) * (NY + 1), NT = 4 * NX * NY + 2 * NY };
    double p[3 * NP], w[NP], c[3] = {0.5, 0.1, 0.0};
    int tris[3 * NT], idx[NP], np = 0, nt = 0, ns;
    grid(p, tris, NX, NY, 0.1, 0.0, 0.0, 0, &np, &nt);
    grid(p, tris, NX, NY, 0.1, 0.0, 0.2, np, &np, &nt);
    for (int j = 0; j < NY; ++j) { /* the fold: lower (10, j) -- upper (10, j) */
        int a = j * (NX + 1) + NX, b = a + NX + 1, u = (NX + 1) * (NY + 1);
        int *t = tris + 3 * nt;
        t[0] = a, t[1] = b, t[2] = b + u, t[3] = a, t[4] = b + u, t[5] = a + u;
        nt += 2;
    }
    ck_assert_int_eq(nt, NT);
    int above = (NX + 1) * (NY + 1) + 1 * (NX + 1) + 5; /* (0.5, 0.1, 0.2) */
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, 0.3, CABLE_AREA_SPHERE, idx, w, &ns), PL_OK);
    ck_assert_int_ge(selected(idx, ns, above), 0);
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, 0.3, CABLE_AREA_GEODESIC, idx, w, &ns), PL_OK);
    ck_assert_int_lt(selected(idx, ns, above), 0);
    for (int k = 0; k < ns; ++k) ck_assert_double_eq(p[3 * idx[k] + 2], 0.0);
    /* along the surface the upper sheet is 0.5 + 0.2 + 0.5 away */
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, 1.25, CABLE_AREA_GEODESIC, idx, w, &ns), PL_OK);
    ck_assert_int_ge(selected(idx, ns, above), 0);
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, 1.19, CABLE_AREA_GEODESIC, idx, w, &ns), PL_OK);
    ck_assert_int_lt(selected(idx, ns, above), 0);
}
END_TEST

START_TEST(weights_sum_to_one_and_follow_distance)
{
    enum { N = 6 };
    double p[3 * (N + 1) * (N + 1)], w[(N + 1) * (N + 1)];
    int tris[6 * N * N], idx[(N + 1) * (N + 1)], np = 0, nt = 0, ns;
    grid(p, tris, N, N, 0.1, 0.0, 0.0, 0, &np, &nt);
    /* a center off the vertices, 0.05 above the sheet: the search starts at
     * its projection (0.23, 0.31, 0); a corner at distance s from it starts at
     * 0.05 + s */
    double c[3] = {0.23, 0.31, 0.05}, R = 0.3;
    for (int m = CABLE_AREA_SPHERE; m <= CABLE_AREA_GEODESIC; ++m) {
        ck_assert_int_eq(cable_area(p, np, tris, nt, c, R, m, idx, w, &ns), PL_OK);
        double sum = 0.0;
        for (int k = 0; k < ns; ++k) {
            ck_assert(w[k] > 0.0);
            sum += w[k];
        }
        ck_assert_double_eq_tol(sum, 1.0, 1e-14);
        int a = selected(idx, ns, 3 * (N + 1) + 2), b = selected(idx, ns, 3 * (N + 1) + 3);
        ck_assert(a >= 0 && b >= 0); /* (0.2, 0.3) and (0.3, 0.3) */
        double da = hypot(0.03, 0.01), db = hypot(0.07, 0.01);
        if (m == CABLE_AREA_SPHERE) da = hypot(da, 0.05), db = hypot(db, 0.05);
        else da += 0.05, db += 0.05;
        ck_assert_double_eq_tol(w[a] / w[b], (R - da) / (R - db), 1e-12);
    }
}
END_TEST

START_TEST(empty_area_and_broken_surface_refused)
{
    double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, w[3], far[3] = {5, 5, 5}, c[3] = {0, 0, 0};
    int tris[] = {0, 1, 2}, bad[] = {0, 1, 7}, idx[3], ns;
    ck_assert_int_eq(cable_area(p, 3, tris, 1, far, 1.0, CABLE_AREA_GEODESIC, idx, w, &ns),
                     PL_EINPUT);
    ck_assert_int_eq(ns, 0);
    ck_assert_int_eq(cable_area(p, 3, bad, 1, c, 1.0, CABLE_AREA_GEODESIC, idx, w, &ns), PL_EINPUT);
    ck_assert_int_eq(cable_area(p, 3, tris, 0, c, 1.0, CABLE_AREA_GEODESIC, idx, w, &ns), PL_EINPUT);
    ck_assert_int_eq(cable_area(p, 3, tris, 1, c, 0.0, CABLE_AREA_SPHERE, idx, w, &ns), PL_EINPUT);
}
END_TEST

/* The bar's end face x = 0.1 as an OBJ surface: its 5 x 5 vertices. */
static void write_end_face(const char *path, double *p, int *tris, int *np, int *nt)
{
    *np = *nt = 0;
    grid(p, tris, 4, 4, 0.005, 0.0, 0.0, 0, np, nt);
    for (int v = 0; v < *np; ++v) { /* (x, y, 0) -> (0.1, x, y) */
        double y = p[3 * v], z = p[3 * v + 1];
        p[3 * v] = 0.1, p[3 * v + 1] = y, p[3 * v + 2] = z;
    }
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    for (int v = 0; v < *np; ++v) fprintf(f, "v %.17g %.17g %.17g\n", p[3 * v], p[3 * v + 1], p[3 * v + 2]);
    for (int t = 0; t < *nt; ++t)
        fprintf(f, "f %d %d %d\n", tris[3 * t] + 1, tris[3 * t + 1] + 1, tris[3 * t + 2] + 1);
    fclose(f);
}

START_TEST(pulled_area_centroid_moves_by_the_displacement)
{
    char obj[256], xml[4096];
    snprintf(obj, sizeof obj, "%s/cable_area.obj", test_tmp_dir()); /* under $TMPDIR */
    double p[3 * 25], w[25], c[3] = {0.1, 0.01, 0.01}, d = 0.002;
    int tris[3 * 32], idx[25], np, nt, ns;
    write_end_face(obj, p, tris, &np, &nt);
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n"
             "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
             "<RequiredPlugin name=\"ncp_contact\"/><RequiredPlugin name=\"cable\"/>\n"
             "<LocalGlobalSolver name=\"solver\" damping=\"50\" iterations=\"300\" "
             "forceTolerance=\"1e-6\" initialGuess=\"inertia\"/>\n"
             "<SparseInverseSolver/><NonSmoothNewtonContactSolver/>\n"
             "<Node name=\"bar\">\n"
             "<RegularGridTetrahedra name=\"grid\" min=\"0 0 0\" max=\"0.1 0.02 0.02\" n=\"6 5 5\"/>\n"
             "<MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
             "<MeshLoader name=\"face\" filename=\"%s\"/>\n"
             "<DiagonalMass massDensity=\"1000\"/>\n"
             "<NeoHookean youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
             "<FixedConstraint box=\"-0.001 -1 -1  0.001 1 1\"/>\n"
             "<CableConstraint name=\"cable\" value=\"%g\" minForce=\"0\" pullPoint=\"0.2 0.012 "
             "0.01\" centers=\"0.1 0.01 0.01\" radii=\"0.008\" method=\"geodesic\" "
             "surface=\"@face\" src=\"@grid\"/>\n"
             "</Node></Node>\n",
             obj, d);
    pl_sim *s = ct_load(xml);
    int n;
    const double *x0 = ct_positions(s, "bar/dofs", 1, &n);
    ck_assert_int_eq(cable_area(p, np, tris, nt, c, 0.008, CABLE_AREA_GEODESIC, idx, w, &ns), PL_OK);
    ck_assert_int_ge(ns, 5);
    double c0[3] = {0, 0, 0}, c1[3] = {0, 0, 0}, u[3] = {0.2, 0.012, 0.01}, un = 0.0, moved = 0.0;
    int vert[25];
    for (int k = 0; k < ns; ++k) {
        const double *q = p + 3 * idx[k];
        vert[k] = ct_vertex_at(x0, n, q[0], q[1], q[2]);
        ck_assert_int_ge(vert[k], 0);
        for (int j = 0; j < 3; ++j) c0[j] += w[k] * x0[3 * vert[k] + j];
    }
    for (int j = 0; j < 3; ++j) u[j] -= c0[j], un += u[j] * u[j];
    ct_step(s, 10);
    const double *x = ct_positions(s, "bar/dofs", 0, &n);
    for (int k = 0; k < ns; ++k)
        for (int j = 0; j < 3; ++j) c1[j] += w[k] * x[3 * vert[k] + j];
    for (int j = 0; j < 3; ++j) moved += (c1[j] - c0[j]) * u[j] / sqrt(un);
    fprintf(stderr, "surface cable on a bar: %d area points, the centroid moves %.6f mm along the "
                    "cable for %.3f mm commanded; reported displacement %.6f mm, tension %.4f N\n",
            ns, 1e3 * moved, 1e3 * d, 1e3 * ct_get(s, "bar/cable.displacement"),
            ct_get(s, "bar/cable.force"));
    ck_assert_double_eq_tol(moved, d, 0.01 * d);
    ck_assert_double_eq_tol(ct_get(s, "bar/cable.displacement"), d, 1e-3 * d);
    ck_assert(ct_get(s, "bar/cable.force") > 0.0);
    pl_sim_free(s);
    remove(obj);
}
END_TEST

int main(void)
{
    Suite *su = suite_create("cable_area");
    TCase *tc = tcase_create("area");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, flat_grid_disc_and_axes);
    tcase_add_test(tc, folded_sheet_geodesic_differs);
    tcase_add_test(tc, weights_sum_to_one_and_follow_distance);
    tcase_add_test(tc, empty_area_and_broken_surface_refused);
    tcase_add_test(tc, pulled_area_centroid_moves_by_the_displacement);
    suite_add_tcase(su, tc);
    SRunner *sr = srunner_create(su);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
