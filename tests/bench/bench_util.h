/* bench_util.h - what the two benchmark programs share: loading a scene with
 * overrides (printing its diagnostics), describing it (vertices, elements,
 * materials, iterations) and reading the timers by name.  Only the public
 * embedding API (sim.h, timer.h) and the role tables are used. */
#ifndef PLIANT_BENCH_UTIL_H
#define PLIANT_BENCH_UTIL_H

#include <stddef.h>

#include "pliant/sim.h"

typedef struct bench_scene_info {
    int vertices;       /* sum over the states */
    int elements;       /* tetrahedra, or triangles for a surface, over the topologies */
    int iterations;     /* local-global iterations per step, 0 when not a LocalGlobalSolver */
    char material[96];  /* type names of the local terms, "ARAP", "NeoHookean+..." */
} bench_scene_info;

/* Loads a scene from `path`, or from `xml` text (then `path` names it in
 * messages), with "path.field=value" overrides and exporters writing into
 * out_dir.  Prints the diagnostics to stderr and returns NULL on failure. */
pl_sim *bench_load(const char *path, const char *xml, const char *const *overrides,
                   int noverrides, const char *out_dir);

/* Fills info from the loaded scene; PL_OK or PL_EINPUT. */
int bench_describe(pl_sim *sim, bench_scene_info *info);

/* A statistic by name, or NAN when the scene did not set it. */
double bench_stat(const pl_timers *t, const char *name);
/* Median per frame [ms] of a phase by name, or NAN when it never ran. */
double bench_phase_median_ms(const pl_timers *t, const char *name);

/* The median of v[0..n-1] (n >= 1), which it sorts in place. */
double bench_median(double *v, int n);

/* The whole file as a NUL-terminated string (malloc'd), or NULL. */
char *bench_read_file(const char *path);

/* Splits "a,b,c" in place into at most max items; returns the count. */
int bench_split_list(char *list, char **items, int max);

/* Formats v with printf format fmt into buf, or "n/a" when v is NaN. */
const char *bench_fmt(char *buf, size_t size, const char *fmt, double v);

#endif
