/* test_scene.c - the scene loader: every mistake reported with file:line,
 * the component path and the closest valid name; broken XML never crashes. */
#include <check.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static pl_diag diag;

static void setup(void)
{
    pl_diag_init(&diag);
    setenv("PLIANT_PLUGIN_PATH", PL_TEST_PLUGIN_DIR, 1);
}
static void teardown(void) { pl_diag_free(&diag); }

/* Loads xml as "scene.xml"; returns the sim (NULL on failure). */
static pl_sim *load(const char *xml)
{
    return pl_sim_load_string(xml, "scene.xml", NULL, &diag);
}

/* Whether some diagnostic contains all the given fragments. */
static int has(const char *a, const char *b, int line)
{
    for (int k = 0; k < diag.count; ++k) {
        char buf[2048];
        pl_error_format(&diag.items[k], buf, sizeof buf);
        if (strstr(buf, a) && (!b || strstr(buf, b)) && (line <= 0 || diag.items[k].line == line))
            return 1;
    }
    return 0;
}

static const char *GOOD =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
    "  <RequiredPlugin name=\"pl_test_plugin\"/>\n"
    "  <TestMover/>\n"
    "  <Node name=\"body\">\n"
    "    <MechanicalObject name=\"dofs\" position=\"0 0 0  1 0 0  0 1 0\" velocity=\"1 0 0\"/>\n"
    "  </Node>\n"
    "</Node>\n";

START_TEST(a_good_scene_loads)
{
    pl_sim *s = load(GOOD);
    pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(diag.nerrors, 0);
    pl_sim_free(s);
}
END_TEST

START_TEST(a_misspelled_attribute_names_file_line_and_suggestion)
{
    const char *xml = "<Node name=\"root\">\n"
                      "  <Node name=\"bar\">\n"
                      "    <MechanicalObject name=\"dofs\" positon=\"0 0 0\"/>\n"
                      "  </Node>\n"
                      "</Node>\n";
    ck_assert_ptr_null(load(xml));
    ck_assert(has("scene.xml:3:", "did you mean position?", 3));
    ck_assert(has("root/bar/dofs", NULL, 3));
}
END_TEST

START_TEST(an_unknown_component_gets_a_suggestion_and_all_errors_are_collected)
{
    const char *xml = "<Node name=\"root\">\n"
                      "  <MechanicalObjet position=\"0 0 0\"/>\n"
                      "  <UniformMass totalMas=\"1\"/>\n"
                      "  <MechanicalObject position=\"0 0 x\"/>\n"
                      "  <Zebra/>\n"
                      "</Node>\n";
    ck_assert_ptr_null(load(xml));
    ck_assert(has("did you mean MechanicalObject?", NULL, 2));
    ck_assert(has("did you mean totalMass?", NULL, 3));
    ck_assert(has("expected a finite number, found 'x'", NULL, 4));
    ck_assert(has("unknown component type 'Zebra'", "RequiredPlugin", 5));
    ck_assert_int_ge(diag.nerrors, 4);
}
END_TEST

START_TEST(node_attributes_are_checked)
{
    ck_assert_ptr_null(load("<Node name=\"r\" dt=\"-1\"/>"));
    ck_assert(has("dt", "positive", 1));
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    ck_assert_ptr_null(load("<Node name=\"r\" gravty=\"0 0 0\"/>"));
    ck_assert(has("did you mean gravity?", NULL, 1));
}
END_TEST

START_TEST(malformed_xml_reports_its_line)
{
    ck_assert_ptr_null(load("<Node name=\"root\">\n  <MechanicalObject position=\"0 0 0\">\n</Node>\n"));
    ck_assert(has("malformed XML", NULL, 0));
    ck_assert_int_gt(diag.items[0].line, 0);
}
END_TEST

START_TEST(entity_bombs_and_dtds_are_refused_quickly)
{
    const char *bomb =
        "<?xml version=\"1.0\"?>\n"
        "<!DOCTYPE lolz [<!ENTITY lol \"lol\">"
        "<!ENTITY lol2 \"&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;\">"
        "<!ENTITY lol3 \"&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;\">"
        "<!ENTITY lol4 \"&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;\">"
        "<!ENTITY lol9 \"&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;\">]>\n"
        "<Node name=\"&lol9;\"/>\n";
    double t0 = pl_now();
    ck_assert_ptr_null(load(bomb));
    ck_assert(pl_now() - t0 < 1.0);
    ck_assert(has("DTD", NULL, 0));
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    const char *ext = "<?xml version=\"1.0\"?>\n<!DOCTYPE x SYSTEM \"http://example.com/x.dtd\">\n"
                      "<Node/>\n";
    ck_assert_ptr_null(load(ext));
}
END_TEST

