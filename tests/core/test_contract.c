/* test_contract.c - the plugin contract as the core enforces it: a
 * lifecycle status is honoured even when the plugin says nothing, types are
 * identified by pointer, and plugins of an older minor ABI version load
 * while newer or other-major ones, and role tables of unknown versions, are
 * refused with both versions named. */
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

/* Whether some diagnostic contains both fragments (b may be NULL). */
static int has(const char *a, const char *b)
{
    for (int k = 0; k < diag.count; ++k) {
        char buf[2048];
        pl_error_format(&diag.items[k], buf, sizeof buf);
        if (strstr(buf, a) && (!b || strstr(buf, b))) return 1;
    }
    return 0;
}

/* A scene with a TestFailer on line 4 failing at `stage` with `code`. */
static pl_sim *load_failer(const char *stage, int code)
{
    char xml[1024];
    snprintf(xml, sizeof xml,
             "<Node name=\"root\">\n"
             "  <RequiredPlugin name=\"pl_contract\"/>\n"
             "  <Node name=\"body\"/>\n"
             "  <TestFailer name=\"failer\" failAt=\"%s\" code=\"%d\"/>\n"
             "</Node>\n",
             stage, code);
    return pl_sim_load_string(xml, "failer.xml", NULL, &diag);
}

START_TEST(a_silent_load_failure_stops_the_load_naming_the_component)
{
    const char *stages[] = {"init", "bind", "reinit"};
    for (int k = 0; k < 3; ++k) {
        pl_diag_free(&diag);
        pl_diag_init(&diag);
        ck_assert_ptr_null(load_failer(stages[k], PL_EINPUT));
        char what[64];
        snprintf(what, sizeof what, "%s failed (status 2) without saying why", stages[k]);
        ck_assert_msg(has(what, "TestFailer root/failer"), "no generic error for %s", stages[k]);
        ck_assert_int_eq(diag.nerrors, 1);
        ck_assert_int_eq(diag.items[0].line, 4);
        ck_assert_str_eq(diag.items[0].file, "failer.xml");
        ck_assert_int_eq(pl_diag_status(&diag), PL_EINPUT);
    }
    /* any other non-zero status is a failure too, reported as internal */
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    ck_assert_ptr_null(load_failer("init", 7));
    ck_assert(has("init failed (status 7)", NULL));
    ck_assert_int_eq(pl_diag_status(&diag), PL_EINTERNAL);
}
END_TEST

START_TEST(a_silent_step_failure_stops_the_step_naming_the_component)
{
    const char *stages[] = {"begin_step", "end_step"};
    for (int k = 0; k < 2; ++k) {
        pl_sim *s = load_failer(stages[k], PL_EINPUT);
        ck_assert_ptr_nonnull(s);
        pl_error err;
        ck_assert_int_eq(pl_sim_step(s, 3, &err), PL_EINPUT);
        ck_assert_ptr_nonnull(strstr(err.msg, stages[k]));
        ck_assert_ptr_nonnull(strstr(err.msg, "without saying why"));
        ck_assert_ptr_nonnull(strstr(err.where, "TestFailer root/failer"));
        ck_assert_int_eq(err.line, 4);
        /* begin_step stops the first step before time advances */
        if (k == 0) ck_assert_double_eq(pl_sim_time(s), 0.0);
        pl_sim_free(s);
    }
}
END_TEST

START_TEST(a_silent_reinit_failure_after_a_change_is_an_error)
{
    pl_sim *s = load_failer("none", PL_EINPUT);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    /* failAt is a model field: changing it runs reinit over the tree */
    ck_assert_int_eq(pl_sim_set(s, "failer.failAt", "reinit", &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "reinit failed"));
    pl_sim_free(s);
}
END_TEST

static const pl_type DUMMY = {.abi_version = PL_ABI_VERSION,
                              .name = "DummyThing",
                              .size = sizeof(pl_component)};

START_TEST(types_are_kept_and_identified_by_pointer)
{
    pl_error err;
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_register_builtin_components(r, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &DUMMY, &err), PL_OK);
    ck_assert_ptr_eq(pl_registry_find(r, "DummyThing"), &DUMMY);
    ck_assert_str_eq(pl_registry_type_plugin(r, &DUMMY), "builtin");
    ck_assert_ptr_null(pl_registry_type_plugin(r, NULL));
    /* a component's type is the definition itself */
    pl_sim_options opt = {.registry = r};
    pl_sim *s = pl_sim_load_string("<Node name=\"root\"><DummyThing name=\"d\"/></Node>", "d.xml",
                                   &opt, &diag);
    ck_assert_ptr_nonnull(s);
    ck_assert_ptr_eq(pl_sim_component(s, "d")->type, &DUMMY);
    pl_sim_free(s);
    /* a plugin's types carry its name */
    ck_assert_int_eq(pl_registry_load_plugin(r, "pl_contract", &err), PL_OK);
    ck_assert_str_eq(pl_registry_type_plugin(r, pl_registry_find(r, "TestFailer")), "pl_contract");
    pl_registry_free(r);
}
END_TEST

