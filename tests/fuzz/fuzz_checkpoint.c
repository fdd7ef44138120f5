/* fuzz_checkpoint.c - saved states (pl_data_load, then a step): the input
 * is restored into tests/fuzz/checkpoint_scene.xml, reset first so that
 * every input starts from the same state, and stepped once when it loads.
 * PL_FUZZ_SEED_DIR=dir makes LLVMFuzzerInitialize write the seeds there:
 * states of the scene after 0, 8, 20 and 40 steps (a slot layout changes
 * with the code, so the seeds are made by the code, not kept in git). */
#include <stdio.h>
#include <stdlib.h>

#include <pliant/pliant.h>

#include "fuzz_util.h"

static pl_sim *sim;

static void make_seeds(const char *dir)
{
    static const int steps[] = {0, 8, 20, 40};
    int done = 0;
    for (size_t k = 0; k < sizeof steps / sizeof steps[0]; ++k) {
        pl_error err;
        if (pl_sim_step(sim, steps[k] - done, &err) != PL_OK) break;
        done = steps[k];
        char path[1024];
        snprintf(path, sizeof path, "%s/state_after_%d_steps.bin", dir, done);
        pl_sim_save_state(sim, path, &err);
    }
    pl_sim_reset(sim);
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    fuzz_quiet();
    setenv("PLIANT_DEVICE", "cpu", 1);
    pl_sim_options opt = {.device = "cpu"};
    pl_diag diag;
    pl_diag_init(&diag);
    sim = pl_sim_load_file(PL_SOURCE_DIR "/tests/fuzz/checkpoint_scene.xml", &opt, &diag);
    if (!sim) {
        pl_diag_print(&diag, stderr);
        abort();
    }
    pl_diag_free(&diag);
    const char *dir = getenv("PL_FUZZ_SEED_DIR");
    if (dir && *dir) make_seeds(dir);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20) return 0;
    FILE *f = fmemopen((void *)data, size ? size : 1, "rb");
    if (!f) return 0;
    if (!size) {
        fclose(f);
        return 0;
    }
    pl_sim_reset(sim);
    pl_error err;
    int rc = pl_data_load(pl_sim_data(sim), f, &err);
    fclose(f);
    if (rc == PL_OK) pl_sim_step(sim, 1, &err);
    return 0;
}
