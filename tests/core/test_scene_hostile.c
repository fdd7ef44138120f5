/* test_scene_hostile.c - scenes written to attack the program that loads
 * them (issue 13): a RequiredPlugin that names a shared object by path, a
 * DTD spelled in UTF-16 so that a byte search misses it, entity bombs and
 * external entities.  Each is an input error naming the file and line, and
 * nothing of it takes effect. */
#include <check.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "test_tmp.h"

static pl_diag diag;
static char *dir;

static void setup(void)
{
    pl_diag_init(&diag);
    setenv("PLIANT_PLUGIN_PATH", PL_TEST_PLUGIN_DIR, 1);
    unsetenv("PL_CTOR_PLUGIN_RAN");
    dir = test_tmp_mkdtemp("hostile");
    ck_assert_ptr_nonnull(dir);
}

static void teardown(void)
{
    pl_diag_free(&diag);
    test_tmp_rmtree(dir);
    free(dir);
}

/* The first diagnostic whose message holds `needle`, or NULL. */
static const pl_error *find(const char *needle)
{
    for (int k = 0; k < diag.count; ++k)
        if (strstr(diag.items[k].msg, needle)) return &diag.items[k];
    return NULL;
}

static const char *write_file(const char *name, const void *data, size_t n)
{
    static char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    ck_assert_ptr_nonnull(f);
    ck_assert_uint_eq(fwrite(data, 1, n, f), n);
    fclose(f);
    return path;
}

/* ASCII text as UTF-16 (little- or big-endian), with a byte order mark or not. */
static const char *write_utf16(const char *name, const char *text, int big, int bom)
{
    size_t n = strlen(text), o = 0;
    unsigned char *u = malloc(2 * n + 2);
    ck_assert_ptr_nonnull(u);
    if (bom) {
        u[o++] = big ? 0xfe : 0xff;
        u[o++] = big ? 0xff : 0xfe;
    }
    for (size_t i = 0; i < n; ++i) {
        u[o++] = big ? 0 : (unsigned char)text[i];
        u[o++] = big ? (unsigned char)text[i] : 0;
    }
    const char *p = write_file(name, u, o);
    free(u);
    return p;
}

START_TEST(a_scene_cannot_name_a_shared_object)
{
    const char *lib = PL_TEST_PLUGIN_DIR "/libpliant_pl_ctor_plugin.so";
    ck_assert_int_eq(access(lib, R_OK), 0);
    char xml[512];
    snprintf(xml, sizeof xml, "<Node name=\"root\">\n  <RequiredPlugin name=\"%s\"/>\n</Node>\n",
             lib);
    ck_assert_ptr_null(pl_sim_load_string(xml, "scene.xml", NULL, &diag));
    const pl_error *e = find("is a path");
    ck_assert_ptr_nonnull(e);
    ck_assert_str_eq(e->file, "scene.xml");
    ck_assert_int_eq(e->line, 2);
    ck_assert_int_eq(e->code, PL_EINPUT);
    ck_assert_ptr_null(getenv("PL_CTOR_PLUGIN_RAN")); /* its code never ran */
    /* a relative path, '..' and odd characters likewise */
    const char *names[] = {"../plugins/pl_ctor_plugin", "plugins/pl_ctor_plugin", "..",
                           "pl ctor;rm", NULL};
    for (int k = 0; names[k]; ++k) {
        pl_diag_free(&diag);
        pl_diag_init(&diag);
        snprintf(xml, sizeof xml, "<Node>\n\n  <RequiredPlugin pluginName=\"%s\"/>\n</Node>\n",
                 names[k]);
        ck_assert_ptr_null(pl_sim_load_string(xml, "scene.xml", NULL, &diag));
        ck_assert_int_gt(diag.nerrors, 0);
        ck_assert_msg(diag.count > 0 && diag.items[0].line == 3, "%s", names[k]);
    }
    ck_assert_ptr_null(getenv("PL_CTOR_PLUGIN_RAN"));
    /* the same plugin by name, from the plugin path, is fine */
    pl_diag_free(&diag);
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string("<Node><RequiredPlugin name=\"pl_ctor_plugin\"/></Node>",
                                   "scene.xml", NULL, &diag);
    pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_str_eq(getenv("PL_CTOR_PLUGIN_RAN"), "1");
    pl_sim_free(s);
}
END_TEST

START_TEST(the_user_may_allow_plugin_paths)
{
    char xml[512];
    snprintf(xml, sizeof xml, "<Node name=\"root\">\n  <RequiredPlugin name=\"%s\"/>\n</Node>\n",
             PL_TEST_PLUGIN_DIR "/libpliant_pl_ctor_plugin.so");
    pl_sim_options opt = {.allow_plugin_path = 1};
    pl_sim *s = pl_sim_load_string(xml, "scene.xml", &opt, &diag);
    pl_diag_print(&diag, stderr);
    ck_assert_ptr_nonnull(s);
    ck_assert_str_eq(getenv("PL_CTOR_PLUGIN_RAN"), "1");
    pl_sim_free(s);
}
END_TEST

