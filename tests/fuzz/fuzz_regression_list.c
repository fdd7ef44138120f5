/* fuzz_regression_list.c - SOFA regression lists (pliant regress). */
#include <stdlib.h>
#include <string.h>

#include <pliant/pliant.h>

#include "export/export.h"
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20) return 0;
    const char *path = fuzz_memfile(data, size);
    if (!path) return 0;
    pl_regression_list l;
    pl_diag diag;
    pl_diag_init(&diag);
    int rc = pl_regression_list_load(path, &l, &diag);
    if (rc == PL_EINPUT && diag.nerrors == 0) abort();
    for (int i = 0; i < l.count; ++i)
        if (l.items[i].steps < 1 || !l.items[i].scene || !*l.items[i].scene) abort();
    pl_regression_list_free(&l);
    pl_diag_free(&diag);
    return 0;
}
