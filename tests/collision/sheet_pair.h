/* sheet_pair.h - the setup the mesh-versus-mesh detection tests share
 * (test_collision_detect.c, test_collision_reuse.c, test_collision_cand.c):
 * two random sheets (sheet_fixture.h) and their collision meshes, built
 * under Check's assertions so that a test stops where the fixture fails. */
#ifndef PLIANT_SHEET_PAIR_H
#define PLIANT_SHEET_PAIR_H

#include "sheet_fixture.h"

typedef struct sheet_pair {
    sheet a, b;
    pl_coll_mesh ma, mb; /* over a and b (sheet_pair_mesh) */
} sheet_pair;

/* sheet_make, asserted to succeed. */
void sheet_make_ck(sheet *s, int n, double z0, double bump, double dz, double noise,
                   unsigned *seed);
/* sheet_mesh, asserted to succeed. */
void sheet_mesh_ck(const sheet *s, pl_coll_mesh *m, pl_mesh_sides sides, double margin);
/* The meshes of a pair's sheets with the box margin `margin`: ma with
 * sides_a, mb two-sided. */
void sheet_pair_mesh(sheet_pair *p, pl_mesh_sides sides_a, double margin);
/* Frees the meshes, then the sheets. */
void sheet_pair_free(sheet_pair *p);

#endif
