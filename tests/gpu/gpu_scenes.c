/* gpu_scenes.c - whole scenes with the local-global loop on the GPU
 * (LocalGlobalSolver device="cuda", a CudaDevice added to the scene); needs
 * a GPU (without one it prints "skipped: no GPU" and exits 77).  `ctest -L
 * gpu` runs the checks of the small scenes; tests/bench/run_gpu.sh all.
 *
 *   gpu_scenes CHECKS.md TIMINGS.md [frames [small|timing|SCENE.xml]]
 * (frames 0: checks only; small: all but the 5.3k bar; timing: no checks;
 * SCENE.xml: the checks of that scene only)
 *
 * Checks (tetrahedral bars twisting_bar_small, hanging_bar_small,
 * twisting_bar; the small cloth_extension scenes, ARAP, corotational and
 * Neo-Hookean membranes; tests/gpu/cloth_terms.xml, a cloth with both
 * bending terms, PositionTargets and a ConstantForceField; the contact
 * scenes stick_slip, resting_box, ball_on_plane, sliding_box,
 * template_constraint and every _small contact, cable and gripper scene):
 * the CPU steps 10 frames (more where contact starts later: RUN_UP) and
 * saves its state; from that state one more frame on the CPU and on the
 * device (float64 with and without a CUDA graph, float32 S) must agree:
 * positions within 1e-9 relative (float64) and 1e-4 (float32), velocities
 * and ADMM duals within 1e-9 (float64; relative to an RMS of at least
 * 1 mm/s and 1e-3, for bodies at rest or undeformed).  Scenes with contact
 * or cables take that frame with the constraint solve converged (CONVERGED:
 * CR to 1e-13, no line search); the frame at the scene's own settings is a
 * note.  10 frames from the state are reported; a device run restored twice
 * from one state must repeat itself bitwise (duals go up from the restored
 * slot).  Long runs: squeezing_ball_small, pulling_through_gap_small and
 * grabbing_raptor_small from the start on both, the same qualitative state
 * (ball below the rollers, body through the gap, raptor lifted).  Two data
 * of cable_finger_small on the device (own workspaces: vectors, graph,
 * contact and FEM buffers) stepped interleaved end bitwise as each alone.
 * Timings: the twisting bars 5.3k, 11.3k, 20.8k; medians of the wall time
 * of a frame (pl_sim_step of one frame) over `frames` frames after 5
 * warm-up frames, next to the paper's Table 3 Frame; Local / Assembly /
 * Global: the phase timers' medians (with CudaDevice profile="1" on the
 * device, where every phase waits for the GPU).
 * Experiments: GPU_SCENES_SET="contact.crIterations=400;contact.lineSearch=0"
 * sets fields on every loaded scene (CPU and device), GPU_SCENES_RUNUP=N
 * saves the state after N frames instead of the scene's RUN_UP. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_scenes.h"
#include "gpu_util.h"
#include "test_tmp.h"
#include "pliant/pliant.h"

#define PROG "gpu_scenes"

static FILE *md;
/* The checkpoint of the restore checks, in this run's temporary folder. */
static const char *state_file(void)
{
    static char path[1100];
    if (!path[0]) snprintf(path, sizeof path, "%s/state.bin", test_tmp_dir());
    return path;
}


/* Set while a contact scene is checked: its contact solver runs to
 * convergence (CONVERGED).  At the scenes' own settings (10 CR iterations,
 * a few Newton steps) the iterates are far from the solution, and rounding
 * differences of reordered sums (1e-16) grow through them to 1e-8; the
 * converged step is a well-defined result that both paths must reproduce. */
static int converge;
static const char *const CONVERGED[3][2] = {
    {"contact.crIterations", "400"}, {"contact.crTolerance", "1e-13"}, {"contact.lineSearch", "0"}};

/* Sets CONVERGED on sim, keeping the scene's own values in old (when not
 * NULL); 0 when done. */
static int set_converged(pl_sim *sim, char old[3][64])
{
    pl_error err;
    for (int k = 0; k < 3; ++k) {
        if (old) {
            const char *dot = strchr(CONVERGED[k][0], '.');
            pl_component *c = pl_sim_component(sim, "contact");
            const pl_field *f = c ? pl_component_field(c, dot + 1) : NULL;
            if (!f || pl_field_format(f, c, old[k], sizeof old[k]) != PL_OK) return -1;
        }
        if (pl_sim_set(sim, CONVERGED[k][0], CONVERGED[k][1], &err) != PL_OK) {
            printf("set %s: %s\n", CONVERGED[k][0], err.msg);
            return -1;
        }
    }
    return 0;
}

