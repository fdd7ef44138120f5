/* test_state.c - model apart from state: save/restore round-trips exactly,
 * reset returns to the loaded state, two states step over one model, input
 * fields live in each state, workspaces are per state and remade after a
 * model change, slot versions follow writes from outside a slot's owner. */
#include <check.h>
#include <math.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "test_tmp.h"

static const char *SCENE =
    "<Node name=\"root\" dt=\"0.01\">\n"
    "  <RequiredPlugin name=\"pl_test_plugin\"/>\n"
    "  <TestMover name=\"mover\" acceleration=\"0 -9.81 0\"/>\n"
    "  <Node name=\"body\">\n"
    "    <MechanicalObject name=\"dofs\" position=\"0 0 0  1 0 0  0 1 0  0 0 1\" "
    "velocity=\"0.3 0.1 0\"/>\n"
    "  </Node>\n"
    "</Node>\n";

static pl_sim *load(void)
{
    pl_diag diag;
    pl_diag_init(&diag);
    setenv("PLIANT_PLUGIN_PATH", PL_TEST_PLUGIN_DIR, 1);
    pl_sim *s = pl_sim_load_string(SCENE, "state.xml", NULL, &diag);
    pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    return s;
}

static long get_long(pl_sim *s, pl_data *d, const char *path)
{
    char buf[128];
    pl_error err;
    ck_assert_int_eq(pl_sim_get_data(s, d, path, buf, sizeof buf, &err), PL_OK);
    return strtol(buf, NULL, 10);
}

static void positions(pl_sim *s, pl_data *d, double *out)
{
    pl_component *c = pl_sim_component(s, "body/dofs");
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    pl_buffer b = ops->positions(c, d);
    memcpy(out, b.data, 12 * sizeof *out);
}

