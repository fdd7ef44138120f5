/* term_ws.h - the per-data workspace of the plugin's local terms (FEM,
 * bending, PositionTarget): the host local step's scratch, and the device
 * copies (CUDA builds) made by the first project() on device buffers with
 * that pl_data, kept until the data is freed or the model rebuilt.  The
 * terms' element and stencil sets (the model) are only read during a step.
 * Internal to the plugin. */
#ifndef PLIANT_HYPER_TERM_WS_H
#define PLIANT_HYPER_TERM_WS_H

#include "hyperelastic.h"
#include "pliant/pliant.h"

typedef struct hyper_term_ws {
    double *work;                      /* host scratch of project() */
    hyper_prox_stats prox;             /* FEM terms: this step's local solves (end_step
                                        * adds them to the timers' statistics) */
    double prox_seconds;               /* FEM terms: this step's host time in project() */
    double *warm;                      /* FEM terms: n x HM_WARM_LEN(d), each element's
                                        * last local solve (singular values, V), the
                                        * next one's start; zeroed (cold) by begin_step,
                                        * so that a step depends on the pl_data's slots
                                        * only */
    size_t nwarm;
    double *prev;                      /* FEM terms with admmRelaxation != 1: n x dual_size,
                                        * each element's last prox solution of this step */
    size_t nprev;
    int relax_ready;                   /* prev holds this step's last p (begin_step: 0) */
    struct hyper_fem_gpu *fem;         /* ARAP, Corotational, NeoHookean: fem_term_device.c */
    struct hyper_stencil_gpu *stencil; /* bending, PositionTarget: stencil_device.c */
} hyper_term_ws;

/* c's host scratch of n doubles in d (made on first use: n depends only on
 * the model); NULL with err set when memory runs out. */
double *hyper_term_work(const pl_component *c, pl_data *d, size_t n, pl_error *err);
/* c's warm-start rows (n doubles, zeros when new) in d; NULL with err set
 * when memory runs out. */
double *hyper_term_warm(const pl_component *c, pl_data *d, size_t n, pl_error *err);
/* c's over-relaxation rows (n doubles) in d; NULL with err set when memory
 * runs out. */
double *hyper_term_prev(const pl_component *c, pl_data *d, size_t n, pl_error *err);
/* The types' workspace_free. */
void hyper_term_workspace_free(const pl_component *c, void *ws);

#endif
