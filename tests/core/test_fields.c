/* test_fields.c - typed field parsing: good values, malformed values, exact
 * round trips, suggestions. */
#include <check.h>
#include <math.h>
#include <pliant/pliant.h>
#include <stdlib.h>
#include <string.h>

typedef struct obj {
    double d;
    int i, b, e;
    char *s;
    double v[3];
    pl_doubles dl;
    pl_ints il;
    pl_link l;
} obj;

static const char *const CHOICES[] = {"metis", "nesdis", "amd", "natural", NULL};
static const pl_field F[] = {
    PL_FIELD(obj, d, "youngModulus", PL_F_DOUBLE, "1e5", "[Pa]", 0),
    PL_FIELD(obj, i, "iterations", PL_F_INT, "5", "", 0),
    PL_FIELD(obj, b, "flag", PL_F_BOOL, "0", "", 0),
    PL_FIELD_ENUM(obj, e, "ordering", CHOICES, "metis", "", 0),
    PL_FIELD(obj, s, "filename", PL_F_STRING, NULL, "", 0),
    PL_FIELD(obj, v, "gravity", PL_F_VEC3, "0 -9.81 0", "", 0),
    PL_FIELD(obj, dl, "position", PL_F_DOUBLES, NULL, "", 0),
    PL_FIELD(obj, il, "indices", PL_F_INTS, NULL, "", 0),
    PL_FIELD(obj, l, "src", PL_F_LINK, NULL, "", 0),
};

static obj o;
static pl_error err;

static void setup(void) { memset(&o, 0, sizeof o); }
static void teardown(void)
{
    for (size_t k = 0; k < sizeof F / sizeof F[0]; ++k) pl_field_release(&F[k], &o);
}

START_TEST(double_parses_exactly_and_rejects_garbage)
{
    ck_assert_int_eq(pl_field_parse(&F[0], &o, " 1.5e5 ", &err), PL_OK);
    ck_assert(o.d == 1.5e5);
    ck_assert_int_eq(pl_field_parse(&F[0], &o, "abc", &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "youngModulus"));
    ck_assert_int_eq(pl_field_parse(&F[0], &o, "1e5 2", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[0], &o, "nan", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[0], &o, "inf", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[0], &o, "1e999", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[0], &o, "", &err), PL_EINPUT);
    ck_assert(o.d == 1.5e5); /* a failed parse leaves the old value */
    /* %.17g round trip is bit exact */
    char buf[64];
    o.d = 0.1 + 0.2;
    pl_field_format(&F[0], &o, buf, sizeof buf);
    double before = o.d;
    ck_assert_int_eq(pl_field_parse(&F[0], &o, buf, &err), PL_OK);
    ck_assert(o.d == before);
}
END_TEST

START_TEST(int_and_bool_values)
{
    ck_assert_int_eq(pl_field_parse(&F[1], &o, "12", &err), PL_OK);
    ck_assert_int_eq(o.i, 12);
    ck_assert_int_eq(pl_field_parse(&F[1], &o, "3.5", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[1], &o, "99999999999", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[2], &o, "true", &err), PL_OK);
    ck_assert_int_eq(o.b, 1);
    ck_assert_int_eq(pl_field_parse(&F[2], &o, "0", &err), PL_OK);
    ck_assert_int_eq(o.b, 0);
    ck_assert_int_eq(pl_field_parse(&F[2], &o, "maybe", &err), PL_EINPUT);
}
END_TEST

START_TEST(enum_by_name_or_index_with_suggestion)
{
    ck_assert_int_eq(pl_field_parse(&F[3], &o, "amd", &err), PL_OK);
    ck_assert_int_eq(o.e, 2);
    ck_assert_int_eq(pl_field_parse(&F[3], &o, "1", &err), PL_OK); /* SOFA's option index */
    ck_assert_int_eq(o.e, 1);
    ck_assert_int_eq(pl_field_parse(&F[3], &o, "metsi", &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "did you mean metis"));
    ck_assert_int_eq(pl_field_parse(&F[3], &o, "7", &err), PL_EINPUT);
}
END_TEST

