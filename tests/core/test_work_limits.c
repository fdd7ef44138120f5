/* test_work_limits.c - what a scene asks for is estimated before it starts
 * and refused above the caps of pliant/work_limits.h, with the file and
 * line of what asked (issue 13): subdivision rounds, generated mesh sizes,
 * solver iterations, the time step.  A WorkLimits component moves the caps,
 * both ways. */
#include <check.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "test_tmp.h"

static pl_diag diag;
static char tet_path[1024];

static void setup(void)
{
    pl_diag_init(&diag);
    int fd = test_tmp_file(tet_path, sizeof tet_path, "limits");
    ck_assert_int_ge(fd, 0);
    const char *vtk = "# vtk DataFile Version 2.0\none tetrahedron\nASCII\nDATASET "
                      "UNSTRUCTURED_GRID\nPOINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                      "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n";
    ck_assert_int_eq(write(fd, vtk, strlen(vtk)), (int)strlen(vtk));
    close(fd);
}

static void teardown(void)
{
    pl_diag_free(&diag);
    unlink(tet_path);
}

/* Loads `body` (the children of the root node, from line 2 on); NULL on failure. */
static pl_sim *load(const char *root_attrs, const char *body)
{
    char xml[2600];
    snprintf(xml, sizeof xml, "<Node name=\"root\"%s>\n%s</Node>\n", root_attrs, body);
    pl_sim *s = pl_sim_load_string(xml, "limits.xml", NULL, &diag);
    if (getenv("PL_TEST_VERBOSE")) pl_diag_print(&diag, stderr);
    return s;
}

/* The error mentioning `needle`: input error, the scene file, `line`. */
static void expect_refused(const char *needle, int line)
{
    for (int k = 0; k < diag.count; ++k)
        if (strstr(diag.items[k].msg, needle)) {
            ck_assert_int_eq(diag.items[k].code, PL_EINPUT);
            ck_assert_str_eq(diag.items[k].file, "limits.xml");
            ck_assert_int_eq(diag.items[k].line, line);
            pl_diag_free(&diag);
            pl_diag_init(&diag);
            return;
        }
    pl_diag_print(&diag, stderr);
    ck_abort_msg("no error mentioning '%s'", needle);
}

static int tets_of(pl_sim *s, const char *path)
{
    const pl_topology_ops *t = pl_component_role(pl_sim_component(s, path), PL_ROLE_TOPOLOGY);
    return t->mesh(pl_sim_component(s, path))->ntets;
}

START_TEST(subdivision_is_estimated_before_it_starts)
{
    char body[2048];
    /* the case: 30 rounds of one tetrahedron (8^30 of them) */
    snprintf(body, sizeof body, "  <MeshLoader name=\"m\" filename=\"%s\" subdivide=\"30\"/>\n",
             tet_path);
    clock_t t0 = clock();
    ck_assert_ptr_null(load("", body));
    ck_assert(clock() - t0 < CLOCKS_PER_SEC / 2);
    expect_refused("subdivide=\"30\"", 2);
    /* 3 rounds make 8^3 = 512 tetrahedra: within the default cap... */
    snprintf(body, sizeof body, "  <MeshLoader name=\"m\" filename=\"%s\" subdivide=\"3\"/>\n",
             tet_path);
    pl_sim *s = load("", body);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(tets_of(s, "m"), 512);
    pl_sim_free(s);
    /* ...above a cap of 500 set by the scene, in this node or above */
    snprintf(body, sizeof body, "  <WorkLimits maxElements=\"500\"/>\n  <Node name=\"a\">\n"
             "    <MeshLoader name=\"m\" filename=\"%s\" subdivide=\"3\"/>\n  </Node>\n",
             tet_path);
    ck_assert_ptr_null(load("", body));
    expect_refused("maxElements", 4);
    /* and a node below may raise it again for itself */
    snprintf(body, sizeof body, "  <WorkLimits maxElements=\"500\"/>\n  <Node name=\"a\">\n"
             "    <WorkLimits maxElements=\"512\"/>\n"
             "    <MeshLoader name=\"m\" filename=\"%s\" subdivide=\"3\"/>\n  </Node>\n",
             tet_path);
    s = load("", body);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(tets_of(s, "a/m"), 512);
    /* a program running scenes it does not trust sets ceilings no scene can raise */
    char xml[2600];
    snprintf(xml, sizeof xml, "<Node name=\"root\">\n%s</Node>\n", body);
    pl_work_limits ceiling = {100, 10, 10, 1, 0.1};
    pl_sim_options opt = {.max_limits = &ceiling};
    ck_assert_ptr_null(pl_sim_load_string(xml, "limits.xml", &opt, &diag));
    expect_refused("above the cap of 100 ", 5);
    pl_sim_free(s);
}
END_TEST

