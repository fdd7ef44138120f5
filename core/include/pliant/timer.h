/* timer.h - named per-phase timers and statistics.
 *
 * Phases (Local, Global, Assembly, Schur, Constraint solve, Correction,
 * Constraint global, Frame, ...) accumulate wall time within a frame;
 * pl_timers_end_frame() turns each phase's sum into one sample so that
 * medians per frame can be reported as in the paper's Table 3.  Statistics
 * (nnz(S), memory, contacts) are plain named values. */
#ifndef PLIANT_TIMER_H
#define PLIANT_TIMER_H

#include "api.h"
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pl_timers pl_timers;

PL_API pl_timers *pl_timers_create(void);
PL_API void pl_timers_free(pl_timers *t);
/* Drops every value (samples, statistics, series, the per-frame table); the
 * phases stay registered, so ids from pl_timer_id stay valid. */
PL_API void pl_timers_clear(pl_timers *t);

/* Monotonic wall clock in seconds. */
PL_API double pl_now(void);

/* Id of the phase `name` (created on first use); -1 on allocation failure. */
PL_API int pl_timer_id(pl_timers *t, const char *name);
PL_API void pl_timer_start(pl_timers *t, int id);
/* Also records, per frame, what the host did to the thread that times phase
 * `id`: "<name> off-CPU ms" (its wall time less the thread's CPU time: the
 * thread descheduled, or asleep at a wait such as a passive OpenMP barrier
 * or a blocking read-back), "<name> page faults" (the whole process's, minor
 * and major) and "<name> preemptions" (the thread's involuntary context
 * switches).  Three system calls at each start and stop: for phases timed a
 * few times a step (Frame, Detection), not per iteration. */
#if PL_ABI_TARGET_MINOR >= 7
PL_API void pl_timer_watch(pl_timers *t, int id);
#endif
PL_API void pl_timer_stop(pl_timers *t, int id);
/* Adds seconds to a phase directly. */
PL_API void pl_timer_add(pl_timers *t, int id, double seconds);
/* Closes the frame: every phase's accumulated time becomes a sample (phases
 * that did not run this frame get no sample).  It also appends one row to the
 * per-frame table: every phase's time [ms] in this frame (0 if it did not
 * run) and every pl_stat_max statistic's largest value given in this frame. */
PL_API void pl_timers_end_frame(pl_timers *t);

PL_API int pl_timers_count(const pl_timers *t);
PL_API const char *pl_timers_name(const pl_timers *t, int id);
PL_API int pl_timers_samples(const pl_timers *t, int id);
PL_API double pl_timers_median_ms(const pl_timers *t, int id);
PL_API double pl_timers_max_ms(const pl_timers *t, int id);
PL_API double pl_timers_total_ms(const pl_timers *t, int id);

/* Named statistics ("nnz(S)", "S memory [MB]", "contacts max"). */
PL_API void pl_stat_set(pl_timers *t, const char *name, double value);
/* Keeps the maximum of the values given (and, per frame, the maximum of the
 * frame: the "frames" table, e.g. each frame's "contacts max"). */
PL_API void pl_stat_max(pl_timers *t, const char *name, double value);
/* Appends a value to a named series (e.g. "energy" after each iteration). */
PL_API void pl_series_push(pl_timers *t, const char *name, double value);
PL_API int pl_stat_get(const pl_timers *t, const char *name, double *value);
/* Values of a series; returns the count (0 if absent). */
PL_API int pl_series_get(const pl_timers *t, const char *name, const double **values);

/* {"phases": {name: {median_ms, max_ms, total_ms, samples}}, "stats": {...}, "series": {...},
 *  "frames": {"count": N, name: [N values, one per frame], ...}} */
PL_API int pl_timers_write_json(const pl_timers *t, FILE *f);
/* A human table of the phases. */
PL_API void pl_timers_print(const pl_timers *t, FILE *f);

#ifdef __cplusplus
}
#endif
#endif
