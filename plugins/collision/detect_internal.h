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
 * NULL in the first).  Fills out and *face (the vertex projects inside the
 * triangle); returns 1 when the pair is kept. */
int coll_vf_candidate(const pl_coll_mesh *P, int ip, int p, const pl_coll_mesh *T, int it, int j,
                      int self, const coll_vv_kept *second, const pl_detect_params *prm,
                      pl_proximity *out, int *face);

/* Edge e of A against edge f of B; fills out, returns 1 when kept. */
int coll_ee_candidate(const pl_coll_mesh *A, int ia, int e, const pl_coll_mesh *B, int ib, int f,
                      int self, const pl_detect_params *prm, pl_proximity *out);

#endif
