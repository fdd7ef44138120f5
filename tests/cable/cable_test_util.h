/* cable_test_util.h - helpers of the cable tests: load a scene from text,
 * step it, read fields and state blocks. */
#ifndef CABLE_TEST_UTIL_H
#define CABLE_TEST_UTIL_H

#include "pliant/pliant.h"

/* Loads XML text (fails the test with the diagnostics on error). */
pl_sim *ct_load(const char *xml);
/* Loads XML text that must fail; returns the diagnostics (caller frees). */
pl_diag ct_load_fail(const char *xml);
/* Steps n times (fails the test on error). */
void ct_step(pl_sim *s, int n);
/* A field's value as a number (the first number of a list). */
double ct_get(pl_sim *s, const char *path);
/* The state block of the MechanicalObject at path: positions (or rest
 * positions when rest != 0), n x 3, owned by the simulation. */
const double *ct_positions(pl_sim *s, const char *path, int rest, int *n);
/* Index of the vertex of x (n x 3) at p (within 1e-9 m), or -1. */
int ct_vertex_at(const double *x, int n, double px, double py, double pz);
/* The first error of diag whose message contains `what`, or NULL. */
const pl_error *ct_find_error(const pl_diag *d, const char *what);
/* A whole text file (fails the test when it cannot be read; caller frees). */
char *ct_read_text(const char *path);
/* *text with its first `from` replaced by `to` (fails the test when `from`
 * is absent; *text is reallocated). */
void ct_replace(char **text, const char *from, const char *to);

#endif
