/* buffer.h - array descriptors that cross role interfaces.
 *
 * An interface never passes a bare double*: it passes a pl_buffer that says
 * where the data lives (host or device memory) and in which precision, so a
 * CUDA implementation of a role can take and return device arrays through
 * the same vtable as the CPU one. */
#ifndef PLIANT_BUFFER_H
#define PLIANT_BUFFER_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pl_location { PL_HOST = 0, PL_DEVICE = 1 } pl_location;
typedef enum pl_precision { PL_F64 = 0, PL_F32 = 1, PL_I32 = 2 } pl_precision;

typedef struct pl_buffer {
    void *data;            /* first element */
    size_t rows;           /* e.g. number of vertices */
    size_t cols;           /* e.g. 3 for an n x 3 row-major block of xyz */
    pl_location location;
    pl_precision precision;
} pl_buffer;

/* A host float64 n x cols block (the common case on the CPU). */
static inline pl_buffer pl_buffer_host_f64(double *data, size_t rows, size_t cols)
{
    pl_buffer b = {data, rows, cols, PL_HOST, PL_F64};
    return b;
}

/* The host float64 pointer of b, or NULL if b is not a host float64 buffer. */
static inline double *pl_buffer_f64(const pl_buffer *b)
{
    return (b && b->location == PL_HOST && b->precision == PL_F64) ? (double *)b->data : NULL;
}

#ifdef __cplusplus
}
#endif
#endif
