/* gpu_kprof.c - device time of every kernel of an unmodified run, for
 * machines without nsys: a CUPTI injection library (a benchmark tool, not a
 * test).  The CUDA driver loads it at cuInit when named by
 * CUDA_INJECTION64_PATH; it records each kernel's start and end on the
 * device (also kernels replayed from CUDA graphs) and, at exit, writes one
 * table row per kernel: launches, median, mean and total device time.
 *
 *   CUDA_INJECTION64_PATH=build/lib/libgpu_kprof.so GPU_KPROF_OUT=k.md \
 *     build/bin/pliant run scenes/stick_slip.xml -n 150 --device gpu-always
 *
 * GPU_KPROF_OUT: the table's file (default: standard error).  Tracing adds
 * a little host time to each launch, so frame times come from runs
 * without it; the kernels' own times are the device's.
 *
 * GPU_KPROF_TIMELINE (a file): also every kernel (k), memset (s), memory
 * copy (c) and CUDA runtime call of the host (r: launches, copies, waits;
 * CUPTI's clock is one for both), in start order ("start_us end_us kind
 * name", the first record's start as 0), to find the gaps between them:
 * host work, waits and launch latencies that no kernel's time shows. */
#include <cupti.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct kstat {
    char *name;     /* as CUPTI gives it (mangled for C++ kernels) */
    double *us;     /* durations, microseconds */
    size_t n, cap;
} kstat;

static kstat *stats;
static size_t nstats, capstats;

/* The timeline's records (GPU_KPROF_TIMELINE): name points into stats. */
typedef struct event {
    uint64_t start, end;
    char kind; /* k kernel, s memset, c copy, r runtime call */
    const char *name;
} event;
static event *events;
static size_t nevents, capevents;
static int timeline; /* GPU_KPROF_TIMELINE set */
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

enum { BUF_BYTES = 8 << 20 };

static void CUPTIAPI buffer_requested(uint8_t **buf, size_t *size, size_t *max_records)
{
    *buf = aligned_alloc(8, BUF_BYTES);
    *size = *buf ? BUF_BYTES : 0;
    *max_records = 0;
}

static kstat *find(const char *name)
{
    for (size_t i = 0; i < nstats; ++i)
        if (!strcmp(stats[i].name, name)) return &stats[i];
    if (nstats == capstats) {
        size_t c = capstats ? 2 * capstats : 64;
        kstat *s = realloc(stats, c * sizeof *s);
        if (!s) return NULL;
        stats = s, capstats = c;
    }
    kstat *k = &stats[nstats];
    memset(k, 0, sizeof *k);
    if (!(k->name = strdup(name))) return NULL;
    ++nstats;
    return k;
}

static void add_event(uint64_t start, uint64_t end, char kind, const char *name)
{
    if (nevents == capevents) {
        size_t c = capevents ? 2 * capevents : 4096;
        event *e = realloc(events, c * sizeof *e);
        if (!e) return;
        events = e, capevents = c;
    }
    events[nevents++] = (event){start, end, kind, name};
}

static void add(const char *name, double us, uint64_t start, uint64_t end)
{
    kstat *k = find(name ? name : "?");
    if (!k) return;
    if (timeline) add_event(start, end, 'k', k->name);
    if (k->n == k->cap) {
        size_t c = k->cap ? 2 * k->cap : 256;
        double *u = realloc(k->us, c * sizeof *u);
        if (!u) return;
        k->us = u, k->cap = c;
    }
    k->us[k->n++] = us;
}

static void CUPTIAPI buffer_completed(CUcontext ctx, uint32_t stream, uint8_t *buf, size_t size,
                                      size_t valid)
{
    (void)ctx, (void)stream, (void)size;
    CUpti_Activity *rec = NULL;
    pthread_mutex_lock(&lock);
    while (cuptiActivityGetNextRecord(buf, valid, &rec) == CUPTI_SUCCESS)
        if (rec->kind == CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL ||
            rec->kind == CUPTI_ACTIVITY_KIND_KERNEL) {
            const CUpti_ActivityKernel10 *k = (const CUpti_ActivityKernel10 *)rec;
            add(k->name, (double)(k->end - k->start) * 1e-3, k->start, k->end);
        } else if (rec->kind == CUPTI_ACTIVITY_KIND_MEMSET) {
            const CUpti_ActivityMemset4 *m = (const CUpti_ActivityMemset4 *)rec;
            add_event(m->start, m->end, 's', "memset");
        } else if (rec->kind == CUPTI_ACTIVITY_KIND_RUNTIME) {
            const CUpti_ActivityAPI *a = (const CUpti_ActivityAPI *)rec;
            const char *nm = NULL;
            if (cuptiGetCallbackName(CUPTI_CB_DOMAIN_RUNTIME_API, a->cbid, &nm) != CUPTI_SUCCESS)
                nm = NULL;
            kstat *k = find(nm ? nm : "runtime"); /* names interned there, no times added */
            if (k) add_event(a->start, a->end, 'r', k->name);
        } else if (rec->kind == CUPTI_ACTIVITY_KIND_MEMCPY) {
            const CUpti_ActivityMemcpy6 *m = (const CUpti_ActivityMemcpy6 *)rec;
            add_event(m->start, m->end, 'c',
                      m->copyKind == CUPTI_ACTIVITY_MEMCPY_KIND_HTOD   ? "copy HtoD"
                      : m->copyKind == CUPTI_ACTIVITY_MEMCPY_KIND_DTOH ? "copy DtoH"
                                                                      : "copy");
        }
    pthread_mutex_unlock(&lock);
    free(buf);
}

