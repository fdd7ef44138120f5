/* test_export_regression.c - SOFA's regression list format and its error
 * measure (per compared step ||x - x_ref||_2 / nDoF, summed over the steps,
 * averaged over the states). */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "export/export.h"
#include "export_test_util.h"

/* The two liver references (dofs, spheres) as state 0 and 1. */
static void load_liver(pl_state_records recs[2])
{
    pl_error err;
    pl_state_records_init(&recs[0]);
    pl_state_records_init(&recs[1]);
    ck_assert_int_eq(pl_state_file_read(tu_data("liver.scn.reference_0_dofs_mstate.txt.gz"),
                                        &recs[0], &err),
                     PL_OK);
    ck_assert_int_eq(pl_state_file_read(tu_data("liver.scn.reference_1_spheres_mstate.txt.gz"),
                                        &recs[1], &err),
                     PL_OK);
}

static void copy_records(pl_state_records *dst, const pl_state_records *src, double dt_shift)
{
    pl_error err;
    pl_state_records_init(dst);
    for (int r = 0; r < src->count; ++r) {
        const pl_state_record *s = &src->items[r];
        ck_assert_int_eq(pl_state_records_add(dst, s->time + dt_shift, s->x, s->nx, s->v, s->nv,
                                              &err),
                         PL_OK);
    }
}

START_TEST(metric_is_zero_on_identical_records)
{
    pl_state_records ref[2], cur[2];
    load_liver(ref);
    /* the current run's times carry rounding (1.98 after 99 additions of 0.02) */
    copy_records(&cur[0], &ref[0], 3e-15);
    copy_records(&cur[1], &ref[1], -3e-15);
    pl_regression_result res;
    pl_error err;
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.01, 1e-4, &res, &err), PL_OK);
    ck_assert_double_eq(res.error_by_dof, 0.0);
    ck_assert_double_eq(res.total_error, 0.0);
    ck_assert_int_eq(res.compared, 4); /* 2 states x (T=0, T=1.98) */
    ck_assert_int_eq(res.missing, 0);
    ck_assert_int_eq(res.passed, 1);
    /* even epsilon 0 passes when nothing differs */
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.01, 0.0, &res, &err), PL_OK);
    ck_assert_int_eq(res.passed, 1);
    for (int k = 0; k < 2; ++k) {
        pl_state_records_free(&ref[k]);
        pl_state_records_free(&cur[k]);
    }
}
END_TEST

START_TEST(metric_equals_hand_computed_value_on_exact_perturbation)
{
    /* state 0: 2 vertices (6 DoF), two steps; state 1 unchanged */
    double zero[6] = {0}, a[6] = {0}, b[6] = {0};
    const double u = ldexp(1.0, -10);
    a[0] = 3 * u; a[1] = 4 * u;         /* ||.|| = 5u */
    b[3] = -12 * u; b[5] = 5 * u;       /* ||.|| = 13u */
    pl_state_records ref[2], cur[2];
    pl_error err;
    for (int k = 0; k < 2; ++k) {
        pl_state_records_init(&ref[k]);
        pl_state_records_init(&cur[k]);
    }
    pl_state_records_add(&ref[0], 0.0, zero, 6, NULL, 0, &err);
    pl_state_records_add(&ref[0], 0.5, zero, 6, NULL, 0, &err);
    pl_state_records_add(&cur[0], 0.0, a, 6, NULL, 0, &err);
    pl_state_records_add(&cur[0], 0.25, zero, 6, NULL, 0, &err); /* not in the reference */
    pl_state_records_add(&cur[0], 0.5, b, 6, NULL, 0, &err);
    pl_state_records_add(&ref[1], 0.0, zero, 3, NULL, 0, &err);
    pl_state_records_add(&cur[1], 0.0, zero, 3, NULL, 0, &err);
    pl_regression_result res;
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.1, 1.0, &res, &err), PL_OK);
    /* (5u/6 + 13u/6 + 0) / 2 states = 1.5 u */
    ck_assert_double_eq_tol(res.error_by_dof, 1.5 * u, 1e-18);
    ck_assert_double_eq_tol(res.total_error, 9.0 * u, 1e-18);
    ck_assert_int_eq(res.compared, 3);
    ck_assert_double_eq_tol(pl_regression_step_error(b, zero, 6), 13.0 * u / 6.0, 1e-18);
    /* epsilon just below / above the value */
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.1, 1.49 * u, &res, &err), PL_OK);
    ck_assert_int_eq(res.passed, 0);
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.1, 1.51 * u, &res, &err), PL_OK);
    ck_assert_int_eq(res.passed, 1);
    for (int k = 0; k < 2; ++k) {
        pl_state_records_free(&ref[k]);
        pl_state_records_free(&cur[k]);
    }
}
END_TEST