START_TEST(vec3_needs_exactly_three_numbers)
{
    ck_assert_int_eq(pl_field_parse(&F[5], &o, "1, 2, 3", &err), PL_OK);
    ck_assert(o.v[0] == 1 && o.v[1] == 2 && o.v[2] == 3);
    ck_assert_int_eq(pl_field_parse(&F[5], &o, "1 2", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[5], &o, "1 2 3 4", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[5], &o, "1 nan 3", &err), PL_EINPUT);
    ck_assert(o.v[1] == 2);
}
END_TEST

START_TEST(lists_strings_and_links)
{
    ck_assert_int_eq(pl_field_parse(&F[6], &o, "0 0 0  1 0 0\n 0 1 0", &err), PL_OK);
    ck_assert_int_eq(o.dl.n, 9);
    ck_assert(o.dl.v[3] == 1.0);
    ck_assert_int_eq(pl_field_parse(&F[6], &o, "0 0 x", &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "value 3"));
    ck_assert_int_eq(o.dl.n, 9);
    ck_assert_int_eq(pl_field_parse(&F[7], &o, "3 39 64", &err), PL_OK);
    ck_assert_int_eq(o.il.n, 3);
    ck_assert_int_eq(o.il.v[2], 64);
    ck_assert_int_eq(pl_field_parse(&F[7], &o, "3 -1e3", &err), PL_EINPUT);
    ck_assert_int_eq(pl_field_parse(&F[6], &o, "", &err), PL_OK);
    ck_assert_int_eq(o.dl.n, 0);
    ck_assert_int_eq(pl_field_parse(&F[4], &o, "meshes/bar.vtk", &err), PL_OK);
    ck_assert_str_eq(o.s, "meshes/bar.vtk");
    ck_assert_int_eq(pl_field_parse(&F[8], &o, "@../loader", &err), PL_OK);
    ck_assert_str_eq(o.l.path, "../loader");
    ck_assert_int_eq(pl_field_parse(&F[8], &o, "loader", &err), PL_EINPUT);
}
END_TEST

START_TEST(edit_distance_finds_close_names)
{
    ck_assert_int_eq(pl_edit_distance("youngModulus", "youngModulus"), 0);
    ck_assert_int_eq(pl_edit_distance("youngModulu", "youngModulus"), 1);
    ck_assert_int_eq(pl_edit_distance("yuongModulus", "youngModulus"), 2);
    ck_assert_int_eq(pl_edit_distance("YoungModulus", "youngModulus"), 0);
}
END_TEST

START_TEST(sparse_triplets_sum_duplicates)
{
    pl_triplets t;
    pl_csc a;
    ck_assert_int_eq(pl_triplets_init(&t, 3, 3, 4), PL_OK);
    pl_triplets_add(&t, 2, 0, 1.0);
    pl_triplets_add(&t, 0, 0, 2.0);
    pl_triplets_add(&t, 2, 0, 3.0);
    pl_triplets_add(&t, 1, 2, 5.0);
    for (int k = 0; k < 100; ++k) pl_triplets_add(&t, 1, 1, 0.5); /* forces growth */
    ck_assert_int_eq(pl_triplets_to_csc(&t, &a), PL_OK);
    ck_assert_int_eq(pl_csc_nnz(&a), 4);
    ck_assert_int_eq(a.p[1], 2);
    ck_assert_int_eq(a.i[0], 0);
    ck_assert(a.x[0] == 2.0);
    ck_assert_int_eq(a.i[1], 2);
    ck_assert(a.x[1] == 4.0);
    ck_assert(a.x[2] == 50.0);
    ck_assert(a.x[3] == 5.0);
    pl_csc_free(&a);
    pl_triplets_free(&t);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("fields");
    TCase *tc = tcase_create("parse");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, double_parses_exactly_and_rejects_garbage);
    tcase_add_test(tc, int_and_bool_values);
    tcase_add_test(tc, enum_by_name_or_index_with_suggestion);
    tcase_add_test(tc, vec3_needs_exactly_three_numbers);
    tcase_add_test(tc, lists_strings_and_links);
    tcase_add_test(tc, edit_distance_finds_close_names);
    tcase_add_test(tc, sparse_triplets_sum_duplicates);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
