/* dyn_test_util.c - helpers for scene-level dynamics tests. */
#include "dyn_test_util.h"

#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "test_tmp.h"

static pl_sim *finish_load(pl_sim *s, pl_diag *diag)
{
    if (!s) pl_diag_print(diag, stderr);
    pl_diag_free(diag);
    ck_assert_ptr_nonnull(s);
    return s;
}

pl_sim *dyn_load(const char *xml)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = pl_sim_load_string(xml, PL_SOURCE_DIR "/scenes/test.xml", NULL, &diag);
    return finish_load(s, &diag);
}

pl_sim *dyn_load_file(const char *rel_path, const char **sets, int nsets)
{
    char path[1024];
    pl_diag diag;
    pl_diag_init(&diag);
    snprintf(path, sizeof path, "%s/%s", PL_SOURCE_DIR, rel_path);
    pl_sim_options opt = {.out_dir = test_tmp_dir(), .overrides = sets, .noverrides = nsets};
    return finish_load(pl_sim_load_file(path, &opt, &diag), &diag);
}

static const pl_state_ops *state(pl_sim *s, const char *path, pl_component **c)
{
    *c = pl_sim_component(s, path);
    ck_assert_ptr_nonnull(*c);
    const pl_state_ops *ops = pl_component_role(*c, PL_ROLE_STATE);
    ck_assert_ptr_nonnull(ops);
    return ops;
}

const double *dyn_positions(pl_sim *s, const char *path, int *n)
{
    pl_component *c;
    pl_buffer b = state(s, path, &c)->positions(c, pl_sim_data(s));
    *n = (int)b.rows;
    return b.data;
}

const double *dyn_velocities(pl_sim *s, const char *path, int *n)
{
    pl_component *c;
    pl_buffer b = state(s, path, &c)->velocities(c, pl_sim_data(s));
    *n = (int)b.rows;
    return b.data;
}

const double *dyn_rest(pl_sim *s, const char *path, int *n)
{
    pl_component *c;
    pl_buffer b = state(s, path, &c)->rest_positions(c);
    *n = (int)b.rows;
    return b.data;
}

double *dyn_masses(pl_sim *s, const char *mass_path, int n)
{
    pl_component *m = pl_sim_component(s, mass_path);
    ck_assert_ptr_nonnull(m);
    const pl_mass_ops *ops = pl_component_role(m, PL_ROLE_MASS);
    double *mass = calloc((size_t)n, sizeof *mass);
    pl_error err;
    ck_assert_int_eq(ops->add_vertex_masses(m, mass, n, &err), PL_OK);
    return mass;
}

void dyn_step(pl_sim *s, int n)
{
    pl_error err;
    int rc = pl_sim_step(s, n, &err);
    if (rc != PL_OK) {
        char buf[1600];
        fprintf(stderr, "step failed: %s\n", pl_error_format(&err, buf, sizeof buf));
    }
    ck_assert_int_eq(rc, PL_OK);
}

char *dyn_format(const double *x, int n)
{
    size_t size = (size_t)n * 3 * 26 + 1, w = 0;
    char *buf = malloc(size);
    for (int i = 0; i < 3 * n; ++i) w += (size_t)snprintf(buf + w, size - w, "%.17g ", x[i]);
    return buf;
}