/* pl_regression_compare_detail: which state and vertex is worst, how far,
 * when; the relative error at the last reference time; a missing step. */
START_TEST(detail_names_state_vertex_distance_and_relative_error)
{
    double r0[6] = {0, 0, 0, 3, 4, 0}, c0[6] = {0, 0, 0, 3, 4, 0}, c1[6] = {0, 0, 0, 3, 4, 0.5};
    double r1[3] = {1, 1, 1}, c2[3] = {1, 1, 1.1};
    pl_state_records ref[2], cur[2];
    pl_error err;
    for (int k = 0; k < 2; ++k) {
        pl_state_records_init(&ref[k]);
        pl_state_records_init(&cur[k]);
    }
    pl_state_records_add(&ref[0], 0.0, r0, 6, NULL, 0, &err);
    pl_state_records_add(&ref[0], 1.0, r0, 6, NULL, 0, &err);
    pl_state_records_add(&cur[0], 0.0, c0, 6, NULL, 0, &err);
    pl_state_records_add(&cur[0], 1.0, c1, 6, NULL, 0, &err);
    pl_state_records_add(&ref[1], 1.0, r1, 3, NULL, 0, &err); /* one point: no box */
    pl_state_records_add(&cur[1], 1.0, c2, 3, NULL, 0, &err);
    pl_regression_result res;
    pl_regression_detail why;
    ck_assert_int_eq(pl_regression_compare_detail(ref, cur, 2, 0.1, 1e-3, &res, &why, &err), PL_OK);
    ck_assert_int_eq(res.passed, 0);
    ck_assert_int_eq(why.worst_state, 0); /* 0.5 / 6 against 0.1 / 3 */
    ck_assert_int_eq(why.worst_vertex, 1);
    ck_assert_double_eq_tol(why.worst_distance, 0.5, 1e-15);
    ck_assert_double_eq(why.worst_time, 1.0);
    ck_assert_double_eq_tol(why.last_relative, 0.5 / 5.0, 1e-15); /* the box of (0,0,0)-(3,4,0) */
    ck_assert_double_eq(why.last_time, 1.0);
    ck_assert_int_eq(why.missing_state, -1);
    /* a reference step the run did not record */
    pl_state_records_add(&ref[1], 2.0, r1, 3, NULL, 0, &err);
    ck_assert_int_eq(pl_regression_compare_detail(ref, cur, 2, 0.1, 1.0, &res, &why, &err), PL_OK);
    ck_assert_int_eq(res.passed, 0);
    ck_assert_int_eq(res.missing, 1);
    ck_assert_int_eq(why.missing_state, 1);
    ck_assert_double_eq(why.missing_time, 2.0);
    for (int k = 0; k < 2; ++k) {
        pl_state_records_free(&ref[k]);
        pl_state_records_free(&cur[k]);
    }
}
END_TEST

START_TEST(metric_on_perturbed_liver_matches_formula)
{
    pl_state_records ref[2], cur[2];
    load_liver(ref);
    copy_records(&cur[0], &ref[0], 0.0);
    copy_records(&cur[1], &ref[1], 0.0);
    /* every coordinate of the dofs at T=1.98 moved by delta */
    const double delta = 1e-3;
    pl_state_record *last = &cur[0].items[1];
    double sum2 = 0.0;
    for (int i = 0; i < last->nx; ++i) {
        double moved = last->x[i] + delta;
        double d = moved - ref[0].items[1].x[i]; /* delta up to rounding */
        sum2 += d * d;
        last->x[i] = moved;
    }
    ck_assert_int_eq(last->nx, 543);
    double expected = sqrt(sum2) / 543.0 / 2.0; /* one step of one of two states */
    ck_assert_double_eq_tol(expected, delta / sqrt(543.0) / 2.0, 1e-12);
    pl_regression_result res;
    pl_error err;
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.01, 1e-4, &res, &err), PL_OK);
    ck_assert_double_eq_tol(res.error_by_dof, expected, 1e-13 * expected);
    ck_assert_int_eq(res.passed, 1); /* 2.1e-5 <= 1e-4, SOFA's liver tolerance */
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.01, 1e-5, &res, &err), PL_OK);
    ck_assert_int_eq(res.passed, 0);
    for (int k = 0; k < 2; ++k) {
        pl_state_records_free(&ref[k]);
        pl_state_records_free(&cur[k]);
    }
}
END_TEST

