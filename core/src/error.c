/* error.c - pl_error values and the pl_diag list. */
#include "pliant/error.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void pl_error_clear(pl_error *e)
{
    if (e) memset(e, 0, sizeof *e);
}

int pl_error_vset(pl_error *e, int code, const char *file, int line, const char *where,
                  const char *fmt, va_list ap)
{
    if (!e) return code;
    e->code = code;
    snprintf(e->file, sizeof e->file, "%s", file ? file : "");
    e->line = line;
    snprintf(e->where, sizeof e->where, "%s", where ? where : "");
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    return code;
}

int pl_error_set(pl_error *e, int code, const char *file, int line, const char *where,
                 const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    pl_error_vset(e, code, file, line, where, fmt, ap);
    va_end(ap);
    return code;
}

const char *pl_error_format(const pl_error *e, char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = '\0';
    if (e->file[0]) {
        n += (size_t)snprintf(buf + n, size - n, e->line > 0 ? "%s:%d: " : "%s: ", e->file,
                              e->line);
        if (n >= size) return buf;
    }
    if (e->where[0]) {
        n += (size_t)snprintf(buf + n, size - n, "%s: ", e->where);
        if (n >= size) return buf;
    }
    snprintf(buf + n, size - n, "%s", e->msg);
    return buf;
}

void pl_diag_init(pl_diag *d)
{
    memset(d, 0, sizeof *d);
}

void pl_diag_free(pl_diag *d)
{
    free(d->items);
    memset(d, 0, sizeof *d);
}

void pl_diag_add(pl_diag *d, const pl_error *e)
{
    if (!d) return;
    if (d->count == d->cap) {
        int cap = d->cap ? 2 * d->cap : 8;
        pl_error *items = realloc(d->items, (size_t)cap * sizeof *items);
        if (!items) { /* keep counting errors even when we cannot store them */
            if (e->code != PL_OK) d->nerrors++;
            return;
        }
        d->items = items;
        d->cap = cap;
    }
    d->items[d->count++] = *e;
    if (e->code != PL_OK) d->nerrors++;
}

int pl_diag_error(pl_diag *d, int code, const char *file, int line, const char *where,
                  const char *fmt, ...)
{
    pl_error e;
    va_list ap;
    va_start(ap, fmt);
    pl_error_vset(&e, code, file, line, where, fmt, ap);
    va_end(ap);
    pl_diag_add(d, &e);
    return code;
}

void pl_diag_warn(pl_diag *d, const char *file, int line, const char *where, const char *fmt,
                  ...)
{
    pl_error e;
    va_list ap;
    va_start(ap, fmt);
    pl_error_vset(&e, PL_OK, file, line, where, fmt, ap);
    va_end(ap);
    pl_diag_add(d, &e);
}

void pl_diag_print(const pl_diag *d, void *stream)
{
    FILE *f = stream ? (FILE *)stream : stderr;
    for (int k = 0; k < d->count; ++k) {
        const pl_error *e = &d->items[k];
        if (e->file[0]) fprintf(f, e->line > 0 ? "%s:%d: " : "%s: ", e->file, e->line);
        fprintf(f, "%s: ", e->code != PL_OK ? "error" : "warning");
        if (e->where[0]) fprintf(f, "%s: ", e->where);
        fprintf(f, "%s\n", e->msg);
    }
}

int pl_diag_status(const pl_diag *d)
{
    for (int k = 0; k < d->count; ++k)
        if (d->items[k].code != PL_OK) return d->items[k].code;
    return d->nerrors ? PL_EINTERNAL : PL_OK;
}
