/* timer.c - per-phase timers (samples per frame), statistics and series.
 *
 * Besides the samples (one per frame in which a phase ran), every frame
 * appends to a per-frame table: each phase's time in that frame (0 when it
 * did not run) and, for each statistic kept by pl_stat_max, the largest value
 * given in that frame (0 when none), so that a frame's phases can be read
 * beside its contact count ("frames" in the JSON). */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* RUSAGE_THREAD */
#endif
#include "pliant/timer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

/* What the host did to the calling thread while a watched phase ran
 * (pl_timer_watch): a spike with as much off-CPU time is the machine's (a
 * thread descheduled, or asleep at a wait), not more work. */
typedef struct host_watch {
    double cpu0;                    /* the thread's CPU time at start [s] */
    double faults0, preempt0;       /* counters at start */
    double off_cpu, faults, preempt; /* this frame's sums */
    char column[3][128];            /* their columns' names in the per-frame table */
} host_watch;

typedef struct phase {
    char *name;
    double start;       /* when running: start time; else -1 */
    double frame_sum;   /* seconds accumulated in the current frame */
    int ran;            /* ran in the current frame */
    double *samples;    /* per-frame sums [s] */
    int nsamples, cap;
    host_watch *watch;  /* NULL unless pl_timer_watch asked */
} phase;

typedef struct named_values {
    char *name;
    double *v;
    int n, cap;
    double frame; /* statistics: the largest pl_stat_max value of this frame */
    int per_frame; /* statistics: kept by pl_stat_max (0: by pl_stat_set only) */
} named_values;

struct pl_timers {
    phase *phases;
    int nphases, cap;
    named_values *stats;   /* one value each */
    int nstats, cap_stats;
    named_values *series;
    int nseries, cap_series;
    named_values *frames;  /* per frame: phases [ms], then the pl_stat_max statistics */
    int nframe_cols, cap_frames;
    int nframes;           /* frames ended */
};

double pl_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

pl_timers *pl_timers_create(void)
{
    return calloc(1, sizeof(pl_timers));
}

static void free_named(named_values *a, int n)
{
    for (int k = 0; k < n; ++k) {
        free(a[k].name);
        free(a[k].v);
    }
}

/* Every value goes; the phases stay registered (their names, ids and
 * watches), since components keep the ids they got at init and time into
 * them after a clear too. */
void pl_timers_clear(pl_timers *t)
{
    for (int k = 0; k < t->nphases; ++k) {
        phase *p = &t->phases[k];
        free(p->samples);
        p->samples = NULL;
        p->nsamples = p->cap = 0;
        p->frame_sum = 0.0;
        p->ran = 0;
        p->start = -1.0;
        if (p->watch) p->watch->off_cpu = p->watch->faults = p->watch->preempt = 0.0;
    }
    free_named(t->stats, t->nstats);
    free_named(t->series, t->nseries);
    free_named(t->frames, t->nframe_cols);
    t->nstats = t->nseries = t->nframe_cols = t->nframes = 0;
}

void pl_timers_free(pl_timers *t)
{
    if (!t) return;
    pl_timers_clear(t);
    for (int k = 0; k < t->nphases; ++k) {
        free(t->phases[k].name);
        free(t->phases[k].watch);
    }
    free(t->phases);
    free(t->stats);
    free(t->series);
    free(t->frames);
    free(t);
}

int pl_timer_id(pl_timers *t, const char *name)
{
    if (!t) return -1;
    for (int k = 0; k < t->nphases; ++k)
        if (!strcmp(t->phases[k].name, name)) return k;
    if (t->nphases == t->cap) {
        int cap = t->cap ? 2 * t->cap : 16;
        phase *p = realloc(t->phases, (size_t)cap * sizeof *p);
        if (!p) return -1;
        t->phases = p;
        t->cap = cap;
    }
    phase *p = &t->phases[t->nphases];
    memset(p, 0, sizeof *p);
    if (!(p->name = strdup(name))) return -1;
    p->start = -1.0;
    return t->nphases++;
}

/* The calling thread's CPU time [s], its involuntary context switches and
 * the process's page faults (minor and major, every thread's). */
