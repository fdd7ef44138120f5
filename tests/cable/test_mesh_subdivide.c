/* test_mesh_subdivide.c - 1-to-8 tetrahedral subdivision
 * (components/io/mesh_subdivide.c) and MeshLoader's `subdivide` field:
 *  - a tetrahedron gives 8 children of exactly 1/8 of its volume, all
 *    positively oriented, on its 4 corners and 6 edge midpoints; the inner
 *    octahedron is cut along its shortest diagonal;
 *  - on real meshes: 8x the tetrahedra, one new vertex per edge (no two
 *    vertices at the same place), the volume kept to round-off, every
 *    child positive, a conforming mesh (each face shared by at most two
 *    tetrahedra, 4x the boundary faces) with the same Euler characteristic
 *    V - E + F - T; triangles split in 4 keeping their normals;
 *  - raptorTetra_8418.vtu: 8418 -> 67344 tetrahedra;
 *  - MeshLoader subdivide="1" feeds the refined mesh to the MechanicalObject. */
#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cable_test_util.h"
#include "io/mesh_subdivide.h"

static double tet_volume(const pl_mesh *m, int t)
{
    const int *v = m->tets + 4 * t;
    const double *a = m->verts + 3 * v[0], *b = m->verts + 3 * v[1], *c = m->verts + 3 * v[2],
                 *d = m->verts + 3 * v[3];
    double u[3], w[3], z[3];
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], w[k] = c[k] - a[k], z[k] = d[k] - a[k];
    return (u[0] * (w[1] * z[2] - w[2] * z[1]) - u[1] * (w[0] * z[2] - w[2] * z[0]) +
            u[2] * (w[0] * z[1] - w[1] * z[0])) / 6.0;
}

static double total_volume(const pl_mesh *m)
{
    double s = 0;
    for (int t = 0; t < m->ntets; ++t) s += tet_volume(m, t);
    return s;
}

static pl_mesh subdivided(const pl_mesh *in, int rounds)
{
    pl_mesh out;
    pl_error err;
    ck_assert_int_eq(pl_mesh_copy(&out, in), PL_OK);
    ck_assert_int_eq(pl_mesh_subdivide(&out, rounds, &err), PL_OK);
    return out;
}

START_TEST(one_tetrahedron)
{
    /* a stretched tetrahedron: its octahedron's diagonals differ */
    double x[] = {0, 0, 0, 3, 0, 0, 0.4, 1, 0, 2.5, 0.3, 0.5};
    int t[] = {0, 1, 2, 3};
    pl_mesh m = {4, x, 1, t, 0, NULL};
    pl_mesh s = subdivided(&m, 1);
    ck_assert_int_eq(s.ntets, 8);
    ck_assert_int_eq(s.nverts, 10);
    double V = tet_volume(&m, 0);
    for (int k = 0; k < 8; ++k) ck_assert_double_eq_tol(tet_volume(&s, k), V / 8, 1e-15 * V);
    /* every new vertex is the midpoint of an edge of the parent */
    for (int i = 4; i < 10; ++i) {
        int found = 0;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) {
                int same = 1;
                for (int k = 0; k < 3; ++k)
                    same &= fabs(s.verts[3 * i + k] - 0.5 * (x[3 * a + k] + x[3 * b + k])) < 1e-15;
                found += same;
            }
        ck_assert_int_eq(found, 1);
    }
    /* the last four children share the octahedron's diagonal: the shortest
     * of the three segments joining midpoints of opposite edges */
    int common[2], nc = 0;
    for (int a = 0; a < 4; ++a) {
        int v = s.tets[16 + a], in_all = 1;
        for (int c = 1; c < 4; ++c) {
            int hit = 0;
            for (int b = 0; b < 4; ++b) hit |= s.tets[16 + 4 * c + b] == v;
            in_all &= hit;
        }
        if (in_all && nc < 2) common[nc++] = v;
    }
    ck_assert_int_eq(nc, 2);
    double dl = 0;
    for (int k = 0; k < 3; ++k)
        dl += pow(s.verts[3 * common[0] + k] - s.verts[3 * common[1] + k], 2);
    /* the three diagonals of this tetrahedron: |(m01 - m23)|, |(m02 - m13)|, |(m03 - m12)| */
    double dmin = INFINITY;
    const int opp[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
    for (int d = 0; d < 3; ++d) {
        double l = 0;
        for (int k = 0; k < 3; ++k) {
            double p = 0.5 * (x[3 * opp[d][0] + k] + x[3 * opp[d][1] + k]);
            double q = 0.5 * (x[3 * opp[d][2] + k] + x[3 * opp[d][3] + k]);
            l += (p - q) * (p - q);
        }
        dmin = fmin(dmin, l);
    }
    ck_assert_double_eq_tol(dl, dmin, 1e-15);
    pl_mesh_free(&s);
}
END_TEST

