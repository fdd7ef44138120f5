/* test_export_state_file.c - SOFA WriteState files: exact round trips and
 * SOFA's own regression references read as its README describes them. */
#include <check.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"
#include "export_test_util.h"

/* Doubles from random bit patterns (every exponent, subnormals) plus the
 * awkward ones; NaN and infinities are left out (a reader refuses them). */
static void awkward_doubles(double *v, int n, uint64_t seed)
{
    /* finite only: a state file with inf or NaN is refused (see below) */
    const double fixed[] = {0.0, -0.0, DBL_MAX, -DBL_MAX, DBL_MIN, DBL_TRUE_MIN, 0.1,
                            1.0 / 3.0, 1e-310, 2.5};
    int nf = (int)(sizeof fixed / sizeof fixed[0]);
    uint64_t x = seed;
    for (int i = 0; i < n; ++i) {
        if (i < nf) {
            v[i] = fixed[i];
            continue;
        }
        do {
            x ^= x << 13; /* xorshift64 */
            x ^= x >> 7;
            x ^= x << 17;
            memcpy(&v[i], &x, sizeof x);
        } while (!isfinite(v[i]));
    }
}

static void round_trip(const char *path, int gz)
{
    enum { N = 300, R = 4 };
    static double x[R][N], v[R][N];
    double times[R] = {0.0, 0.01, 0.1 + 0.2, 1e-300};
    for (int r = 0; r < R; ++r) {
        awkward_doubles(x[r], N, 88172645463325252ull + (uint64_t)r);
        awkward_doubles(v[r], N, 1234567ull + 7u * (uint64_t)r);
    }
    pl_error err;
    pl_state_writer *w = pl_state_writer_open(path, 0, &err);
    ck_assert_ptr_nonnull(w);
    for (int r = 0; r < R; ++r)
        ck_assert_int_eq(pl_state_writer_write(w, times[r], x[r], N, r % 2 ? v[r] : NULL, N, &err),
                         PL_OK);
    ck_assert_int_eq(pl_state_writer_close(w, &err), PL_OK);

    /* gzip magic iff asked for */
    size_t n;
    char *raw = tu_read_file(path, &n);
    ck_assert_uint_ge(n, 2);
    ck_assert_int_eq(gz, (unsigned char)raw[0] == 0x1f && (unsigned char)raw[1] == 0x8b);
    if (!gz) ck_assert_int_eq(strncmp(raw, "T= 0\n  X= 0 -0 1.7976931348623157e+308", 38), 0);
    free(raw);

    pl_state_records recs;
    pl_state_records_init(&recs);
    ck_assert_int_eq(pl_state_file_read(path, &recs, &err), PL_OK);
    ck_assert_int_eq(recs.count, R);
    for (int r = 0; r < R; ++r) {
        ck_assert_mem_eq(&recs.items[r].time, &times[r], sizeof(double));
        ck_assert_int_eq(recs.items[r].nx, N);
        ck_assert_mem_eq(recs.items[r].x, x[r], sizeof x[r]); /* bit for bit */
        if (r % 2) {
            ck_assert_int_eq(recs.items[r].nv, N);
            ck_assert_mem_eq(recs.items[r].v, v[r], sizeof v[r]);
        } else {
            ck_assert_int_eq(recs.items[r].nv, 0);
            ck_assert_ptr_null(recs.items[r].v);
        }
    }
    pl_state_records_free(&recs);
}

