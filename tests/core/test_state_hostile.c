/* test_state_hostile.c - a saved state is input like any other file (issue
 * 13): slot sizes are checked against the slots' declarations before
 * anything is allocated, a variable slot grows only as its bytes arrive,
 * the time must be finite, and restored contents are checked by their
 * components.  A refused file leaves the state untouched. */
#include <check.h>
#include <math.h>
#include <pliant/pliant.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

/* ---- a model built by hand: one fixed slot, one variable slot ------------ */

typedef struct rec {
    int32_t index;
    int32_t pad;
    double value;
} rec;

static pl_model model;
static int fixed_slot, var_slot;

static int check_rec(const pl_component *owner, const void *data, size_t bytes, pl_error *err)
{
    const rec *r = data;
    for (size_t k = 0; k < bytes / sizeof *r; ++k)
        if (r[k].index < 0 || r[k].index >= 4)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "record %zu: index %d out of "
                                "0..3", k, r[k].index);
    return PL_OK;
}

static void setup(void)
{
    memset(&model, 0, sizeof model);
    fixed_slot = pl_model_add_slot(&model, NULL, "x", 4 * sizeof(double));
    var_slot = pl_model_add_var_slot(&model, NULL, "records", sizeof(rec), 8);
    ck_assert_int_eq(fixed_slot, 0);
    ck_assert_int_eq(var_slot, 1);
    pl_model_set_slot_check(&model, var_slot, check_rec);
    pl_model_set_slot_check(&model, fixed_slot, pl_slot_check_finite);
}

static void teardown(void)
{
    for (int k = 0; k < model.nslots; ++k) free(model.slots[k].name);
    free(model.slots);
}

/* A saved state in memory (open_memstream), and its bytes. */
typedef struct blob {
    char *buf;
    size_t n;
} blob;

static blob save(const pl_data *d)
{
    blob b = {0};
    FILE *f = open_memstream(&b.buf, &b.n);
    pl_error err;
    ck_assert_int_eq(pl_data_save(d, f, &err), PL_OK);
    fclose(f);
    return b;
}

/* Offset of slot `name`'s byte count in a saved state. */
static size_t bytes_field(const blob *b, const char *name)
{
    size_t o = 8 + 8 + 8 + 8;
    for (;;) {
        uint64_t len, bytes;
        ck_assert_uint_le(o + 8, b->n);
        memcpy(&len, b->buf + o, 8);
        int match = len == strlen(name) && !memcmp(b->buf + o + 8, name, len);
        o += 8 + len;
        if (match) return o;
        memcpy(&bytes, b->buf + o, 8);
        o += 8 + bytes;
    }
}

/* Loads b into d; returns the status and the message. */
static int load(pl_data *d, const blob *b, pl_error *err)
{
    FILE *f = fmemopen(b->buf, b->n, "rb");
    ck_assert_ptr_nonnull(f);
    int rc = pl_data_load(d, f, err);
    fclose(f);
    if (rc) fprintf(stderr, "refused as expected: %s\n", err->msg);
    return rc;
}

static pl_data *filled(void)
{
    pl_data *d = pl_data_create(&model);
    ck_assert_ptr_nonnull(d);
    double *x = pl_data_slot(d, fixed_slot);
    for (int i = 0; i < 4; ++i) x[i] = 1.5 * i;
    rec r[3] = {{0, 0, 1.0}, {3, 0, 2.0}, {1, 0, 3.0}};
    ck_assert_int_eq(pl_data_store(d, var_slot, r, sizeof r), PL_OK);
    d->time = 0.25;
    d->step = 25;
    return d;
}

START_TEST(slots_keep_their_declared_sizes)
{
    pl_data *d = filled();
    /* a fixed slot keeps its size; a variable one takes whole records, up to its bound */
    ck_assert_int_eq(pl_data_resize_slot(d, fixed_slot, 3 * sizeof(double)), -1);
    ck_assert_int_eq(pl_data_resize_slot(d, var_slot, sizeof(rec) + 1), -1);
    ck_assert_int_eq(pl_data_resize_slot(d, var_slot, 9 * sizeof(rec)), -1);
    ck_assert_int_eq(pl_data_resize_slot(d, var_slot, 8 * sizeof(rec)), 0);
    ck_assert_int_eq(pl_data_resize_slot(d, var_slot, 0), 0);
    ck_assert_int_lt(pl_model_add_var_slot(&model, NULL, "zero", 0, 4), 0);
    ck_assert_int_lt(pl_model_add_var_slot(&model, NULL, "huge", 1 << 20, SIZE_MAX / 2), 0);
    pl_data_free(d);
}
END_TEST

