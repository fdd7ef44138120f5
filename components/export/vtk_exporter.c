/* vtk_exporter.c - VTKExporter: the node's state as a ParaView series.
 *
 * Writes <prefix>_0000.vtu, <prefix>_0001.vtu, ... (one per exported step,
 * numbered by frame) and <prefix>.pvd listing them with their times.  Cells
 * come from the node's topology (tetrahedra and triangles); without one only
 * the points are written.  Point data: the velocity and the constraint
 * forces.  With drawings="1" (the default) the obstacles, cable paths and
 * contacts of the node and of the nodes below without a VTKExporter of
 * their own go into the same series as further parts (vtk_parts.h), so
 * ParaView shows what pliant view shows; a node without a state exports
 * only those. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"
#include "export/export_internal.h"
#include "export/vtk_parts.h"
#include "pliant/log.h"
#include "pliant/node.h"
#include "pliant/plugin.h"
#include "pliant/roles.h"

enum { MAX_POINT_DATA = 8 };

typedef struct vtk_exporter {
    pl_component base;
    /* fields */
    char *filename;
    int every;
    int binary;
    int export_velocity;
    int drawings;
    /* partners (bind) */
    pl_component *state;
    pl_component *topology;
    pl_vtk_parts parts;
    /* output (first write) */
    char *prefix;      /* resolved path prefix, out_dir applied */
    char *pvd_path;
    pl_pvd *pvd;
    int frame;         /* frames written so far */
    int warned_mesh;
} vtk_exporter;

/* What one frame carries besides the points. */
typedef struct point_data_list {
    pl_vtu_array arrays[MAX_POINT_DATA];
    double *owned[MAX_POINT_DATA]; /* converted copies to free */
    int count;
} point_data_list;

static const pl_field vtk_exporter_fields[] = {
    PL_FIELD(vtk_exporter, filename, "filename", PL_F_STRING, NULL,
             "path prefix of the output: <prefix>_0000.vtu, ... and <prefix>.pvd "
             "(default: the node's name)",
             0),
    PL_FIELD_ALIAS(vtk_exporter, every, "every", PL_F_INT, "1",
                   "export every k-th step (the state after loading is frame 0)", 0,
                   "exportEveryNumberOfSteps"),
    PL_FIELD(vtk_exporter, binary, "binary", PL_F_BOOL, "0",
             "base64 binary arrays instead of ascii text", 0),
    PL_FIELD(vtk_exporter, export_velocity, "exportVelocity", PL_F_BOOL, "1",
             "write the velocity [m/s] as point data", 0),
    PL_FIELD(vtk_exporter, drawings, "drawings", PL_F_BOOL, "1",
             "also write the obstacles (planes as a finite patch, meshes, at their pose), cable "
             "paths and contact points with their forces of this node and the nodes below "
             "without their own VTKExporter, as further parts of the series "
             "(<prefix>_<node>_<component>_0000.vtu, ...)",
             0),
};

/* Drops a ".vtu", ".pvd" or ".vtk" the user may have added to the prefix. */
static void strip_extension(char *s)
{
    size_t n = strlen(s);
    if (n > 4 && (!strcmp(s + n - 4, ".vtu") || !strcmp(s + n - 4, ".pvd") ||
                  !strcmp(s + n - 4, ".vtk")))
        s[n - 4] = '\0';
}

static int vtk_exporter_init(pl_component *c, pl_ctx *ctx)
{
    vtk_exporter *e = (vtk_exporter *)c;
    if (e->every < 1)
        return pl_component_error(c, ctx, PL_EINPUT, "every must be >= 1, found %d", e->every);
    if (!e->filename || !*e->filename) {
        free(e->filename);
        e->filename = strdup(c->node && c->node->name ? c->node->name : "pliant");
        if (!e->filename) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    }
    strip_extension(e->filename);
    return PL_OK;
}