START_TEST(a_plugin_of_an_older_minor_version_loads_and_runs)
{
    pl_sim *s = pl_sim_load_string("<Node name=\"root\">\n"
                                   "  <RequiredPlugin name=\"pl_old_minor\"/>\n"
                                   "  <OldMinorCounter name=\"counter\"/>\n"
                                   "</Node>\n",
                                   "old.xml", NULL, &diag);
    ck_assert_msg(s != NULL, "%s", diag.count ? diag.items[0].msg : "");
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 5, &err), PL_OK);
    char buf[32];
    ck_assert_int_eq(pl_sim_get(s, "counter.count", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "5");
    const pl_type *t = pl_sim_component(s, "counter")->type;
    ck_assert_int_eq(t->abi_version, PL_ABI(PL_ABI_MAJOR, 0)); /* built for minor 0 */
    pl_sim_free(s);
}
END_TEST

START_TEST(plugins_this_host_cannot_run_are_refused_naming_both_versions)
{
    pl_error err;
    char host[32], newer[32];
    snprintf(host, sizeof host, "ABI version %d.%d", PL_ABI_MAJOR, PL_ABI_MINOR);
    snprintf(newer, sizeof newer, "ABI version %d.%d", PL_ABI_MAJOR, PL_ABI_MINOR + 1);
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_registry_load_plugin(r, "pl_new_minor", &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, newer) && strstr(err.msg, host), "%s", err.msg);
    ck_assert_int_eq(pl_registry_plugin_count(r), 0);
    /* before the major.minor scheme: one number */
    ck_assert_int_eq(pl_registry_load_plugin(r, "pl_wrong_abi_plugin", &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, "ABI version 999") && strstr(err.msg, host), "%s", err.msg);
    pl_registry_free(r);
}
END_TEST

static int noop_apply(const pl_component *c, pl_ctx *ctx, double t, pl_error *err) { return PL_OK; }
static const pl_controller_ops FUTURE_TABLE = {.version = PL_CONTROLLER_OPS_VERSION + 1,
                                               .apply = noop_apply};
static const pl_type FUTURE_ROLE = {.abi_version = PL_ABI_VERSION,
                                    .name = "FutureThing",
                                    .size = sizeof(pl_component),
                                    .roles = {[PL_ROLE_CONTROLLER] = &FUTURE_TABLE}};
static const pl_type OTHER_MAJOR = {.abi_version = PL_ABI(PL_ABI_MAJOR - 1, PL_ABI_MINOR),
                                    .name = "OldMajorThing",
                                    .size = sizeof(pl_component)};
static const pl_type UNKNOWN_ROLE = {.abi_version = PL_ABI_VERSION,
                                     .name = "UnknownRoleThing",
                                     .size = sizeof(pl_component),
                                     .roles = {[PL_ROLE_MAX - 1] = &FUTURE_TABLE}};

START_TEST(types_with_tables_this_host_cannot_read_are_refused)
{
    pl_error err;
    char expect[96];
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_registry_add(r, &FUTURE_ROLE, &err), PL_EINPUT);
    snprintf(expect, sizeof expect, "its controller table has version %d, this Pliant reads "
             "versions 1 to %d", PL_CONTROLLER_OPS_VERSION + 1, PL_CONTROLLER_OPS_VERSION);
    ck_assert_msg(strstr(err.msg, expect), "%s", err.msg);
    ck_assert_int_eq(pl_registry_add(r, &OTHER_MAJOR, &err), PL_EINPUT);
    snprintf(expect, sizeof expect, "built for ABI version %d.%d", PL_ABI_MAJOR - 1, PL_ABI_MINOR);
    ck_assert_msg(strstr(err.msg, expect), "%s", err.msg);
    ck_assert_int_eq(pl_registry_add(r, &UNKNOWN_ROLE, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "does not know"));
    ck_assert_int_eq(pl_registry_count(r), 0);
    pl_registry_free(r);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("contract");
    TCase *tc = tcase_create("contract");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, a_silent_load_failure_stops_the_load_naming_the_component);
    tcase_add_test(tc, a_silent_step_failure_stops_the_step_naming_the_component);
    tcase_add_test(tc, a_silent_reinit_failure_after_a_change_is_an_error);
    tcase_add_test(tc, types_are_kept_and_identified_by_pointer);
    tcase_add_test(tc, a_plugin_of_an_older_minor_version_loads_and_runs);
    tcase_add_test(tc, plugins_this_host_cannot_run_are_refused_naming_both_versions);
    tcase_add_test(tc, types_with_tables_this_host_cannot_read_are_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
