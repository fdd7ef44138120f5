/* fem_term.h - what the ARAP, Corotational and NeoHookean components share
 * (one struct, one field table, one local-term role); each component file
 * only fixes its material.  Internal to the plugin. */
#ifndef PLIANT_HYPER_FEM_TERM_H
#define PLIANT_HYPER_FEM_TERM_H

#include "hyperelastic.h"
#include "pliant/pliant.h"
#include "term_ws.h"

typedef struct hyper_fem {
    pl_component base;
    /* fields */
    pl_doubles young;       /* youngModulus [Pa]: one value or one per element */
    pl_doubles poisson;     /* poissonRatio */
    int elements;           /* 0 auto, 1 tetrahedra, 2 triangles */
    pl_link src;            /* topology (default: the node's first) */
    double thickness;       /* [m] membranes */
    int warm_start;         /* keep ADMM duals across steps */
    int rotation;           /* Corotational only: 0 polar, 1 edges (SOFA's 'large') */
    double admm_weight;     /* ADMM-PD penalty scale (Corotational, NeoHookean) */
    double admm_relaxation; /* ADMM over-relaxation alpha (Corotational, NeoHookean) */
    /* model */
    pl_hyper_material material;
    const pl_mesh *mesh;
    pl_component *state;
    int k;                  /* 4 (tetrahedra) or 3 (triangles) */
    int nelem;
    pl_hyper_elements el;
    int dual_slot;          /* -1: none (ARAP) */
} hyper_fem;

extern const char *const hyper_fem_element_choices[];
extern const char *const hyper_fem_rotation_choices[];

#define HYPER_FEM_FIELDS                                                                          \
    PL_FIELD(hyper_fem, young, "youngModulus", PL_F_DOUBLES, "5000",                              \
             "Young's modulus [Pa]: one value, or one per element",                               \
             0),                                                                                  \
        PL_FIELD(hyper_fem, poisson, "poissonRatio", PL_F_DOUBLES, "0.45",                        \
                 "Poisson's ratio in (-1, 0.5): one value, or one per element (membranes use "    \
                 "the plane-stress lambda)",                                                      \
                 0),                                                                              \
        PL_FIELD_ENUM(hyper_fem, elements, "elements", hyper_fem_element_choices, "auto",         \
                      "which cells of the mesh: auto (tetrahedra if any, else triangles), "       \
                      "tetrahedra or triangles",                                                  \
                      0),                                                                         \
        PL_FIELD(hyper_fem, src, "src", PL_F_LINK, NULL,                                          \
                 "loader or generator with the elements (default: the node's first)", 0),         \
        PL_FIELD(hyper_fem, thickness, "thickness", PL_F_DOUBLE, "0.001",                         \
                 "membrane thickness [m] (triangles): energy = psi * area * thickness, as "       \
                 "DiagonalMass's thickness",                                                      \
                 0),                                                                              \
        PL_FIELD(hyper_fem, warm_start, "warmStart", PL_F_BOOL, "1",                              \
                 "keep the ADMM-PD duals from one time step to the next (0: reset each step; "    \
                 "ARAP has none)",                                                                \
                 PL_FIELD_RUNTIME),                                                               \
        PL_FIELD(hyper_fem, admm_weight, "admmWeight", PL_F_DOUBLE, "1",                          \
                 "scale of the ADMM-PD penalty weight, w = admmWeight (2 mu + lambda) V "          \
                 "(Corotational, NeoHookean; ARAP's weight is its stiffness): the converged "     \
                 "step is the same, the iterations to reach it are not (a nearly incompressible " \
                 "body that bends, scenes/cable_finger.xml: 0.35 needs 2.6x fewer iterations to " \
                 "1e-3 N; too small and ADMM stalls: 0.125 there); it changes the system matrix " \
                 "[1]",                                                                           \
                 0),                                                                              \
        PL_FIELD(hyper_fem, admm_relaxation, "admmRelaxation", PL_F_DOUBLE, "1",                  \
                 "over-relaxed ADMM (Boyd et al. 2011, 3.4.3), alpha in (0, 2): from a step's "   \
                 "second iteration on, the local step and the dual update use alpha G q + "       \
                 "(1 - alpha) p_prev for G q (Corotational, NeoHookean); the converged step is "  \
                 "the same, the iterations to reach it are not (scenes/cable_finger.xml: 1.5 "    \
                 "needs 1.5x fewer iterations to 1e-3 N; 1.7 diverges there) [1]",               \
                 PL_FIELD_RUNTIME)

#define HYPER_FEM_NFIELDS 8

/* Lifecycle pieces (init takes the material). */
int hyper_fem_init(pl_component *c, pl_ctx *ctx, pl_hyper_material material);
int hyper_fem_bind(pl_component *c, pl_ctx *ctx);
int hyper_fem_reinit(pl_component *c, pl_ctx *ctx);
int hyper_fem_begin_step(const pl_component *c, pl_ctx *ctx, pl_error *err);
int hyper_fem_end_step(const pl_component *c, pl_ctx *ctx, pl_error *err);
void hyper_fem_destroy(pl_component *c);

/* The device path (fem_term_device.c, CUDA builds only).  The duals live
 * in the pl_data slot "dual" between steps (save, restore and clone see
 * them as on the CPU); during a step the device copy in d's workspace
 * (term_ws.h: the elements and the duals) is used: the duals uploaded from
 * the slot by the first device project() of the step, downloaded into the
 * slot by end_step.  Later project() calls of the step only queue kernels
 * on the device's stream (they may be captured in a graph and replayed
 * without being called). */
int hyper_fem_project_device(const hyper_fem *f, pl_data *d, int offset, double h2,
                             const pl_buffer *q, pl_buffer *rhs, pl_error *err);
/* grad += d psi / dq at q, both device n x 3 blocks (the force residual of
 * a device loop); the element data goes up at the first call with d. */
int hyper_fem_gradient_device(const hyper_fem *f, pl_data *d, int offset, const pl_buffer *q,
                              pl_buffer *grad, pl_error *err);
/* Duals back into d's slot, the local step's statistics checked. */
int hyper_fem_device_end_step(const hyper_fem *f, pl_data *d, pl_error *err);
/* Next device project() with d uploads the duals again. */
void hyper_fem_device_begin_step(const hyper_fem *f, pl_data *d);
/* Frees a device copy (term_ws.c). */
void hyper_fem_device_free(struct hyper_fem_gpu **gpu);

extern const pl_local_term_ops hyper_fem_local_term_ops;

/* A host float64 n x 3 block covering offset + nverts rows, or NULL with
 * err filled about c. */
double *hyper_term_block(const pl_component *c, const pl_buffer *b, int offset, int nverts,
                         const char *what, pl_error *err);

#endif