START_TEST(a_good_state_round_trips)
{
    pl_data *d = filled(), *e = pl_data_create(&model);
    blob b = save(d);
    pl_error err;
    ck_assert_int_eq(load(e, &b, &err), PL_OK);
    ck_assert(e->time == 0.25 && e->step == 25);
    ck_assert_uint_eq(pl_data_slot_bytes(e, var_slot), 3 * sizeof(rec));
    ck_assert_mem_eq(pl_data_slot(e, var_slot), pl_data_slot(d, var_slot), 3 * sizeof(rec));
    ck_assert_mem_eq(pl_data_slot(e, fixed_slot), pl_data_slot(d, fixed_slot), 32);
    free(b.buf);
    pl_data_free(d);
    pl_data_free(e);
}
END_TEST

/* Expects the load of b to fail with `needle` and leave d as filled() made it. */
static void expect_refused(const blob *b, const char *needle)
{
    pl_data *d = filled(), *ref = filled();
    pl_error err;
    ck_assert_int_eq(load(d, b, &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, needle), "'%s' lacks '%s'", err.msg, needle);
    ck_assert(d->time == ref->time && d->step == ref->step);
    ck_assert_uint_eq(pl_data_slot_bytes(d, var_slot), pl_data_slot_bytes(ref, var_slot));
    ck_assert_mem_eq(pl_data_slot(d, var_slot), pl_data_slot(ref, var_slot),
                     pl_data_slot_bytes(ref, var_slot));
    pl_data_free(d);
    pl_data_free(ref);
}

static void put_u64(blob *b, size_t at, uint64_t v) { memcpy(b->buf + at, &v, 8); }

START_TEST(wrong_sizes_are_refused_before_allocating)
{
    pl_data *d = filled();
    blob b = save(d);
    size_t fx = bytes_field(&b, ".x"), vr = bytes_field(&b, ".records");
    /* the 384 GiB fixed slot: refused at its size, nothing allocated */
    put_u64(&b, fx, (uint64_t)384 << 30);
    expect_refused(&b, "slot '.x' holds 412316860416 bytes in the state file; this scene's has 32");
    /* a fixed slot shrunk below what the model needs (the gathers would read past it) */
    put_u64(&b, fx, 16);
    expect_refused(&b, "this scene's has 32");
    put_u64(&b, fx, 32);
    /* a variable slot: not whole records, more than its bound */
    put_u64(&b, vr, 3 * sizeof(rec) - 1);
    expect_refused(&b, "expected a multiple of 16, at most 8 elements");
    put_u64(&b, vr, 9 * sizeof(rec));
    expect_refused(&b, "at most 8 elements");
    free(b.buf);
    pl_data_free(d);
}
END_TEST

START_TEST(a_variable_slot_grows_only_as_its_bytes_arrive)
{
    /* a model whose variable slot may be huge: the file announces 256 GiB
     * and holds 48 bytes; the load must fail as truncated, quickly, within a
     * small address space (not under ASan, which reserves terabytes) */
    pl_model big;
    memset(&big, 0, sizeof big);
    int k = pl_model_add_var_slot(&big, NULL, "records", sizeof(rec), (size_t)1 << 36);
    ck_assert_int_eq(k, 0);
    pl_data *d = pl_data_create(&big);
    rec r[3] = {{0, 0, 1}, {1, 0, 2}, {2, 0, 3}};
    ck_assert_int_eq(pl_data_store(d, k, r, sizeof r), PL_OK);
    blob b = save(d);
    put_u64(&b, bytes_field(&b, ".records"), (uint64_t)256 << 30);
#ifndef __SANITIZE_ADDRESS__
    struct rlimit saved, lim;
    ck_assert_int_eq(getrlimit(RLIMIT_AS, &saved), 0);
    lim = saved;
    lim.rlim_cur = (rlim_t)2 << 30; /* a 256 GiB allocation would fail */
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &lim), 0);
#endif
    clock_t t0 = clock();
    pl_error err;
    ck_assert_int_eq(load(d, &b, &err), PL_EINPUT);
    ck_assert_msg(strstr(err.msg, "truncated state file: slot '.records' announces 274877906944"),
                  "%s", err.msg);
    ck_assert(clock() - t0 < CLOCKS_PER_SEC);