static int vtk_exporter_bind(pl_component *c, pl_ctx *ctx)
{
    vtk_exporter *e = (vtk_exporter *)c;
    e->state = pl_node_find_role(c->node, PL_ROLE_STATE);
    if (e->drawings && pl_vtk_parts_find(&e->parts, c) != PL_OK)
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    if (!e->state && e->parts.nowners == 0)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "nothing to export: no state (MechanicalObject) in this node, "
                                  "and no obstacle, cable or contacts in it or below%s",
                                  e->drawings ? "" : " (drawings=\"0\")");
    if (!e->state) return PL_OK;
    const pl_state_ops *so = pl_component_role(e->state, PL_ROLE_STATE);
    if (!so->positions || !so->count)
        return pl_component_error(c, ctx, PL_EINTERNAL, "the state cannot give its positions");
    e->topology = pl_node_find_role(c->node, PL_ROLE_TOPOLOGY);
    return PL_OK;
}

/* Opens the series at the first write (out_dir is known only then) and
 * again after a finish (appending to what was written). */
static int open_series(vtk_exporter *e, const pl_export_info *info, pl_error *err)
{
    if (!e->prefix) {
        e->prefix = pl_export_output_path(info->out_dir, e->filename);
        size_t n = e->prefix ? strlen(e->prefix) : 0;
        e->pvd_path = e->prefix ? malloc(n + 5) : NULL;
        if (!e->pvd_path) return pl_component_fail(&e->base, err, PL_EINTERNAL, "out of memory");
        snprintf(e->pvd_path, n + 5, "%s.pvd", e->prefix);
        int rc = pl_export_make_parent_dirs(e->prefix, err);
        if (rc != PL_OK) return rc;
    }
    e->pvd = pl_pvd_open(e->pvd_path, e->frame > 0, err);
    return e->pvd ? PL_OK : err->code;
}

static void point_data_free(point_data_list *pd)
{
    for (int k = 0; k < pd->count; ++k) free(pd->owned[k]);
    pd->count = 0;
}

/* Adds a state array of n x 3 values (a pl_buffer) under name. */
static int point_data_add(point_data_list *pd, const char *name, pl_buffer b, int n,
                          pl_error *err)
{
    if (pd->count == MAX_POINT_DATA)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "too many point-data arrays");
    const double *v;
    int rc = pl_export_buffer_f64(&b, (size_t)n, &v, &pd->owned[pd->count], err);
    if (rc != PL_OK) return rc;
    pd->arrays[pd->count++] = (pl_vtu_array){name, 3, v};
    return PL_OK;
}

/* The point data of this frame. */
static int gather_point_data(vtk_exporter *e, pl_ctx *ctx, int n, point_data_list *pd,
                             pl_error *err)
{
    const pl_state_ops *so = pl_component_role(e->state, PL_ROLE_STATE);
    if (e->export_velocity && so->velocities) {
        int rc = point_data_add(pd, "velocity", so->velocities(e->state, ctx->data), n, err);
        if (rc != PL_OK) return rc;
    }
    /* contact, friction and cable forces of the last step [N] */
    if (so->constraint_forces) {
        int rc = point_data_add(pd, "constraintForce", so->constraint_forces(e->state, ctx->data), n,
                                err);
        if (rc != PL_OK) return rc;
    }
    return PL_OK;
}

/* The topology's mesh when it describes this state's vertices, else NULL. */
static const pl_mesh *frame_mesh(vtk_exporter *e, int n)
{
    if (!e->topology) return NULL;
    const pl_topology_ops *to = pl_component_role(e->topology, PL_ROLE_TOPOLOGY);
    const pl_mesh *m = to->mesh ? to->mesh(e->topology) : NULL;
    if (m && m->nverts == n) return m;
    if (!e->warned_mesh) {
        char path[192];
        pl_log_warn("%s: the topology has %d vertices but the state %d; writing points only",
                    pl_component_path(&e->base, path, sizeof path), m ? m->nverts : 0, n);
        e->warned_mesh = 1;
    }
    return NULL;
}

