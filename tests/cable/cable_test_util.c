/* cable_test_util.c - see cable_test_util.h. */
#include "cable_test_util.h"

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

pl_sim *ct_load(const char *xml)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, "scene.xml", NULL, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    return s;
}

pl_diag ct_load_fail(const char *xml)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, "scene.xml", NULL, &diag);
    ck_assert_ptr_null(s);
    ck_assert_int_gt(diag.nerrors, 0);
    return diag;
}

void ct_step(pl_sim *s, int n)
{
    pl_error err;
    int rc = pl_sim_step(s, n, &err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
}

double ct_get(pl_sim *s, const char *path)
{
    char buf[256];
    pl_error err;
    int rc = pl_sim_get(s, path, buf, sizeof buf, &err);
    if (rc) {
        char b[1600];
        fprintf(stderr, "%s\n", pl_error_format(&err, b, sizeof b));
    }
    ck_assert_int_eq(rc, PL_OK);
    return strtod(buf, NULL);
}

const double *ct_positions(pl_sim *s, const char *path, int rest, int *n)
{
    pl_component *c = pl_sim_component(s, path);
    ck_assert_ptr_nonnull(c);
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    ck_assert_ptr_nonnull(ops);
    pl_buffer b = rest ? ops->rest_positions(c) : ops->positions(c, pl_sim_data(s));
    *n = (int)b.rows;
    return pl_buffer_f64(&b);
}

int ct_vertex_at(const double *x, int n, double px, double py, double pz)
{
    for (int i = 0; i < n; ++i)
        if (fabs(x[3 * i] - px) < 1e-9 && fabs(x[3 * i + 1] - py) < 1e-9 &&
            fabs(x[3 * i + 2] - pz) < 1e-9)
            return i;
    return -1;
}

const pl_error *ct_find_error(const pl_diag *d, const char *what)
{
    for (int k = 0; k < d->count; ++k)
        if (d->items[k].code != PL_OK && strstr(d->items[k].msg, what)) return &d->items[k];
    return NULL;
}

char *ct_read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)n + 1);
    ck_assert_uint_eq(fread(b, 1, (size_t)n, f), (size_t)n);
    b[n] = '\0';
    fclose(f);
    return b;
}

void ct_replace(char **text, const char *from, const char *to)
{
    char *p = strstr(*text, from);
    ck_assert_msg(p != NULL, "'%s' not in the text", from);
    size_t n = strlen(*text) - strlen(from) + strlen(to) + 1;
    char *r = malloc(n);
    snprintf(r, n, "%.*s%s%s", (int)(p - *text), *text, to, p + strlen(from));
    free(*text);
    *text = r;
}