static int cmp_key(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    for (int k = 0; k < 2; ++k)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* Edges and faces of the tetrahedra, counted by sorting; *bfaces gets the
 * faces used once, *over the faces used more than twice. */
static void count_topology(const pl_mesh *m, long *edges, long *faces, long *bfaces, long *over)
{
    int64_t *e = malloc(sizeof(int64_t) * 2 * 6 * (size_t)m->ntets);
    int64_t *f = malloc(sizeof(int64_t) * 2 * 4 * (size_t)m->ntets);
    const int E[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    for (int t = 0; t < m->ntets; ++t) {
        const int *v = m->tets + 4 * t;
        for (int k = 0; k < 6; ++k) {
            int a = v[E[k][0]], b = v[E[k][1]];
            e[2 * (6 * t + k)] = a < b ? a : b;
            e[2 * (6 * t + k) + 1] = a < b ? b : a;
        }
        for (int k = 0; k < 4; ++k) {
            int w[3], n = 0;
            for (int j = 0; j < 4; ++j)
                if (j != k) w[n++] = v[j];
            for (int i = 0; i < 3; ++i) /* sort 3 */
                for (int j = i + 1; j < 3; ++j)
                    if (w[j] < w[i]) { int s = w[i]; w[i] = w[j]; w[j] = s; }
            f[2 * (4 * t + k)] = w[0];
            f[2 * (4 * t + k) + 1] = ((int64_t)w[1] << 32) | w[2];
        }
    }
    qsort(e, 6 * (size_t)m->ntets, 2 * sizeof(int64_t), cmp_key);
    qsort(f, 4 * (size_t)m->ntets, 2 * sizeof(int64_t), cmp_key);
    *edges = 0;
    for (long k = 0; k < 6L * m->ntets; ++k)
        if (k == 0 || cmp_key(e + 2 * k, e + 2 * (k - 1))) ++*edges;
    *faces = *bfaces = *over = 0;
    for (long k = 0; k < 4L * m->ntets;) {
        long j = k;
        while (j < 4L * m->ntets && !cmp_key(f + 2 * j, f + 2 * k)) j++;
        ++*faces;
        if (j - k == 1) ++*bfaces;
        if (j - k > 2) ++*over;
        k = j;
    }
    free(e);
    free(f);
}

static int cmp_point(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* Checks a subdivision of `m` by `rounds` rounds against the invariants. */
static pl_mesh check_mesh(const char *file, int rounds)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/meshes/%s", PL_SOURCE_DIR, file);
    pl_mesh m;
    pl_diag d;
    pl_diag_init(&d);
    pl_mesh_init(&m);
    pl_mesh_load_options opt = {.drop_unused = 1}; /* drop unused vertices: Euler's formula counts used ones */
    ck_assert_int_eq(pl_mesh_load(path, &opt, &m, &d), PL_OK);
    pl_diag_free(&d);
    pl_mesh s = subdivided(&m, rounds);
    long p8 = 1, p4 = 1;
    for (int r = 0; r < rounds; ++r) p8 *= 8, p4 *= 4;
    ck_assert_int_eq(s.ntets, m.ntets * p8);
    double V = total_volume(&m), Vs = total_volume(&s);
    ck_assert_double_eq_tol(Vs, V, 1e-12 * V);
    for (int t = 0; t < s.ntets; ++t) ck_assert_double_gt(tet_volume(&s, t), 0.0);
    long E0, F0, B0, O0, E1, F1, B1, O1;
    count_topology(&m, &E0, &F0, &B0, &O0);
    count_topology(&s, &E1, &F1, &B1, &O1);
    ck_assert_int_eq(O1, 0);
    ck_assert_int_eq(B1, B0 * p4); /* each boundary triangle split in 4 per round */
    ck_assert_int_eq(m.nverts - E0 + F0 - m.ntets, s.nverts - E1 + F1 - s.ntets);
    if (rounds == 1) ck_assert_int_eq(s.nverts, m.nverts + E0); /* one new vertex per edge */
    /* no two vertices at the same place: midpoints are shared, not repeated */
    double *p = malloc(sizeof(double) * 3 * (size_t)s.nverts);
    memcpy(p, s.verts, sizeof(double) * 3 * (size_t)s.nverts);
    qsort(p, (size_t)s.nverts, 3 * sizeof(double), cmp_point);
    for (int i = 1; i < s.nverts; ++i) ck_assert_int_ne(cmp_point(p + 3 * i, p + 3 * (i - 1)), 0);
    free(p);
    pl_mesh_free(&m);
    return s;
}

START_TEST(real_meshes_conform)
{
    pl_mesh s = check_mesh("cube_low_res.msh", 1);
    pl_mesh_free(&s);
    s = check_mesh("cube_low_res.msh", 2);
    pl_mesh_free(&s);
    s = check_mesh("liver.msh", 1);
    pl_mesh_free(&s);
}
END_TEST

START_TEST(raptor_8418)
{
    pl_mesh s = check_mesh("raptorTetra_8418.vtu", 1);
    ck_assert_int_eq(s.ntets, 67344);
    pl_mesh_free(&s);
}
END_TEST

START_TEST(triangles_split_in_four)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/meshes/finger.vtk", PL_SOURCE_DIR);
    pl_mesh m;
    pl_diag d;
    pl_diag_init(&d);
    pl_mesh_init(&m);
    ck_assert_int_eq(pl_mesh_load(path, NULL, &m, &d), PL_OK);
    pl_diag_free(&d);
    ck_assert_int_gt(m.ntris, 0);
    pl_mesh s = subdivided(&m, 1);
    ck_assert_int_eq(s.ntris, 4 * m.ntris);
    for (int t = 0; t < m.ntris; ++t) {
        double n0[3], a0;
        const int *v = m.tris + 3 * t;
        const double *A = m.verts + 3 * v[0], *B = m.verts + 3 * v[1], *C = m.verts + 3 * v[2];
        double u[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]}, w[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
        n0[0] = u[1] * w[2] - u[2] * w[1], n0[1] = u[2] * w[0] - u[0] * w[2], n0[2] = u[0] * w[1] - u[1] * w[0];
        a0 = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
        for (int c = 0; c < 4; ++c) {
            const int *k = s.tris + 3 * (4 * t + c);
            const double *P = s.verts + 3 * k[0], *Q = s.verts + 3 * k[1], *R = s.verts + 3 * k[2];
            double a[3] = {Q[0] - P[0], Q[1] - P[1], Q[2] - P[2]}, b[3] = {R[0] - P[0], R[1] - P[1], R[2] - P[2]};
            double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
            for (int j = 0; j < 3; ++j) ck_assert_double_eq_tol(n[j], n0[j] / 4, 1e-12 * a0);
        }
    }
    pl_mesh_free(&s);
    pl_mesh_free(&m);
}
END_TEST

START_TEST(mesh_loader_field)
{
    char xml[1024];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\"><MeshLoader name=\"m\" filename=\"%s/scenes/meshes/liver.msh\" "
             "subdivide=\"1\"/><MechanicalObject name=\"dofs\"/></Node>",
             PL_SOURCE_DIR);
    pl_sim *s = ct_load(xml);
    int n;
    ct_positions(s, "dofs", 0, &n);
    pl_sim_free(s);
    pl_mesh m, sub;
    pl_diag d;
    pl_diag_init(&d);
    pl_mesh_init(&m);
    snprintf(xml, sizeof xml, "%s/scenes/meshes/liver.msh", PL_SOURCE_DIR);
    ck_assert_int_eq(pl_mesh_load(xml, NULL, &m, &d), PL_OK);
    sub = subdivided(&m, 1);
    ck_assert_int_eq(n, sub.nverts);
    pl_mesh_free(&m);
    pl_mesh_free(&sub);
    pl_diag_free(&d);
    /* a negative count is an error on the loader's line */
    snprintf(xml, sizeof xml,
             "<Node name=\"root\">\n<MeshLoader filename=\"%s/scenes/meshes/liver.msh\" "
             "subdivide=\"-1\"/></Node>",
             PL_SOURCE_DIR);
    d = ct_load_fail(xml);
    const pl_error *e = ct_find_error(&d, "subdivide must be >= 0");
    ck_assert_ptr_nonnull(e);
    ck_assert_int_eq(e->line, 2);
    pl_diag_free(&d);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("mesh_subdivide");
    TCase *tc = tcase_create("subdivide");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, one_tetrahedron);
    tcase_add_test(tc, real_meshes_conform);
    tcase_add_test(tc, raptor_8418);
    tcase_add_test(tc, triangles_split_in_four);
    tcase_add_test(tc, mesh_loader_field);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
