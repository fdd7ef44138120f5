/* field.c - parsing and formatting typed fields (the C numeric locale is
 * assumed: strtod with '.' as the decimal point, as SOFA scenes are). */
#include "pliant/field.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *pl_field_type_name(pl_field_type t)
{
    switch (t) {
    case PL_F_DOUBLE: return "double";
    case PL_F_INT: return "int";
    case PL_F_BOOL: return "bool";
    case PL_F_STRING: return "string";
    case PL_F_VEC3: return "vec3";
    case PL_F_DOUBLES: return "double list";
    case PL_F_INTS: return "int list";
    case PL_F_ENUM: return "enum";
    case PL_F_LINK: return "link";
    }
    return "?";
}

static const char *skip_space(const char *s)
{
    while (*s && isspace((unsigned char)*s)) s++;
    return s;
}

/* Reads one finite double token; returns the end or NULL. Separators are
 * blanks or commas (SOFA writes lists blank-separated; people type commas). */
static const char *read_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s) return NULL;
    if (*end && !isspace((unsigned char)*end) && *end != ',') return NULL;
    if (!isfinite(v)) return NULL; /* NaN and inf are never valid input */
    *out = v;
    return end;
}

static const char *read_int(const char *s, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || errno == ERANGE || v < INT_MIN || v > INT_MAX) return NULL;
    if (*end && !isspace((unsigned char)*end) && *end != ',') return NULL;
    *out = (int)v;
    return end;
}

static const char *next_token(const char *s)
{
    s = skip_space(s);
    if (*s == ',') s = skip_space(s + 1);
    return s;
}

/* The offending token, for messages. */
static void token_at(const char *s, char *buf, size_t n)
{
    size_t k = 0;
    s = skip_space(s);
    while (s[k] && !isspace((unsigned char)s[k]) && s[k] != ',' && k + 1 < n) {
        buf[k] = s[k];
        k++;
    }
    buf[k] = '\0';
}

/* Parses a blank- or comma-separated list with `read` (read_double or
 * read_int) into a malloc'ed array of `elem` bytes per value. */
typedef const char *(*read_fn)(const char *s, void *out);
static const char *read_double_v(const char *s, void *out) { return read_double(s, out); }
static const char *read_int_v(const char *s, void *out) { return read_int(s, out); }

static int parse_list(const char *text, read_fn read, size_t elem, const char *what, void **out,
                      int *n, pl_error *err, const char *name)
{
    int cap = 16, count = 0;
    char *v = malloc((size_t)cap * elem);
    if (!v) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    const char *s = next_token(text);
    while (*s) {
        if (count == cap) {
            cap *= 2;
            char *nv = realloc(v, (size_t)cap * elem);
            if (!nv) {
                free(v);
                return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
            }
            v = nv;
        }
        const char *e = read(s, v + (size_t)count * elem);
        if (!e) {
            char tok[64];
            token_at(s, tok, sizeof tok);
            free(v);
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s: expected %s, found '%s' (value %d)",
                                name, what, tok, count + 1);
        }
        count++;
        s = next_token(e);
    }
    *out = v;
    *n = count;
    return PL_OK;
}

static int parse_doubles(const char *text, double **out, int *n, pl_error *err, const char *name)
{
    return parse_list(text, read_double_v, sizeof **out, "a finite number", (void **)out, n, err,
                      name);
}

static int parse_ints(const char *text, int **out, int *n, pl_error *err, const char *name)
{
    return parse_list(text, read_int_v, sizeof **out, "an integer", (void **)out, n, err, name);
}

static int parse_bool(const char *s, int *out)
{
    char w[16];
    token_at(s, w, sizeof w);
    if (*next_token(skip_space(s) + strlen(w))) return -1;
    for (char *p = w; *p; ++p) *p = (char)tolower((unsigned char)*p);
    if (!strcmp(w, "1") || !strcmp(w, "true") || !strcmp(w, "yes") || !strcmp(w, "on")) {
        *out = 1;
        return 0;
    }
    if (!strcmp(w, "0") || !strcmp(w, "false") || !strcmp(w, "no") || !strcmp(w, "off")) {
        *out = 0;
        return 0;
    }
    return -1;
}

