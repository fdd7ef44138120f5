/* export.h - the two built-in exporters, VTKExporter and WriteState (both
 * play PL_ROLE_EXPORTER); the file formats they write are in the SDK
 * (pliant/export.h). */
#ifndef PLIANT_COMPONENTS_EXPORT_H
#define PLIANT_COMPONENTS_EXPORT_H

#include "pliant/component.h"
#include "pliant/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- components ---------------------------------------------------------- */

/* "VTKExporter": filename (path prefix), every, binary, exportVelocity. */
extern const pl_type pl_vtk_exporter_type;
/* "WriteState": filename, period, writeX, writeV. */
extern const pl_type pl_write_state_type;

#ifdef __cplusplus
}
#endif
#endif
