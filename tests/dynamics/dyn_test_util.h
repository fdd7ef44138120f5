/* dyn_test_util.h - helpers for scene-level dynamics tests. */
#ifndef DYN_TEST_UTIL_H
#define DYN_TEST_UTIL_H

#include <pliant/pliant.h>

/* Loads XML (fails the test with the diagnostics on error). */
pl_sim *dyn_load(const char *xml);
/* Loads a scene file of the source tree with overrides. */
pl_sim *dyn_load_file(const char *rel_path, const char **sets, int nsets);
/* Current positions of the state at `path` (n x 3, owned by the sim). */
const double *dyn_positions(pl_sim *s, const char *path, int *n);
const double *dyn_velocities(pl_sim *s, const char *path, int *n);
const double *dyn_rest(pl_sim *s, const char *path, int *n);
/* Lumped masses of the state's node (the first mass component there). */
double *dyn_masses(pl_sim *s, const char *mass_path, int n);
/* Steps and fails the test on error. */
void dyn_step(pl_sim *s, int n);
/* Formats n x 3 doubles as a field value (malloc'ed). */
char *dyn_format(const double *x, int n);

#endif
