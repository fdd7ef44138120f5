/* mesh_text.c - the pl_text cursor: tokens, numbers with messages, files. */
#include "mesh_io.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>


void pl_io_text_init(pl_text *t, const char *path, const char *buf, size_t size, int first_line,
                     pl_diag *diag)
{
    t->path = path;
    t->buf = buf;
    t->size = size;
    t->pos = 0;
    t->line = first_line;
    t->diag = diag;
}

static int fail_v(pl_text *t, int line, const char *fmt, va_list ap)
{
    pl_error e;
    pl_error_vset(&e, PL_EINPUT, t->path, line, NULL, fmt, ap);
    pl_diag_add(t->diag, &e);
    return PL_EINPUT;
}

int pl_io_fail(pl_text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fail_v(t, t->line, fmt, ap);
    va_end(ap);
    return PL_EINPUT;
}

int pl_io_fail_at(pl_text *t, int line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fail_v(t, line, fmt, ap);
    va_end(ap);
    return PL_EINPUT;
}

int pl_io_nomem(pl_text *t)
{
    return pl_diag_error(t->diag, PL_EINTERNAL, t->path, t->line, NULL,
                         "out of memory while reading the mesh");
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

void pl_io_skip_ws(pl_text *t)
{
    while (t->pos < t->size) {
        char c = t->buf[t->pos];
        if (c == '\n') t->line++;
        else if (!is_blank(c)) break;
        t->pos++;
    }
}

void pl_io_skip_blank(pl_text *t)
{
    while (t->pos < t->size && is_blank(t->buf[t->pos])) t->pos++;
}

int pl_io_at_eol(pl_text *t)
{
    pl_io_skip_blank(t);
    return t->pos >= t->size || t->buf[t->pos] == '\n';
}

int pl_io_at_eof(pl_text *t)
{
    pl_io_skip_ws(t);
    return t->pos >= t->size;
}

void pl_io_next_line(pl_text *t)
{
    const char *nl = memchr(t->buf + t->pos, '\n', t->size - t->pos);
    if (!nl) {
        t->pos = t->size;
        return;
    }
    t->pos = (size_t)(nl - t->buf) + 1;
    t->line++;
}

int pl_io_token(pl_text *t, char *tok, size_t cap, int same_line)
{
    if (same_line) pl_io_skip_blank(t);
    else pl_io_skip_ws(t);
    size_t start = t->pos;
    while (t->pos < t->size) {
        char c = t->buf[t->pos];
        if (c == '\n' || is_blank(c)) break;
        t->pos++;
    }
    size_t len = t->pos - start;
    if (len >= cap) return -1;
    memcpy(tok, t->buf + start, len);
    tok[len] = '\0';
    return (int)len;
}

int pl_io_parse_int(const char *tok, long long *v)
{
    char *end;
    errno = 0;
    long long x = strtoll(tok, &end, 10);
    if (end == tok || *end != '\0' || errno == ERANGE) return -1;
    *v = x;
    return 0;
}

int pl_io_parse_double(const char *tok, double *v)
{
    char *end;
    errno = 0;
    double x = strtod(tok, &end);
    if (end == tok || *end != '\0') return -1;
    /* ERANGE on underflow gives a usable denormal or zero; on overflow it
     * gives inf, which the finiteness check below refuses. */
    *v = x;
    return 0;
}

/* Shared front half of the number readers: fetches one token or fails. */
static int number_token(pl_text *t, char *tok, size_t cap, const char *what, int same_line)
{
    int n = pl_io_token(t, tok, cap, same_line);
    if (n < 0) return pl_io_fail(t, "expected %s, found an overlong token", what);
    if (n == 0) {
        if (t->pos >= t->size) return pl_io_fail(t, "unexpected end of file: expected %s", what);
        return pl_io_fail(t, "line ended early: expected %s", what);
    }
    return PL_OK;
}

int pl_io_read_int(pl_text *t, long long *v, const char *what, int same_line)
{
    char tok[64];
    if (number_token(t, tok, sizeof tok, what, same_line)) return PL_EINPUT;
    if (pl_io_parse_int(tok, v))
        return pl_io_fail(t, "expected %s (an integer), found '%s'", what, tok);
    return PL_OK;
}

int pl_io_read_int_range(pl_text *t, long long *v, long long lo, long long hi, const char *what,
                         int same_line)
{
    if (pl_io_read_int(t, v, what, same_line)) return PL_EINPUT;
    if (*v < lo || *v > hi)
        return pl_io_fail(t, "%s %lld is out of range: expected %lld..%lld", what, *v, lo, hi);
    return PL_OK;
}

int pl_io_read_double(pl_text *t, double *v, const char *what, int same_line)
{
    char tok[96];
    if (number_token(t, tok, sizeof tok, what, same_line)) return PL_EINPUT;
    if (pl_io_parse_double(tok, v))
        return pl_io_fail(t, "expected %s (a number), found '%s'", what, tok);
    if (!isfinite(*v))
        return pl_io_fail(t, "%s is not finite ('%s'): expected a finite number", what, tok);
    return PL_OK;
}

int pl_io_check_count(pl_text *t, int line, long long count, size_t bytes, size_t min_bytes,
                      const char *what)
{
    if (!line) line = t->line;
    if (count < 0) return pl_io_fail_at(t, line, "negative %s count %lld", what, count);
    if (count > INT_MAX / 4)
        return pl_io_fail_at(t, line, "%s count %lld is too large (at most %d supported)", what,
                             count, INT_MAX / 4);
    if (min_bytes && (unsigned long long)count > bytes / min_bytes)
        return pl_io_fail_at(t, line,
                          "file declares %lld %s but only %zu bytes remain, room for at most "
                          "%zu: the file is truncated or the count is wrong",
                          count, what, bytes, bytes / min_bytes);
    return PL_OK;
}

uint32_t pl_io_u32(const unsigned char *p, int big_endian)
{
    if (big_endian)
        return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
    return (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}

uint64_t pl_io_u64(const unsigned char *p, int big_endian)
{
    uint64_t hi = pl_io_u32(p + (big_endian ? 0 : 4), big_endian);
    uint64_t lo = pl_io_u32(p + (big_endian ? 4 : 0), big_endian);
    return hi << 32 | lo;
}

double pl_io_f32(const unsigned char *p, int big_endian)
{
    uint32_t u = pl_io_u32(p, big_endian);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

double pl_io_f64(const unsigned char *p, int big_endian)
{
    uint64_t u = pl_io_u64(p, big_endian);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

int pl_io_read_file(const char *path, char **buf, size_t *size, pl_diag *diag)
{
    *buf = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return pl_diag_error(diag, PL_EINPUT, path, 0, NULL, "cannot open mesh file: %s",
                             strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return pl_diag_error(diag, PL_EINPUT, path, 0, NULL,
                             "not a regular file: expected a mesh file");
    }
    if ((unsigned long long)st.st_size > PL_IO_MAX_FILE) {
        fclose(f);
        return pl_diag_error(diag, PL_EINPUT, path, 0, NULL,
                             "file is too large (%lld bytes): meshes up to %zu bytes are read",
                             (long long)st.st_size, PL_IO_MAX_FILE);
    }
    size_t n = (size_t)st.st_size;
    char *b = malloc(n + 1);
    if (!b) {
        fclose(f);
        return pl_diag_error(diag, PL_EINTERNAL, path, 0, NULL, "out of memory reading the file");
    }
    size_t got = fread(b, 1, n, f);
    int bad = ferror(f);
    fclose(f);
    if (bad || got != n) {
        free(b);
        return pl_diag_error(diag, PL_EINPUT, path, 0, NULL,
                             "read error: got %zu of %zu bytes", got, n);
    }
    b[n] = '\0';
    *buf = b;
    *size = n;
    return PL_OK;
}