pl_sim *gpu_scenes_load(const char *path, const config *c)
{
    char *xml = c->cuda ? gpu_scene_with_device(path) : NULL;
    /* forceTolerance (the cable fingers) and stickStart (stick_slip) keep
     * the iterations on the CPU (a device loop refuses them): off on both
     * sides, set at load so that the device is chosen with them off */
    const char *ov[5] = {"solver.device=cuda", "global.device=cuda",
                         c->f32 ? "global.precision=float32" : "global.precision=float64",
                         "solver.forceTolerance=0", "contact.stickStart=0"};
    int stick = strstr(path, "stick_slip") != NULL;
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = test_tmp_dir();
    opt.export_every = 1000000; /* the first frame only */
    opt.overrides = c->cuda ? ov : ov + 3;
    opt.noverrides = (c->cuda ? 4 : 1) + stick;
    opt.device = c->cuda ? NULL : "cpu"; /* no implicit device on the CPU side */
    pl_sim *sim = c->cuda ? (xml ? pl_sim_load_string(xml, path, &opt, &diag) : NULL)
                          : pl_sim_load_file(path, &opt, &diag);
    if (!sim) pl_diag_print(&diag, stdout);
    pl_diag_free(&diag);
    free(xml);
    pl_error err;
    if (sim && c->cuda && pl_sim_set(sim, "gpu.graph", c->graph ? "1" : "0", &err) != PL_OK) {
        printf("set: %s\n", err.msg);
        pl_sim_free(sim);
        return NULL;
    }
    /* the device path has no stick start of new contacts (contact_stick_start.c): off on both
     * sides, so that the two compute the same thing */
    if (sim && pl_sim_component(sim, "contact") &&
        pl_sim_set(sim, "contact.stickStart", "0", &err) != PL_OK) {
        printf("set: %s\n", err.msg);
        pl_sim_free(sim);
        return NULL;
    }
    if (sim && converge && set_converged(sim, NULL) != 0) {
        pl_sim_free(sim);
        return NULL;
    }
    /* GPU_SCENES_SET="a.b=v;c.d=w": fields set on every loaded scene, CPU
     * and device alike (experiments: delassus, crIterations, ...) */
    const char *set = getenv("GPU_SCENES_SET");
    if (sim && set && *set) {
        char buf[1024];
        snprintf(buf, sizeof buf, "%s", set);
        for (char *save = NULL, *kv = strtok_r(buf, ";", &save); kv; kv = strtok_r(NULL, ";", &save)) {
            char *eq = strchr(kv, '=');
            if (!eq) continue;
            *eq = '\0';
            if (pl_sim_set(sim, kv, eq + 1, &err) != PL_OK) {
                printf("GPU_SCENES_SET %s: %s\n", kv, err.msg);
                pl_sim_free(sim);
                return NULL;
            }
        }
    }
    return sim;
}

/* Positions, velocities and every ".dual" slot of the state. */
typedef struct snap {
    double *x, *v, *u;
    size_t nx, nu;
} snap;

static void snap_free(snap *s)
{
    free(s->x), free(s->v), free(s->u);
    memset(s, 0, sizeof *s);
}

static int first_state(pl_component *c, void *user)
{
    *(pl_component **)user = c;
    return 1;
}

