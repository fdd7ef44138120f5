/* fuzz_state_file.c - SOFA state files (plain or gzip), as regression
 * references are read. */
#include <stdlib.h>

#include <pliant/pliant.h>

#include "export/export.h"
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20) return 0;
    const char *path = fuzz_memfile(data, size);
    if (!path) return 0;
    pl_state_records recs;
    pl_state_records_init(&recs);
    pl_error err;
    if (pl_state_file_read(path, &recs, &err) == PL_OK) {
        /* what the reader promises: finite values, sizes that match */
        for (int r = 0; r < recs.count; ++r) {
            if (!(recs.items[r].time == recs.items[r].time)) abort();
            for (int i = 0; i < recs.items[r].nx; ++i)
                if (recs.items[r].x[i] - recs.items[r].x[i] != 0) abort();
        }
    }
    pl_state_records_free(&recs);
    return 0;
}