START_TEST(save_and_restore_round_trip_exactly)
{
    pl_sim *s = load();
    pl_error err;
    char path[1024];
    int fd = test_tmp_file(path, sizeof path, "state");
    ck_assert_int_ge(fd, 0);
    close(fd);
    double a[12], b[12];
    ck_assert_int_eq(pl_sim_step(s, 10, &err), PL_OK);
    ck_assert_int_eq(pl_sim_save_state(s, path, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step(s, 7, &err), PL_OK);
    positions(s, pl_sim_data(s), a);
    double t_end = pl_sim_time(s);
    ck_assert_int_eq(pl_sim_restore_state(s, path, &err), PL_OK);
    ck_assert(pl_sim_time(s) == 10 * 0.01 || fabs(pl_sim_time(s) - 0.1) < 1e-15);
    ck_assert_int_eq(pl_sim_step(s, 7, &err), PL_OK);
    positions(s, pl_sim_data(s), b);
    ck_assert(pl_sim_time(s) == t_end);
    ck_assert_int_eq(memcmp(a, b, sizeof a), 0); /* bit for bit */
    char buf[64];
    ck_assert_int_eq(pl_sim_get(s, "mover.count", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "17");
    /* the free fall moved the body: the test is not vacuous */
    ck_assert(b[1] < -0.1);
    unlink(path);
    pl_sim_free(s);
}
END_TEST

START_TEST(restoring_a_foreign_or_broken_file_fails_cleanly)
{
    pl_sim *s = load();
    pl_error err;
    char path[1024];
    int fd = test_tmp_file(path, sizeof path, "bad");
    ck_assert_int_ge(fd, 0);
    ck_assert_int_eq(write(fd, "PLSTATE1garbage", 15), 15);
    close(fd);
    double before[12], after[12];
    positions(s, pl_sim_data(s), before);
    ck_assert_int_eq(pl_sim_restore_state(s, path, &err), PL_EINPUT);
    positions(s, pl_sim_data(s), after);
    ck_assert_int_eq(memcmp(before, after, sizeof before), 0);
    ck_assert_int_eq(pl_sim_restore_state(s, "/nonexistent/state", &err), PL_EINPUT);
    unlink(path);
    pl_sim_free(s);
}
END_TEST

START_TEST(reset_returns_to_the_loaded_state)
{
    pl_sim *s = load();
    pl_error err;
    double a[12], b[12];
    positions(s, pl_sim_data(s), a);
    ck_assert_int_eq(pl_sim_step(s, 5, &err), PL_OK);
    positions(s, pl_sim_data(s), b);
    ck_assert(memcmp(a, b, sizeof a) != 0);
    ck_assert_int_eq(pl_sim_reset(s), PL_OK);
    positions(s, pl_sim_data(s), b);
    ck_assert_int_eq(memcmp(a, b, sizeof a), 0);
    ck_assert(pl_sim_time(s) == 0.0);
    pl_sim_free(s);
}
END_TEST

START_TEST(two_states_step_independently_over_one_model)
{
    pl_sim *s = load();
    pl_error err;
    pl_data *other = pl_data_clone(pl_sim_data(s));
    ck_assert_ptr_nonnull(other);
    double a[12], b[12];
    ck_assert_int_eq(pl_sim_step(s, 12, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step_data(s, other, 5, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step_data(s, other, 7, &err), PL_OK);
    positions(s, pl_sim_data(s), a);
    positions(s, other, b);
    ck_assert_int_eq(memcmp(a, b, sizeof a), 0);
    ck_assert(other->time == pl_sim_time(s));
    pl_data_free(other);
    pl_sim_free(s);
}
END_TEST

START_TEST(set_at_run_time_changes_the_motion)
{
    pl_sim *s = load();
    pl_error err;
    double a[12];
    ck_assert_int_eq(pl_sim_set(s, "mover.acceleration", "0 0 0", &err), PL_OK);
    ck_assert_int_eq(pl_sim_step(s, 10, &err), PL_OK);
    positions(s, pl_sim_data(s), a);
    ck_assert(a[1] > 0.0); /* no gravity any more: the initial vy carries it up */
    ck_assert_int_eq(pl_sim_set(s, "mover.acceleratio", "0 0 0", &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "did you mean acceleration?"));
    ck_assert_int_eq(pl_sim_set(s, "nobody.acceleration", "0 0 0", &err), PL_EINPUT);
    pl_sim_free(s);
}
END_TEST

START_TEST(input_fields_live_in_each_data)
{
    pl_sim *s = load();
    pl_error err;
    char buf[128];
    pl_data *a = pl_sim_data(s), *b = pl_data_clone(a);
    ck_assert_int_eq(pl_sim_set_data(s, b, "mover.acceleration", "0 5 0", &err), PL_OK);
    ck_assert_int_eq(pl_sim_get_data(s, a, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 -9.8100000000000005 0");
    ck_assert_int_eq(pl_sim_get_data(s, b, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 5 0");
    /* the model keeps the scene's value: a new data starts from it */
    pl_data *c = pl_data_create(pl_sim_model(s));
    ck_assert_int_eq(pl_sim_get_data(s, c, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 -9.8100000000000005 0");
    /* each falls, or rises, by its own */
    double pa[12], pb[12];
    ck_assert_int_eq(pl_sim_step_data(s, a, 10, &err), PL_OK);
    ck_assert_int_eq(pl_sim_step_data(s, b, 10, &err), PL_OK);
    positions(s, a, pa);
    positions(s, b, pb);
    ck_assert(pa[1] < 0.0 && pb[1] > 0.0);
    /* a saved data brings its input along; reset restores the scene's */
    char path[1024];
    int fd = test_tmp_file(path, sizeof path, "input");
    ck_assert_int_ge(fd, 0);
    FILE *f = fdopen(fd, "wb");
    ck_assert_int_eq(pl_data_save(b, f, &err), PL_OK);
    fclose(f);
    ck_assert_int_eq(pl_sim_restore_state(s, path, &err), PL_OK);
    ck_assert_int_eq(pl_sim_get(s, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 5 0");
    ck_assert_int_eq(pl_sim_reset(s), PL_OK);
    ck_assert_int_eq(pl_sim_get(s, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 -9.8100000000000005 0");
    /* a malformed value is refused and leaves the data as it was */
    ck_assert_int_eq(pl_sim_set_data(s, b, "mover.acceleration", "0 1", &err), PL_EINPUT);
    ck_assert_int_eq(pl_sim_get_data(s, b, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 5 0");
    unlink(path);
    pl_data_free(c);
    pl_data_free(b);
    pl_sim_free(s);
}
END_TEST

/* Slot versions (ABI 5.10): what an owner keeping a device copy of its slot
 * relies on to skip re-reading it.  Every write from outside the owner makes
 * a new version; an open writable view reads 0; closing it is a new one. */
START_TEST(slot_versions_change_with_every_write_from_outside)
{
    pl_sim *s = load();
    pl_error err;
    pl_data *d = pl_sim_data(s);
    int pos = pl_model_find_slot(pl_sim_model(s), "root/body/dofs.position");
    int acc = pl_model_find_slot(pl_sim_model(s), "root/mover.acceleration");
    ck_assert_int_ge(pos, 0);
    ck_assert_int_ge(acc, 0);
    ck_assert_uint_eq(pl_data_slot_version(d, -1), 0);
    ck_assert_uint_eq(pl_data_slot_version(d, d->nslots), 0);
    unsigned long v = pl_data_slot_version(d, pos), w;
    ck_assert_uint_ne(v, 0);
    ck_assert_uint_eq(pl_data_slot_version(d, pos), v); /* reading makes none */
    pl_data_slot_touch(d, pos);
    ck_assert_uint_ne(w = pl_data_slot_version(d, pos), 0);
    ck_assert_uint_ne(w, v);
    /* reset and restore copy into every slot */
    ck_assert_int_eq(pl_sim_step(s, 2, &err), PL_OK);
    v = pl_data_slot_version(d, pos);
    ck_assert_int_eq(pl_sim_reset(s), PL_OK);
    ck_assert_uint_ne(w = pl_data_slot_version(d, pos), v);
    ck_assert_uint_ne(w, 0);
    char path[1024];
    int fd = test_tmp_file(path, sizeof path, "versions");
    ck_assert_int_ge(fd, 0);
    close(fd);
    ck_assert_int_eq(pl_sim_save_state(s, path, &err), PL_OK);
    v = pl_data_slot_version(d, pos);
    ck_assert_int_eq(pl_sim_restore_state(s, path, &err), PL_OK);
    ck_assert_uint_ne(pl_data_slot_version(d, pos), v);
    unlink(path);
    /* an input set from outside (pl_data_store underneath) */
    v = pl_data_slot_version(d, acc);
    ck_assert_int_eq(pl_sim_set(s, "mover.acceleration", "0 0 0", &err), PL_OK);
    ck_assert_uint_ne(pl_data_slot_version(d, acc), v);
    /* a copy into another data makes new versions there, not in the source */
    pl_data *other = pl_data_create(pl_sim_model(s));
    ck_assert_ptr_nonnull(other);
    v = pl_data_slot_version(other, pos);
    w = pl_data_slot_version(d, pos);
    ck_assert_int_eq(pl_data_copy(other, d), 0);
    ck_assert_uint_ne(pl_data_slot_version(other, pos), v);
    ck_assert_uint_eq(pl_data_slot_version(d, pos), w);
    pl_data_free(other);
    /* writable views: 0 while any is open, then a version not seen before */
    v = pl_data_slot_version(d, pos);
    pl_data_slot_writers(d, pos, +1);
    pl_data_slot_writers(d, pos, +1);
    ck_assert_uint_eq(pl_data_slot_version(d, pos), 0);
    pl_data_slot_writers(d, pos, -1);
    ck_assert_uint_eq(pl_data_slot_version(d, pos), 0);
    ck_assert_uint_ne(pl_data_slot_version(d, acc), 0); /* other slots unaffected */
    pl_data_slot_writers(d, pos, -1);
    ck_assert_uint_ne(w = pl_data_slot_version(d, pos), 0);
    ck_assert_uint_ne(w, v);
    pl_sim_free(s);
}
END_TEST

START_TEST(workspaces_are_per_data_and_remade_with_the_model)
{
    pl_sim *s = load();
    pl_error err;
    pl_data *a = pl_sim_data(s);
    long freed0 = get_long(s, a, "mover.wsFreed");
    ck_assert_int_eq(get_long(s, a, "mover.wsSteps"), -1); /* none before the first step */
    ck_assert_int_eq(pl_sim_step(s, 3, &err), PL_OK);
    ck_assert_int_eq(get_long(s, a, "mover.wsSteps"), 3);
    /* a clone copies the state, not the workspace */
    pl_data *b = pl_data_clone(a);
    ck_assert_int_eq(get_long(s, b, "mover.wsSteps"), -1);
    ck_assert_int_eq(pl_sim_step_data(s, b, 2, &err), PL_OK);
    ck_assert_int_eq(get_long(s, b, "mover.wsSteps"), 2);
    ck_assert_int_eq(get_long(s, a, "mover.wsSteps"), 3);
    /* freeing a data frees its workspaces through the component */
    pl_data_free(b);
    ck_assert_int_eq(get_long(s, a, "mover.wsFreed"), freed0 + 1);
    /* a model change (dt) rebuilds the model: workspaces are remade */
    ck_assert_int_eq(pl_sim_set(s, "root.dt", "0.02", &err), PL_OK);
    ck_assert_int_eq(get_long(s, a, "mover.wsSteps"), -1);
    ck_assert_int_eq(pl_sim_step(s, 1, &err), PL_OK);
    ck_assert_int_eq(get_long(s, a, "mover.wsSteps"), 1);
    ck_assert_int_eq(get_long(s, a, "mover.wsFreed"), freed0 + 2);
    /* the step count itself is state: it went on */
    ck_assert_int_eq(get_long(s, a, "mover.count"), 4);
    pl_sim_free(s);
}
END_TEST

static int drive_up(pl_sim *s, double t, void *user)
{
    int *calls = user;
    pl_error err;
    (*calls)++;
    /* an embedding program drives the scene: acceleration grows with time */
    char value[64];
    snprintf(value, sizeof value, "0 %.17g 0", 100.0 * t);
    return pl_sim_set(s, "mover.acceleration", value, &err);
}

static int refuse(pl_sim *s, double t, void *user) { return t > 0.025; }

START_TEST(a_step_callback_drives_the_scene_and_can_stop_it)
{
    pl_sim *s = load();
    pl_error err;
    int calls = 0;
    pl_sim_set_callback(s, drive_up, &calls);
    ck_assert_int_eq(pl_sim_step(s, 10, &err), PL_OK);
    ck_assert_int_eq(calls, 10);
    double a[12];
    positions(s, pl_sim_data(s), a);
    ck_assert(a[1] > 0.0); /* pushed up instead of falling */
    pl_sim_set_callback(s, refuse, NULL);
    pl_sim_reset(s);
    ck_assert_int_eq(pl_sim_step(s, 10, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "callback"));
    ck_assert(fabs(pl_sim_time(s) - 0.03) < 1e-12); /* stopped at the 4th step */
    pl_sim_free(s);
}
END_TEST

START_TEST(a_step_callback_drives_the_data_being_stepped)
{
    pl_sim *s = load();
    pl_error err;
    char buf[128];
    int calls = 0;
    pl_data *a = pl_sim_data(s), *b = pl_data_clone(a);
    pl_sim_set_callback(s, drive_up, &calls);
    ck_assert_int_eq(pl_sim_step_data(s, b, 3, &err), PL_OK);
    ck_assert_int_eq(calls, 3);
    /* b got the callback's last value (t = 0.02 s), the sim's own data did not */
    ck_assert_int_eq(pl_sim_get_data(s, b, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 2 0");
    ck_assert_int_eq(pl_sim_get(s, "mover.acceleration", buf, sizeof buf, &err), PL_OK);
    ck_assert_str_eq(buf, "0 -9.8100000000000005 0");
    pl_data_free(b);
    pl_sim_free(s);
}
END_TEST

/* A type whose input field cannot be one (a string): refused at load. */
typedef struct bad_input {
    pl_component base;
    char *label;
} bad_input;

static const pl_field BAD_FIELDS[] = {
    PL_FIELD(bad_input, label, "label", PL_F_STRING, "x", "a text", PL_FIELD_INPUT),
};

static const pl_type BAD_INPUT = {.abi_version = PL_ABI_VERSION,
                                  .name = "BadInput",
                                  .size = sizeof(bad_input),
                                  .fields = BAD_FIELDS,
                                  .nfields = 1};

START_TEST(an_input_field_must_be_numeric)
{
    pl_registry *r = pl_registry_create();
    pl_error err;
    ck_assert_int_eq(pl_register_builtin_components(r, &err), PL_OK);
    ck_assert_int_eq(pl_registry_add(r, &BAD_INPUT, &err), PL_OK);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.registry = r;
    pl_sim *s = pl_sim_load_string("<Node name=\"root\">\n  <BadInput name=\"bad\"/>\n</Node>",
                                   "bad.xml", &opt, &diag);
    ck_assert_ptr_null(s);
    ck_assert_int_eq(diag.nerrors, 1);
    ck_assert_ptr_nonnull(strstr(diag.items[0].msg, "BadInput.label: an input field must be"));
    ck_assert_str_eq(diag.items[0].file, "bad.xml");
    ck_assert_int_eq(diag.items[0].line, 2);
    pl_diag_free(&diag);
    pl_registry_free(r);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("state");
    TCase *tc = tcase_create("model_and_data");
    tcase_add_test(tc, save_and_restore_round_trip_exactly);
    tcase_add_test(tc, restoring_a_foreign_or_broken_file_fails_cleanly);
    tcase_add_test(tc, reset_returns_to_the_loaded_state);
    tcase_add_test(tc, two_states_step_independently_over_one_model);
    tcase_add_test(tc, set_at_run_time_changes_the_motion);
    tcase_add_test(tc, a_step_callback_drives_the_scene_and_can_stop_it);
    tcase_add_test(tc, input_fields_live_in_each_data);
    tcase_add_test(tc, a_step_callback_drives_the_data_being_stepped);
    tcase_add_test(tc, an_input_field_must_be_numeric);
    tcase_add_test(tc, workspaces_are_per_data_and_remade_with_the_model);
    tcase_add_test(tc, slot_versions_change_with_every_write_from_outside);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