/* The scene's first state (its body) in d. */
static int take(pl_sim *sim, pl_data *d, snap *s)
{
    memset(s, 0, sizeof *s);
    pl_component *c = NULL;
    pl_node_visit_role(pl_sim_model(sim)->root, PL_ROLE_STATE, first_state, &c);
    const pl_state_ops *ops = c ? pl_component_role(c, PL_ROLE_STATE) : NULL;
    if (!ops) return -1;
    pl_buffer x = ops->positions(c, d), v = ops->velocities(c, d);
    s->nx = x.rows * 3;
    s->x = malloc(s->nx * sizeof(double));
    s->v = malloc(s->nx * sizeof(double));
    const pl_model *m = pl_sim_model(sim);
    for (int k = 0; k < m->nslots; ++k) {
        const char *nm = m->slots[k].name, *dot = strrchr(nm, '.');
        if (dot && !strcmp(dot, ".dual")) s->nu += pl_data_slot_bytes(d, k) / sizeof(double);
    }
    s->u = malloc((s->nu ? s->nu : 1) * sizeof(double));
    if (!s->x || !s->v || !s->u) return -1;
    memcpy(s->x, x.data, s->nx * sizeof(double));
    memcpy(s->v, v.data, s->nx * sizeof(double));
    size_t at = 0;
    for (int k = 0; k < m->nslots; ++k) {
        const char *nm = m->slots[k].name, *dot = strrchr(nm, '.');
        if (!dot || strcmp(dot, ".dual")) continue;
        size_t b = pl_data_slot_bytes(d, k);
        memcpy(s->u + at, pl_data_slot(d, k), b);
        at += b / sizeof(double);
    }
    return 0;
}

/* Restores the state file at path, steps, takes a snapshot. */
static int step_from(pl_sim *sim, const char *path, int frames, snap *s)
{
    pl_error err;
    if (pl_sim_restore_state(sim, path, &err) != PL_OK ||
        pl_sim_step(sim, frames, &err) != PL_OK) {
        printf("restore/step: %s\n", err.msg);
        return -1;
    }
    return take(sim, pl_sim_data(sim), s);
}

/* ||a - b|| / ||b|| (0 for empty vectors). */
static double rel(const double *a, const double *b, size_t n)
{
    double d = 0.0, r = 0.0;
    for (size_t i = 0; i < n; ++i) d += (a[i] - b[i]) * (a[i] - b[i]), r += b[i] * b[i];
    return n ? (r > 0 ? sqrt(d / r) : sqrt(d)) : 0.0;
}

/* ||a - b|| / max(||b||, floor sqrt(n)): relative, but against an RMS of
 * at least `floor` per value, for quantities that may all be near zero (the
 * velocities of a body at rest, the duals of an undeformed one). */
static double rel_floor(const double *a, const double *b, size_t n, double floor)
{
    double d = 0.0, r = 0.0;
    for (size_t i = 0; i < n; ++i) d += (a[i] - b[i]) * (a[i] - b[i]), r += b[i] * b[i];
    return n ? sqrt(d) / fmax(sqrt(r), floor * sqrt((double)n)) : 0.0;
}

/* Frames the CPU runs before the state is saved: the ball must have
 * reached the floor (contact from about frame 25). */
/* Steps run before the saved state, so that contacts (and cables) are active. */
static const struct {
    const char *scene;
    int run_up;
} RUN_UP[] = {{"ball_on_plane", 40},           {"cloth_on_knives_small", 30}, {"sharp_corner_small", 30},
              {"squeezing_ball_small", 40},    {"pulling_through_gap_small", 90},
              {"gingerbread_small", 60},       {"cable_finger_small", 20},
              {"grabbing_raptor_small", 100}};

static int run_up(const char *scene)
{
    const char *env = getenv("GPU_SCENES_RUNUP"); /* experiments: a later state */
    if (env && atoi(env) > 0) return atoi(env);
    for (size_t k = 0; k < sizeof RUN_UP / sizeof RUN_UP[0]; ++k)
        if (strstr(scene, RUN_UP[k].scene)) return RUN_UP[k].run_up;
    return 10;
}

/* Scenes with contact or cables: their velocities, duals and float32 runs are
 * notes (see the checks below). */
static int has_contact(const char *scene)
{
    static const char *const with[] = {"stick_slip", "resting_box", "ball_on_plane", "sliding_box",
                                       "cloth_on_knives", "sharp_corner", "squeezing_ball",
                                       "pulling_through_gap", "gingerbread", "cable_finger",
                                       "template_constraint", "grabbing_raptor"};
    for (size_t k = 0; k < sizeof with / sizeof with[0]; ++k)
        if (strstr(scene, with[k])) return 1;
    return 0;
}