START_TEST(metric_reports_missing_steps_and_size_mismatch)
{
    pl_state_records ref[2], cur[2];
    load_liver(ref);
    pl_error err;
    pl_regression_result res;
    /* a run that stopped early: T=1.98 is missing for both states */
    for (int k = 0; k < 2; ++k) {
        pl_state_records_init(&cur[k]);
        const pl_state_record *s = &ref[k].items[0];
        pl_state_records_add(&cur[k], s->time, s->x, s->nx, NULL, 0, &err);
        pl_state_records_add(&cur[k], 1.0, s->x, s->nx, NULL, 0, &err);
    }
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.01, 1e-4, &res, &err), PL_OK);
    ck_assert_int_eq(res.missing, 2);
    ck_assert_int_eq(res.compared, 2);
    ck_assert_int_eq(res.passed, 0);
    /* a state of another size is an input error */
    ck_assert_int_eq(pl_regression_compare(ref, &cur[1], 1, 0.01, 1e-4, &res, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "543"));
    ck_assert_int_eq(pl_regression_compare(ref, cur, 0, 0.01, 1e-4, &res, &err), PL_EINPUT);
    ck_assert_int_eq(pl_regression_compare(ref, cur, 2, 0.0, 1e-4, &res, &err), PL_EINPUT);
    for (int k = 0; k < 2; ++k) {
        pl_state_records_free(&ref[k]);
        pl_state_records_free(&cur[k]);
    }
}
END_TEST

/* ---- the list format ----------------------------------------------------- */

START_TEST(list_parses_sofa_format)
{
    const char *text = "### Regression state scenes ###\n"
                       "$REGRESSION_DIR/references/examples\n"
                       "\n"
                       "  # Demo scenes\n"
                       "Demos/liver.scn 100 1e-4 1 1\n"
                       "Demos/fallingBeamLagrangianCollision.scn\t46  1e-7 1 1   # beam\r\n"
                       "Component/Mass/MeshMatrixMass.scn 200 0.5\n"
                       "x.scn 3 0 1";
    pl_regression_list l;
    pl_diag d;
    pl_diag_init(&d);
    ck_assert_int_eq(pl_regression_list_parse(text, "list.regression-tests", &l, &d), PL_OK);
    ck_assert_int_eq(d.nerrors, 0);
    ck_assert_str_eq(l.ref_dir, "$REGRESSION_DIR/references/examples");
    ck_assert_int_eq(l.count, 4);
    ck_assert_str_eq(l.items[0].scene, "Demos/liver.scn");
    ck_assert_int_eq(l.items[0].steps, 100);
    ck_assert_double_eq(l.items[0].epsilon, 1e-4);
    ck_assert_int_eq(l.items[0].mapped, 1);
    ck_assert_int_eq(l.items[0].last_only, 1);
    ck_assert_int_eq(l.items[0].line, 5);
    ck_assert_str_eq(l.items[1].scene, "Demos/fallingBeamLagrangianCollision.scn");
    ck_assert_int_eq(l.items[1].steps, 46);
    ck_assert_double_eq(l.items[1].epsilon, 1e-7);
    ck_assert_int_eq(l.items[1].line, 6);
    ck_assert_int_eq(l.items[2].mapped, 0);   /* defaults */
    ck_assert_int_eq(l.items[2].last_only, 0);
    ck_assert_double_eq(l.items[2].epsilon, 0.5);
    ck_assert_int_eq(l.items[3].steps, 3);
    ck_assert_int_eq(l.items[3].mapped, 1);
    ck_assert_int_eq(l.items[3].line, 8);
    pl_regression_list_free(&l);
    pl_diag_free(&d);
}
END_TEST

START_TEST(list_rejects_malformed_lines_with_their_numbers)
{
    const char *text = "# header comment\n"              /* 1 */
                       "good.scn 10 1e-3\n"             /* 2 */
                       "steps.scn abc 1e-3\n"           /* 3: steps not an integer */
                       "zero.scn 0 1e-3\n"              /* 4: steps must be > 0 */
                       "\n"                             /* 5 */
                       "eps.scn 10 -1\n"                /* 6: negative epsilon */
                       "eps2.scn 10 1e-3x\n"            /* 7: trailing garbage */
                       "map.scn 10 1e-3 2\n"            /* 8: mapped not 0/1 */
                       "last.scn 10 1e-3 0 yes\n"       /* 9: lastonly not 0/1 */
                       "many.scn 10 1e-3 0 0 extra\n"   /* 10: too many fields */
                       "short.scn 10\n"                 /* 11: epsilon missing */
                       "lonely.scn\n"                   /* 12: one field after the first line */
                       "also_good.scn 5 0 0 1\n";       /* 13 */
    const int bad_lines[] = {3, 4, 6, 7, 8, 9, 10, 11, 12};
    const char *needles[] = {"'abc'", "'0'", "'-1'", "'1e-3x'", "'2'", "'yes'", "more than 5",
                             "found 2", "found 1"};
    pl_regression_list l;
    pl_diag d;
    pl_diag_init(&d);
    ck_assert_int_eq(pl_regression_list_parse(text, "my.list", &l, &d), PL_EINPUT);
    ck_assert_int_eq(d.nerrors, 9);
    for (int k = 0; k < 9; ++k) {
        ck_assert_int_eq(d.items[k].line, bad_lines[k]);
        ck_assert_str_eq(d.items[k].file, "my.list");
        ck_assert_msg(strstr(d.items[k].msg, needles[k]), "line %d: '%s' lacks %s", bad_lines[k],
                      d.items[k].msg, needles[k]);
    }
    /* the good lines are still there: the user sees everything at once */
    ck_assert_ptr_null(l.ref_dir);
    ck_assert_int_eq(l.count, 2);
    ck_assert_str_eq(l.items[0].scene, "good.scn");
    ck_assert_str_eq(l.items[1].scene, "also_good.scn");
    ck_assert_int_eq(l.items[1].last_only, 1);
    pl_regression_list_free(&l);
    pl_diag_free(&d);
}
END_TEST

