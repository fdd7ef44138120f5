/* state_writer.c - writing SOFA WriteState files, records of
 *     T= <time>
 *       X= x0 y0 z0 ...
 *       V= ...
 * with %.17g so that a reader gets back the very same doubles.  Output goes
 * through zlib: gzip-compressed for "*.gz" (as SOFA does), "transparent"
 * (plain text) otherwise. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "export/export.h"

struct pl_state_writer {
    gzFile gz;
    char *path;
    char buf[8192];   /* text waiting for gzwrite */
    size_t n;
    int failed;
};

static void flush_buf(pl_state_writer *w)
{
    if (w->n && gzwrite(w->gz, w->buf, (unsigned)w->n) != (int)w->n) w->failed = 1;
    w->n = 0;
}

static void put_text(pl_state_writer *w, const char *s, size_t len)
{
    if (w->n + len > sizeof w->buf) flush_buf(w);
    memcpy(w->buf + w->n, s, len);
    w->n += len;
}

static void put_number(pl_state_writer *w, double v, int leading_space)
{
    char num[40];
    int len = snprintf(num, sizeof num, leading_space ? " %.17g" : "%.17g", v);
    put_text(w, num, (size_t)len);
}

static void put_values(pl_state_writer *w, const char *key, const double *v, int n)
{
    put_text(w, key, strlen(key));
    for (int i = 0; i < n; ++i) put_number(w, v[i], i > 0);
    put_text(w, "\n", 1);
}

static int ends_with_gz(const char *path)
{
    size_t n = strlen(path);
    return n >= 3 && strcmp(path + n - 3, ".gz") == 0;
}

pl_state_writer *pl_state_writer_open(const char *path, int append, pl_error *err)
{
    if (!path || !*path) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "a state file needs a file name");
        return NULL;
    }
    pl_state_writer *w = calloc(1, sizeof *w);
    if (w) w->path = strdup(path);
    if (!w || !w->path) {
        free(w);
        pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "out of memory");
        return NULL;
    }
    const char *mode = ends_with_gz(path) ? (append ? "ab" : "wb") : (append ? "aT" : "wT");
    w->gz = gzopen(path, mode);
    if (!w->gz) {
        pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot write the state file");
        free(w->path);
        free(w);
        return NULL;
    }
    return w;
}

int pl_state_writer_write(pl_state_writer *w, double time, const double *x, int nx,
                          const double *v, int nv, pl_error *err)
{
    if (!w || (x && nx < 0) || (v && nv < 0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "invalid state record");
    put_text(w, "T= ", 3);
    put_number(w, time, 0);
    put_text(w, "\n", 1);
    if (x) put_values(w, "  X= ", x, nx);
    if (v) put_values(w, "  V= ", v, nv);
    flush_buf(w);
    if (w->failed)
        return pl_error_set(err, PL_EINTERNAL, w->path, 0, NULL, "writing the state file failed");
    return PL_OK;
}

int pl_state_writer_close(pl_state_writer *w, pl_error *err)
{
    if (!w) return PL_OK;
    flush_buf(w);
    int rc = PL_OK;
    if (gzclose(w->gz) != Z_OK || w->failed)
        rc = pl_error_set(err, PL_EINTERNAL, w->path, 0, NULL, "writing the state file failed");
    free(w->path);
    free(w);
    return rc;
}