static void check_scene(const char *path)
{
    char what[512];
    const char *slash = strrchr(path, '/');
    char scene[128];
    snprintf(scene, sizeof scene, "%s", slash ? slash + 1 : path);
    char *dot = strrchr(scene, '.');
    if (dot) *dot = '\0';
    const config cpu = {"cpu", 0, 0, 0, 0};
    const config gpus[3] = {{"cuda float64, no graph", 1, 0, 0, 0},
                            {"cuda float64, graph", 1, 0, 1, 0},
                            {"cuda float32 S, graph", 1, 1, 1, 0}};
    converge = 0; /* the run-up at the scene's own settings */
    pl_sim *ref = gpu_scenes_load(path, &cpu);
    pl_error err;
    snap one = {0}, ten = {0}, s = {0}, s2 = {0};
    const int contact = has_contact(scene);
    char own[3][64];
    if (!ref || pl_sim_step(ref, run_up(scene), &err) != PL_OK ||
        pl_sim_save_state(ref, state_file(), &err) != PL_OK || (contact && set_converged(ref, own)) ||
        step_from(ref, state_file(), 1, &one) ||
        step_from(ref, state_file(), 10, &ten)) {
        snprintf(what, sizeof what, "%s: CPU reference", scene);
        gpu_check_line(md, what, INFINITY, 0.0);
        goto done;
    }
    converge = contact;
    for (int g = 0; g < 3; ++g) {
        pl_sim *sim = gpu_scenes_load(path, &gpus[g]);
        int f32 = gpus[g].f32;
        if (!sim || step_from(sim, state_file(), 1, &s)) {
            snprintf(what, sizeof what, "%s, %s: loads and steps", scene, gpus[g].name);
            gpu_check_line(md, what, INFINITY, 0.0);
            pl_sim_free(sim);
            continue;
        }
        snprintf(what, sizeof what, "%s, 1 frame from a saved state, %s: positions", scene,
                 gpus[g].name);
        /* float32 S with contact: W is built in float64 on the CPU while the
         * solves run in float32, so the constraint update sees two operators */
        if (f32 && contact)
            gpu_note_line(md, what, rel(s.x, one.x, one.nx));
        else
            gpu_check_line(md, what, rel(s.x, one.x, one.nx), f32 ? 1e-4 : 1e-9);
        snprintf(what, sizeof what, "%s, 1 frame, %s: velocities", scene, gpus[g].name);
        /* velocities against an RMS of at least 1 mm/s, duals (F units) 1e-3;
         * with contact notes: the converged constraint solve ends at its
         * tolerance (1e-13 relative), which leaves positions ~1e-12 apart
         * (checked above), and the velocities of a body at rest,
         * (q - q_t) / h, are small */
        if (f32 || contact)
            gpu_note_line(md, what, rel_floor(s.v, one.v, one.nx, 1e-3));
        else
            gpu_check_line(md, what, rel_floor(s.v, one.v, one.nx, 1e-3), 1e-9);
        if (one.nu) {
            snprintf(what, sizeof what, "%s, 1 frame, %s: ADMM duals", scene, gpus[g].name);
            if (f32 || contact)
                gpu_note_line(md, what, rel_floor(s.u, one.u, one.nu, 1e-3));
            else
                gpu_check_line(md, what, rel_floor(s.u, one.u, one.nu, 1e-3), 1e-9);
        }
        snap_free(&s);
        if (step_from(sim, state_file(), 10, &s) == 0) {
            snprintf(what, sizeof what, "%s, 10 frames from the state, %s: positions", scene,
                     gpus[g].name);
            gpu_note_line(md, what, rel(s.x, ten.x, ten.nx));
        }
        if (g == 1 && step_from(sim, state_file(), 5, &s2) == 0) {
            snap_free(&s);
            if (step_from(sim, state_file(), 5, &s) == 0) {
                size_t diff = 0;
                for (size_t i = 0; i < s.nx; ++i)
                    diff += memcmp(&s.x[i], &s2.x[i], sizeof(double)) != 0;
                for (size_t i = 0; i < s.nu; ++i)
                    diff += memcmp(&s.u[i], &s2.u[i], sizeof(double)) != 0;
                snprintf(what, sizeof what,
                         "%s, %s: restored twice, 5 frames each: values that differ", scene,
                         gpus[g].name);
                gpu_check_line(md, what, (double)diff, 0.0);
            }
        }
        snap_free(&s), snap_free(&s2);
        pl_sim_free(sim);
    }
    /* W explicit (built on the device by the global solver: cuBLAS) and
     * matrix-free (products through device solves), each against the CPU */
    static const char *const MODES[2] = {"explicit", "matrix-free"};
    for (int w = 0; contact && w < 2; ++w) {
        pl_sim *sim = gpu_scenes_load(path, &gpus[1]);
        snprintf(what, sizeof what, "%s, 1 frame from a saved state, cuda float64, graph, "
                 "delassus=%s: positions", scene, MODES[w]);
        if (!sim || pl_sim_set(sim, "contact.delassus", MODES[w], &err) != PL_OK ||
            step_from(sim, state_file(), 1, &s) != 0)
            gpu_check_line(md, what, INFINITY, 0.0);
        else
            gpu_check_line(md, what, rel(s.x, one.x, one.nx), 1e-9);
        snap_free(&s);
        pl_sim_free(sim);
    }
    converge = 0;
    if (contact) {
        /* a note: one frame at the scene's own contact settings */
        pl_sim *sim = gpu_scenes_load(path, &gpus[1]);
        snap_free(&one);
        for (int k = 0; k < 3; ++k)
            if (pl_sim_set(ref, CONVERGED[k][0], own[k], &err) != PL_OK) printf("set: %s\n", err.msg);
        if (sim && step_from(ref, state_file(), 1, &one) == 0 &&
            step_from(sim, state_file(), 1, &s) == 0) {
            snprintf(what, sizeof what,
                     "%s, 1 frame, cuda float64, graph, the scene's contact settings (crIterations "
                     "%s, unconverged): positions",
                     scene, own[0]);
            gpu_note_line(md, what, rel(s.x, one.x, one.nx));
        }
        snap_free(&s);
        pl_sim_free(sim);
    }
done:
    snap_free(&one), snap_free(&ten);
    pl_sim_free(ref);
}

