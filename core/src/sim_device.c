/* sim_device.c - the implicit device: a scene that declares none runs on the
 * GPU when one is usable and the cost model (device_cost.h) predicts it
 * faster there.
 *
 * Components with device="auto" (LocalGlobalSolver, SparseInverseSolver,
 * NonSmoothNewtonContactSolver) use the device service they find above them.
 * A scene written without one (every scene of scenes/) gets a CudaDevice in
 * its root when the loader's device policy is "auto" (the default), the
 * scene has an animation loop, the cuda plugin can be loaded and a GPU
 * answers (its CudaDevice does not report PL_DEVICE_ABSENT); otherwise it
 * stays on the CPU without a word.  After every component's init (sizes
 * known, nothing on the device yet: device buffers are made at reinit and
 * on first use) pl_sim_device_cost predicts the step on both devices and
 * takes the implicit device out again when the CPU is predicted faster;
 * the choice and why go to the log and the timings' statistics.  A device
 * the scene declares is never overridden.  libpliant itself
 * knows nothing of CUDA: it only asks the registry for the plugin. */
#include "device_cost.h"
#include "walk.h"
#include "pliant/log.h"
#include "pliant/roles.h"
#include "pliant/sim.h"
#include "pliant/timer.h"
#include "pliant/util.h"
#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define DEVICE_PLUGIN "cuda"
#define DEVICE_TYPE "CudaDevice"

/* The policy: 1 "auto" (the cost model chooses), 2 "gpu-always" (the GPU whenever
 * one answers: what device=auto did before the cost model, for calibration
 * runs), 0 "cpu": the options', else PLIANT_DEVICE, else auto.  Anything
 * else is an error in diag (and 0). */
static int policy_of(const pl_sim_options *opt, pl_diag *diag, const char *file)
{
    const char *p = opt && opt->device ? opt->device : getenv("PLIANT_DEVICE");
    const char *from = opt && opt->device ? "the loader's device option" : "PLIANT_DEVICE";
    if (!p || !*p || !strcmp(p, "auto")) return 1;
    if (!strcmp(p, "gpu-always")) return 2;
    if (strcmp(p, "cpu"))
        pl_diag_error(diag, PL_EINPUT, file, 0, NULL,
                      "%s: '%s' is not a device policy (cpu or auto); gpu-always: the GPU "
                      "whenever one answers",
                      from, p);
    return 0;
}

pl_component *pl_sim_implicit_device(pl_node *root, pl_registry *reg, pl_model *model,
                                     const pl_sim_options *opt, int *forced, pl_diag *diag)
{
    int policy = policy_of(opt, diag, model->file);
    *forced = policy == 2;
    if (!policy) return NULL;
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

pl_component *pl_sim_implicit_device_try(pl_node *root, pl_component *c, pl_registry *reg,
                                         pl_model *model)
{
    if (!c) return NULL;
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
        c = NULL;
    }
    pl_diag_free(&scratch);
    return c;
}

/* ---- the cost model's sizes, from the initialised scene ------------------ */

/* A field's value as text ("" when c has no such field). */
static const char *field_text(const pl_component *c, const char *name, char *buf, size_t size)
{
    const pl_field *f = pl_component_field(c, name);
    buf[0] = '\0';
    if (f && pl_field_format(f, c, buf, size) != PL_OK) buf[0] = '\0';
    return buf;
}

static double field_num(const pl_component *c, const char *name, double dflt)
{
    char v[64];
    return field_text(c, name, v, sizeof v)[0] ? strtod(v, NULL) : dflt;
}

/* The mesh c works on: its "src" link, else the node's topology. */
static const pl_mesh *mesh_of(const pl_component *c)
{
    const pl_field *f = pl_component_field(c, "src");
    const pl_component *t = NULL;
    if (f && f->type == PL_F_LINK) t = ((const pl_link *)((const char *)c + f->offset))->target;
    if (!t || !pl_component_role(t, PL_ROLE_TOPOLOGY)) t = pl_node_find_role(c->node, PL_ROLE_TOPOLOGY);
    const pl_topology_ops *ops = t ? pl_component_role(t, PL_ROLE_TOPOLOGY) : NULL;
    return ops && ops->mesh ? ops->mesh(t) : NULL;
}

