/* lg_device_scene.h - the scene of test_lg_device and test_lg_device_stop
 * (a bar of springs with a fixed and a turning end, lg_device_fakes.h's
 * components) and its helpers: load it with a setup, run it, compare two
 * runs' states bitwise. */
#ifndef PLIANT_TESTS_LG_DEVICE_SCENE_H
#define PLIANT_TESTS_LG_DEVICE_SCENE_H

#include <stddef.h>

#include "lg_device_fakes.h"

typedef struct setup {
    const char *device;        /* cpu, cuda, auto */
    const char *tolerance;
    const char *energy;
    const char *before;        /* text before the solver (a HostDevice) */
    const char *after;         /* after the global solver */
    const char *solver_ok, *springs_ok;
    const char *extra;         /* more components in the bar */
    const char *scheme;        /* more solver attributes (firstOrder, ...) */
} setup;

typedef struct result {
    double x[3 * 200], v[3 * 200];
    size_t m;
    int nenergy;
    double energy[64];
} result;

/* A registry with the builtin components and the fakes. */
pl_registry *registry(void);
/* The scene on `device` (cpu, cuda, auto) with a HostDevice before the solver. */
setup plain(const char *device);
/* Loads the scene; NULL with the first message in msg when it fails. */
pl_sim *load(pl_registry *r, const setup *s, char *msg, size_t size);
/* Steps it; the bar's state (and energies) in out; the sim in *keep, or freed. */
void run(pl_registry *r, const setup *s, int steps, result *out, pl_sim **keep);
/* Bitwise the same positions, velocities and energies. */
void assert_same(const result *a, const result *b);
/* The bar moved: not a trivial agreement of two states at rest. */
void assert_moved(const result *a, const result *rest);
/* A series of the run's timings, copied (n values at most). */
int series(pl_sim *sim, const char *name, double *out, int n);
/* The scene with a NaN at step 3, iteration 3, run into it: the third step's
 * failure message in msg. */
pl_sim *run_into_nan(pl_registry *r, setup s, char *msg, size_t size);

#endif
