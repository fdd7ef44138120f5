/* vtk_parts.h - what VTKExporter writes next to its body: the drawings of
 * the visual components (obstacles at their pose, cable paths, contact
 * points with their forces; pliant/draw.h) of its node and of the nodes
 * below that have no VTKExporter of their own, each part as its own .vtu
 * per frame, listed in the same .pvd with its part number. */
#ifndef PLIANT_EXPORT_VTK_PARTS_H
#define PLIANT_EXPORT_VTK_PARTS_H

#include "pliant/pliant.h"
#include "export/export.h"

typedef struct pl_vtk_parts {
    pl_component **owners;   /* visual components, scene order */
    int nowners;
    pl_drawing drawing;      /* the frame's parts */
} pl_vtk_parts;

/* Finds the visual components exporter e writes.  PL_OK or PL_EINTERNAL. */
int pl_vtk_parts_find(pl_vtk_parts *p, const pl_component *e);
void pl_vtk_parts_free(pl_vtk_parts *p);
/* Writes the parts of state d as <prefix>_<node>_<component>[_contacts]_<frame>.vtu
 * and lists them in pvd as parts first_part, first_part + 1, ... */
int pl_vtk_parts_write(pl_vtk_parts *p, const char *prefix, int frame, const pl_data *d,
                       pl_pvd *pvd, int first_part, int binary, pl_error *err);

#endif