#ifndef __SANITIZE_ADDRESS__
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &saved), 0);
#endif
    ck_assert_uint_eq(pl_data_slot_bytes(d, k), sizeof r); /* untouched */
    free(b.buf);
    pl_data_free(d);
    free(big.slots[0].name);
    free(big.slots);
}
END_TEST

START_TEST(non_finite_times_and_bad_contents_are_refused)
{
    pl_data *d = filled();
    blob b = save(d);
    double t = NAN;
    memcpy(b.buf + 8, &t, 8);
    expect_refused(&b, "expected a finite time");
    t = INFINITY;
    memcpy(b.buf + 8, &t, 8);
    expect_refused(&b, "expected a finite time");
    t = 0.25;
    memcpy(b.buf + 8, &t, 8);
    int64_t step = -3;
    memcpy(b.buf + 16, &step, 8);
    expect_refused(&b, "step count -3");
    step = 25;
    memcpy(b.buf + 16, &step, 8);
    /* the slot checks: a record index out of range, a NaN in the fixed slot */
    size_t vr = bytes_field(&b, ".records") + 8;
    int32_t bad = 7;
    memcpy(b.buf + vr + sizeof(rec), &bad, 4);
    expect_refused(&b, "slot '.records': record 1: index 7 out of 0..3");
    bad = 3;
    memcpy(b.buf + vr + sizeof(rec), &bad, 4);
    double nan = NAN;
    memcpy(b.buf + bytes_field(&b, ".x") + 8 + 16, &nan, 8);
    expect_refused(&b, "slot '.x': value 2 is nan");
    /* trailing bytes after the last slot */
    nan = 3.0;
    memcpy(b.buf + bytes_field(&b, ".x") + 8 + 16, &nan, 8);
    blob longer = {malloc(b.n + 1), b.n + 1};
    memcpy(longer.buf, b.buf, b.n);
    longer.buf[b.n] = 'x';
    expect_refused(&longer, "goes on after its last slot");
    free(longer.buf);
    free(b.buf);
    pl_data_free(d);
}
END_TEST

/* ---- in a scene: the MechanicalObject's slots ------------------------------- */

START_TEST(a_restored_nan_position_is_refused_by_the_state)
{
    setenv("PLIANT_PLUGIN_PATH", PL_TEST_PLUGIN_DIR, 1);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(
        "<Node name=\"root\" dt=\"0.01\">\n  <RequiredPlugin name=\"pl_test_plugin\"/>\n"
        "  <TestMover name=\"mover\"/>\n"
        "  <MechanicalObject name=\"dofs\" position=\"0 0 0  1 0 0\" velocity=\"1 0 0\"/>\n"
        "</Node>\n",
        "state.xml", NULL, &diag);
    pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    pl_error err;
    ck_assert_int_eq(pl_sim_step(s, 3, &err), PL_OK);
    blob b = save(pl_sim_data(s));
    double inf = INFINITY;
    memcpy(b.buf + bytes_field(&b, "root/dofs.velocity") + 8 + 8, &inf, 8);
    FILE *f = fmemopen(b.buf, b.n, "rb");
    ck_assert_int_eq(pl_data_load(pl_sim_data(s), f, &err), PL_EINPUT);
    fclose(f);
    ck_assert_msg(strstr(err.msg, "slot 'root/dofs.velocity': value 1 is inf"), "%s", err.msg);
    ck_assert(fabs(pl_sim_time(s) - 0.03) < 1e-15); /* untouched */
    free(b.buf);
    pl_sim_free(s);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("state_hostile");
    TCase *tc = tcase_create("hostile");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, slots_keep_their_declared_sizes);
    tcase_add_test(tc, a_good_state_round_trips);
    tcase_add_test(tc, wrong_sizes_are_refused_before_allocating);
    tcase_add_test(tc, a_variable_slot_grows_only_as_its_bytes_arrive);
    tcase_add_test(tc, non_finite_times_and_bad_contents_are_refused);
    tcase_add_test(tc, a_restored_nan_position_is_refused_by_the_state);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
