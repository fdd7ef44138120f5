/* regression_list.c - SOFA's regression list format.
 *
 *     # comment
 *     references/examples          <- optional first line: references folder
 *     Demos/liver.scn 100 1e-4 1 1 <- scene steps epsilon [mapped] [lastonly]
 *
 * (SOFA: Regression_test/RegressionSceneList.inl and
 * SofaRegressionProgram/tools/RegressionSceneList.py.)  Unlike SOFA, which
 * falls back to defaults on unreadable fields, a malformed line is an error
 * naming its line: a regression run should never test something other than
 * what its list says. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"

enum { MAX_FIELDS = 5 };

static const char expected[] = "expected 'scene steps epsilon [mapped 0|1] [lastonly 0|1]'";

void pl_regression_list_free(pl_regression_list *l)
{
    if (!l) return;
    for (int i = 0; i < l->count; ++i) free(l->items[i].scene);
    free(l->items);
    free(l->ref_dir);
    memset(l, 0, sizeof *l);
}

/* Splits line into at most MAX_FIELDS + 1 whitespace-separated fields (the
 * extra one only to detect too many); '#' at the start of a field begins a
 * comment.  Fields are NUL-terminated in place. */
static int split_fields(char *line, char *fields[MAX_FIELDS + 1])
{
    int n = 0;
    char *p = line;
    while (n <= MAX_FIELDS) {
        while (*p && isspace((unsigned char)*p)) ++p;
        if (!*p || *p == '#') break;
        fields[n++] = p;
        while (*p && !isspace((unsigned char)*p)) ++p;
        if (*p) *p++ = '\0';
    }
    return n;
}

static int parse_int(const char *s, long lo, long hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end || errno || v < lo || v > hi) return 0;
    *out = (int)v;
    return 1;
}

static int parse_flag(const char *s, int *out)
{
    if ((s[0] == '0' || s[0] == '1') && s[1] == '\0') {
        *out = s[0] == '1';
        return 1;
    }
    return 0;
}

/* Fills e from the fields of one scene line; an error goes to diag. */
static int parse_entry(char **f, int n, const char *name, int line, pl_regression_entry *e,
                       pl_diag *diag)
{
    if (n > MAX_FIELDS)
        return pl_diag_error(diag, PL_EINPUT, name, line, NULL, "%s, found more than %d fields",
                             expected, MAX_FIELDS);
    if (n < 3)
        return pl_diag_error(diag, PL_EINPUT, name, line, NULL, "%s, found %d field%s", expected,
                             n, n == 1 ? "" : "s");
    if (!parse_int(f[1], 1, INT_MAX, &e->steps))
        return pl_diag_error(diag, PL_EINPUT, name, line, NULL,
                             "steps must be a positive integer, found '%s'", f[1]);
    char *end;
    e->epsilon = strtod(f[2], &end);
    if (end == f[2] || *end || !isfinite(e->epsilon) || e->epsilon < 0)
        return pl_diag_error(diag, PL_EINPUT, name, line, NULL,
                             "epsilon must be a finite number >= 0, found '%s'", f[2]);
    if (n > 3 && !parse_flag(f[3], &e->mapped))
        return pl_diag_error(diag, PL_EINPUT, name, line, NULL,
                             "mapped must be 0 or 1, found '%s'", f[3]);
    if (n > 4 && !parse_flag(f[4], &e->last_only))
        return pl_diag_error(diag, PL_EINPUT, name, line, NULL,
                             "lastonly must be 0 or 1, found '%s'", f[4]);
    e->scene = strdup(f[0]);
    if (!e->scene) return pl_diag_error(diag, PL_EINTERNAL, name, line, NULL, "out of memory");
    e->line = line;
    return PL_OK;
}

static int push_entry(pl_regression_list *l, const pl_regression_entry *e)
{
    if (l->count == l->cap) {
        if (l->cap > INT_MAX / 2) return PL_EINTERNAL;
        int cap = l->cap ? 2 * l->cap : 16;
        pl_regression_entry *items = realloc(l->items, (size_t)cap * sizeof *items);
        if (!items) return PL_EINTERNAL;
        l->items = items;
        l->cap = cap;
    }
    l->items[l->count++] = *e;
    return PL_OK;
}

