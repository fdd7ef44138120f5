/* detect_device.h - detection's candidate pairs on an NVIDIA GPU
 * (detect_device.cu and detect_device_tree.cu, CUDA builds only), for a
 * batch of pairs at once: the swept boxes, a Morton-sorted tree over each
 * mesh's primitives (kept across batches), the box overlaps, then the
 * narrow filter on each, by the item bodies of detect_cand.h.  The lists
 * equal coll_cand_host's; detect_pair_given turns them into the contacts of
 * detect_pair.  Positions are uploaded once per batch (the host computes
 * x0 / x1 today). */
#ifndef PLIANT_COLLISION_DETECT_DEVICE_H
#define PLIANT_COLLISION_DETECT_DEVICE_H

#include "detect.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct coll_dev coll_dev;

/* A context on the current device; PL_OK, or PL_EINTERNAL with err set
 * (no device, out of memory). */
int coll_dev_open(coll_dev **d, pl_error *err);
void coll_dev_close(coll_dev *d);

/* coll_cand_host_counted's lists and box overlaps for npairs pairs of
 * prepared meshes (A[p], B[p]) in one batch: out[3 p .. 3 p + 2] pair p's
 * lists, broad[p] its box overlaps.  Each distinct mesh is uploaded once.
 * *ms (may be NULL): the device's time for it, transfers included [ms].
 * PL_OK or PL_EINTERNAL (err set). */
int coll_dev_batch(coll_dev *d, int npairs, const pl_coll_mesh *const *A,
                   const pl_coll_mesh *const *B, const pl_detect_params *prm,
                   coll_cand_list *out, long long *broad, double *ms, pl_error *err);

/* coll_cand_host's lists for the prepared meshes A and B, made on the
 * device (a batch of one).  *ms (may be NULL): the device's time for it, uploads and
 * downloads included [ms].  PL_OK or PL_EINTERNAL (err set). */
int coll_dev_candidates(coll_dev *d, const pl_coll_mesh *A, const pl_coll_mesh *B,
                        const pl_detect_params *prm, coll_cand_list out[3], double *ms,
                        pl_error *err);

#ifdef __cplusplus
}
#endif
#endif