/* Centroid of every state's positions after `steps` steps from the start. */
static int long_run(const char *path, const config *c, int steps, double cen[3], double *xmax)
{
    pl_sim *sim = gpu_scenes_load(path, c);
    pl_error err;
    snap s = {0};
    int rc = !sim || pl_sim_step(sim, steps, &err) != PL_OK || take(sim, pl_sim_data(sim), &s) ||
             s.nx == 0;
    if (!rc) {
        cen[0] = cen[1] = cen[2] = 0.0;
        *xmax = -INFINITY;
        for (size_t i = 0; i < s.nx / 3; ++i) {
            for (int k = 0; k < 3; ++k) cen[k] += s.x[3 * i + k] / (double)(s.nx / 3);
            *xmax = fmax(*xmax, s.x[3 * i]);
        }
    }
    snap_free(&s);
    pl_sim_free(sim);
    return rc;
}

/* A long run of a scene on the CPU and on the GPU (float64, graph) ends in
 * the same qualitative state: the ball below the rollers, the pulled body
 * through the gap (the criteria of tests/collision), the raptor lifted
 * (tests/gripper). */
static void long_runs(void)
{
    const config cpu = {"cpu", 0, 0, 0, 0}, gpu = {"cuda float64, graph", 1, 0, 1, 0};
    struct {
        const char *path, *what;
        int steps;
    } runs[] = {{"scenes/squeezing_ball_small.xml", "ball centre below the rollers (y < -0.1 m)", 150},
                {"scenes/pulling_through_gap_small.xml", "body through the gap (front x < -0.392 m)", 150},
                /* t = 1.25 s, the end of the turn: the raptor rested at a
                 * centre height of 9 mm and must be lifted by half its
                 * height, 12.7 mm (tests/gripper) */
                {"scenes/grabbing_raptor_small.xml", "raptor lifted (centre y > 0.0216 m)", 500}};
    for (int k = 0; k < 3; ++k) {
        double c[2][3], xm[2];
        int bad = long_run(runs[k].path, &cpu, runs[k].steps, c[0], &xm[0]) ||
                  long_run(runs[k].path, &gpu, runs[k].steps, c[1], &xm[1]);
        char what[256];
        for (int d = 0; d < 2 && !bad; ++d) {
            int ok = k == 0 ? c[d][1] < -0.1 : k == 1 ? xm[d] < -0.392 : c[d][1] > 0.0216;
            snprintf(what, sizeof what, "%s, %d steps, %s: %s (centre %.4f %.4f %.4f m, front %.4f m)",
                     runs[k].path, runs[k].steps, d ? "cuda" : "cpu", runs[k].what, c[d][0], c[d][1],
                     c[d][2], xm[d]);
            gpu_check_line(md, what, ok ? 0.0 : 1.0, 0.5);
        }
        if (bad) {
            snprintf(what, sizeof what, "%s: long runs", runs[k].path);
            gpu_check_line(md, what, INFINITY, 0.0);
        } else {
            snprintf(what, sizeof what, "%s, %d steps: |centre cpu - centre cuda| [m]", runs[k].path,
                     runs[k].steps);
            gpu_note_line(md, what, sqrt(pow(c[0][0] - c[1][0], 2) + pow(c[0][1] - c[1][1], 2) +
                                         pow(c[0][2] - c[1][2], 2)));
        }
    }
}

