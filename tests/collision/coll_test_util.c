/* coll_test_util.c - see coll_test_util.h. */
#include "coll_test_util.h"

#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

pl_sim *ct_load(const char *xml, const char *const *overrides, int noverrides)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt;
    memset(&opt, 0, sizeof opt);
    opt.overrides = overrides;
    opt.noverrides = noverrides;
    pl_sim *s = pl_sim_load_string(xml, "scene", &opt, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    return s;
}

void ct_load_fail(const char *xml, pl_error *e)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, "scene", NULL, &diag);
    ck_assert_ptr_null(s);
    ck_assert_int_gt(diag.nerrors, 0);
    int k = 0;
    while (diag.items[k].code == PL_OK) k++;
    *e = diag.items[k];
    pl_diag_free(&diag);
}

char *ct_read_source(const char *relpath)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", PL_SOURCE_DIR, relpath);
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)len + 1);
    ck_assert_ptr_nonnull(text);
    ck_assert_int_eq((long)fread(text, 1, (size_t)len, f), len);
    text[len] = '\0';
    fclose(f);
    return text;
}

char *ct_replace_lines(const char *text, const char *needle, const char *line)
{
    size_t cap = strlen(text) + 1, w = 0;
    const char *p = text;
    size_t extra = strlen(line);
    for (const char *q = text; (q = strstr(q, needle)); q++) cap += extra;
    char *out = malloc(cap);
    ck_assert_ptr_nonnull(out);
    while (*p) {
        const char *end = strchr(p, '\n');
        size_t len = end ? (size_t)(end - p) + 1 : strlen(p);
        const char *hit = strstr(p, needle);
        if (hit && hit < p + len) {
            memcpy(out + w, line, extra);
            w += extra;
            if (end) out[w++] = '\n'; /* keep the line count: errors keep their lines */
        } else {
            memcpy(out + w, p, len);
            w += len;
        }
        p += len;
    }
    out[w] = '\0';
    return out;
}

void ct_system_make(ct_system *s, int n, double h, const int *prescribed)
{
    memset(s, 0, sizeof *s);
    s->free_index = malloc((size_t)n * sizeof *s->free_index);
    s->free_vertex = malloc((size_t)n * sizeof *s->free_vertex);
    ck_assert(s->free_index && s->free_vertex);
    int nf = 0;
    for (int v = 0; v < n; ++v) {
        if (prescribed && prescribed[v]) {
            s->free_index[v] = -1;
        } else {
            s->free_index[v] = nf;
            s->free_vertex[nf++] = v;
        }
    }
    s->sys.nverts = n;
    s->sys.nfree = nf;
    s->sys.free_index = s->free_index;
    s->sys.free_vertex = s->free_vertex;
    s->sys.h = h;
}

void ct_system_free(ct_system *s)
{
    free(s->free_index);
    free(s->free_vertex);
}

double *ct_positions(pl_sim *sim, const char *state_path, int *n)
{
    pl_component *st = pl_sim_component(sim, state_path);
    ck_assert_ptr_nonnull(st);
    const pl_state_ops *ops = pl_component_role(st, PL_ROLE_STATE);
    ck_assert_ptr_nonnull(ops);
    ck_assert_int_eq(ops->offset(st), 0);
    pl_buffer b = ops->positions(st, pl_sim_data(sim));
    *n = (int)b.rows;
    return pl_buffer_f64(&b);
}

int ct_build_rows(pl_sim *sim, const char *path, const pl_system *sys, double *q, int n,
                  pl_rows *rows, pl_error *err)
{
    pl_component *c = pl_sim_component(sim, path);
    ck_assert_ptr_nonnull(c);
    const pl_constraint_ops *ops = pl_component_role(c, PL_ROLE_CONSTRAINT);
    ck_assert_ptr_nonnull(ops);
    ck_assert_int_ge(ops->version, 1);
    pl_diag diag;
    pl_diag_init(&diag);
    pl_ctx ctx = {pl_sim_model(sim), pl_sim_data(sim), pl_sim_registry(sim), pl_sim_timers(sim),
                  &diag, NULL};
    pl_buffer qb = pl_buffer_host_f64(q, (size_t)n, 3);
    int rc = ops->build_rows(c, &ctx, sys, &qb, rows, err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(err, b, sizeof b));
    }
    pl_diag_free(&diag);
    return rc;
}

int ct_get_doubles(pl_sim *sim, const char *path, double **out)
{
    size_t size = 1 << 20;
    char *buf = malloc(size), *p = buf;
    ck_assert_ptr_nonnull(buf);
    pl_error err;
    ck_assert_int_eq(pl_sim_get(sim, path, buf, size, &err), PL_OK);
    int cap = 64, k = 0;
    double *x = malloc(sizeof(double) * (size_t)cap);
    ck_assert_ptr_nonnull(x);
    for (char *end;; p = end) {
        double v = strtod(p, &end);
        if (end == p) break;
        if (k == cap) {
            x = realloc(x, sizeof(double) * (size_t)(cap *= 2));
            ck_assert_ptr_nonnull(x);
        }
        x[k++] = v;
    }
    free(buf);
    *out = x;
    return k;
}
