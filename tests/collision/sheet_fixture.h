/* sheet_fixture.h - random wavy sheets for the detection tests (host and GPU):
 * n x n vertices over [0,1]^2, two triangles a quad, with the edges. */
#ifndef PLIANT_SHEET_FIXTURE_H
#define PLIANT_SHEET_FIXTURE_H

#include "detect.h"

typedef struct sheet {
    int nv, nt, ne;
    double *x0, *x1; /* positions at the start and at the end of the step */
    int *tris, *edges;
} sheet;

/* A linear congruential draw in [0,1]: the same sequence on every platform. */
double sheet_urand(unsigned *s);

/* x0: the grid at height z0, moved by 0.2 bump in x, y and by bump in z at
 * random; x1 = x0 + dz along z + noise at random in each coordinate.
 * Returns PL_OK, or -1 when memory runs out (s is then freed). */
int sheet_make(sheet *s, int n, double z0, double bump, double dz, double noise, unsigned *seed);
void sheet_free(sheet *s);

/* A collision mesh over the sheet's arrays (not copied), prepared with the
 * given box margin; returns coll_mesh_prepare's status. */
int sheet_mesh(const sheet *s, pl_coll_mesh *m, pl_mesh_sides sides, double margin,
               pl_error *err);

#endif
