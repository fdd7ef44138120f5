/* surface_pressure.h - SurfacePressureConstraint's component struct, shared
 * by surface_pressure.c (fields, rows, outputs) and surface_pressure_surface.c
 * (the cavity's surface built from the scene's description and checked). */
#ifndef PLIANT_SURFACE_PRESSURE_H
#define PLIANT_SURFACE_PRESSURE_H

#include "cable.h"
#include "cavity.h"

typedef struct surface_pressure {
    pl_component base;
    /* fields */
    pl_ints triangles, quads;
    pl_doubles position, box;
    pl_link surface, src;
    int flip;
    pl_doubles value;
    int value_index, value_type;
    pl_doubles min_p, max_p, eq_p, max_dp, min_g, max_g, max_dg;
    double out_pressure, out_growth, out_volume, out_v0;
    /* model */
    pl_component *state;
    cavity_surface surf;
    double V0;  /* initialCavityVolume [m^3] */
    int slot;   /* "pressure": the multiplier of the last step [Pa] */
} surface_pressure;

/* sp->surf from the fields (triangles of the state's vertices, points mapped
 * into its tetrahedra, a surface loader's, or the boundary faces in `box`),
 * at the rest positions x (n vertices); PL_OK or an error on the component. */
int sp_build_surface(surface_pressure *sp, pl_ctx *ctx, const double *x, int n);
/* Closed and consistently oriented, turned around when it faces inward
 * (flipNormal, with a warning); PL_OK or an error on the component. */
int sp_check_surface(surface_pressure *sp, pl_ctx *ctx, const double *x);

#endif