/* Local terms the device step knows (local_global_device.c's list). */
static int has_device_step(const char *type)
{
    static const char *const known[] = {"ARAP", "Corotational", "NeoHookean", "IsometricBending",
                                        "LaplaceBeltramiBending", "PositionTarget",
                                        "ConstantForceField"};
    for (size_t k = 0; k < sizeof known / sizeof known[0]; ++k)
        if (!strcmp(type, known[k])) return 1;
    return 0;
}

/* Local terms whose gradient takes device buffers (the device force
 * residual of forceTolerance, local_global_device_residual.c). */
static int has_device_gradient(const char *type)
{
    return !strcmp(type, "ARAP") || !strcmp(type, "Corotational") || !strcmp(type, "NeoHookean");
}

typedef struct gathered {
    pl_device_sizes z;
    int cuda_asked; /* a component says device="cuda": the device stays */
    int host_gradient; /* a local term without a device gradient (forceTolerance: the CPU) */
    int rayleigh;      /* rayleighStiffness > 0 (forceTolerance: the CPU) */
} gathered;

static int gather(pl_component *c, void *user)
{
    gathered *g = user;
    pl_device_sizes *z = &g->z;
    const char *type = c->type->name;
    char v[64];
    if (!strcmp(field_text(c, "device", v, sizeof v), "cuda")) g->cuda_asked = 1;
    if (pl_component_role(c, PL_ROLE_STATE)) {
        const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
        int n = ops->count ? ops->count(c) : 0;
        const pl_mesh *m = mesh_of(c);
        z->vertices += n;
        if (n > 1 && m && m->ntets > 0) z->s_tet += pow(n, 4.0 / 3.0);
        else if (n > 1) z->s_tri += n * log2(n);
    }
    if (pl_component_role(c, PL_ROLE_LOCAL_TERM)) {
        const pl_mesh *m = mesh_of(c);
        int law = !strcmp(type, "NeoHookean")     ? PL_COST_NH
                  : !strcmp(type, "Corotational") ? PL_COST_COROT
                  : !strcmp(type, "PositionTarget") ? -1
                                                    : PL_COST_ARAP;
        if (law >= 0 && m && m->ntets > 0) z->tets[law] += m->ntets;
        else if (law >= 0 && m) z->tris[law] += m->ntris;
        if (!has_device_step(type)) z->device_path = 0;
        if (!has_device_gradient(type)) g->host_gradient = 1;
    }
    if (pl_component_role(c, PL_ROLE_CONSTRAINT)) z->constraints++;
    if (pl_component_role(c, PL_ROLE_COLLISION_MODEL) && pl_node_find_role(c->node, PL_ROLE_STATE)) {
        const pl_mesh *m = mesh_of(c);
        if (m) z->surface_vertices += m->nverts;
    }
    if (pl_component_role(c, PL_ROLE_CONTACT_SOLVER)) {
        z->cr_iterations = (int)field_num(c, "crIterations", 10);
        /* stickStart runs in the device loop (its first iterate) */
        if (!strcmp(field_text(c, "device", v, sizeof v), "cpu") || !v[0]) z->device_path = 0;
    }
    if (pl_component_role(c, PL_ROLE_GLOBAL_SOLVER) && !z->sparse_inverse)
        z->sparse_inverse = !strcmp(type, "SparseInverseSolver") ? 1 : -1;
    if (pl_component_role(c, PL_ROLE_ANIMATION_LOOP) && !strcmp(type, "LocalGlobalSolver")) {
        z->iterations_max = (int)field_num(c, "iterations", 5);
        z->force_tolerance = field_num(c, "forceTolerance", 0) > 0;
        g->rayleigh = field_num(c, "rayleighStiffness", 0) > 0;
        if (!strcmp(field_text(c, "device", v, sizeof v), "cpu")) z->device_path = 0;
    }
    return 0;
}

