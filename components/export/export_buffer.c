/* export_buffer.c - state arrays as host doubles for writing. */
#include <stdlib.h>

#include "export/export_internal.h"

int pl_export_buffer_f64(const pl_buffer *b, size_t rows, const double **out, double **owned,
                         pl_error *err)
{
    *out = NULL;
    *owned = NULL;
    if (!b->data && rows > 0)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "the state gave no array");
    if (b->rows != rows || b->cols != 3)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "the state gave a %zu x %zu array, expected %zu x 3", b->rows,
                            b->cols, rows);
    if (b->location != PL_HOST)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "the state's array is in device memory; exporters need it on the host");
    if (b->precision == PL_F64) {
        *out = b->data;
        return PL_OK;
    }
    if (b->precision != PL_F32)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "the state's array is not real");
    double *d = malloc((rows ? rows : 1) * 3 * sizeof *d);
    if (!d) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    const float *f = b->data;
    for (size_t i = 0; i < rows * 3; ++i) d[i] = f[i];
    *out = *owned = d;
    return PL_OK;
}