/* A scene that declares no device runs on the GPU by default (the loader's
 * implicit CudaDevice): the same frames as with a declared one, bitwise. */
static void implicit_device_check(void)
{
    const char *path = "scenes/twisting_bar_small.xml";
    const config declared = {"cuda float64, graph", 1, 0, 1, 0}, cpu = {"cpu", 0, 0, 0, 0};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = test_tmp_dir();
    opt.export_every = 1000000;
    opt.device = "auto";
    pl_sim *sim = pl_sim_load_file(path, &opt, &diag), *ref = gpu_scenes_load(path, &declared),
           *host = gpu_scenes_load(path, &cpu);
    if (!sim) pl_diag_print(&diag, stdout);
    pl_diag_free(&diag);
    pl_error err;
    snap a = {0}, b = {0}, c = {0};
    int ok = sim && ref && host && pl_sim_step(sim, 5, &err) == PL_OK &&
             pl_sim_step(ref, 5, &err) == PL_OK && pl_sim_step(host, 5, &err) == PL_OK &&
             !take(sim, pl_sim_data(sim), &a) && !take(ref, pl_sim_data(ref), &b) &&
             !take(host, pl_sim_data(host), &c);
    gpu_check_line(md, "implicit device: twisting_bar_small without a CudaDevice gets one",
                   ok && pl_sim_component(sim, "cudaDevice") ? 0.0 : 1.0, 0.0);
    gpu_check_line(md, "implicit device: 5 frames against a declared CudaDevice (bitwise)",
                   ok ? rel(a.x, b.x, b.nx) : INFINITY, 0.0);
    gpu_note_line(md, "implicit device: 5 frames against the CPU", ok ? rel(a.x, c.x, c.nx) : INFINITY);
    snap_free(&a), snap_free(&b), snap_free(&c);
    pl_sim_free(sim), pl_sim_free(ref), pl_sim_free(host);
}

/* Two data of one model on the device, interleaved, against each alone. */
static void two_data_check(void)
{
    const char *path = "scenes/cable_finger_small.xml";
    char sa[1100], sb[1100];
    snprintf(sa, sizeof sa, "%s/two_a.bin", test_tmp_dir());
    snprintf(sb, sizeof sb, "%s/two_b.bin", test_tmp_dir());
    const config gpu = {"cuda float64, graph", 1, 0, 1, 0};
    pl_sim *sim = gpu_scenes_load(path, &gpu), *ref = gpu_scenes_load(path, &gpu);
    pl_data *other = sim ? pl_data_clone(pl_sim_data(sim)) : NULL;
    pl_error err = {0};
    snap a1 = {0}, b1 = {0}, a2 = {0}, b2 = {0};
    FILE *f = NULL;
    /* A at 0.1 s (the cable being pulled), B at 0.25 s (nearly held) */
    int ok = sim && ref && other && !pl_sim_step(ref, 10, &err) && !pl_sim_save_state(ref, sa, &err) &&
             !pl_sim_step(ref, 15, &err) && !pl_sim_save_state(ref, sb, &err) &&
             !step_from(ref, sa, 10, &a1) && !step_from(ref, sb, 10, &b1) &&
             !pl_sim_restore_state(sim, sa, &err) && (f = fopen(sb, "rb")) && !pl_data_load(other, f, &err);
    if (f) fclose(f);
    for (int k = 0; ok && k < 10; ++k)
        ok = !pl_sim_step_data(sim, pl_sim_data(sim), 1, &err) && !pl_sim_step_data(sim, other, 1, &err);
    ok = ok && !take(sim, pl_sim_data(sim), &a2) && !take(sim, other, &b2);
    if (!ok) printf("two data: %s\n", err.msg);
    gpu_check_line(md, "two data interleaved on the device (cable_finger_small): A as alone, bitwise",
                   ok ? rel(a2.x, a1.x, a1.nx) + rel(a2.u, a1.u, a1.nu) : INFINITY, 0.0);
    gpu_check_line(md, "two data interleaved on the device (cable_finger_small): B as alone, bitwise",
                   ok ? rel(b2.x, b1.x, b1.nx) + rel(b2.u, b1.u, b1.nu) : INFINITY, 0.0);
    gpu_note_line(md, "two data: A against B (relative)", ok ? rel(a2.x, b2.x, b2.nx) : NAN);
    snap_free(&a1), snap_free(&b1), snap_free(&a2), snap_free(&b2);
    pl_data_free(other);
    pl_sim_free(sim), pl_sim_free(ref);
    remove(sa), remove(sb);
}