START_TEST(empty_wrong_root_and_missing_files)
{
    ck_assert_ptr_null(load(""));
    ck_assert(has("empty", NULL, 0));
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    ck_assert_ptr_null(load("<Scene/>"));
    ck_assert(has("root element must be <Node>", NULL, 1));
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    ck_assert_ptr_null(load("x"));
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    ck_assert_ptr_null(pl_sim_load_file("/nonexistent/scene.xml", NULL, &diag));
    ck_assert(has("/nonexistent/scene.xml", "cannot open", 0));
}
END_TEST

START_TEST(missing_plugin_wrong_link_and_required_field)
{
    const char *xml = "<Node name=\"root\">\n"
                      "  <RequiredPlugin name=\"no_such_plugin\"/>\n"
                      "  <MechanicalObject src=\"@nowhere\"/>\n"
                      "  <DiagonalMass/>\n"
                      "</Node>\n";
    ck_assert_ptr_null(load(xml));
    ck_assert(has("plugin 'no_such_plugin' not found", NULL, 2));
    ck_assert(has("missing required attribute 'massDensity'", NULL, 4));
}
END_TEST

START_TEST(overrides_apply_before_init_and_bad_ones_fail)
{
    const char *sets[] = {"dofs.velocity=2 0 0", "root.dt=0.005"};
    pl_sim_options opt = {.overrides = sets, .noverrides = 2};
    pl_sim *s = pl_sim_load_string(GOOD, "scene.xml", &opt, &diag);
    ck_assert_ptr_nonnull(s);
    char buf[256];
    pl_error err;
    ck_assert_int_eq(pl_sim_get(s, "root.dt", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0.0050000000000000001");
    ck_assert_int_eq(pl_sim_get(s, "body/dofs.velocity", buf, sizeof buf, &err), PL_OK);
    ck_assert(!strncmp(buf, "2 0 0 2 0 0", 11));
    pl_sim_free(s);
    const char *bad[] = {"dofs.velocityy=1"};
    opt.overrides = bad;
    opt.noverrides = 1;
    ck_assert_ptr_null(pl_sim_load_string(GOOD, "scene.xml", &opt, &diag));
    ck_assert(has("--set", "did you mean velocity?", 0));
}
END_TEST

/* The implicit device: loads GOOD (it has an animation loop) with the
 * cuda plugin's stand-in first on the plugin path. */
static pl_sim *load_with_device(const char *xml, const char *policy)
{
    setenv("PLIANT_PLUGIN_PATH", PL_FAKE_DEVICE_DIR ":" PL_TEST_PLUGIN_DIR, 1);
    pl_sim_options opt = {.device = policy};
    return pl_sim_load_string(xml, "scene.xml", &opt, &diag);
}

START_TEST(a_scene_without_a_device_gets_one_when_a_gpu_answers)
{
    unsetenv("FAKE_GPU");
    pl_sim *s = load_with_device(GOOD, "auto");
    ck_assert_ptr_nonnull(s);
    pl_component *dev = pl_sim_component(s, "cudaDevice");
    ck_assert_ptr_nonnull(dev);
    /* first in the root: it outlives the solvers that allocate through it */
    ck_assert_ptr_eq(pl_sim_model(s)->root->components[0], dev);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 2, &err), PL_OK);
    pl_sim_free(s);
    /* overrides reach it (applied before its trial init) */
    const char *sets[] = {"cudaDevice.device=1"};
    pl_sim_options opt = {.overrides = sets, .noverrides = 1, .device = "auto"};
    s = pl_sim_load_string(GOOD, "scene.xml", &opt, &diag);
    ck_assert_ptr_nonnull(s);
    char buf[64];
    ck_assert_int_eq(pl_sim_get(s, "cudaDevice.device", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "1");
    pl_sim_free(s);
}
END_TEST

START_TEST(no_implicit_device_without_a_gpu_with_cpu_or_a_declared_one)
{
    /* no GPU: the scene loads and runs on the CPU, without an error */
    setenv("FAKE_GPU", "0", 1);
    pl_sim *s = load_with_device(GOOD, "auto");
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(diag.nerrors, 0);
    ck_assert_ptr_null(pl_sim_component(s, "cudaDevice"));
    pl_sim_free(s);
    unsetenv("FAKE_GPU");
    /* policy cpu, from the options or from PLIANT_DEVICE */
    s = load_with_device(GOOD, "cpu");
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_null(pl_sim_component(s, "cudaDevice"));
    pl_sim_free(s);
    setenv("PLIANT_DEVICE", "cpu", 1);
    s = load_with_device(GOOD, NULL);
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_null(pl_sim_component(s, "cudaDevice"));
    pl_sim_free(s);
    unsetenv("PLIANT_DEVICE");
    /* a scene with its own device keeps it alone */
    const char *own = "<Node name=\"root\">\n"
                      "  <RequiredPlugin name=\"pl_test_plugin cuda\"/>\n"
                      "  <CudaDevice name=\"mine\"/>\n"
                      "  <TestMover/>\n"
                      "</Node>\n";
    s = load_with_device(own, "auto");
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_nonnull(pl_sim_component(s, "mine"));
    ck_assert_ptr_null(pl_sim_component(s, "cudaDevice"));
    pl_sim_free(s);
}
END_TEST

/* The cost model (core/src/device_cost.c) behind device=auto, with the
 * stand-in device as the GPU and the real plugins for the physics. */
static char log_text[8192];
static void keep_log(pl_log_level level, const char *msg, void *user)
{
    (void)level, (void)user;
    strncat(log_text, msg, sizeof log_text - strlen(log_text) - 2);
    strcat(log_text, "\n");
}

/* A 3 x 4 x 3 Neo-Hookean bar (36 vertices, 72 tetrahedra); %s: the root's
 * extra components, %s: the global solver. */
static pl_sim *load_bar(const char *extra, const char *global, const char *policy)
{
    char xml[2048];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
             "  <RequiredPlugin name=\"cuda hyperelastic sparse_inverse\"/>\n%s"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"10\"/>\n  %s\n"
             "  <Node name=\"bar\">\n"
             "    <RegularGridTetrahedra name=\"grid\" min=\"0 -0.3 0\" max=\"0.1 0 0.1\" "
             "n=\"3 4 3\"/>\n"
             "    <MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
             "    <DiagonalMass massDensity=\"1000\"/>\n"
             "    <NeoHookean youngModulus=\"1e6\" poissonRatio=\"0.3\"/>\n"
             "    <FixedConstraint box=\"-1 -0.001 -1  1 0.001 1\"/>\n"
             "  </Node>\n</Node>\n",
             extra, global);
    setenv("PLIANT_PLUGIN_PATH", PL_FAKE_DEVICE_DIR ":" PL_BINARY_DIR "/plugins", 1);
    pl_sim_options opt = {.device = policy};
    log_text[0] = '\0';
    pl_log_level level = pl_log_get_level();
    pl_log_set_level(PL_LOG_INFO);
    pl_log_set_sink(keep_log, NULL);
    pl_sim *sim = pl_sim_load_string(xml, "bar.xml", &opt, &diag);
    pl_log_set_sink(NULL, NULL);
    pl_log_set_level(level);
    return sim;
}

