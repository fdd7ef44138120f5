/* fuzz_scene.c - scene XML: loaded (plugins from the plugin path, meshes
 * from scenes/ through PLIANT_DATA_PATH) under tight work ceilings, then
 * stepped twice when it loads.  Seeds: the small scenes of scenes/. */
#include <stdlib.h>

#include <pliant/pliant.h>

#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    setenv("PLIANT_DATA_PATH", PL_SOURCE_DIR "/scenes", 1);
    setenv("PLIANT_DEVICE", "cpu", 1);
    unsetenv("PLIANT_PLUGIN_PATH");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 16) return 0; /* larger scenes add nothing but time */
    fuzz_quiet();
    const char *path = fuzz_memfile(data, size);
    if (!path) return 0;
    /* a tiny scene's worth of work: the caps bound every load and step */
    pl_work_limits ceiling = {.max_elements = 4000, .max_iterations = 50, .max_steps = 10,
                              .max_record_mb = 16, .max_dt = 1.0};
    /* exporters write into memory (tmpfs): a shared machine's disk stalls would be timeouts */
    pl_sim_options opt = {.out_dir = "/dev/shm/pliant_fuzz_scene_out", .export_every = 1000000,
                          .device = "cpu", .max_limits = &ceiling};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *sim = pl_sim_load_file(path, &opt, &diag);
    if (!sim && diag.nerrors == 0) abort(); /* a refusal always says why */
    pl_diag_free(&diag);
    if (sim) {
        pl_error err;
        pl_sim_step(sim, 2, &err);
        pl_sim_free(sim);
    }
    return 0;
}
