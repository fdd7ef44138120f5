/* cuda_loop.h - the device service's loop graph (cuda_loop.cu): an
 * iteration loop kept on the GPU by a conditional WHILE node. */
#ifndef PLIANT_CUDA_LOOP_H
#define PLIANT_CUDA_LOOP_H

#ifdef __cplusplus
extern "C" {
#endif

struct CUstream_st;
struct pl_device_loop;

/* Whether the driver runs conditional graph nodes (CUDA 12.4 or later). */
int cuda_loop_supported(void);
/* Records `rule; while (cond) { body(arg); rule }` (pl_device_loop_rule on
 * state, change, residual: device addresses) into an executable graph
 * (cudaGraphExec_t) in *exec_out.  body queues one iteration on st while
 * st is being captured; its status goes to *body_rc (non-zero: no graph).
 * Returns a cudaError_t as an int (0: built). */
int cuda_loop_build(struct CUstream_st *st, int (*body)(void *arg), void *arg,
                    struct pl_device_loop *state, const double *change, const double *residual,
                    void **exec_out, int *body_rc);

#ifdef __cplusplus
}
#endif
#endif
