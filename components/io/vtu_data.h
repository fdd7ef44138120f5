/* vtu_data.h - decoding one VTU <DataArray> (private to components/io). */
#ifndef PLIANT_IO_VTU_DATA_H
#define PLIANT_IO_VTU_DATA_H

#include <libxml/tree.h>

#include "mesh_io.h"

/* What the <VTKFile> element says about every binary array. */
typedef struct vtu_format {
    int big_endian; /* byte_order="BigEndian" */
    int header64;   /* header_type="UInt64" (else UInt32) */
    int zlib;       /* compressor="vtkZLibDataCompressor" */
} vtu_format;

/* Reads exactly n values of a DataArray into *out, a malloc'ed array of
 * doubles (as_int = 0) or long longs (as_int = 1, integer types only) that
 * the caller frees.  n is checked against what the array's text can hold
 * before *out is allocated, so an absurd declared count costs nothing.
 * Errors name the array and its line; a wrong number of values is an
 * error, never padded or cut.  *out is NULL on error. */
PL_IO_HIDDEN int pl_io_vtu_array(pl_text *t, const vtu_format *f, xmlNode *node, long long n,
                                 int as_int, void **out);

#endif