/* The function's own identifier from an Itanium-mangled name
 * (_ZN<len>id...<len>idE...: the last id), else the name itself. */
static void short_name(const char *name, char *out, size_t cap)
{
    const char *p = name, *best = NULL;
    size_t blen = 0;
    if (!strncmp(p, "_Z", 2)) {
        p += 2;
        if (*p == 'N') ++p;
        while (*p >= '0' && *p <= '9') {
            size_t len = strtoul(p, (char **)&p, 10);
            if (strlen(p) < len) break;
            best = p, blen = len;
            p += len;
        }
    }
    if (!best) best = name, blen = strlen(name);
    if (blen >= cap) blen = cap - 1;
    memcpy(out, best, blen);
    out[blen] = '\0';
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int cmp_total(const void *a, const void *b)
{
    const kstat *x = a, *y = b;
    double tx = 0.0, ty = 0.0;
    for (size_t i = 0; i < x->n; ++i) tx += x->us[i];
    for (size_t i = 0; i < y->n; ++i) ty += y->us[i];
    return (tx < ty) - (tx > ty);
}

static int cmp_start(const void *a, const void *b)
{
    const event *x = a, *y = b;
    return (x->start > y->start) - (x->start < y->start);
}

static void write_timeline(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) return;
    qsort(events, nevents, sizeof *events, cmp_start);
    const uint64_t t0 = nevents ? events[0].start : 0;
    for (size_t i = 0; i < nevents; ++i) {
        char nm[96];
        short_name(events[i].name, nm, sizeof nm);
        fprintf(f, "%.3f %.3f %c %s\n", (double)(events[i].start - t0) * 1e-3,
                (double)(events[i].end - t0) * 1e-3, events[i].kind, nm);
    }
    fclose(f);
}

static void report(void)
{
    cuptiActivityFlushAll(1);
    pthread_mutex_lock(&lock);
    if (timeline) write_timeline(getenv("GPU_KPROF_TIMELINE"));
    const char *path = getenv("GPU_KPROF_OUT");
    FILE *f = path && *path ? fopen(path, "w") : stderr;
    if (!f) f = stderr;
    qsort(stats, nstats, sizeof *stats, cmp_total);
    fprintf(f, "| kernel | launches | median us | mean us | total ms |\n|---|--:|--:|--:|--:|\n");
    for (size_t i = 0; i < nstats; ++i) {
        kstat *k = &stats[i];
        if (!k->n) continue; /* a runtime call's name (the timeline's) */
        double tot = 0.0;
        for (size_t j = 0; j < k->n; ++j) tot += k->us[j];
        qsort(k->us, k->n, sizeof *k->us, cmp_double);
        double med = k->n % 2 ? k->us[k->n / 2] : 0.5 * (k->us[k->n / 2 - 1] + k->us[k->n / 2]);
        char nm[96];
        short_name(k->name, nm, sizeof nm);
        fprintf(f, "| %s | %zu | %.2f | %.2f | %.3f |\n", nm, k->n, med, tot / (double)k->n,
                tot * 1e-3);
    }
    if (f != stderr) fclose(f);
    pthread_mutex_unlock(&lock);
}

/* Called by the CUDA driver (CUDA_INJECTION64_PATH) during cuInit. */
__attribute__((visibility("default"))) int InitializeInjection(void)
{
    if (cuptiActivityRegisterCallbacks(buffer_requested, buffer_completed) != CUPTI_SUCCESS ||
        cuptiActivityEnable(CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL) != CUPTI_SUCCESS) {
        fprintf(stderr, "gpu_kprof: CUPTI activity tracing refused\n");
        return 0;
    }
    const char *tl = getenv("GPU_KPROF_TIMELINE");
    if (tl && *tl && (cuptiActivityEnable(CUPTI_ACTIVITY_KIND_MEMSET) != CUPTI_SUCCESS ||
                      cuptiActivityEnable(CUPTI_ACTIVITY_KIND_MEMCPY) != CUPTI_SUCCESS ||
                      cuptiActivityEnable(CUPTI_ACTIVITY_KIND_RUNTIME) != CUPTI_SUCCESS))
        fprintf(stderr, "gpu_kprof: no memset, copy or runtime records for the timeline\n");
    timeline = tl && *tl;
    atexit(report);
    return 1;
}
