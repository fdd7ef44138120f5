/* state_file_read.c - reading SOFA WriteState files (plain or gzip) into
 * records.  The format, as SOFA writes it and as regression references
 * store it:
 *     T= 0
 *       X= x0 y0 z0 x1 y1 z1 ...
 *       V= ...
 *     T= 0.02
 *     ...
 * zlib's gzopen reads uncompressed files transparently, so one path serves
 * both. */
#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "export/export.h"

void pl_state_records_init(pl_state_records *r)
{
    memset(r, 0, sizeof *r);
}

void pl_state_records_free(pl_state_records *r)
{
    if (!r) return;
    for (int i = 0; i < r->count; ++i) {
        free(r->items[i].x);
        free(r->items[i].v);
    }
    free(r->items);
    pl_state_records_init(r);
}

/* A new zeroed record at the end, or NULL when out of memory. */
static pl_state_record *push_record(pl_state_records *r, double time)
{
    if (r->count == r->cap) {
        if (r->cap > INT_MAX / 2) return NULL;
        int cap = r->cap ? 2 * r->cap : 16;
        pl_state_record *items = realloc(r->items, (size_t)cap * sizeof *items);
        if (!items) return NULL;
        r->items = items;
        r->cap = cap;
    }
    pl_state_record *rec = &r->items[r->count++];
    memset(rec, 0, sizeof *rec);
    rec->time = time;
    return rec;
}

static double *copy_doubles(const double *v, int n)
{
    double *c = malloc((size_t)(n > 0 ? n : 1) * sizeof *c);
    if (c && n > 0) memcpy(c, v, (size_t)n * sizeof *c);
    return c;
}

int pl_state_records_add(pl_state_records *r, double time, const double *x, int nx,
                         const double *v, int nv, pl_error *err)
{
    if (!r || nx < 0 || nv < 0 || (nx && !x) || (nv && !v))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "invalid state record");
    pl_state_record *rec = push_record(r, time);
    if (!rec) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    if (x) rec->x = copy_doubles(x, nx);
    if (v) rec->v = copy_doubles(v, nv);
    rec->nx = x ? nx : 0;
    rec->nv = v ? nv : 0;
    if ((x && !rec->x) || (v && !rec->v))
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    return PL_OK;
}

/* ---- lines of any length from a gzFile ----------------------------------- */

typedef struct line_reader {
    gzFile gz;
    char *buf;
    size_t cap;
    int lineno;
} line_reader;

/* 1: a line is in buf (without its end of line); 0: end of file; <0: error. */
static int read_line(line_reader *lr)
{
    size_t n = 0;
    for (;;) {
        if (lr->cap - n < 2) {
            size_t cap = lr->cap ? 2 * lr->cap : 4096;
            char *b = realloc(lr->buf, cap);
            if (!b) return -2;
            lr->buf = b;
            lr->cap = cap;
        }
        size_t room = lr->cap - n;
        if (room > INT_MAX) room = INT_MAX;
        if (!gzgets(lr->gz, lr->buf + n, (int)room)) {
            int code;
            gzerror(lr->gz, &code);
            if (code != Z_OK && code != Z_STREAM_END) return -1;
            if (n == 0) return 0;
            break;
        }
        n += strlen(lr->buf + n);
        if (n > 0 && lr->buf[n - 1] == '\n') break;
    }
    while (n > 0 && (lr->buf[n - 1] == '\n' || lr->buf[n - 1] == '\r')) lr->buf[--n] = '\0';
    lr->lineno++;
    return 1;
}

/* ---- parsing ------------------------------------------------------------- */

