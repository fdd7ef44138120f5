/* gpu_scenes.h - what gpu_scenes.c (the CPU against GPU checks of whole
 * scenes) shares with gpu_scenes_time.c (the timings of the bars). */
#ifndef PLIANT_TESTS_GPU_SCENES_H
#define PLIANT_TESTS_GPU_SCENES_H

#include <stdio.h>

#include "pliant/pliant.h"

typedef struct config {
    const char *name;
    int cuda;           /* LocalGlobalSolver and SparseInverseSolver on the device */
    int f32;            /* S in float32 */
    int graph, profile; /* CudaDevice (profile: set by time_run) */
} config;

/* The scene at path on the CPU or on the device as c says (NULL: the load
 * failed, its diagnostics printed). */
pl_sim *gpu_scenes_load(const char *path, const config *c);

/* Table rows of the bar `scene` (scenes/<scene>.xml): the CPU, then cuda
 * float64 and float32 S, each with a graph, without one and profiled;
 * median frame over `frames` frames against the paper's Frame `paper`. */
void gpu_scenes_time_bar(FILE *tab, const char *scene, const char *size, double paper, int frames);

#endif