int main(int argc, char **argv)
{
    gpu_require(PROG);
    md = argc > 1 ? fopen(argv[1], "w") : NULL;
    FILE *tab = argc > 2 ? fopen(argv[2], "w") : stdout;
    int frames = argc > 3 ? atoi(argv[3]) : 100;
    if (!tab) return 1;
    if (md) fprintf(md, "| check | value | tolerance | result |\n|---|---|---|---|\n");
    int small = argc > 4 && !strcmp(argv[4], "small");
    int timing_only = argc > 4 && !strcmp(argv[4], "timing");
    const char *only = argc > 4 && strstr(argv[4], ".xml") ? argv[4] : NULL;
    /* the small ones first (small: only those) */
    const char *scenes[] = {"scenes/twisting_bar_small.xml",
                            "scenes/hanging_bar_small.xml",
                            "scenes/cloth_extension_arap_small.xml",
                            "scenes/cloth_extension_corotational_small.xml",
                            "scenes/cloth_extension_neohookean_small.xml",
                            "tests/gpu/cloth_terms.xml",
                            "scenes/resting_box.xml",
                            "scenes/stick_slip.xml",
                            "scenes/ball_on_plane.xml",
                            "scenes/sliding_box.xml",
                            "scenes/template_constraint.xml",
                            "scenes/cable_finger_small.xml",
                            "scenes/cloth_on_knives_small.xml",
                            "scenes/sharp_corner_small.xml",
                            "scenes/squeezing_ball_small.xml",
                            "scenes/pulling_through_gap_small.xml",
                            "scenes/gingerbread_small.xml",
                            "scenes/grabbing_raptor_small.xml",
                            "scenes/twisting_bar.xml"};
    const int nscenes = (int)(sizeof scenes / sizeof scenes[0]);
    if (!only && !timing_only) implicit_device_check();
    if (!only && !timing_only) two_data_check();
    if (only)
        check_scene(only);
    for (int k = 0; !only && !timing_only && k < (small ? nscenes - 1 : nscenes); ++k)
        check_scene(scenes[k]);
    if (!only && !timing_only && !small) long_runs();
    printf("gpu_scenes checks: %d failed\n", gpu_failures());
    fprintf(tab, "| bar | run | Frame ms | paper Frame ms | speed-up | Local ms | Assembly ms | "
                 "Global ms |\n|---|---|--:|--:|--:|--:|--:|--:|\n");
    const char *bars[3] = {"twisting_bar", "twisting_bar_11k", "twisting_bar_20k"};
    const char *sizes[3] = {"5.3k", "11.3k", "20.8k"};
    const double paper[3] = {6.23, 13.55, 28.55};
    for (int b = 0; frames > 0 && b < 3; ++b) gpu_scenes_time_bar(tab, bars[b], sizes[b], paper[b], frames);
    if (md) fclose(md);
    if (tab != stdout) fclose(tab);
    printf("gpu_scenes: %d failed\n", gpu_failures());
    return gpu_failures() > 100 ? 100 : gpu_failures();
}