START_TEST(generated_meshes_are_estimated_before_they_are_made)
{
    clock_t t0 = clock();
    ck_assert_ptr_null(load("", "  <RegularGridTetrahedra n=\"20000 20000 20000\"/>\n"));
    expect_refused("would generate would be 4.79928e+13", 2);
    ck_assert_ptr_null(load("", "\n  <RegularGridTriangles n=\"100000 1 100000\"/>\n"));
    expect_refused("above the cap of 10000000", 3);
    ck_assert_ptr_null(load("", "  <SphereMesh vertices=\"40000000\"/>\n"));
    expect_refused("maxElements", 2);
    ck_assert_ptr_null(load("", "  <CylinderMesh rings=\"4000\" layers=\"100000\"/>\n"));
    expect_refused("maxElements", 2);
    ck_assert(clock() - t0 < CLOCKS_PER_SEC);
    /* 6 (n-1)^3 exactly at the cap passes, one cell more is refused */
    pl_sim *s = load("", "  <WorkLimits maxElements=\"6000\"/>\n"
                         "  <RegularGridTetrahedra name=\"g\" n=\"11 11 11\"/>\n");
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(tets_of(s, "g"), 6000);
    pl_sim_free(s);
    ck_assert_ptr_null(load("", "  <WorkLimits maxElements=\"5999\"/>\n"
                                "  <RegularGridTetrahedra name=\"g\" n=\"11 11 11\"/>\n"));
    expect_refused("maxElements", 3);
}
END_TEST

START_TEST(iterations_and_time_steps_are_capped)
{
    const char *bar = "  <Node name=\"bar\">\n    <RegularGridTetrahedra n=\"3 2 2\"/>\n"
                      "    <MechanicalObject/>\n    <DiagonalMass massDensity=\"1000\"/>\n"
                      "  </Node>\n";
    char body[1024];
    snprintf(body, sizeof body, "  <LocalGlobalSolver iterations=\"2000000000\"/>\n%s", bar);
    ck_assert_ptr_null(load("", body));
    expect_refused("iterations (per time step) would be 2e+09", 2);
    snprintf(body, sizeof body, "\n  <NewtonSolver maxIterations=\"100001\"/>\n%s", bar);
    ck_assert_ptr_null(load("", body));
    expect_refused("maxIterations (per time step) would be 100001", 3);
    /* dt = 1e308 is finite, and overflows at the first step: bad input */
    snprintf(body, sizeof body, "  <NewtonSolver maxIterations=\"5\"/>\n%s", bar);
    ck_assert_ptr_null(load(" dt=\"1e308\"", body));
    expect_refused("dt = 1e+308 s is above the cap of 1 s", 1);
    ck_assert_ptr_null(load("", "  <Node name=\"n\" dt=\"2\"/>\n"));
    expect_refused("maxTimeStep", 2);
    /* the same scenes within their caps load and step */
    pl_sim *s = load(" dt=\"0.01\"", body);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 2, &err), PL_OK);
    pl_sim_free(s);
    snprintf(body, sizeof body, "  <WorkLimits maxTimeStep=\"5\" maxIterations=\"10\"/>\n"
             "  <NewtonSolver maxIterations=\"10\"/>\n%s", bar);
    s = load(" dt=\"2\"", body);
    ck_assert_ptr_nonnull(s);
    pl_sim_free(s);
    /* bad caps are input errors too */
    ck_assert_ptr_null(load("", "  <WorkLimits maxElements=\"-1\"/>\n"));
    expect_refused("maxElements must be positive", 2);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("work_limits");
    TCase *tc = tcase_create("limits");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, subdivision_is_estimated_before_it_starts);
    tcase_add_test(tc, generated_meshes_are_estimated_before_they_are_made);
    tcase_add_test(tc, iterations_and_time_steps_are_capped);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