START_TEST(device_auto_keeps_a_tiny_neohookean_scene_on_the_cpu)
{
    unsetenv("FAKE_GPU");
    pl_sim *s = load_bar("", "<SparseInverseSolver name=\"global\"/>", "auto");
    ck_assert_ptr_nonnull(s);
    /* a GPU answers, but the model predicts the CPU faster: no device */
    ck_assert_ptr_null(pl_sim_component(s, "cudaDevice"));
    double gpu = -1, cpu_ms = 0, gpu_ms = 0, tets = 0;
    pl_timers *t = pl_sim_timers(s);
    ck_assert_int_eq(pl_stat_get(t, "device auto: GPU chosen", &gpu), 0);
    ck_assert(gpu == 0);
    ck_assert_int_eq(pl_stat_get(t, "predicted CPU [ms/step]", &cpu_ms), 0);
    ck_assert_int_eq(pl_stat_get(t, "predicted GPU [ms/step]", &gpu_ms), 0);
    ck_assert(cpu_ms > 0 && cpu_ms < gpu_ms);
    /* the sizes the model read, and the log line that says why */
    ck_assert_int_eq(pl_stat_get(t, "cost: Neo-Hookean tetrahedra", &tets), 0);
    ck_assert_msg(tets == 2 * 3 * 2 * 6 || tets == 2 * 3 * 2 * 5, "%g tetrahedra", tets);
    double verts = 0;
    ck_assert_int_eq(pl_stat_get(t, "cost: vertices", &verts), 0);
    ck_assert(verts == 36);
    ck_assert_msg(strstr(log_text, "bar.xml: no device in the scene (device=auto): CPU chosen: "
                                   "predicted") &&
                      strstr(log_text, "tetrahedra Neo-Hookean"),
                  "%s", log_text);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 2, &err), PL_OK);
    pl_sim_free(s);
}
END_TEST

