/* coll_test_util.h - helpers of the collision scene tests: load a scene
 * (with the plugin from the build tree), build an obstacle's rows through
 * its constraint role with a hand-made pl_system, read vector outputs. */
#ifndef PLIANT_COLL_TEST_UTIL_H
#define PLIANT_COLL_TEST_UTIL_H

#include "pliant/pliant.h"

/* Loads XML text (overrides "path=value" may be NULL); fails the test with
 * the diagnostics printed when the scene does not load. */
pl_sim *ct_load(const char *xml, const char *const *overrides, int noverrides);
/* Loads XML text that must fail; returns the first error (copied into *e). */
void ct_load_fail(const char *xml, pl_error *e);
/* Reads a scene file into a malloc'ed string (PL_SOURCE_DIR-relative path). */
char *ct_read_source(const char *relpath);
/* Replaces every line of text containing `needle` by `line` (may be ""). */
char *ct_replace_lines(const char *text, const char *needle, const char *line);

/* A system over n vertices, all free except those with prescribed[v] != 0
 * (prescribed may be NULL); free it with ct_system_free. */
typedef struct ct_system {
    pl_system sys;
    int *free_index, *free_vertex;
} ct_system;
void ct_system_make(ct_system *s, int n, double h, const int *prescribed);
void ct_system_free(ct_system *s);

/* The positions of the scene's single state (its offset must be 0): a
 * pointer into the current data, *n its vertex count. */
double *ct_positions(pl_sim *sim, const char *state_path, int *n);
/* Calls build_rows of the component at `path` through its constraint role;
 * returns the status (error printed when not PL_OK). */
int ct_build_rows(pl_sim *sim, const char *path, const pl_system *sys, double *q, int n,
                  pl_rows *rows, pl_error *err);
/* Parses the numbers of a field read by pl_sim_get; returns the count,
 * *out malloc'ed. */
int ct_get_doubles(pl_sim *sim, const char *path, double **out);

#endif
