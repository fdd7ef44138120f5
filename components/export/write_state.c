/* write_state.c - WriteState: records the node's state in SOFA's WriteState
 * format ("T= t", "  X= ...", "  V= ..."), the format of SOFA's regression
 * references, so a run of Pliant can be compared with SOFA's and with its
 * own earlier runs (pl_state_file_read, pl_regression_compare).
 *
 * It honours the run's output folder but not the run's `every`: what a state
 * file samples is part of what it records. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"
#include "export/export_internal.h"
#include "pliant/node.h"
#include "pliant/plugin.h"
#include "pliant/roles.h"

typedef struct write_state {
    pl_component base;
    /* fields */
    char *filename;
    double period;
    int write_x;
    int write_v;
    /* partner (bind) */
    pl_component *state;
    /* output (first write) */
    char *path;
    pl_state_writer *writer;
    int records;         /* records written so far */
    double next_time;    /* time of the next record when period > 0 [s] */
} write_state;

static const pl_field write_state_fields[] = {
    PL_FIELD(write_state, filename, "filename", PL_F_STRING, NULL,
             "output file, gzip-compressed when it ends in .gz (default: <node name>.state)", 0),
    PL_FIELD(write_state, period, "period", PL_F_DOUBLE, "0",
             "time between two records [s]; 0 = every step", 0),
    PL_FIELD(write_state, write_x, "writeX", PL_F_BOOL, "1", "record the positions [m]", 0),
    PL_FIELD(write_state, write_v, "writeV", PL_F_BOOL, "0", "record the velocities [m/s]", 0),
};

static int write_state_init(pl_component *c, pl_ctx *ctx)
{
    write_state *w = (write_state *)c;
    if (!(w->period >= 0))
        return pl_component_error(c, ctx, PL_EINPUT, "period must be >= 0 s, found %g", w->period);
    if (!w->filename || !*w->filename) {
        const char *node = c->node && c->node->name ? c->node->name : "pliant";
        size_t n = strlen(node) + 7;
        free(w->filename);
        w->filename = malloc(n);
        if (!w->filename) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
        snprintf(w->filename, n, "%s.state", node);
    }
    if (!w->write_x && !w->write_v)
        pl_component_warn(c, ctx, "writeX and writeV are both 0: only times will be written");
    return PL_OK;
}

static int write_state_bind(pl_component *c, pl_ctx *ctx)
{
    write_state *w = (write_state *)c;
    w->state = pl_node_find_role(c->node, PL_ROLE_STATE);
    if (!w->state)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "no state (MechanicalObject) in this node to record");
    const pl_state_ops *so = pl_component_role(w->state, PL_ROLE_STATE);
    if (!so->count || (w->write_x && !so->positions))
        return pl_component_error(c, ctx, PL_EINTERNAL, "the state cannot give its positions");
    if (w->write_v && !so->velocities)
        return pl_component_error(c, ctx, PL_EINPUT, "writeV is set but the state has no velocities");
    return PL_OK;
}

/* Slack on times compared with next_time: t is a sum of steps and carries
 * their rounding errors. */
static double time_slack(const write_state *w)
{
    return 1e-6 * pl_node_dt(w->base.node);
}

/* Whether a record is due at time t: always the first one, then the first
 * step at or after each t0 + k * period. */
static int record_due(const write_state *w, double t)
{
    if (w->records == 0 || w->period <= 0) return 1;
    return t + time_slack(w) >= w->next_time;
}

static int open_writer(write_state *w, const pl_export_info *info, pl_error *err)
{
    if (!w->path) {
        w->path = pl_export_output_path(info->out_dir, w->filename);
        if (!w->path) return pl_component_fail(&w->base, err, PL_EINTERNAL, "out of memory");
        int rc = pl_export_make_parent_dirs(w->path, err);
        if (rc != PL_OK) return rc;
    }
    /* after a finish, further records go after the ones written */
    w->writer = pl_state_writer_open(w->path, w->records > 0, err);
    return w->writer ? PL_OK : err->code;
}

/* One record: time, then positions and velocities as asked. */
static int write_record(write_state *w, pl_ctx *ctx, double t, pl_error *err)
{
    const pl_state_ops *so = pl_component_role(w->state, PL_ROLE_STATE);
    size_t n = (size_t)so->count(w->state);
    const double *x = NULL, *v = NULL;
    double *ox = NULL, *ov = NULL;
    int rc = PL_OK;
    if (w->write_x) {
        pl_buffer b = so->positions(w->state, ctx->data);
        rc = pl_export_buffer_f64(&b, n, &x, &ox, err);
    }
    if (rc == PL_OK && w->write_v) {
        pl_buffer b = so->velocities(w->state, ctx->data);
        rc = pl_export_buffer_f64(&b, n, &v, &ov, err);
    }
    /* an empty state has a NULL array: still write its (empty) lines */
    static const double none[1] = {0};
    if (rc == PL_OK)
        rc = pl_state_writer_write(w->writer, t, w->write_x ? (x ? x : none) : NULL, 3 * (int)n,
                                   w->write_v ? (v ? v : none) : NULL, 3 * (int)n, err);
    free(ox);
    free(ov);
    return rc;
}

static int write_state_write(pl_component *c, pl_ctx *ctx, const pl_export_info *info,
                             pl_error *err)
{
    write_state *w = (write_state *)c;
    double t = info->time;
    if (!record_due(w, t)) return PL_OK;
    int rc = w->writer ? PL_OK : open_writer(w, info, err);
    if (rc == PL_OK) rc = write_record(w, ctx, t, err);
    if (rc != PL_OK) return pl_export_blame(c, err);
    if (w->records++ == 0) w->next_time = t;
    if (w->period > 0) {
        while (w->next_time <= t + time_slack(w)) w->next_time += w->period;
    }
    return PL_OK;
}

static int write_state_finish(pl_component *c, pl_ctx *ctx, const pl_export_info *info,
                              pl_error *err)
{
    write_state *w = (write_state *)c;
    int rc = pl_state_writer_close(w->writer, err);
    w->writer = NULL;
    return rc;
}

static const char *write_state_output_path(const pl_component *c)
{
    return ((const write_state *)c)->path;
}

static void write_state_destroy(pl_component *c)
{
    write_state *w = (write_state *)c;
    pl_state_writer_close(w->writer, NULL);
    free(w->path);
}

static const pl_exporter_ops write_state_exporter_ops = {
    .version = PL_EXPORTER_OPS_VERSION,
    .write = write_state_write,
    .finish = write_state_finish,
    .output_path = write_state_output_path,
};

const pl_type pl_write_state_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "WriteState",
    .help = "records the node's state over time in SOFA's WriteState format",
    .size = sizeof(write_state),
    .fields = write_state_fields,
    .nfields = sizeof write_state_fields / sizeof write_state_fields[0],
    .ops = {.init = write_state_init,
            .bind = write_state_bind,
            .destroy = write_state_destroy},
    .roles = {[PL_ROLE_EXPORTER] = &write_state_exporter_ops},
};
