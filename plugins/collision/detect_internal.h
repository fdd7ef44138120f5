/* detect_internal.h - what the two halves of detection share (collision_core
 * internal): the measure of one candidate pair (detect.c) and the list
 * append used by the loops (detect_run.c). */
#ifndef PLIANT_COLLISION_DETECT_INTERNAL_H
#define PLIANT_COLLISION_DETECT_INTERNAL_H

#include "detect.h"

/* Appends x; PL_OK or PL_EINTERNAL. */
int coll_prox_push(pl_proximities *p, const pl_proximity *x);

/* The vertex-vertex proximities that the first direction of a pair kept,
 * as sorted keys (vertex of the first direction's points) * nb + (vertex of
 * its triangles' mesh, nb vertices). */
typedef struct coll_vv_kept {
    long long *key;
    int n, nb;
} coll_vv_kept;

/* Collects the vertex-vertex proximities among items[from ..] (the first
 * direction's); PL_OK or PL_EINTERNAL.  Free kv->key. */
int coll_vv_collect(const pl_proximities *items, int from, int nb, coll_vv_kept *kv);

/* Vertex p of P against triangle j of T (self: P == T; second: in the
 * second direction of a pair, the vertex-vertex proximities the first kept,
 * NULL in the first).  Fills out, *face (the vertex projects inside the
 * triangle) and *rank (the order in which a vertex's proximities are
 * considered: nearest first, those found by look-ahead after the others,
 * earliest first); returns 1 when the pair is kept. */
int coll_vf_candidate(const pl_coll_mesh *P, int ip, int p, const pl_coll_mesh *T, int it, int j,
                      int self, const coll_vv_kept *second, const pl_detect_params *prm,
                      pl_proximity *out, int *face, double *rank);

/* Edge e of A against edge f of B; fills out, returns 1 when kept. */
int coll_ee_candidate(const pl_coll_mesh *A, int ia, int e, const pl_coll_mesh *B, int ib, int f,
                      int self, const pl_detect_params *prm, pl_proximity *out);

/* Look-ahead (lookahead.c).  Position of vertex v of m at the instant s of
 * the step, x0 + s (x1 - x0) (exactly x0 at s = 0). */
void coll_at(const pl_coll_mesh *m, int v, double s, double out[3]);
/* For a pair farther apart than alarm at the start of the step (distance
 * d0): whether it comes within alarm + margin during the step, and *s the
 * instant at which to measure it: the first at which it is within the
 * kept gap (contactDistance), or the last instant the advancement reached
 * before it (never past it) when that is within alarm + margin; else the
 * end of the step when it is nearer.  1 or 0. */
int coll_vf_lookahead(const pl_coll_mesh *P, int p, const pl_coll_mesh *T, const int *tri,
                      double d0, const pl_detect_params *prm, double *s);
int coll_ee_lookahead(const pl_coll_mesh *A, const int *ea, const pl_coll_mesh *B,
                      const int *eb, double d0, const pl_detect_params *prm, double *s);

#endif
