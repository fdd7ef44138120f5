/* export_internal.h - helpers shared by the files of components/export
 * (not part of the public API). */
#ifndef PLIANT_EXPORT_INTERNAL_H
#define PLIANT_EXPORT_INTERNAL_H

#include <stdio.h>
#include "pliant/buffer.h"
#include "pliant/component.h"
#include "pliant/error.h"

/* Creates dir and its missing parents (mkdir -p). */
int pl_export_make_dirs(const char *dir, pl_error *err);
/* Creates the folder that will hold file `path` (nothing for a bare name). */
int pl_export_make_parent_dirs(const char *path, pl_error *err);
/* The last component of a path (after the last '/'). */
const char *pl_export_basename(const char *path);
/* Where an output goes: out_dir/<basename of path> when out_dir is given,
 * else path itself.  Returns a malloc'd string, NULL on allocation failure. */
char *pl_export_output_path(const char *out_dir, const char *path);
/* Names component c in err->where ("VTKExporter root/bar/vtk") unless a
 * callee already named something; returns err->code. */
int pl_export_blame(const pl_component *c, pl_error *err);
/* Writes s escaped for an XML attribute value. */
int pl_export_xml_attr(FILE *f, const char *s);

/* The host float64 view of a rows x 3 state buffer: b's own memory when it
 * is host float64, else a converted copy in *owned (free it after use).
 * Device buffers are refused: the state must bring positions to the host
 * before exporters run. */
int pl_export_buffer_f64(const pl_buffer *b, size_t rows, const double **out, double **owned,
                         pl_error *err);

#endif