/* Parses the whitespace-separated numbers of p into a new array. */
static int parse_numbers(const char *p, double **out, int *count, const char *path, int line,
                         pl_error *err)
{
    double *v = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        while (isspace((unsigned char)*p)) ++p;
        if (!*p) break;
        char *end;
        double d = strtod(p, &end);
        if (end == p || (*end && !isspace((unsigned char)*end))) {
            int len = 0;
            while (p[len] && !isspace((unsigned char)p[len]) && len < 40) ++len;
            free(v);
            return pl_error_set(err, PL_EINPUT, path, line, NULL,
                                "expected a number, found '%.*s'", len, p);
        }
        if (!isfinite(d)) { /* a reference must be a state, not a NaN to compare with */
            free(v);
            return pl_error_set(err, PL_EINPUT, path, line, NULL,
                                "value %zu is '%.*s': expected a finite number", n + 1,
                                (int)(end - p < 40 ? end - p : 40), p);
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            double *g = cap > INT_MAX ? NULL : realloc(v, cap * sizeof *g);
            if (!g) {
                free(v);
                return pl_error_set(err, PL_EINTERNAL, path, line, NULL, "out of memory");
            }
            v = g;
        }
        v[n++] = d;
        p = end;
    }
    *out = v;
    *count = (int)n;
    return PL_OK;
}

/* One non-empty line "KEY= values". */
static int parse_line(char *s, pl_state_records *out, int first_record, const char *path,
                      int line, pl_error *err)
{
    char *key = s;
    while (isalnum((unsigned char)*s) || *s == '_') ++s;
    if (s == key || *s != '=')
        return pl_error_set(err, PL_EINPUT, path, line, NULL,
                            "expected 'T= <time>' or 'X= <values>', found '%.40s'", key);
    size_t keylen = (size_t)(s - key);
    ++s;
    if (keylen == 1 && key[0] == 'T') {
        double *t = NULL;
        int n = 0;
        int rc = parse_numbers(s, &t, &n, path, line, err);
        if (rc != PL_OK) return rc;
        double time = n == 1 ? t[0] : 0.0;
        free(t);
        if (n != 1)
            return pl_error_set(err, PL_EINPUT, path, line, NULL,
                                "'T=' takes one time, found %d numbers", n);
        return push_record(out, time) ? PL_OK
                                      : pl_error_set(err, PL_EINTERNAL, path, line, NULL,
                                                     "out of memory");
    }
    int is_x = keylen == 1 && key[0] == 'X', is_v = keylen == 1 && key[0] == 'V';
    if (!is_x && !is_v) return PL_OK; /* X0=, F=, ...: not needed here */
    if (out->count <= first_record)
        return pl_error_set(err, PL_EINPUT, path, line, NULL, "'%c=' before any 'T=' line",
                            key[0]);
    pl_state_record *rec = &out->items[out->count - 1];
    if (is_x ? rec->x != NULL : rec->v != NULL)
        return pl_error_set(err, PL_EINPUT, path, line, NULL,
                            "a second '%c=' line in the record of T= %g", key[0], rec->time);
    return parse_numbers(s, is_x ? &rec->x : &rec->v, is_x ? &rec->nx : &rec->nv, path, line,
                         err);
}

int pl_state_file_read(const char *path, pl_state_records *out, pl_error *err)
{
    if (!path || !out) return pl_error_set(err, PL_EINPUT, path, 0, NULL, "invalid arguments");
    line_reader lr = {0};
    lr.gz = gzopen(path, "rb");
    if (!lr.gz) return pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot open the state file");
    int first = out->count, rc = PL_OK, got;
    while ((got = read_line(&lr)) > 0) {
        char *s = lr.buf;
        while (isspace((unsigned char)*s)) ++s;
        if (!*s) continue;
        rc = parse_line(s, out, first, path, lr.lineno, err);
        if (rc != PL_OK) break;
    }
    if (rc == PL_OK && got == -2)
        rc = pl_error_set(err, PL_EINTERNAL, path, lr.lineno + 1, NULL, "out of memory");
    else if (rc == PL_OK && got < 0)
        rc = pl_error_set(err, PL_EINPUT, path, lr.lineno + 1, NULL,
                          "corrupt or truncated gzip data");
    gzclose(lr.gz);
    free(lr.buf);
    return rc;
}
