/* test_collision_mesh_clean.c - an obstacle mesh damaged on purpose and
 * cleaned on load (plugins/collision/mesh_clean.c, issue 14 item 2): a unit
 * cube's 12 outward triangles with a duplicate, a reversed copy, a
 * triangle missing (a hole), a zero-area triangle, a triangle with a
 * repeated vertex and a fin (a third triangle on edge 0-1).  The counts
 * are worked out by hand from the cube's 18 edges. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"

/* vertex i of the unit cube is (i & 1, (i >> 1) & 1, (i >> 2) & 1) */
static const int CUBE[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};

static void make(pl_mesh *m, const int (*tris)[3], int ntris)
{
    pl_mesh_init(m);
    m->nverts = 10;
    m->verts = calloc(30, sizeof *m->verts);
    m->tris = malloc((size_t)ntris * 3 * sizeof *m->tris);
    ck_assert(m->verts && m->tris);
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) m->verts[3 * i + k] = (i >> k) & 1;
    m->verts[3 * 8] = 0.5;                                  /* midpoint of edge 0-1 */
    m->verts[3 * 9 + 1] = -1.0, m->verts[3 * 9 + 2] = -1.0; /* the fin's tip */
    memcpy(m->tris, tris, (size_t)ntris * 3 * sizeof *m->tris);
    m->ntris = ntris;
}

START_TEST(test_damaged_cube_is_cleaned)
{
    int t[17][3], n = 0;
    for (int k = 0; k < 12; ++k)
        if (k != 3) memcpy(t[n++], CUBE[k], sizeof t[0]); /* (4, 7, 6) missing: a hole */
    memcpy(t[n++], CUBE[0], sizeof t[0]);                    /* a duplicate */
    t[n][0] = 0, t[n][1] = 3, t[n++][2] = 2;                 /* a reversed copy of (0, 2, 3) */
    t[n][0] = 0, t[n][1] = 8, t[n++][2] = 1;                 /* no area */
    t[n][0] = 3, t[n][1] = 3, t[n++][2] = 4;                 /* a repeated vertex */
    t[n][0] = 0, t[n][1] = 1, t[n++][2] = 9;                 /* a fin on edge 0-1 */
    pl_mesh m;
    make(&m, (const int(*)[3])t, n);
    coll_clean_report r;
    ck_assert_int_eq(coll_mesh_clean(&m, &r), PL_OK);
    ck_assert_int_eq(r.duplicate, 2);
    ck_assert_int_eq(r.degenerate, 2);
    ck_assert_int_eq(m.ntris, 12);                /* 11 of the cube and the fin */
    ck_assert_int_eq(r.edges, 20);                /* 18 and the fin's two others */
    ck_assert_int_eq(r.border_edges, 5);          /* the hole's 3, the fin's 2 */
    ck_assert_int_eq(r.nonmanifold_edges, 1);     /* 0-1 */
    ck_assert_int_eq(r.misoriented_edges, 0);
    ck_assert(!coll_mesh_encloses(&r));
    /* the first of the copies stays, in its orientation */
    ck_assert_int_eq(m.tris[0], 0);
    ck_assert_int_eq(m.tris[1], 2);
    ck_assert_int_eq(m.tris[2], 3);
    pl_mesh_free(&m);
}
END_TEST

START_TEST(test_orientation_is_checked)
{
    int t[12][3];
    memcpy(t, CUBE, sizeof t);
    t[10][1] = 7, t[10][2] = 3; /* (1, 3, 7) flipped: its three edges misoriented */
    pl_mesh m;
    make(&m, (const int(*)[3])t, 12);
    coll_clean_report r;
    ck_assert_int_eq(coll_mesh_clean(&m, &r), PL_OK);
    ck_assert_int_eq(r.duplicate + r.degenerate + r.border_edges + r.nonmanifold_edges, 0);
    ck_assert_int_eq(r.misoriented_edges, 3);
    ck_assert_int_eq(r.edges, 18);
    ck_assert(!coll_mesh_encloses(&r));
    /* the rule's threshold: at most 1 % of the edges */
    coll_clean_report big = {.edges = 3732, .border_edges = 26, .misoriented_edges = 2,
                             .nonmanifold_edges = 97};
    ck_assert(coll_mesh_encloses(&big)); /* the dragon */
    big.border_edges = 40;
    ck_assert(!coll_mesh_encloses(&big));
    pl_mesh_free(&m);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("collision_mesh_clean");
    TCase *tc = tcase_create("clean");
    tcase_add_test(tc, test_damaged_cube_is_cleaned);
    tcase_add_test(tc, test_orientation_is_checked);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