START_TEST(state_file_round_trip_is_bitwise_exact_plain)
{
    char *dir = tu_tmpdir();
    round_trip(tu_path(dir, "bar.state"), 0);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(state_file_round_trip_is_bitwise_exact_gzip)
{
    char *dir = tu_tmpdir();
    round_trip(tu_path(dir, "bar.state.txt.gz"), 1);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(state_file_append_continues_the_records)
{
    char *dir = tu_tmpdir();
    const char *names[] = {"a.state", "a.state.gz"};
    for (int k = 0; k < 2; ++k) {
        const char *path = tu_path(dir, names[k]);
        double x[3] = {1, 2, 3};
        pl_error err;
        pl_state_writer *w = pl_state_writer_open(path, 0, &err);
        ck_assert_int_eq(pl_state_writer_write(w, 0.0, x, 3, NULL, 0, &err), PL_OK);
        ck_assert_int_eq(pl_state_writer_write(w, 0.5, x, 3, NULL, 0, &err), PL_OK);
        ck_assert_int_eq(pl_state_writer_close(w, &err), PL_OK);
        w = pl_state_writer_open(path, 1, &err);
        x[0] = 4;
        ck_assert_int_eq(pl_state_writer_write(w, 1.0, x, 3, NULL, 0, &err), PL_OK);
        ck_assert_int_eq(pl_state_writer_close(w, &err), PL_OK);
        pl_state_records recs;
        pl_state_records_init(&recs);
        ck_assert_int_eq(pl_state_file_read(path, &recs, &err), PL_OK);
        ck_assert_int_eq(recs.count, 3);
        ck_assert_double_eq(recs.items[2].time, 1.0);
        ck_assert_double_eq(recs.items[2].x[0], 4.0);
        ck_assert_double_eq(recs.items[1].x[0], 1.0);
        pl_state_records_free(&recs);
    }
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A reference as the Regression README states it: node count and times. */
static void check_reference(const char *name, int nodes, double t_last, const double first3[3],
                            const double last_record_first3[3])
{
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    ck_assert_int_eq(pl_state_file_read(tu_data(name), &recs, &err), PL_OK);
    ck_assert_int_eq(recs.count, 2); /* T=0 and the last step only */
    ck_assert_double_eq(recs.items[0].time, 0.0);
    ck_assert_double_eq(recs.items[1].time, t_last);
    for (int r = 0; r < 2; ++r) {
        ck_assert_int_eq(recs.items[r].nx, 3 * nodes);
        ck_assert_int_eq(recs.items[r].nv, 3 * nodes); /* SOFA wrote V= too */
    }
    ck_assert_mem_eq(recs.items[0].x, first3, 3 * sizeof(double));
    ck_assert_mem_eq(recs.items[1].x, last_record_first3, 3 * sizeof(double));
    for (int i = 0; i < 3 * nodes; ++i) ck_assert_double_eq(recs.items[0].v[i], 0.0);
    pl_state_records_free(&recs);
}

START_TEST(reads_sofa_liver_references)
{
    /* values as printed in the files (SOFA's 6 significant digits) */
    check_reference("liver.scn.reference_0_dofs_mstate.txt.gz", 181, 1.98,
                    (double[]){-0.979259, 2.23512, 2.61245}, (double[]){-0.991771, 2.18764, 2.62366});
    check_reference("liver.scn.reference_1_spheres_mstate.txt.gz", 34, 1.98,
                    (double[]){-4, 1.25, 2.77556e-17}, (double[]){-4.02087, 1.12272, 0.00320932});
}
END_TEST

START_TEST(reads_sofa_falling_beam_reference)
{
    check_reference("fallingBeamLagrangianCollision.scn.reference_0_mstate_mstate.txt.gz", 625,
                    0.45, (double[]){0, 0, 0}, (double[]){4.95099e-16, 2.53128e-15, -0.999617});
}
END_TEST

/* Writes text to a fresh file and reads it, expecting an error at `line`. */
static void expect_error(const char *text, int line, const char *needle)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "bad.state");
    ck_assert_int_eq(tu_write_file(path, text), 0);
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    ck_assert_int_eq(pl_state_file_read(path, &recs, &err), PL_EINPUT);
    ck_assert_int_eq(err.line, line);
    ck_assert_str_eq(err.file, path);
    ck_assert_msg(strstr(err.msg, needle), "message '%s' lacks '%s'", err.msg, needle);
    pl_state_records_free(&recs);
    tu_rmtree(dir);
    free(dir);
}

START_TEST(malformed_state_files_name_their_line)
{
    expect_error("T= 0\n  X= 1 2 abc\n", 2, "'abc'");
    expect_error("\n  X= 1 2 3\nT= 0\n", 2, "before any 'T='");
    expect_error("T= 0 1\n", 1, "one time");
    expect_error("T= 0\n  X= 1\n  X= 2\n", 3, "second 'X='");
    expect_error("T= 0\n  X= 1 2 3\nhello world\n", 3, "expected 'T=");
    expect_error("T= 0\n  X= 1 2 3\nT= 1\n  V= 1 2,5\n", 4, "'2,5'");
    /* non-finite values are errors of the file, not a FAIL of the comparison */
    expect_error("T= inf\n  X= 1 2 3\n", 1, "'inf': expected a finite number");
    expect_error("T= 0\n  X= 1 2 3\nT= NaN\n", 3, "'NaN': expected a finite number");
    expect_error("T= 0\n  X= 1 nan 3\n", 2, "value 2 is 'nan'");
    expect_error("T= 0\n  X= 1 2 3\n  V= 0 -inf 0\n", 3, "'-inf'");
    expect_error("T= 0\n  X= 1 1e999 3\n", 2, "'1e999'"); /* overflows to inf */
}
END_TEST

START_TEST(tolerates_crlf_unknown_keys_and_long_lines)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "ok.state");
    /* a 200000-value line is far longer than any read buffer */
    size_t cap = 200000 * 4 + 256;
    char *text = malloc(cap), *p = text;
    p += sprintf(p, "T= 0.5\r\n  X0= 9 9 9\r\n  X=");
    for (int i = 0; i < 200000; ++i) p += sprintf(p, " %d", i % 7);
    p += sprintf(p, "\r\n  F= 1 2 3\r\n\r\nT= 1\n  X= 1 2 3"); /* no final newline */
    ck_assert_int_eq(tu_write_file(path, text), 0);
    free(text);
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    ck_assert_int_eq(pl_state_file_read(path, &recs, &err), PL_OK);
    ck_assert_int_eq(recs.count, 2);
    ck_assert_int_eq(recs.items[0].nx, 200000);
    ck_assert_double_eq(recs.items[0].x[199999], 199999 % 7);
    ck_assert_int_eq(recs.items[1].nx, 3);
    ck_assert_double_eq(recs.items[1].x[2], 3.0);
    pl_state_records_free(&recs);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(truncated_gzip_is_an_error)
{
    char *dir = tu_tmpdir();
    size_t n;
    char *gz = tu_read_file(tu_data("liver.scn.reference_0_dofs_mstate.txt.gz"), &n);
    ck_assert_ptr_nonnull(gz);
    const char *path = tu_path(dir, "cut.txt.gz");
    FILE *f = fopen(path, "wb");
    fwrite(gz, 1, n / 2, f);
    fclose(f);
    free(gz);
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    ck_assert_int_ne(pl_state_file_read(path, &recs, &err), PL_OK);
    pl_state_records_free(&recs);
    ck_assert_int_eq(pl_state_file_read(tu_path(dir, "missing.state"), &recs, &err), PL_EINPUT);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("export_state_file");
    TCase *tc = tcase_create("state_file");
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, state_file_round_trip_is_bitwise_exact_plain);
    tcase_add_test(tc, state_file_round_trip_is_bitwise_exact_gzip);
    tcase_add_test(tc, state_file_append_continues_the_records);
    tcase_add_test(tc, reads_sofa_liver_references);
    tcase_add_test(tc, reads_sofa_falling_beam_reference);
    tcase_add_test(tc, malformed_state_files_name_their_line);
    tcase_add_test(tc, tolerates_crlf_unknown_keys_and_long_lines);
    tcase_add_test(tc, truncated_gzip_is_an_error);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