/* One line (already NUL-terminated, end of line removed). */
static int parse_line(char *line, const char *name, int lineno, int *seen_content,
                      pl_regression_list *out, pl_diag *diag)
{
    char *f[MAX_FIELDS + 1];
    int n = split_fields(line, f);
    if (n == 0) return PL_OK;
    int first = !*seen_content;
    *seen_content = 1;
    if (first && n == 1) { /* SOFA's header: the references folder */
        out->ref_dir = strdup(f[0]);
        return out->ref_dir ? PL_OK
                            : pl_diag_error(diag, PL_EINTERNAL, name, lineno, NULL, "out of memory");
    }
    pl_regression_entry e = {0};
    int rc = parse_entry(f, n, name, lineno, &e, diag);
    if (rc != PL_OK) return rc;
    if (push_entry(out, &e) != PL_OK) {
        free(e.scene);
        return pl_diag_error(diag, PL_EINTERNAL, name, lineno, NULL, "out of memory");
    }
    return PL_OK;
}

int pl_regression_list_parse(const char *text, const char *name, pl_regression_list *out,
                             pl_diag *diag)
{
    if (!text || !out) {
        pl_diag_error(diag, PL_EINPUT, name, 0, NULL, "invalid arguments");
        return PL_EINPUT;
    }
    memset(out, 0, sizeof *out);
    if (!strncmp(text, "\xEF\xBB\xBF", 3)) /* else it would become part of a folder name */
        return pl_diag_error(diag, PL_EINPUT, name, 1, NULL,
                             "the list starts with a UTF-8 byte order mark: save it as plain "
                             "text (ASCII or UTF-8 without BOM)");
    int status = PL_OK, lineno = 0, seen_content = 0;
    const char *p = text;
    char *line = NULL;
    while (*p) {
        const char *eol = strchr(p, '\n');
        size_t len = eol ? (size_t)(eol - p) : strlen(p);
        char *grown = realloc(line, len + 1);
        if (!grown) {
            status = pl_diag_error(diag, PL_EINTERNAL, name, lineno + 1, NULL, "out of memory");
            break;
        }
        line = grown;
        memcpy(line, p, len);
        line[len] = '\0';
        if (len && line[len - 1] == '\r') line[len - 1] = '\0';
        ++lineno;
        /* keep going after an error: the user sees every bad line at once */
        int rc = parse_line(line, name, lineno, &seen_content, out, diag);
        if (rc != PL_OK && status != PL_EINTERNAL) status = rc;
        if (rc == PL_EINTERNAL) break;
        p = eol ? eol + 1 : p + len;
    }
    free(line);
    return status;
}

int pl_regression_list_load(const char *path, pl_regression_list *out, pl_diag *diag)
{
    FILE *f = path ? fopen(path, "rb") : NULL;
    if (!f) {
        memset(out, 0, sizeof *out);
        return pl_diag_error(diag, PL_EINPUT, path, 0, NULL, "cannot open the regression list");
    }
    size_t cap = 4096, n = 0;
    char *text = malloc(cap);
    int rc = PL_OK;
    while (text) {
        n += fread(text + n, 1, cap - n - 1, f);
        if (n < cap - 1) break;
        char *g = realloc(text, cap * 2);
        if (!g) {
            free(text);
            text = NULL;
            break;
        }
        text = g;
        cap *= 2;
    }
    if (!text || ferror(f)) {
        rc = pl_diag_error(diag, text ? PL_EINPUT : PL_EINTERNAL, path, 0, NULL,
                           text ? "reading the regression list failed" : "out of memory");
        memset(out, 0, sizeof *out);
    } else if (memchr(text, '\0', n)) { /* else what follows it would be silently ignored */
        const char *nul = memchr(text, '\0', n);
        int line = 1;
        for (const char *p = text; p < nul; ++p) line += *p == '\n';
        rc = pl_diag_error(diag, PL_EINPUT, path, line, NULL,
                           "the list holds a NUL byte (at byte %zu): expected text",
                           (size_t)(nul - text));
        memset(out, 0, sizeof *out);
    } else {
        text[n] = '\0';
        rc = pl_regression_list_parse(text, path, out, diag);
    }
    free(text);
    fclose(f);
    return rc;
}

int pl_regression_reference_path(char *buf, size_t size, const char *base, int k,
                                 const char *state_name)
{
    return snprintf(buf, size, "%s.reference_%d_%s_mstate.txt.gz", base, k, state_name);
}
