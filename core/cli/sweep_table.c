/* sweep_table.c - what a sweep keeps on disk: the request (OUT/sweep.txt,
 * so that a resumed sweep is the same sweep), the completed runs
 * (run_NNNN/result.txt) and the tables (sweep.csv, sweep.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_jobs.h"
#include "sweep.h"

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, n = 0, k;
    char *b = malloc(cap);
    while (b && (k = fread(b + n, 1, cap - n - 1, f)) > 0) {
        n += k;
        if (cap - n < 2) {
            char *nb = realloc(b, cap *= 2);
            if (!nb) free(b);
            b = nb;
        }
    }
    fclose(f);
    if (b) b[n] = '\0';
    return b;
}

static char *spec_text(const sweep *s)
{
    size_t cap = 256 + strlen(s->scene);
    for (int a = 0; a < s->naxes; ++a) cap += strlen(s->axes[a].path) + strlen(s->axes[a].spec) + 8;
    for (int k = 0; k < s->nrecords; ++k) cap += strlen(s->records[k]) + 8;
    char *t = malloc(cap);
    if (!t) return NULL;
    size_t n = (size_t)snprintf(t, cap, "# pliant sweep: what this folder holds\nscene %s\n"
                                        "steps %d\n", s->scene, s->steps);
    for (int a = 0; a < s->naxes; ++a)
        n += (size_t)snprintf(t + n, cap - n, "set %s=%s\n", s->axes[a].path, s->axes[a].spec);
    for (int k = 0; k < s->nrecords; ++k)
        n += (size_t)snprintf(t + n, cap - n, "record %s\n", s->records[k]);
    return t;
}

int sweep_spec_check(const sweep *s)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/sweep.txt", s->out);
    char *want = spec_text(s), *have = slurp(path);
    int rc = 0;
    if (!want) {
        rc = 1;
    } else if (have && strcmp(have, want)) {
        fprintf(stderr, "pliant sweep: %s holds another sweep (%s differs: scene, steps, --set "
                        "or --record); give another --out, or remove it to start again\n",
                s->out, path);
        rc = 2;
    } else if (!have) {
        FILE *f = fopen(path, "w");
        if (!f || fputs(want, f) < 0 || fclose(f) != 0) {
            fprintf(stderr, "pliant sweep: cannot write %s\n", path);
            rc = 2;
        }
    }
    free(want);
    free(have);
    return rc;
}

char *sweep_completed(const sweep *s, int run)
{
    char path[1200], dir[1100], buf[64];
    sweep_run_dir(s, run, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/result.txt", dir);
    char *r = slurp(path);
    const char *st = r ? cli_report_get(r, "status", buf, sizeof buf) : NULL;
    if (st && !strcmp(st, "ok")) return r;
    free(r);
    return NULL;
}

/* A CSV field, quoted when it holds a comma, a quote or a space. */
static void csv(FILE *f, const char *v, int last)
{
    if (strpbrk(v, ",\" ")) {
        fputc('"', f);
        for (; *v; ++v) {
            if (*v == '"') fputc('"', f);
            fputc(*v, f);
        }
        fputc('"', f);
    } else {
        fputs(v, f);
    }
    fputc(last ? '\n' : ',', f);
}

static void md(FILE *f, const char *v, int last)
{
    fputs(" ", f);
    for (; *v; ++v) {
        if (*v == '|') fputc('\\', f);
        fputc(*v, f);
    }
    fputs(last ? " |\n" : " |", f);
}

typedef void (*cell_fn)(FILE *f, const char *v, int last);

static void header(FILE *f, const sweep *s, cell_fn cell, int markdown)
{
    if (markdown) fputs("|", f);
    cell(f, "run", 0);
    for (int a = 0; a < s->naxes; ++a) cell(f, s->axes[a].path, 0);
    for (int k = 0; k < s->nrecords; ++k) cell(f, s->records[k], 0);
    cell(f, "steps", 0);
    cell(f, markdown ? "ms/step" : "ms_per_step", 0);
    cell(f, "status", 0);
    cell(f, "message", 1);
    if (!markdown) return;
    fputs("|", f);
    for (int k = 0; k < 3 + s->naxes + s->nrecords; ++k) fputs(k ? " --: |" : " --- |", f);
    fputs(" --- | --- |\n", f);
}

static void row(FILE *f, const sweep *s, int run, const char *rep, const char *status,
                cell_fn cell, int markdown)
{
    char buf[1 << 12], key[32];
    char *big = malloc(1 << 20);
    if (markdown) fputs("|", f);
    snprintf(buf, sizeof buf, "%04d", run);
    cell(f, buf, 0);
    for (int a = 0; a < s->naxes; ++a) cell(f, sweep_value(s, run, a), 0);
    for (int k = 0; k < s->nrecords; ++k) {
        snprintf(key, sizeof key, "rec %d", k);
        const char *v = big && rep ? cli_report_get(rep, key, big, 1 << 20) : NULL;
        cell(f, v ? v : "", 0);
    }
    cell(f, rep && cli_report_get(rep, "steps", buf, sizeof buf) ? buf : "", 0);
    double ms = rep && cli_report_get(rep, "ms", buf, sizeof buf) ? atof(buf) : 0;
    snprintf(buf, sizeof buf, "%.3f", ms);
    cell(f, rep ? buf : "", 0);
    cell(f, status, 0);
    cell(f, rep && cli_report_get(rep, "msg", buf, sizeof buf) ? buf : "", 1);
    free(big);
}

int sweep_write_tables(const sweep *s, char *const *reports, char *const *status)
{
    char path[1100];
    int rc = 0;
    for (int markdown = 0; markdown < 2; ++markdown) {
        snprintf(path, sizeof path, "%s/sweep.%s", s->out, markdown ? "md" : "csv");
        FILE *f = fopen(path, "w");
        if (!f) {
            fprintf(stderr, "pliant sweep: cannot write %s\n", path);
            rc = 1;
            continue;
        }
        cell_fn cell = markdown ? md : csv;
        header(f, s, cell, markdown);
        for (int r = 0; r < s->nruns; ++r)
            row(f, s, r, reports[r], status[r] ? status[r] : "not run", cell, markdown);
        if (fclose(f) != 0) rc = 1;
    }
    return rc;
}
