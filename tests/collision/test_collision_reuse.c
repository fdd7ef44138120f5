/* test_collision_reuse.c - what detection keeps from step to step gives
 * what computing it afresh gives, bitwise (the host detection's fixed cost,
 * issue 16; docs/benchmarks.md, "The host detection's fixed cost"):
 *  - a tree fitted to ungrown boxes and compared grown by h
 *    (bvh_query_grown) finds the hits of the same tree refitted to the
 *    boxes grown by h, and its node boxes grown by h are those boxes'
 *    union, bitwise: coll_mesh_inflate grows nothing;
 *  - meshes prepared again after their vertices moved (trees refitted only
 *    when detect_pair walks them, coll_mesh_fit) and inflated for a second
 *    pass give the proximities and box overlaps of meshes built afresh at
 *    the new positions with that margin, bitwise and in order;
 *  - a tree left stale by coll_mesh_prepare is refitted by detect_pair (its
 *    boxes then equal a fresh build's refit); the trees detect_pair does
 *    not walk stay stale. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "detect.h"
#include "sheet_pair.h"

static void random_boxes(unsigned *s, pl_aabb *b, int n)
{
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double c = sheet_urand(s), h = 0.06 * sheet_urand(s);
            b[i].lo[k] = c - h;
            b[i].hi[k] = c + h;
        }
}

START_TEST(test_grown_tree_equals_tree_of_grown_boxes)
{
    unsigned s = 99u;
    const int n = 700;
    pl_aabb *raw = malloc(n * sizeof *raw), *grown = malloc(n * sizeof *grown);
    ck_assert(raw && grown);
    random_boxes(&s, raw, n);
    pl_bvh a, b;
    bvh_init(&a);
    bvh_init(&b);
    ck_assert_int_eq(bvh_build(&a, raw, n), PL_OK);
    ck_assert_int_eq(bvh_build(&b, raw, n), PL_OK);
    pl_ivec got = {0}, want = {0};
    long hits = 0;
    for (int trial = 0; trial < 6; ++trial) {
        double h = trial == 0 ? 0.0 : 0.001 * trial * (1.0 + sheet_urand(&s)) / 3.0;
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                grown[i].lo[k] = raw[i].lo[k] - h;
                grown[i].hi[k] = raw[i].hi[k] + h;
            }
        bvh_refit(&b, grown); /* the same topology, fitted to the grown boxes */
        for (int node = 0; node < a.nnodes; ++node)
            for (int k = 0; k < 3; ++k) {
                ck_assert(a.box[node].lo[k] - h == b.box[node].lo[k]);
                ck_assert(a.box[node].hi[k] + h == b.box[node].hi[k]);
            }
        for (int qi = 0; qi < 200; ++qi) {
            pl_aabb q, qg;
            random_boxes(&s, &q, 1);
            double hq = 0.02 * sheet_urand(&s);
            for (int k = 0; k < 3; ++k) {
                qg.lo[k] = q.lo[k] - hq;
                qg.hi[k] = q.hi[k] + hq;
            }
            got.n = want.n = 0;
            ck_assert_int_eq(bvh_query_grown(&a, raw, h, &q, hq, &got), PL_OK);
            ck_assert_int_eq(bvh_query(&b, grown, &qg, &want), PL_OK);
            ck_assert_int_eq(got.n, want.n);
            for (int i = 0; i < got.n; ++i) ck_assert_int_eq(got.v[i], want.v[i]);
            hits += got.n;
        }
        /* the raw boxes move: both trees refitted */
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                double d = 0.05 * (sheet_urand(&s) - 0.5);
                raw[i].lo[k] += d;
                raw[i].hi[k] += d;
            }
        bvh_refit(&a, raw);
    }
    ck_assert_int_gt(hits, 1000); /* the queries found something */
    ivec_free(&got);
    ivec_free(&want);
    bvh_free(&a);
    bvh_free(&b);
    free(raw);
    free(grown);
}
END_TEST

static int same_proximities(const pl_proximities *p, const pl_proximities *q)
{
    if (p->n != q->n) return 0;
    for (int k = 0; k < p->n; ++k)
        if (memcmp(&p->items[k], &q->items[k], sizeof p->items[k])) return 0;
    return 1;
}

/* The sheets' vertices moved: x0 and x1 by d, different per vertex. */
static void move(sheet *s, unsigned *seed)
{
    for (int i = 0; i < 3 * s->nv; ++i) {
        double d = 0.004 * (sheet_urand(seed) - 0.5);
        s->x0[i] += d;
        s->x1[i] += d + 0.002 * (sheet_urand(seed) - 0.5);
    }
}