/* A byte order mark would become part of the first folder name, and a NUL
 * byte would silently end the list: both are errors naming the line. */
START_TEST(list_with_a_bom_or_a_nul_byte_is_refused)
{
    pl_regression_list l;
    pl_diag d;
    pl_diag_init(&d);
    ck_assert_int_eq(pl_regression_list_parse("\xEF\xBB\xBFrefs\na.scn 10 1e-3\n", "bom.list", &l,
                                               &d), PL_EINPUT);
    ck_assert_int_eq(d.items[0].line, 1);
    ck_assert_msg(strstr(d.items[0].msg, "byte order mark"), "%s", d.items[0].msg);
    ck_assert_int_eq(l.count, 0);
    ck_assert_ptr_null(l.ref_dir);
    pl_diag_free(&d);
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "nul.list");
    const char text[] = "a.scn 10 1e-3\nb.scn 10\0 1e-3\nc.scn 10 1e-3\n";
    FILE *f = fopen(path, "wb");
    ck_assert_ptr_nonnull(f);
    ck_assert_uint_eq(fwrite(text, 1, sizeof text - 1, f), sizeof text - 1);
    fclose(f);
    pl_diag_init(&d);
    ck_assert_int_eq(pl_regression_list_load(path, &l, &d), PL_EINPUT);
    ck_assert_int_eq(d.items[0].line, 2);
    ck_assert_str_eq(d.items[0].file, path);
    ck_assert_msg(strstr(d.items[0].msg, "NUL byte (at byte 22)"), "%s", d.items[0].msg);
    ck_assert_int_eq(l.count, 0);
    pl_diag_free(&d);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(list_loads_from_file_and_names_reference_files)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "refs.regression-tests");
    ck_assert_int_eq(tu_write_file(path, "data\nliver.scn 100 1e-4 1 1\nbad 1\n"), 0);
    pl_regression_list l;
    pl_diag d;
    pl_diag_init(&d);
    ck_assert_int_eq(pl_regression_list_load(path, &l, &d), PL_EINPUT);
    ck_assert_int_eq(d.nerrors, 1);
    ck_assert_int_eq(d.items[0].line, 3);
    ck_assert_str_eq(d.items[0].file, path);
    ck_assert_str_eq(l.ref_dir, "data");
    ck_assert_int_eq(l.count, 1);
    /* SOFA's naming finds the copied references */
    char ref[1024];
    int n = pl_regression_reference_path(ref, sizeof ref, PL_SOURCE_DIR "/tests/export/data/liver.scn",
                                         1, "spheres");
    ck_assert_int_eq(n, (int)strlen(ref));
    ck_assert_str_eq(ref, PL_SOURCE_DIR "/tests/export/data/liver.scn.reference_1_spheres_mstate.txt.gz");
    ck_assert(tu_exists(ref));
    pl_regression_list_free(&l);
    pl_diag_free(&d);
    ck_assert_int_eq(pl_regression_list_load(tu_path(dir, "missing"), &l, &d), PL_EINPUT);
    pl_diag_free(&d);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("export_regression");
    TCase *tm = tcase_create("metric");
    tcase_add_test(tm, metric_is_zero_on_identical_records);
    tcase_add_test(tm, metric_equals_hand_computed_value_on_exact_perturbation);
    tcase_add_test(tm, metric_on_perturbed_liver_matches_formula);
    tcase_add_test(tm, detail_names_state_vertex_distance_and_relative_error);
    tcase_add_test(tm, metric_reports_missing_steps_and_size_mismatch);
    suite_add_tcase(s, tm);
    TCase *tl = tcase_create("list");
    tcase_add_test(tl, list_parses_sofa_format);
    tcase_add_test(tl, list_rejects_malformed_lines_with_their_numbers);
    tcase_add_test(tl, list_loads_from_file_and_names_reference_files);
    tcase_add_test(tl, list_with_a_bom_or_a_nul_byte_is_refused);
    suite_add_tcase(s, tl);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