/* The statistics `pliant run --timings` records (the fit's inputs). */
static void record(pl_timers *t, const pl_device_sizes *z, const pl_device_estimate *e)
{
    static const char *const LAW[PL_COST_NLAWS] = {"ARAP", "corotational", "Neo-Hookean"};
    char name[64];
    pl_stat_set(t, "cost: vertices", z->vertices);
    for (int l = 0; l < PL_COST_NLAWS; ++l) {
        snprintf(name, sizeof name, "cost: %s tetrahedra", LAW[l]);
        pl_stat_set(t, name, z->tets[l]);
        snprintf(name, sizeof name, "cost: %s triangles", LAW[l]);
        pl_stat_set(t, name, z->tris[l]);
    }
    pl_stat_set(t, "cost: S basis tetrahedra", z->s_tet);
    pl_stat_set(t, "cost: S basis triangles", z->s_tri);
    pl_stat_set(t, "cost: iterations", z->iterations);
    pl_stat_set(t, "cost: force tolerance", z->force_tolerance);
    pl_stat_set(t, "cost: constraints", z->constraints);
    pl_stat_set(t, "cost: CR iterations", z->cr_iterations);
    pl_stat_set(t, "cost: surface vertices", z->surface_vertices);
    pl_stat_set(t, "cost: device path", z->device_path);
    pl_stat_set(t, "cost: sparse inverse", z->sparse_inverse);
    pl_stat_set(t, "cost: nnz(S) estimate", e->nnz_s);
    pl_stat_set(t, "predicted CPU [ms/step]", e->cpu_ms);
    pl_stat_set(t, "predicted GPU [ms/step]", e->gpu_ms);
}

int pl_sim_device_cost(pl_node *root, pl_component *dev, int forced, pl_model *model,
                       pl_timers *timers)
{
    gathered g;
    memset(&g, 0, sizeof g);
    g.z.device_path = 1;
    walk_pre(root, gather, &g);
    pl_device_sizes z = g.z;
    /* forceTolerance runs on the device when every term has a device
     * gradient and there is no Rayleigh damping (local_global_device.c) */
    if (z.force_tolerance && (g.host_gradient || g.rayleigh)) z.device_path = 0;
    /* the scene asks for the GPU by name somewhere (device="cuda"): its
     * word, as a declared CudaDevice's */
    forced = forced || g.cuda_asked;
    if (dev && forced)
        pl_log_info("%s: no device in the scene, running on the GPU found (%s)", model->file,
                    g.cuda_asked ? "a component asks for device=\"cuda\"" : "--device gpu-always");
    if (z.iterations_max == 0) { /* no LocalGlobalSolver: nothing to predict */
        if (dev && !forced)
            pl_log_info("%s: no device in the scene, running on the GPU found (no "
                        "LocalGlobalSolver for the cost model to predict; --device cpu keeps it "
                        "on the CPU)",
                        model->file);
        return 0;
    }
    z.sparse_inverse = z.sparse_inverse > 0;
    z.iterations = pl_device_cost_iterations(z.iterations_max, z.force_tolerance);
#ifdef _OPENMP
    int threads = omp_get_max_threads();
#else
    int threads = 1;
#endif
    pl_device_estimate e;
    char why[768];
    int gpu = pl_device_cost_choose(&z, threads, dev != NULL, &e, why, sizeof why);
    if (timers) record(timers, &z, &e);
    if (!dev || forced) { /* policy cpu or gpu-always, no GPU, or the scene's own device */
        pl_log_debug("%s: device cost model: %s", model->file, why);
        return 0;
    }
    pl_log_info("%s: no device in the scene (device=auto): %s", model->file, why);
    if (timers) pl_stat_set(timers, "device auto: GPU chosen", gpu);
    if (gpu) return 0;
    pl_scene_remove_component(root, dev);
    return 1;
}
