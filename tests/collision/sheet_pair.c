/* sheet_pair.c - two sheets and their meshes for the detection tests
 * (sheet_pair.h). */
#include "sheet_pair.h"

#include <check.h>

void sheet_make_ck(sheet *s, int n, double z0, double bump, double dz, double noise,
                   unsigned *seed)
{
    ck_assert_int_eq(sheet_make(s, n, z0, bump, dz, noise, seed), PL_OK);
}

void sheet_mesh_ck(const sheet *s, pl_coll_mesh *m, pl_mesh_sides sides, double margin)
{
    pl_error err;
    ck_assert_int_eq(sheet_mesh(s, m, sides, margin, &err), PL_OK);
}

void sheet_pair_mesh(sheet_pair *p, pl_mesh_sides sides_a, double margin)
{
    sheet_mesh_ck(&p->a, &p->ma, sides_a, margin);
    sheet_mesh_ck(&p->b, &p->mb, PL_SIDES_TWO, margin);
}

void sheet_pair_free(sheet_pair *p)
{
    coll_mesh_free(&p->ma);
    coll_mesh_free(&p->mb);
    sheet_free(&p->a);
    sheet_free(&p->b);
}
