/* gpu_util.h - device buffers and result lines for the GPU programs. */
#ifndef PLIANT_TESTS_GPU_UTIL_H
#define PLIANT_TESTS_GPU_UTIL_H

#include <stddef.h>
#include <stdio.h>

#include "pliant/buffer.h"
#include "pliant/pliant.h"

/* The exit status ctest reads as "skipped" (SKIP_RETURN_CODE). */
#define GPU_SKIP 77
/* Returns when a GPU answers; otherwise prints one line "<prog>: skipped:
 * no GPU (<reason>)" and exits with GPU_SKIP. */
void gpu_require(const char *prog);

/* A device copy of m doubles of h, stored as prec (float32 converts);
 * NULL (message printed) on a CUDA error. h NULL: zeros. */
void *gpu_put(const double *h, size_t m, pl_precision prec);
/* h (m doubles) <- device d stored as prec; 0, or -1 (message printed). */
int gpu_get(double *h, const void *d, size_t m, pl_precision prec);
void gpu_free(void *d);
/* Waits for the device; 0, or -1 with the error printed. */
int gpu_sync(const char *what);

/* Result lines: printed, and appended as table rows to md (may be NULL).
 * gpu_check_line counts a failure when !(value <= tol). */
void gpu_check_line(FILE *md, const char *what, double value, double tol);
void gpu_note_line(FILE *md, const char *what, double value);
int gpu_failures(void);

double gpu_median(double *v, int n);

/* The text of scene file `path` with <RequiredPlugin name="cuda"/> and
 * <CudaDevice name="gpu" graph="1"/> first in its root node (malloc'ed), or
 * NULL. */
char *gpu_scene_with_device(const char *path);

/* Loads the scene text xml (taken: freed here; NULL gives NULL) named path
 * with the overrides ov[0..nov), exporters off, outputs under out_dir; a
 * failed load prints its diagnostics and returns NULL. */
pl_sim *gpu_load_scene(char *xml, const char *path, const char *const *ov, int nov,
                       const char *out_dir);

#endif