static int parse_enum(const pl_field *f, const char *s, int *out, pl_error *err)
{
    char w[64];
    token_at(s, w, sizeof w);
    int best = -1, bestd = 1 << 30;
    for (int k = 0; f->choices && f->choices[k]; ++k) {
        if (!strcmp(w, f->choices[k])) {
            *out = k;
            return PL_OK;
        }
        int d = pl_edit_distance(w, f->choices[k]);
        if (d < bestd) bestd = d, best = k;
    }
    /* SOFA scenes sometimes give an option index ("valueType=1") */
    int idx;
    const char *e = read_int(s, &idx);
    int nchoices = 0;
    while (f->choices && f->choices[nchoices]) nchoices++;
    if (e && !*next_token(e) && idx >= 0 && idx < nchoices) {
        *out = idx;
        return PL_OK;
    }
    char list[256] = "";
    for (int k = 0; k < nchoices; ++k) {
        strncat(list, f->choices[k], sizeof list - strlen(list) - 1);
        if (k + 1 < nchoices) strncat(list, "|", sizeof list - strlen(list) - 1);
    }
    if (best >= 0 && bestd <= 3)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "%s: '%s' is not one of %s (did you mean %s?)", f->name, w, list,
                            f->choices[best]);
    return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "%s: '%s' is not one of %s", f->name, w,
                        list);
}

void pl_field_release(const pl_field *f, void *obj)
{
    char *p = (char *)obj + f->offset;
    switch (f->type) {
    case PL_F_STRING: {
        char **s = (char **)p;
        free(*s);
        *s = NULL;
        break;
    }
    case PL_F_DOUBLES: {
        pl_doubles *d = (pl_doubles *)p;
        free(d->v);
        d->v = NULL;
        d->n = 0;
        break;
    }
    case PL_F_INTS: {
        pl_ints *d = (pl_ints *)p;
        free(d->v);
        d->v = NULL;
        d->n = 0;
        break;
    }
    case PL_F_LINK: {
        pl_link *l = (pl_link *)p;
        free(l->path);
        l->path = NULL;
        l->target = NULL;
        break;
    }
    default: break;
    }
}

int pl_field_parse(const pl_field *f, void *obj, const char *text, pl_error *err)
{
    char *p = (char *)obj + f->offset;
    const char *s = skip_space(text ? text : "");
    switch (f->type) {
    case PL_F_DOUBLE: {
        double v;
        const char *e = read_double(s, &v);
        if (!e || *next_token(e))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "%s: expected one finite number, found '%s'", f->name, text);
        *(double *)p = v;
        return PL_OK;
    }
    case PL_F_INT: {
        int v;
        const char *e = read_int(s, &v);
        if (!e || *next_token(e))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "%s: expected one integer, found '%s'", f->name, text);
        *(int *)p = v;
        return PL_OK;
    }
    case PL_F_BOOL: {
        int v;
        if (parse_bool(s, &v) != 0)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "%s: expected a boolean (0/1, true/false), found '%s'", f->name,
                                text);
        *(int *)p = v;
        return PL_OK;
    }
    case PL_F_STRING: {
        char *copy = strdup(text ? text : "");
        if (!copy) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        pl_field_release(f, obj);
        *(char **)p = copy;
        return PL_OK;
    }
    case PL_F_VEC3: {
        double *v3 = (double *)p, tmp[3];
        const char *e = s;
        for (int k = 0; k < 3; ++k) {
            e = read_double(next_token(e), &tmp[k]);
            if (!e)
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "%s: expected 3 finite numbers (x y z), found '%s'", f->name,
                                    text);
        }
        if (*next_token(e))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "%s: expected 3 numbers (x y z), found more in '%s'", f->name,
                                text);
        memcpy(v3, tmp, sizeof tmp);
        return PL_OK;
    }
    case PL_F_DOUBLES: {
        double *v = NULL;
        int n = 0;
        int rc = parse_doubles(s, &v, &n, err, f->name);
        if (rc) return rc;
        pl_field_release(f, obj);
        ((pl_doubles *)p)->v = v;
        ((pl_doubles *)p)->n = n;
        return PL_OK;
    }
    case PL_F_INTS: {
        int *v = NULL, n = 0;
        int rc = parse_ints(s, &v, &n, err, f->name);
        if (rc) return rc;
        pl_field_release(f, obj);
        ((pl_ints *)p)->v = v;
        ((pl_ints *)p)->n = n;
        return PL_OK;
    }
    case PL_F_ENUM: return parse_enum(f, s, (int *)p, err);
    case PL_F_LINK: {
        if (*s && *s != '@')
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "%s: expected a link '@name' or '@../path/name', found '%s'",
                                f->name, text);
        char *copy = strdup(*s ? s + 1 : "");
        if (!copy) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        size_t len = strlen(copy);
        while (len && isspace((unsigned char)copy[len - 1])) copy[--len] = '\0';
        pl_field_release(f, obj);
        ((pl_link *)p)->path = copy;
        return PL_OK;
    }
    }
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "%s: unknown field type", f->name);
}