static int write_body_frame(vtk_exporter *e, pl_ctx *ctx, const pl_export_info *info,
                            pl_error *err)
{
    const pl_state_ops *so = pl_component_role(e->state, PL_ROLE_STATE);
    int n = so->count(e->state);
    const double *xyz;
    double *owned_xyz = NULL;
    pl_buffer pos = so->positions(e->state, ctx->data);
    int rc = pl_export_buffer_f64(&pos, (size_t)n, &xyz, &owned_xyz, err);
    point_data_list pd = {.count = 0};
    if (rc == PL_OK) rc = gather_point_data(e, ctx, n, &pd, err);
    if (rc == PL_OK) {
        const pl_mesh *m = frame_mesh(e, n);
        size_t len = strlen(e->prefix) + 32;
        char *vtu = malloc(len);
        if (!vtu) {
            rc = pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        } else {
            snprintf(vtu, len, "%s_%04d.vtu", e->prefix, e->frame);
            rc = pl_vtu_write(vtu, n, xyz, m ? m->ntets : 0, m ? m->tets : NULL,
                              m ? m->ntris : 0, m ? m->tris : NULL, pd.arrays, pd.count,
                              e->binary, err);
            /* the .pvd sits beside the frames: entries are bare file names */
            if (rc == PL_OK) rc = pl_pvd_append(e->pvd, info->time, pl_export_basename(vtu), err);
            free(vtu);
        }
    }
    point_data_free(&pd);
    free(owned_xyz);
    if (rc != PL_OK) pl_export_blame(&e->base, err);
    return rc;
}

static int write_frame(vtk_exporter *e, pl_ctx *ctx, const pl_export_info *info, pl_error *err)
{
    int rc = e->state ? write_body_frame(e, ctx, info, err) : PL_OK;
    if (rc == PL_OK && e->parts.nowners)
        rc = pl_vtk_parts_write(&e->parts, e->prefix, e->frame, ctx->data, e->pvd,
                                e->state ? 1 : 0, e->binary, err);
    if (rc == PL_OK) e->frame++;
    if (rc != PL_OK) pl_export_blame(&e->base, err);
    return rc;
}

static int vtk_exporter_write(pl_component *c, pl_ctx *ctx, const pl_export_info *info,
                              pl_error *err)
{
    vtk_exporter *e = (vtk_exporter *)c;
    int every = info->every > 0 ? info->every : e->every;
    if (every > 1 && info->step % every != 0) return PL_OK;
    if (!e->pvd) {
        int rc = open_series(e, info, err);
        if (rc != PL_OK) return pl_export_blame(c, err);
    }
    return write_frame(e, ctx, info, err);
}

static int vtk_exporter_finish(pl_component *c, pl_ctx *ctx, const pl_export_info *info,
                               pl_error *err)
{
    vtk_exporter *e = (vtk_exporter *)c;
    int rc = pl_pvd_close(e->pvd, err);
    e->pvd = NULL;
    return rc;
}

static const char *vtk_exporter_output_path(const pl_component *c)
{
    return ((const vtk_exporter *)c)->pvd_path;
}

static void vtk_exporter_destroy(pl_component *c)
{
    vtk_exporter *e = (vtk_exporter *)c;
    pl_pvd_close(e->pvd, NULL);
    pl_vtk_parts_free(&e->parts);
    free(e->prefix);
    free(e->pvd_path);
}

static const pl_exporter_ops vtk_exporter_exporter_ops = {
    .version = PL_EXPORTER_OPS_VERSION,
    .write = vtk_exporter_write,
    .finish = vtk_exporter_finish,
    .output_path = vtk_exporter_output_path,
};

const pl_type pl_vtk_exporter_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "VTKExporter",
    .help = "writes the node's state as a ParaView series (.vtu frames and a .pvd)",
    .size = sizeof(vtk_exporter),
    .fields = vtk_exporter_fields,
    .nfields = sizeof vtk_exporter_fields / sizeof vtk_exporter_fields[0],
    .ops = {.init = vtk_exporter_init,
            .bind = vtk_exporter_bind,
            .destroy = vtk_exporter_destroy},
    .roles = {[PL_ROLE_EXPORTER] = &vtk_exporter_exporter_ops},
};
