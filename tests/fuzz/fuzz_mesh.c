/* fuzz_mesh.c - one mesh reader, named at compile time (FUZZ_FORMAT, a
 * pl_mesh_format): the input goes to that reader whatever it looks like,
 * then through the validation every loaded mesh passes.  Built as
 * fuzz_vtk_legacy, fuzz_vtu, fuzz_gmsh (v1, v2 and v4.1), fuzz_obj,
 * fuzz_stl_ascii and fuzz_stl_binary. */
#include <stdlib.h>

#include <pliant/pliant.h>

#include "fuzz_util.h"

#ifndef FUZZ_FORMAT
#error "FUZZ_FORMAT names the reader"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_quiet();
    pl_mesh_load_options opt = {.format = FUZZ_FORMAT};
    pl_mesh m;
    pl_diag diag;
    pl_diag_init(&diag);
    int rc = pl_mesh_load_buffer("fuzz.mesh", data, size, &opt, &m, &diag);
    if (rc == PL_OK) {
        /* what the loader promises: valid indices, finite coordinates */
        if (pl_mesh_validate(&m, "fuzz.mesh", &diag) != PL_OK) abort();
        pl_mesh_free(&m);
    } else if (rc == PL_EINPUT && diag.nerrors == 0) {
        abort(); /* an input error always says what is wrong */
    }
    pl_diag_free(&diag);
    return 0;
}
