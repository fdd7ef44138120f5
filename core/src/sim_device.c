/* sim_device.c - the implicit device: a scene that declares none runs on the
 * GPU when one is usable.
 *
 * Components with device="auto" (LocalGlobalSolver, SparseInverseSolver,
 * NonSmoothNewtonContactSolver) use the device service they find above them.
 * A scene written without one (every scene of scenes/) gets a CudaDevice in
 * its root when the loader's device policy is "auto" (the default), the
 * scene has an animation loop, the cuda plugin can be loaded and a GPU
 * answers (its CudaDevice does not report PL_DEVICE_ABSENT); otherwise it
 * stays on the CPU without a word.  libpliant itself
 * knows nothing of CUDA: it only asks the registry for the plugin. */
#include "pliant/log.h"
#include "pliant/roles.h"
#include "pliant/sim.h"
#include "pliant/util.h"
#include "scene.h"

#include <stdlib.h>
#include <string.h>

#define DEVICE_PLUGIN "cuda"
#define DEVICE_TYPE "CudaDevice"

/* 1 for the policy "auto", 0 for "cpu": the options', else PLIANT_DEVICE,
 * else auto.  Anything else is an error in diag (and 0). */
static int policy_auto(const pl_sim_options *opt, pl_diag *diag, const char *file)
{
    const char *p = opt && opt->device ? opt->device : getenv("PLIANT_DEVICE");
    const char *from = opt && opt->device ? "the loader's device option" : "PLIANT_DEVICE";
    if (!p || !*p || !strcmp(p, "auto")) return 1;
    if (strcmp(p, "cpu"))
        pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "%s: '%s' is not a device policy (cpu or auto)",
                      from, p);
    return 0;
}

pl_component *pl_sim_implicit_device(pl_node *root, pl_registry *reg, pl_model *model,
                                     const pl_sim_options *opt, pl_diag *diag)
{
    if (!policy_auto(opt, diag, model->file)) return NULL;
    if (pl_node_count_role(root, PL_ROLE_DEVICE) > 0) return NULL;
    if (pl_node_count_role(root, PL_ROLE_ANIMATION_LOOP) == 0) return NULL;
    const pl_type *t = pl_registry_find(reg, DEVICE_TYPE);
    if (!t) {
        pl_error e;
        if (pl_registry_load_plugin(reg, DEVICE_PLUGIN, &e) != PL_OK) {
            pl_log_debug("no implicit device: %s", e.msg);
            return NULL;
        }
        t = pl_registry_find(reg, DEVICE_TYPE);
    }
    pl_component *c = t ? pl_scene_new_component(root, t, NULL, model->file, 0, diag) : NULL;
    /* first in the root: initialised before and destroyed after every
     * component that allocates through it */
    if (c) pl_scene_move_component_first(root, c);
    return c;
}

void pl_sim_implicit_device_try(pl_node *root, pl_component *c, pl_registry *reg, pl_model *model)
{
    if (!c) return;
    /* a trial init, after the overrides (cudaDevice.device=1): no usable GPU
     * is not an error here, the scene then runs on the CPU.  The loader
     * initialises it again; CudaDevice's init is idempotent. */
    pl_diag scratch;
    pl_diag_init(&scratch);
    pl_ctx ctx = {model, NULL, reg, NULL, &scratch, model};
    int rc = c->type->ops.init ? c->type->ops.init(c, &ctx) : PL_OK;
    if (rc != PL_OK || scratch.nerrors || !pl_util_device(c)) {
        /* an error, or a device service without a device (no GPU answers,
         * a build without CUDA: its warning stays in the scratch list) */
        pl_log_debug("no implicit device: %s",
                     scratch.count > 0 ? scratch.items[0].msg : "its init failed");
        pl_scene_remove_component(root, c);
    } else {
        pl_log_info("%s: no device in the scene, running on the GPU found (PLIANT_DEVICE=cpu or "
                    "--device cpu keeps it on the CPU)",
                    model->file);
    }
    pl_diag_free(&scratch);
}