/* A DTD declaring dt as an entity: the encoding must not matter. */
static const char *ENTITY_SCENE =
    "<?xml version=\"1.0\" encoding=\"%s\"?>\n"
    "<!DOCTYPE r [<!ENTITY e \"0.01\">]>\n"
    "<Node name=\"root\" dt=\"&e;\">\n"
    "  <MechanicalObject name=\"dofs\" position=\"0 0 0\"/>\n"
    "</Node>\n";

static void expect_dtd_refused(const char *path)
{
    pl_sim *s = pl_sim_load_file(path, NULL, &diag);
    if (s || !find("DTD")) pl_diag_print(&diag, stderr);
    ck_assert_ptr_null(s);
    const pl_error *e = find("DTD");
    ck_assert_ptr_nonnull(e);
    ck_assert_int_eq(e->code, PL_EINPUT);
    ck_assert_str_eq(e->file, path);
    ck_assert_int_eq(e->line, 2);
    pl_diag_free(&diag);
    pl_diag_init(&diag);
}

START_TEST(dtds_are_refused_in_any_encoding)
{
    char xml[1024];
    snprintf(xml, sizeof xml, ENTITY_SCENE, "UTF-8");
    expect_dtd_refused(write_file("utf8.xml", xml, strlen(xml)));
    snprintf(xml, sizeof xml, ENTITY_SCENE, "UTF-16");
    expect_dtd_refused(write_utf16("le_bom.xml", xml, 0, 1));
    expect_dtd_refused(write_utf16("be_bom.xml", xml, 1, 1));
    expect_dtd_refused(write_utf16("le.xml", xml, 0, 0));
    expect_dtd_refused(write_utf16("be.xml", xml, 1, 0));
    /* the same scenes without the DTD load, in every encoding: the refusal
     * is about the declaration, not the encoding */
    const char *plain = "<?xml version=\"1.0\" encoding=\"UTF-16\"?>\n"
                        "<Node name=\"root\" dt=\"0.02\">\n"
                        "  <MechanicalObject name=\"dofs\" position=\"0 0 0\"/>\n</Node>\n";
    for (int big = 0; big < 2; ++big) {
        pl_sim *s = pl_sim_load_file(write_utf16("ok.xml", plain, big, 1), NULL, &diag);
        pl_diag_print(&diag, stderr);
        ck_assert_ptr_nonnull(s);
        ck_assert_double_eq(pl_node_dt(pl_sim_model(s)->root), 0.02);
        pl_sim_free(s);
    }
}
END_TEST

START_TEST(entity_bombs_and_external_entities_are_refused_quickly)
{
    char bomb[4096] = "<?xml version=\"1.0\"?>\n<!DOCTYPE lolz [<!ENTITY lol \"lol\">\n";
    for (int k = 1; k <= 9; ++k) {
        char line[200];
        snprintf(line, sizeof line, "<!ENTITY lol%d \"", k);
        for (int j = 0; j < 10; ++j)
            snprintf(line + strlen(line), sizeof line - strlen(line), "&lol%.0d;", k - 1);
        strcat(line, "\">\n");
        strcat(bomb, line);
    }
    strcat(bomb, "]>\n<Node name=\"&lol9;\"/>\n");
    double t0 = pl_now();
    expect_dtd_refused(write_file("bomb.xml", bomb, strlen(bomb)));
    char bomb16[4096];
    snprintf(bomb16, sizeof bomb16, "%s", bomb);
    expect_dtd_refused(write_utf16("bomb16.xml", bomb16, 0, 1));
    ck_assert(pl_now() - t0 < 1.0);
    /* external entities and external DTDs: never fetched, refused */
    const char *ext = "<?xml version=\"1.0\"?>\n"
                      "<!DOCTYPE r [<!ENTITY x SYSTEM \"file:///etc/passwd\">]>\n"
                      "<Node name=\"&x;\"/>\n";
    expect_dtd_refused(write_file("ext.xml", ext, strlen(ext)));
    const char *extdtd = "<?xml version=\"1.0\"?>\n"
                         "<!DOCTYPE r SYSTEM \"http://example.com/x.dtd\">\n<Node/>\n";
    expect_dtd_refused(write_file("extdtd.xml", extdtd, strlen(extdtd)));
}
END_TEST

int main(void)
{
    Suite *s = suite_create("scene_hostile");
    TCase *tc = tcase_create("hostile");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, a_scene_cannot_name_a_shared_object);
    tcase_add_test(tc, the_user_may_allow_plugin_paths);
    tcase_add_test(tc, dtds_are_refused_in_any_encoding);
    tcase_add_test(tc, entity_bombs_and_external_entities_are_refused_quickly);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