START_TEST(a_declared_device_or_gpu_always_is_never_overridden)
{
    unsetenv("FAKE_GPU");
    /* the scene's own CudaDevice stays, whatever the model predicts (the
     * JacobiSolver keeps the stand-in device unused: it has no device path) */
    pl_sim *s = load_bar("  <CudaDevice name=\"mine\"/>\n", "<JacobiSolver name=\"global\"/>",
                         "auto");
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_nonnull(pl_sim_component(s, "mine"));
    double v;
    ck_assert_int_ne(pl_stat_get(pl_sim_timers(s), "device auto: GPU chosen", &v), 0);
    ck_assert_int_eq(pl_stat_get(pl_sim_timers(s), "predicted CPU [ms/step]", &v), 0);
    ck_assert_ptr_null(strstr(log_text, "chosen"));
    pl_sim_free(s);
    /* gpu-always: the implicit device whenever a GPU answers */
    s = load_bar("", "<JacobiSolver name=\"global\"/>", "gpu-always");
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_nonnull(pl_sim_component(s, "cudaDevice"));
    ck_assert_int_ne(pl_stat_get(pl_sim_timers(s), "device auto: GPU chosen", &v), 0);
    pl_sim_free(s);
    /* no GPU: never a device, the model's choice is not asked */
    setenv("FAKE_GPU", "0", 1);
    s = load_bar("", "<SparseInverseSolver name=\"global\"/>", "auto");
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_null(pl_sim_component(s, "cudaDevice"));
    ck_assert_int_ne(pl_stat_get(pl_sim_timers(s), "device auto: GPU chosen", &v), 0);
    pl_sim_free(s);
    unsetenv("FAKE_GPU");
}
END_TEST

START_TEST(a_bad_device_policy_is_an_error)
{
    ck_assert_ptr_null(load_with_device(GOOD, "gpu"));
    ck_assert(has("'gpu' is not a device policy (cpu or auto)", NULL, 0));
    pl_diag_free(&diag); /* the loader stops at errors already in diag */
    pl_diag_init(&diag);
    setenv("PLIANT_DEVICE", "cuda", 1);
    ck_assert_ptr_null(load_with_device(GOOD, NULL));
    unsetenv("PLIANT_DEVICE");
    ck_assert(has("PLIANT_DEVICE: 'cuda' is not a device policy", NULL, 0));
}
END_TEST

int main(void)
{
    Suite *s = suite_create("scene");
    TCase *tc = tcase_create("loader");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, a_good_scene_loads);
    tcase_add_test(tc, a_misspelled_attribute_names_file_line_and_suggestion);
    tcase_add_test(tc, an_unknown_component_gets_a_suggestion_and_all_errors_are_collected);
    tcase_add_test(tc, node_attributes_are_checked);
    tcase_add_test(tc, malformed_xml_reports_its_line);
    tcase_add_test(tc, entity_bombs_and_dtds_are_refused_quickly);
    tcase_add_test(tc, empty_wrong_root_and_missing_files);
    tcase_add_test(tc, missing_plugin_wrong_link_and_required_field);
    tcase_add_test(tc, overrides_apply_before_init_and_bad_ones_fail);
    tcase_add_test(tc, a_scene_without_a_device_gets_one_when_a_gpu_answers);
    tcase_add_test(tc, no_implicit_device_without_a_gpu_with_cpu_or_a_declared_one);
    tcase_add_test(tc, a_bad_device_policy_is_an_error);
    tcase_add_test(tc, device_auto_keeps_a_tiny_neohookean_scene_on_the_cpu);
    tcase_add_test(tc, a_declared_device_or_gpu_always_is_never_overridden);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
