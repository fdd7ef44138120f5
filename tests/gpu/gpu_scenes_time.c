/* gpu_scenes_time.c - gpu_scenes' timings of the bars: the CPU against the
 * device loop in float64 and float32, with and without a CUDA graph, and
 * with the CudaDevice's synced phase profile (the Table 3 columns of
 * docs/benchmarks.md); the checks are in gpu_scenes.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "gpu_scenes.h"
#include "gpu_util.h"
#include "pliant/pliant.h"

/* Median frame (and phase) times over `frames` frames after 5 warm-up
 * frames, as the CudaDevice's graph / profile say (set at run time, so one
 * load, one factorisation, serves several runs). */
static void time_run(FILE *tab, pl_sim *sim, const char *size, double paper, const char *name,
                     int graph, int profile, int frames)
{
    pl_error err;
    if (pl_sim_component(sim, "gpu") &&
        (pl_sim_set(sim, "gpu.graph", graph ? "1" : "0", &err) != PL_OK ||
         pl_sim_set(sim, "gpu.profile", profile ? "1" : "0", &err) != PL_OK))
        printf("set: %s\n", err.msg);
    pl_timers *t = pl_sim_timers(sim);
    double *ms = malloc((size_t)(frames > 0 ? frames : 1) * sizeof *ms);
    if (!ms || pl_sim_step(sim, 5, &err) != PL_OK) goto failed;
    /* each frame timed here: the sim's own timers pool every run of this sim */
    for (int k = 0; k < frames; ++k) {
        double t0 = pl_now();
        if (pl_sim_step(sim, 1, &err) != PL_OK) goto failed;
        ms[k] = 1e3 * (pl_now() - t0);
    }
    double frame = gpu_median(ms, frames);
    free(ms);
    char ph[3][32] = {"", "", ""};
    const char *names[3] = {"Local", "Assembly", "Global"};
    for (int k = 0; k < 3; ++k) {
        int id = pl_timer_id(t, names[k]);
        if (pl_timers_samples(t, id) > 0)
            snprintf(ph[k], sizeof ph[k], "%.3f", pl_timers_median_ms(t, id));
    }
    fprintf(tab, "| %s | %s | **%.3f** | %.2f | %.1fx | %s | %s | %s |\n", size, name, frame, paper,
            paper / frame, ph[0], ph[1], ph[2]);
    printf("%s %s: Frame %.3f ms (paper %.2f), Local %s Assembly %s Global %s\n", size, name, frame,
           paper, ph[0], ph[1], ph[2]);
    fflush(tab);
    return;
failed:
    free(ms);
    printf("%s %s: %s\n", size, name, err.msg);
    fprintf(tab, "| %s | %s | failed | | | | | |\n", size, name);
    gpu_check_line(NULL, "timed scene runs", INFINITY, 0.0);
}

void gpu_scenes_time_bar(FILE *tab, const char *scene, const char *size, double paper, int frames)
{
    char path[256];
    snprintf(path, sizeof path, "scenes/%s.xml", scene);
    const config cfg[3] = {{"cpu", 0, 0, 0, 0}, {"f64", 1, 0, 1, 0}, {"f32", 1, 1, 1, 0}};
    for (int k = 0; k < 3; ++k) {
        pl_sim *sim = gpu_scenes_load(path, &cfg[k]);
        if (!sim) {
            fprintf(tab, "| %s | %s | load failed | | | | | |\n", size, cfg[k].name);
            gpu_check_line(NULL, "timed scene loads", INFINITY, 0.0);
            continue;
        }
        if (k == 0)
            time_run(tab, sim, size, paper, "CPU (16 threads)", 0, 0, frames / 5);
        else {
            const char *p = k == 1 ? "float64" : "float32 S";
            char name[96];
            snprintf(name, sizeof name, "cuda %s, graph", p);
            time_run(tab, sim, size, paper, name, 1, 0, frames);
            snprintf(name, sizeof name, "cuda %s, no graph", p);
            time_run(tab, sim, size, paper, name, 0, 0, frames);
            /* last: the phase timers then hold only synced (profiled) frames */
            snprintf(name, sizeof name, "cuda %s, profile (synced phases)", p);
            time_run(tab, sim, size, paper, name, 0, 1, frames);
        }
        pl_sim_free(sim);
    }
}
