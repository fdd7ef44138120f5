/* test_collision_restore_hostile.c - restored contacts are checked by the
 * components that own them (issue 13): a saved state of a scene in contact
 * (the cloth of scenes/sharp_corner_small.xml after 30 steps, the ball of
 * scenes/ball_on_plane.xml after 40) with one index changed is refused with the slot's name, and
 * the run goes on from its own state. */
#include <check.h>
#include <pliant/pliant.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "contact.h"
#include "pipeline.h"

typedef struct blob {
    char *buf;
    size_t n;
} blob;

static pl_sim *sim;
static blob saved;

/* Loads scenes/<name>, steps it, saves its state into `saved`. */
static void open_scene(const char *name, int steps)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/%s", PL_SOURCE_DIR, name);
    pl_sim_options opt = {.out_dir = PL_BINARY_DIR "/tests/collision/scene_out",
                          .export_every = 1000000};
    pl_diag diag;
    pl_diag_init(&diag);
    sim = pl_sim_load_file(path, &opt, &diag);
    if (!sim) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(sim);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(sim, steps, &err), PL_OK);
    FILE *f = open_memstream(&saved.buf, &saved.n);
    ck_assert_int_eq(pl_data_save(pl_sim_data(sim), f, &err), PL_OK);
    fclose(f);
}

static void teardown(void)
{
    pl_sim_free(sim);
    free(saved.buf);
    memset(&saved, 0, sizeof saved);
}

/* The saved slot whose name ends with `suffix` and holds at least one
 * element of `elem` bytes: its data offset and byte count. */
static size_t slot_data(const char *suffix, size_t elem, uint64_t *bytes)
{
    size_t o = 32;
    while (o + 8 <= saved.n) {
        uint64_t len;
        memcpy(&len, saved.buf + o, 8);
        const char *name = saved.buf + o + 8;
        size_t sl = strlen(suffix);
        int match = len >= sl && !memcmp(name + len - sl, suffix, sl);
        o += 8 + len;
        memcpy(bytes, saved.buf + o, 8);
        o += 8;
        if (match && *bytes >= elem) return o;
        o += *bytes;
    }
    ck_abort_msg("no non-empty slot '*%s' in the saved state", suffix);
    return 0;
}

/* Restores a copy of the saved state with `n` bytes at `at` replaced. */
static int restore_with(size_t at, const void *v, size_t n, pl_error *err)
{
    char *copy = malloc(saved.n);
    ck_assert_ptr_nonnull(copy);
    memcpy(copy, saved.buf, saved.n);
    memcpy(copy + at, v, n);
    FILE *f = fmemopen(copy, saved.n, "rb");
    int rc = pl_data_load(pl_sim_data(sim), f, err);
    fclose(f);
    free(copy);
    return rc;
}

START_TEST(the_saved_contacts_restore_as_they_are)
{
    open_scene("sharp_corner_small.xml", 30);
    pl_error err;
    uint64_t bytes;
    slot_data("root/pipeline.contacts", sizeof(coll_contact_record), &bytes);
    ck_assert_uint_eq(bytes % sizeof(coll_contact_record), 0);
    ck_assert_int_eq(restore_with(0, saved.buf, 8, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step(sim, 1, &err), PL_OK);
}
END_TEST

START_TEST(a_pipeline_contact_naming_a_missing_model_is_refused)
{
    open_scene("sharp_corner_small.xml", 30);
    pl_error err;
    uint64_t bytes;
    size_t at = slot_data("root/pipeline.contacts", sizeof(coll_contact_record), &bytes);
    double t = pl_sim_time(sim);
    int bad = 99;
    ck_assert_int_eq(restore_with(at + offsetof(coll_contact_record, prox.model_b), &bad,
                                  sizeof bad, &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, "pipeline.contacts': contact 0 is corrupt"), "%s", err.msg);
    bad = -5; /* a negative vertex */
    ck_assert_int_eq(restore_with(at + offsetof(coll_contact_record, prox.a), &bad, sizeof bad,
                                  &err), PL_EINPUT);
    ck_assert(pl_sim_time(sim) == t); /* untouched: the run goes on */
    ck_assert_int_eq(pl_sim_step(sim, 1, &err), PL_OK);
}
END_TEST

START_TEST(obstacle_contacts_and_warm_start_records_are_checked)
{
    open_scene("ball_on_plane.xml", 40); /* the ball on the floor */
    pl_error err;
    uint64_t bytes;
    size_t at = slot_data("root/floor.contacts", sizeof(pl_obstacle_contact), &bytes);
    int bad = 7;
    ck_assert_int_eq(restore_with(at + offsetof(pl_obstacle_contact, model), &bad, sizeof bad,
                                  &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, "names model 7"), "%s", err.msg);
    at = slot_data(".warmStart", sizeof(pl_ncpc_key), &bytes);
    int32_t pair = (int32_t)(bytes / sizeof(pl_ncpc_key)) + 3;
    ck_assert_int_eq(restore_with(at + offsetof(pl_ncpc_key, pair), &pair, sizeof pair, &err),
                     PL_EINPUT);
    ck_assert_msg(strstr(err.msg, "warm-start record 0 is corrupt"), "%s", err.msg);
    double nan = NAN;
    ck_assert_int_eq(restore_with(at + offsetof(pl_ncpc_key, lambda), &nan, sizeof nan, &err),
                     PL_EINPUT);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_restore_hostile");
    TCase *tc = tcase_create("restore");
    tcase_add_checked_fixture(tc, NULL, teardown);
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, the_saved_contacts_restore_as_they_are);
    tcase_add_test(tc, a_pipeline_contact_naming_a_missing_model_is_refused);
    tcase_add_test(tc, obstacle_contacts_and_warm_start_records_are_checked);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
