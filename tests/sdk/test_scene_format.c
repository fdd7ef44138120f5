/* test_scene_format.c - the scene format does not depend on the build:
 * every field exists in every build (SparseInverseSolver device/precision,
 * NonSmoothNewtonContactSolver device), the cuda plugin and its CudaDevice
 * exist in a build without CUDA too, and a scene declaring them loads and
 * runs on the CPU with one warning where there is no device (no CUDA in the
 * build, or no GPU on the machine) - bitwise the run of the same scene
 * without them.  Asking for cuda where the build has none is an error at
 * init (and where the device is absent, an input error at load).  Both
 * builds of `make test` run this (with and without CUDA). */
#include <check.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A small box resting on a plane, every device field given (line 9: the
 * SparseInverseSolver).  %s: the device declaration, %s: the global
 * solver's device. */
static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
    "  <RequiredPlugin name=\"hyperelastic\"/>\n"
    "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
    "  <RequiredPlugin name=\"ncp_contact\"/>\n"
    "  <RequiredPlugin name=\"collision\"/>\n"
    "  %s\n"
    "  <LocalGlobalSolver name=\"solver\" iterations=\"5\" device=\"auto\"/>\n"
    "  <NonSmoothNewtonContactSolver name=\"contact\" device=\"auto\"/>\n"
    "  <SparseInverseSolver name=\"global\" device=\"%s\" precision=\"float64\"/>\n"
    "  <PlaneObstacle name=\"floor\" point=\"0 0 0\" normal=\"0 1 0\" mu=\"0.5\"/>\n"
    "  <Node name=\"box\">\n"
    "    <RegularGridTetrahedra name=\"grid\" min=\"0 0.001 0\" max=\"0.1 0.101 0.1\" n=\"3 3 3\"/>\n"
    "    <MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
    "    <DiagonalMass massDensity=\"1000\"/>\n"
    "    <NeoHookean youngModulus=\"1e6\" poissonRatio=\"0.3\"/>\n"
    "    <SurfaceCollisionModel name=\"surface\"/>\n"
    "  </Node>\n"
    "</Node>\n";

static const char *DEVICE = "<RequiredPlugin name=\"cuda\"/><CudaDevice name=\"gpu\"/>";

static pl_sim *load(const char *device, const char *global_device, pl_diag *diag)
{
    char xml[4096];
    snprintf(xml, sizeof xml, SCENE, device, global_device);
    pl_sim_options opt = {.device = "cpu"}; /* no implicit device: the scene says */
    return pl_sim_load_string(xml, "format.xml", &opt, diag);
}

/* Whether the scene's CudaDevice has a device behind it (a GPU answered). */
static int device_present(pl_sim *s)
{
    pl_component *c = pl_sim_component(s, "gpu");
    const pl_device_ops *ops = c ? pl_component_role(c, PL_ROLE_DEVICE) : NULL;
    return ops && ops->flags && !(ops->flags(c) & PL_DEVICE_ABSENT);
}

START_TEST(every_field_and_the_cuda_plugin_exist_in_every_build)
{
    pl_error err;
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_register_builtin_components(r, &err), PL_OK);
    const char *plugins[] = {"sparse_inverse", "ncp_contact", "cuda"};
    for (int k = 0; k < 3; ++k)
        ck_assert_msg(pl_registry_load_plugin(r, plugins[k], &err) == PL_OK, "%s", err.msg);
    struct {
        const char *type, *field;
    } need[] = {{"SparseInverseSolver", "device"}, {"SparseInverseSolver", "precision"},
                {"NonSmoothNewtonContactSolver", "device"}, {"LocalGlobalSolver", "device"},
                {"CudaDevice", "device"}, {"CudaDevice", "graph"}, {"CudaDevice", "profile"}};
    for (size_t k = 0; k < sizeof need / sizeof need[0]; ++k) {
        const pl_type *t = pl_registry_find(r, need[k].type);
        ck_assert_msg(t != NULL, "no %s", need[k].type);
        int found = 0;
        for (int f = 0; f < t->nfields; ++f) found |= !strcmp(t->fields[f].name, need[k].field);
        ck_assert_msg(found, "%s has no field %s in this build", need[k].type, need[k].field);
    }
    ck_assert_ptr_nonnull(pl_registry_find(r, "CudaDevice")->roles[PL_ROLE_DEVICE]);
    ck_assert_str_eq(pl_registry_type_plugin(r, pl_registry_find(r, "CudaDevice")), "cuda");
    pl_registry_free(r);
}
END_TEST

START_TEST(a_declared_device_without_a_device_runs_on_the_cpu_with_one_warning)
{
    pl_diag d0, d1;
    pl_diag_init(&d0);
    pl_diag_init(&d1);
    pl_sim *with = load(DEVICE, "auto", &d1);
    ck_assert_msg(with != NULL, "%s", d1.count ? d1.items[0].msg : "");
    if (device_present(with)) {
        /* a GPU answered: nothing to say, and this test is about its absence */
        ck_assert_int_eq(d1.count, 0);
        pl_sim_free(with);
        pl_diag_free(&d1);
        return;
    }
    ck_assert_int_eq(d1.nerrors, 0);
    ck_assert_int_eq(d1.count, 1);
    ck_assert_ptr_nonnull(strstr(d1.items[0].where, "CudaDevice root/gpu"));
    ck_assert_ptr_nonnull(strstr(d1.items[0].msg, "the scene runs on the CPU"));
#ifndef PLIANT_HAVE_CUDA
    ck_assert_ptr_nonnull(strstr(d1.items[0].msg, "this build has no CUDA"));
#endif
    pl_sim *without = load("", "auto", &d0);
    ck_assert_ptr_nonnull(without);
    ck_assert_int_eq(d0.count, 0);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(with, 8, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step(without, 8, &err), PL_OK);
    char a[8192], b[8192];
    ck_assert_int_eq(pl_sim_get(with, "box/dofs.position", a, sizeof a, &err), PL_OK);
    ck_assert_int_eq(pl_sim_get(without, "box/dofs.position", b, sizeof b, &err), PL_OK);
    ck_assert_str_eq(a, b);
    /* the box has fallen onto the plane: the run is not trivial */
    ck_assert_str_ne(a, "");
    pl_sim_free(with);
    pl_sim_free(without);
    pl_diag_free(&d0);
    pl_diag_free(&d1);
}
END_TEST

START_TEST(asking_for_cuda_without_it_is_an_error_at_init)
{
    pl_diag d;
    pl_diag_init(&d);
    pl_sim *s = load(DEVICE, "cuda", &d);
    if (s && device_present(s)) { /* a GPU machine: cuda is there */
        pl_sim_free(s);
        pl_diag_free(&d);
        return;
    }
    ck_assert_ptr_null(s);
    ck_assert_int_gt(d.nerrors, 0);
#ifndef PLIANT_HAVE_CUDA
    const char *why = "this build has no CUDA";
#else
    const char *why = "has no device here (no GPU answers)";
#endif
    int found = 0;
    for (int k = 0; k < d.count; ++k)
        found |= d.items[k].code == PL_EINPUT && d.items[k].line == 9 &&
                 strstr(d.items[k].msg, why) != NULL;
    ck_assert_msg(found, "no input error '%s' at line 9", why);
    pl_diag_free(&d);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("scene_format");
    TCase *tc = tcase_create("format");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, every_field_and_the_cuda_plugin_exist_in_every_build);
    tcase_add_test(tc, a_declared_device_without_a_device_runs_on_the_cpu_with_one_warning);
    tcase_add_test(tc, asking_for_cuda_without_it_is_an_error_at_init);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
