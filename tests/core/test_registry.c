/* test_registry.c - the registry and plugin loading: a good plugin, a
 * plugin of another ABI version, a .so that is no plugin, a missing one. */
#include <check.h>
#include <pliant/pliant.h>
#include <stdlib.h>
#include <string.h>

static const pl_type DUMMY = {.abi_version = PL_ABI_VERSION,
                              .name = "DummyThing",
                              .size = sizeof(pl_component)};
static const pl_type OLD = {.abi_version = PL_ABI_VERSION + 7,
                            .name = "OldThing",
                            .size = sizeof(pl_component)};

START_TEST(types_are_found_suggested_and_not_duplicated)
{
    pl_error err;
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_register_builtin_components(r, &err), PL_OK);
    ck_assert_ptr_nonnull(pl_registry_find(r, "MechanicalObject"));
    ck_assert_str_eq(pl_registry_suggest(r, "MechanicalObjet"), "MechanicalObject");
    ck_assert_ptr_null(pl_registry_suggest(r, "Zebra"));
    ck_assert_int_eq(pl_registry_add(r, &DUMMY, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &DUMMY, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "twice"));
    ck_assert_int_eq(pl_registry_add(r, &OLD, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "ABI version"));
    pl_registry_free(r);
}
END_TEST

START_TEST(a_good_plugin_registers_its_types)
{
    pl_error err;
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_registry_add_plugin_dir(r, PL_TEST_PLUGIN_DIR), PL_OK);
    ck_assert_ptr_null(pl_registry_find(r, "TestMover"));
    ck_assert_int_eq(pl_registry_load_plugin(r, "pl_test_plugin", &err), PL_OK);
    const pl_type *t = pl_registry_find(r, "TestMover");
    ck_assert_ptr_nonnull(t);
    ck_assert_str_eq(pl_registry_type_plugin(r, t), "pl_test_plugin");
    /* loading again is a no-op */
    ck_assert_int_eq(pl_registry_load_plugin(r, "pl_test_plugin", &err), PL_OK);
    ck_assert_int_eq(pl_registry_plugin_count(r), 1);
    pl_registry_free(r);
}
END_TEST

START_TEST(plugin_path_environment_is_searched)
{
    pl_error err;
    pl_registry *r = pl_registry_create();
    setenv("PLIANT_PLUGIN_PATH", "/nonexistent:" PL_TEST_PLUGIN_DIR, 1);
    ck_assert_int_eq(pl_registry_load_plugin(r, "pl_test_plugin", &err), PL_OK);
    unsetenv("PLIANT_PLUGIN_PATH");
    pl_registry_free(r);
}
END_TEST

START_TEST(a_plugin_of_another_abi_is_refused_naming_both_versions)
{
    pl_error err;
    char expect[64];
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(pl_registry_load_plugin(r, PL_TEST_PLUGIN_DIR "/libpliant_pl_wrong_abi_plugin.so",
                                             &err),
                     PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "ABI version 999"));
    snprintf(expect, sizeof expect, "ABI version %d.%d", PL_ABI_MAJOR, PL_ABI_MINOR);
    ck_assert_ptr_nonnull(strstr(err.msg, expect));
    ck_assert_int_eq(pl_registry_plugin_count(r), 0);
    pl_registry_free(r);
}
END_TEST

START_TEST(a_library_without_entry_point_and_a_missing_plugin_are_refused)
{
    pl_error err;
    pl_registry *r = pl_registry_create();
    ck_assert_int_eq(
        pl_registry_load_plugin(r, PL_TEST_PLUGIN_DIR "/libpliant_pl_not_a_plugin.so", &err),
        PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "not a Pliant plugin"));
    ck_assert_int_eq(pl_registry_load_plugin(r, "no_such_plugin_anywhere", &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "not found"));
    ck_assert_ptr_nonnull(strstr(err.msg, "PLIANT_PLUGIN_PATH"));
    ck_assert_int_eq(pl_registry_load_plugin(r, "/nonexistent/definitely/not/here.so", &err), PL_EINPUT);
    pl_registry_free(r);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("registry");
    TCase *tc = tcase_create("plugins");
    tcase_add_test(tc, types_are_found_suggested_and_not_duplicated);
    tcase_add_test(tc, a_good_plugin_registers_its_types);
    tcase_add_test(tc, plugin_path_environment_is_searched);
    tcase_add_test(tc, a_plugin_of_another_abi_is_refused_naming_both_versions);
    tcase_add_test(tc, a_library_without_entry_point_and_a_missing_plugin_are_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
