/* test_collision_cand.c - the device detection's work replayed on the host
 * (detect_cand.h's kernel bodies through coll_cand_host, no GPU):
 *  - the candidate lists are sorted, each a subset of the BVH's box hits,
 *    and the filter drops pairs (it is not the broad phase alone);
 *  - detect_pair over those candidates gives detect_pair's proximities,
 *    bitwise and in the same order: sheets moving through each other fast
 *    (look-ahead), with a margin (the struck pass), one- and two-sided,
 *    and a sheet against itself. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "detect.h"
#include "sheet_pair.h"

/* Every list sorted and within the BVH's hits; returns the candidates kept
 * and adds the BVH's hits to *hits. */
static long check_lists(const pl_coll_mesh *A, const pl_coll_mesh *B, const coll_cand_list g[3],
                        long *hits)
{
    long kept = 0;
    for (int l = 0; l < 3; ++l) {
        if (l == 1 && A == B) continue;
        const pl_coll_mesh *P = l == 1 ? B : A, *T = l == 1 ? A : B;
        int edges = l == 2, items = edges ? P->nedges : P->nverts;
        ck_assert_int_eq(g[l].n, items);
        pl_ivec q = {0};
        for (int i = 0; i < items; ++i) {
            q.n = 0;
            ck_assert_int_eq(bvh_query_grown(edges ? &T->ebvh : &T->tbvh,
                                             edges ? T->ebox : T->tbox, coll_mesh_half(T),
                                             edges ? &P->ebox[i] : &P->vbox[i],
                                             coll_mesh_half(P), &q),
                             PL_OK);
            *hits += q.n;
            int k = 0;
            for (int c = g[l].start[i]; c < g[l].start[i + 1]; ++c) {
                if (c > g[l].start[i]) ck_assert_int_lt(g[l].idx[c - 1], g[l].idx[c]);
                while (k < q.n && q.v[k] < g[l].idx[c]) k++;
                ck_assert_msg(k < q.n && q.v[k] == g[l].idx[c], "list %d item %d: %d not a hit",
                              l, i, g[l].idx[c]);
                kept++;
            }
        }
        ivec_free(&q);
    }
    return kept;
}

static void expect_given_equal(pl_coll_mesh *A, pl_coll_mesh *B,
                               const pl_detect_params *prm, long *kept, long *hits, int *found)
{
    coll_cand_list g[3];
    memset(g, 0, sizeof g);
    long long broad = -1;
    ck_assert_int_eq(coll_cand_host_counted(A, B, prm, g, &broad), PL_OK);
    *kept += check_lists(A, B, g, hits);
    pl_proximities p = {0}, q = {0};
    /* the box overlaps the candidates' broad phase counts are the BVHs'
     * (detection's statistic, and PLIANT_DETECT=auto's rule, are the same
     * on both paths) */
    pl_detect_counts counts = {0};
    pl_detect_params pc = *prm;
    pc.counts = &counts;
    ck_assert_int_eq(detect_pair(A, 0, B, A == B ? 0 : 1, &pc, &p), PL_OK);
    ck_assert_int_eq(broad, counts.candidates);
    proximities_free(&p);
    memset(&p, 0, sizeof p);
    ck_assert_int_eq(detect_pair(A, 0, B, A == B ? 0 : 1, prm, &p), PL_OK);
    ck_assert_int_eq(detect_pair_given(A, 0, B, A == B ? 0 : 1, prm, g, &q), PL_OK);
    ck_assert_int_eq(p.n, q.n);
    for (int k = 0; k < p.n; ++k)
        ck_assert_msg(memcmp(&p.items[k], &q.items[k], sizeof p.items[k]) == 0,
                      "proximity %d of %d differs", k, p.n);
    *found += p.n;
    proximities_free(&p);
    proximities_free(&q);
    for (int l = 0; l < 3; ++l) coll_cand_list_free(&g[l]);
}

START_TEST(test_given_candidates_equal_detection)
{
    unsigned seed = 77u;
    long kept = 0, hits = 0;
    int found = 0, lookahead = 0;
    for (int trial = 0; trial < 16; ++trial) {
        double alarm = 0.01 + 0.03 * sheet_urand(&seed);
        /* every other trial: B crosses A's plane within the step (look-ahead) */
        double dz = trial % 2 ? -0.12 : 0.0;
        sheet_pair sp;
        sheet_make_ck(&sp.a, 13 + trial % 5, 0.0, 0.1, 0.0, 0.02, &seed);
        /* 20: B has more edges than A (the swapped edge pass) */
        sheet_make_ck(&sp.b, trial % 3 == 2 ? 20 : 10 + trial % 4, 0.06, 0.1, dz, 0.02, &seed);
        double margin = alarm + (trial % 4 == 3 ? 0.04 : 0.0);
        sheet_pair_mesh(&sp, trial % 3 ? PL_SIDES_TWO : PL_SIDES_ONE, margin);
        pl_detect_params prm = detect_defaults(alarm);
        prm.contact = 0.5 * alarm;
        prm.margin = trial % 4 == 3 ? 0.02 : 0.0;
        int before = found;
        expect_given_equal(&sp.ma, &sp.mb, &prm, &kept, &hits, &found);
        if (dz != 0.0 && found > before) lookahead++;
        expect_given_equal(&sp.ma, &sp.ma, &prm, &kept, &hits, &found); /* self */
        sheet_pair_free(&sp);
    }
    ck_assert_int_gt(found, 1000);
    ck_assert_int_gt(lookahead, 4);
    /* the filter drops some of the broad phase's pairs, and keeps more
     * than detection does (the rules are the host's) */
    ck_assert_msg(kept < hits, "filter kept %ld of %ld hits", kept, hits);
    ck_assert_int_ge(kept, found);
}
END_TEST

START_TEST(test_empty_meshes)
{
    unsigned seed = 5u;
    sheet a;
    sheet_make_ck(&a, 6, 0.0, 0.1, 0.0, 0.0, &seed);
    pl_coll_mesh ma, none;
    sheet_mesh_ck(&a, &ma, PL_SIDES_TWO, 0.01);
    coll_mesh_init(&none);
    pl_error err;
    ck_assert_int_eq(coll_mesh_prepare(&none, 0.01, &err), PL_OK);
    pl_detect_params prm = detect_defaults(0.01);
    coll_cand_list g[3];
    memset(g, 0, sizeof g);
    ck_assert_int_eq(coll_cand_host(&ma, &none, &prm, g), PL_OK);
    ck_assert_int_eq(g[0].start[g[0].n], 0);
    ck_assert_int_eq(g[2].start[g[2].n], 0);
    for (int l = 0; l < 3; ++l) coll_cand_list_free(&g[l]);
    coll_mesh_free(&ma);
    coll_mesh_free(&none);
    sheet_free(&a);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("collision_cand");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_given_candidates_equal_detection);
    tcase_add_test(tc, test_empty_meshes);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *sr = srunner_create(suite());
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