START_TEST(test_kept_meshes_equal_fresh_ones)
{
    unsigned seed = 31u;
    int found = 0, inflated = 0;
    for (int trial = 0; trial < 8; ++trial) {
        double alarm = 0.01 + 0.02 * sheet_urand(&seed);
        sheet_pair sp;
        sheet_make_ck(&sp.a, 12 + trial % 4, 0.0, 0.1, 0.0, 0.01, &seed);
        sheet_make_ck(&sp.b, 10 + trial % 3, 0.05, 0.1, -0.04, 0.01, &seed);
        pl_mesh_sides sa = trial % 2 ? PL_SIDES_TWO : PL_SIDES_ONE;
        sheet_pair_mesh(&sp, sa, alarm);
        sheet *a = &sp.a, *b = &sp.b;
        pl_coll_mesh *ka = &sp.ma, *kb = &sp.mb; /* the kept meshes */
        pl_error err;
        for (int step = 0; step < 4; ++step) {
            move(a, &seed);
            move(b, &seed);
            /* the kept meshes: prepared again (trees stale), maybe inflated */
            ck_assert_int_eq(coll_mesh_prepare(ka, alarm, &err), PL_OK);
            ck_assert_int_eq(coll_mesh_prepare(kb, alarm, &err), PL_OK);
            ck_assert_int_eq(ka->stale, COLL_TREE_TRIS | COLL_TREE_EDGES);
            pl_detect_params prm = detect_defaults(alarm);
            prm.contact = 0.5 * alarm;
            prm.margin = step % 2 ? 0.01 * (1.0 + sheet_urand(&seed)) : 0.0;
            if (prm.margin > 0.0) {
                coll_mesh_inflate(ka, alarm + prm.margin);
                coll_mesh_inflate(kb, alarm + prm.margin);
                inflated++;
            }
            /* fresh meshes at the new positions with that margin */
            pl_coll_mesh fa, fb;
            sheet_mesh_ck(a, &fa, sa, alarm + prm.margin);
            sheet_mesh_ck(b, &fb, PL_SIDES_TWO, alarm + prm.margin);
            pl_proximities p = {0}, q = {0};
            pl_detect_counts cp = {0}, cq = {0};
            prm.counts = &cp;
            ck_assert_int_eq(detect_pair(ka, 0, kb, 1, &prm, &p), PL_OK);
            prm.counts = &cq;
            ck_assert_int_eq(detect_pair(&fa, 0, &fb, 1, &prm, &q), PL_OK);
            ck_assert_msg(same_proximities(&p, &q), "trial %d step %d: %d against %d", trial,
                          step, p.n, q.n);
            ck_assert_int_eq(cp.candidates, cq.candidates);
            /* the walked trees were refitted: their boxes are a fresh
             * build's (the same topology: built from the first positions
             * the kept tree was not, so compare the root, which is the
             * union of all boxes whatever the tree) */
            ck_assert_int_eq(ka->stale, COLL_TREE_EDGES); /* A's edges walk B's tree */
            ck_assert_int_eq(kb->stale, 0);
            ck_assert(!memcmp(&ka->tbvh.box[0], &fa.tbvh.box[0], sizeof(pl_aabb)));
            ck_assert(!memcmp(&kb->ebvh.box[0], &fb.ebvh.box[0], sizeof(pl_aabb)));
            found += p.n;
            proximities_free(&p);
            proximities_free(&q);
            coll_mesh_free(&fa);
            coll_mesh_free(&fb);
        }
        sheet_pair_free(&sp);
    }
    ck_assert_int_gt(found, 200);
    ck_assert_int_gt(inflated, 8);
}
END_TEST

START_TEST(test_trees_not_walked_stay_stale)
{
    unsigned seed = 7u;
    sheet_pair sp;
    sheet_make_ck(&sp.a, 8, 0.0, 0.1, 0.0, 0.01, &seed);
    sheet_make_ck(&sp.b, 8, 0.02, 0.1, 0.0, 0.01, &seed);
    sheet_pair_mesh(&sp, PL_SIDES_TWO, 0.01);
    pl_coll_mesh *ma = &sp.ma, *mb = &sp.mb;
    pl_error err;
    ck_assert_int_eq(ma->stale, 0); /* built: fitted */
    move(&sp.a, &seed);
    move(&sp.b, &seed);
    ck_assert_int_eq(coll_mesh_prepare(ma, 0.01, &err), PL_OK);
    ck_assert_int_eq(coll_mesh_prepare(mb, 0.01, &err), PL_OK);
    pl_detect_params prm = detect_defaults(0.01);
    prm.vertex_face = 0; /* edges only: A's edges walk B's edge tree */
    pl_proximities p = {0};
    ck_assert_int_eq(detect_pair(ma, 0, mb, 1, &prm, &p), PL_OK);
    ck_assert_int_eq(ma->stale, COLL_TREE_TRIS | COLL_TREE_EDGES);
    ck_assert_int_eq(mb->stale, COLL_TREE_TRIS);
    coll_mesh_fit(ma, COLL_TREE_EDGES);
    ck_assert_int_eq(ma->stale, COLL_TREE_TRIS);
    proximities_free(&p);
    sheet_pair_free(&sp);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_reuse");
    TCase *tc = tcase_create("reuse");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_grown_tree_equals_tree_of_grown_boxes);
    tcase_add_test(tc, test_kept_meshes_equal_fresh_ones);
    tcase_add_test(tc, test_trees_not_walked_stay_stale);
    suite_add_tcase(s, tc);
    SRunner *r = srunner_create(s);
    srunner_run_all(r, CK_NORMAL);
    int failed = srunner_ntests_failed(r);
    srunner_free(r);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
