/* bending_term.h - what IsometricBending and LaplaceBeltramiBending share:
 * a constant-matrix stencil term built from the mesh triangles and the
 * state's rest positions.  Internal to the plugin. */
#ifndef PLIANT_HYPER_BENDING_TERM_H
#define PLIANT_HYPER_BENDING_TERM_H

#include "hyperelastic.h"
#include "pliant/pliant.h"
#include "term_ws.h"

typedef enum hyper_bending_kind {
    HYPER_BENDING_ISOMETRIC,
    HYPER_BENDING_LAPLACE_BELTRAMI
} hyper_bending_kind;

typedef struct hyper_bending {
    pl_component base;
    double stiffness;       /* [N m] */
    pl_link src;
    /* model */
    hyper_bending_kind kind;
    const pl_mesh *mesh;
    pl_component *state;
    pl_hyper_stencils s;
} hyper_bending;

#define HYPER_BENDING_FIELDS                                                                      \
    PL_FIELD(hyper_bending, stiffness, "stiffness", PL_F_DOUBLE, "1e-3",                          \
             "bending stiffness [N m] (energy stiffness/2 * integral of the squared mean "         \
             "curvature normal (2H)^2 for a flat rest state)",                                    \
             0),                                                                                  \
        PL_FIELD(hyper_bending, src, "src", PL_F_LINK, NULL,                                      \
                 "loader or generator with the triangles (default: the node's first)", 0)

#define HYPER_BENDING_NFIELDS 2

int hyper_bending_init(pl_component *c, pl_ctx *ctx, hyper_bending_kind kind);
int hyper_bending_bind(pl_component *c, pl_ctx *ctx);
int hyper_bending_reinit(pl_component *c, pl_ctx *ctx);
void hyper_bending_destroy(pl_component *c);

extern const pl_local_term_ops hyper_bending_local_term_ops;

#endif