static int append(char *buf, size_t size, size_t *n, const char *fmt, double v)
{
    if (*n >= size) return -1;
    int w = snprintf(buf + *n, size - *n, fmt, v);
    if (w < 0 || (size_t)w >= size - *n) {
        *n = size;
        return -1;
    }
    *n += (size_t)w;
    return 0;
}

int pl_field_format(const pl_field *f, const void *obj, char *buf, size_t size)
{
    const char *p = (const char *)obj + f->offset;
    size_t n = 0;
    if (size == 0) return PL_EINTERNAL;
    buf[0] = '\0';
    switch (f->type) {
    case PL_F_DOUBLE: snprintf(buf, size, "%.17g", *(const double *)p); break;
    case PL_F_INT: snprintf(buf, size, "%d", *(const int *)p); break;
    case PL_F_BOOL: snprintf(buf, size, "%d", *(const int *)p ? 1 : 0); break;
    case PL_F_STRING: snprintf(buf, size, "%s", *(char *const *)p ? *(char *const *)p : ""); break;
    case PL_F_VEC3: {
        const double *v = (const double *)p;
        snprintf(buf, size, "%.17g %.17g %.17g", v[0], v[1], v[2]);
        break;
    }
    case PL_F_DOUBLES: {
        const pl_doubles *d = (const pl_doubles *)p;
        for (int k = 0; k < d->n; ++k)
            if (append(buf, size, &n, k ? " %.17g" : "%.17g", d->v[k])) return PL_EINTERNAL;
        break;
    }
    case PL_F_INTS: {
        const pl_ints *d = (const pl_ints *)p;
        for (int k = 0; k < d->n; ++k) {
            if (n >= size) return PL_EINTERNAL;
            int w = snprintf(buf + n, size - n, k ? " %d" : "%d", d->v[k]);
            if (w < 0 || (size_t)w >= size - n) return PL_EINTERNAL;
            n += (size_t)w;
        }
        break;
    }
    case PL_F_ENUM: {
        int k = *(const int *)p;
        snprintf(buf, size, "%s", f->choices ? f->choices[k] : "?");
        break;
    }
    case PL_F_LINK: {
        const pl_link *l = (const pl_link *)p;
        snprintf(buf, size, l->path && l->path[0] ? "@%s" : "", l->path);
        break;
    }
    }
    return PL_OK;
}

/* Levenshtein distance, case-insensitive, on short names. */
int pl_edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 63 || lb > 63) return 64;
    int prev[64], cur[64];
    for (size_t j = 0; j <= lb; ++j) prev[j] = (int)j;
    for (size_t i = 1; i <= la; ++i) {
        cur[0] = (int)i;
        for (size_t j = 1; j <= lb; ++j) {
            int cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
            int best = prev[j - 1] + cost;
            if (prev[j] + 1 < best) best = prev[j] + 1;
            if (cur[j - 1] + 1 < best) best = cur[j - 1] + 1;
            cur[j] = best;
        }
        memcpy(prev, cur, (lb + 1) * sizeof *cur);
    }
    return prev[lb];
}