static void host_counters(double *cpu, double *faults, double *preempt)
{
    struct timespec ts;
    *cpu = clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0
               ? (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec
               : NAN;
    struct rusage ru;
    *faults = getrusage(RUSAGE_SELF, &ru) == 0 ? (double)(ru.ru_minflt + ru.ru_majflt) : NAN;
#ifdef RUSAGE_THREAD
    *preempt = getrusage(RUSAGE_THREAD, &ru) == 0 ? (double)ru.ru_nivcsw : NAN;
#else
    *preempt = NAN;
#endif
}

void pl_timer_watch(pl_timers *t, int id)
{
    if (!t || id < 0 || t->phases[id].watch) return;
    host_watch *w = calloc(1, sizeof *w);
    if (!w) return; /* not watched, no harm */
    const char *name = t->phases[id].name;
    snprintf(w->column[0], sizeof w->column[0], "%s off-CPU ms", name);
    snprintf(w->column[1], sizeof w->column[1], "%s page faults", name);
    snprintf(w->column[2], sizeof w->column[2], "%s preemptions", name);
    t->phases[id].watch = w;
}

void pl_timer_start(pl_timers *t, int id)
{
    if (!t || id < 0) return;
    host_watch *w = t->phases[id].watch;
    if (w) host_counters(&w->cpu0, &w->faults0, &w->preempt0);
    t->phases[id].start = pl_now(); /* last: the counters' own cost is not timed */
}

void pl_timer_stop(pl_timers *t, int id)
{
    if (!t || id < 0 || t->phases[id].start < 0) return;
    double wall = pl_now() - t->phases[id].start;
    pl_timer_add(t, id, wall);
    t->phases[id].start = -1.0;
    host_watch *w = t->phases[id].watch;
    if (w) {
        double cpu, faults, preempt;
        host_counters(&cpu, &faults, &preempt);
        w->off_cpu += fmax(0.0, wall - (cpu - w->cpu0));
        w->faults += faults - w->faults0;
        w->preempt += preempt - w->preempt0;
    }
}

void pl_timer_add(pl_timers *t, int id, double seconds)
{
    if (!t || id < 0) return;
    t->phases[id].frame_sum += seconds;
    t->phases[id].ran = 1;
}

static named_values *find_named(named_values **arr, int *n, int *cap, const char *name, int create);
static void push_value(named_values *v, double x);

/* Appends this frame's value to column `name` of the per-frame table,
 * with zeros for the frames before the column existed. */
static void frame_value(pl_timers *t, const char *name, double x)
{
    named_values *v = find_named(&t->frames, &t->nframe_cols, &t->cap_frames, name, 1);
    if (!v || v->n > t->nframes) return; /* a statistic named like a phase: the phase's */
    while (v->n < t->nframes) push_value(v, 0.0);
    push_value(v, x);
}

/* A watched phase's three columns of the per-frame table. */
static void watch_columns(pl_timers *t, host_watch *w)
{
    frame_value(t, w->column[0], 1e3 * w->off_cpu);
    frame_value(t, w->column[1], w->faults);
    frame_value(t, w->column[2], w->preempt);
    w->off_cpu = w->faults = w->preempt = 0.0;
}

void pl_timers_end_frame(pl_timers *t)
{
    if (!t) return;
    for (int k = 0; k < t->nphases; ++k)
        frame_value(t, t->phases[k].name, t->phases[k].ran ? 1e3 * t->phases[k].frame_sum : 0.0);
    for (int k = 0; k < t->nphases; ++k)
        if (t->phases[k].watch) watch_columns(t, t->phases[k].watch);
    for (int k = 0; k < t->nstats; ++k) {
        if (!t->stats[k].per_frame) continue;
        frame_value(t, t->stats[k].name, t->stats[k].frame);
        t->stats[k].frame = 0.0;
    }
    t->nframes++;
    for (int k = 0; k < t->nphases; ++k) {
        phase *p = &t->phases[k];
        if (!p->ran) continue;
        if (p->nsamples == p->cap) {
            int cap = p->cap ? 2 * p->cap : 64;
            double *s = realloc(p->samples, (size_t)cap * sizeof *s);
            if (!s) continue; /* a lost sample is better than a failed step */
            p->samples = s;
            p->cap = cap;
        }
        p->samples[p->nsamples++] = p->frame_sum;
        p->frame_sum = 0.0;
        p->ran = 0;
    }
}

int pl_timers_count(const pl_timers *t) { return t ? t->nphases : 0; }
const char *pl_timers_name(const pl_timers *t, int id) { return t->phases[id].name; }
int pl_timers_samples(const pl_timers *t, int id) { return t->phases[id].nsamples; }

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double pl_timers_median_ms(const pl_timers *t, int id)
{
    const phase *p = &t->phases[id];
    if (p->nsamples == 0) return NAN;
    double *s = malloc((size_t)p->nsamples * sizeof *s);
    if (!s) return NAN;
    memcpy(s, p->samples, (size_t)p->nsamples * sizeof *s);
    qsort(s, (size_t)p->nsamples, sizeof *s, cmp_double);
    int n = p->nsamples;
    double m = (n % 2) ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    free(s);
    return 1e3 * m;
}

double pl_timers_max_ms(const pl_timers *t, int id)
{
    const phase *p = &t->phases[id];
    double m = 0.0;
    for (int k = 0; k < p->nsamples; ++k)
        if (p->samples[k] > m) m = p->samples[k];
    return p->nsamples ? 1e3 * m : NAN;
}

double pl_timers_total_ms(const pl_timers *t, int id)
{
    const phase *p = &t->phases[id];
    double s = 0.0;
    for (int k = 0; k < p->nsamples; ++k) s += p->samples[k];
    return 1e3 * s;
}

static named_values *find_named(named_values **arr, int *n, int *cap, const char *name, int create)
{
    for (int k = 0; k < *n; ++k)
        if (!strcmp((*arr)[k].name, name)) return &(*arr)[k];
    if (!create) return NULL;
    if (*n == *cap) {
        int c = *cap ? 2 * *cap : 16;
        named_values *a = realloc(*arr, (size_t)c * sizeof *a);
        if (!a) return NULL;
        *arr = a;
        *cap = c;
    }
    named_values *v = &(*arr)[*n];
    memset(v, 0, sizeof *v);
    if (!(v->name = strdup(name))) return NULL;
    (*n)++;
    return v;
}

static void push_value(named_values *v, double x)
{
    if (v->n == v->cap) {
        int c = v->cap ? 2 * v->cap : 16;
        double *a = realloc(v->v, (size_t)c * sizeof *a);
        if (!a) return;
        v->v = a;
        v->cap = c;
    }
    v->v[v->n++] = x;
}

void pl_stat_set(pl_timers *t, const char *name, double value)
{
    if (!t) return;
    named_values *v = find_named(&t->stats, &t->nstats, &t->cap_stats, name, 1);
    if (!v) return;
    v->n = 0;
    push_value(v, value);
}

void pl_stat_max(pl_timers *t, const char *name, double value)
{
    if (!t) return;
    named_values *v = find_named(&t->stats, &t->nstats, &t->cap_stats, name, 1);
    if (!v) return;
    if (!v->n || v->v[0] < value) {
        v->n = 0;
        push_value(v, value);
    }
    if (!v->per_frame || v->frame < value) v->frame = value;
    v->per_frame = 1;
}

int pl_stat_get(const pl_timers *t, const char *name, double *value)
{
    for (int k = 0; t && k < t->nstats; ++k)
        if (!strcmp(t->stats[k].name, name) && t->stats[k].n) {
            *value = t->stats[k].v[0];
            return 0;
        }
    return -1;
}

void pl_series_push(pl_timers *t, const char *name, double value)
{
    if (!t) return;
    named_values *v = find_named(&t->series, &t->nseries, &t->cap_series, name, 1);
    if (v) push_value(v, value);
}

int pl_series_get(const pl_timers *t, const char *name, const double **values)
{
    for (int k = 0; t && k < t->nseries; ++k)
        if (!strcmp(t->series[k].name, name)) {
            *values = t->series[k].v;
            return t->series[k].n;
        }
    *values = NULL;
    return 0;
}

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\') fputc('\\', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

static void json_number(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.9g", x);
    else
        fputs("null", f);
}

int pl_timers_write_json(const pl_timers *t, FILE *f)
{
    fputs("{\n  \"phases\": {", f);
    for (int k = 0; k < t->nphases; ++k) {
        fputs(k ? ",\n    " : "\n    ", f);
        json_string(f, t->phases[k].name);
        fputs(": {\"median_ms\": ", f);
        json_number(f, pl_timers_median_ms(t, k));
        fputs(", \"max_ms\": ", f);
        json_number(f, pl_timers_max_ms(t, k));
        fputs(", \"total_ms\": ", f);
        json_number(f, pl_timers_total_ms(t, k));
        fprintf(f, ", \"samples\": %d}", t->phases[k].nsamples);
    }
    fputs("\n  },\n  \"stats\": {", f);
    for (int k = 0; k < t->nstats; ++k) {
        fputs(k ? ",\n    " : "\n    ", f);
        json_string(f, t->stats[k].name);
        fputs(": ", f);
        json_number(f, t->stats[k].n ? t->stats[k].v[0] : NAN);
    }
    fputs("\n  },\n  \"series\": {", f);
    for (int k = 0; k < t->nseries; ++k) {
        fputs(k ? ",\n    " : "\n    ", f);
        json_string(f, t->series[k].name);
        fputs(": [", f);
        for (int i = 0; i < t->series[k].n; ++i) {
            if (i) fputs(", ", f);
            json_number(f, t->series[k].v[i]);
        }
        fputs("]", f);
    }
    fputs("\n  },\n  \"frames\": {", f);
    fprintf(f, "\n    \"count\": %d", t->nframes);
    for (int k = 0; k < t->nframe_cols; ++k) {
        fputs(",\n    ", f);
        json_string(f, t->frames[k].name);
        fputs(": [", f);
        for (int i = 0; i < t->nframes; ++i) {
            if (i) fputs(", ", f);
            json_number(f, i < t->frames[k].n ? t->frames[k].v[i] : 0.0);
        }
        fputs("]", f);
    }
    fputs("\n  }\n}\n", f);
    return ferror(f) ? -1 : 0;
}

void pl_timers_print(const pl_timers *t, FILE *f)
{
    fprintf(f, "%-22s %10s %10s %8s\n", "phase", "median ms", "max ms", "frames");
    for (int k = 0; k < t->nphases; ++k)
        fprintf(f, "%-22s %10.3f %10.3f %8d\n", t->phases[k].name, pl_timers_median_ms(t, k),
                pl_timers_max_ms(t, k), t->phases[k].nsamples);
    for (int k = 0; k < t->nstats; ++k)
        fprintf(f, "%-22s %10.6g\n", t->stats[k].name, t->stats[k].n ? t->stats[k].v[0] : NAN);
}
