/* component_util.c - helpers shared by built-in components. */
#include "pliant/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const pl_mesh *pl_util_topology(const pl_component *c, const pl_link *src, pl_ctx *ctx,
                                int required)
{
    const pl_component *t = NULL;
    if (src && src->target) {
        t = src->target;
        if (!pl_component_role(t, PL_ROLE_TOPOLOGY)) {
            pl_component_error(c, ctx, PL_EINPUT,
                               "src: '@%s' is a %s, which provides no mesh (expected a loader "
                               "or a generator such as MeshLoader or RegularGridTetrahedra)",
                               src->path, t->type->name);
            return NULL;
        }
    } else {
        t = pl_node_find_role(c->node, PL_ROLE_TOPOLOGY);
    }
    if (!t) {
        if (required)
            pl_component_error(c, ctx, PL_EINPUT,
                               "needs a mesh: put a loader or generator before it in the node, "
                               "or give src=\"@name\"");
        return NULL;
    }
    const pl_topology_ops *ops = pl_component_role(t, PL_ROLE_TOPOLOGY);
    const pl_mesh *m = ops->mesh(t);
    if (!m && required)
        pl_component_error(c, ctx, PL_EINPUT, "the mesh of '%s' is not available", t->name);
    return m;
}

pl_component *pl_util_state(const pl_component *c, pl_ctx *ctx, int required)
{
    pl_component *s = pl_node_find_role(c->node, PL_ROLE_STATE);
    if (!s && required)
        pl_component_error(c, ctx, PL_EINPUT,
                           "needs a MechanicalObject in its node (none found)");
    return s;
}

const double *pl_util_rest(const pl_component *state, int *n)
{
    const pl_state_ops *ops = pl_component_role(state, PL_ROLE_STATE);
    pl_buffer b = ops->rest_positions(state);
    *n = (int)b.rows;
    return pl_buffer_f64(&b);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int pl_util_select(const double *x, int n, const pl_doubles *boxes, const pl_ints *indices,
                   int **out)
{
    int cap = (indices ? indices->n : 0) + 16, count = 0;
    int *sel = malloc((size_t)cap * sizeof *sel);
    if (!sel) return -1;
    for (int k = 0; indices && k < indices->n; ++k) sel[count++] = indices->v[k];
    int nb = boxes ? boxes->n / 6 : 0;
    for (int v = 0; v < n && nb; ++v) {
        const double *p = &x[3 * v];
        for (int b = 0; b < nb; ++b) {
            const double *bx = &boxes->v[6 * b];
            if (p[0] >= bx[0] && p[0] <= bx[3] && p[1] >= bx[1] && p[1] <= bx[4] &&
                p[2] >= bx[2] && p[2] <= bx[5]) {
                if (count == cap) {
                    cap *= 2;
                    int *s = realloc(sel, (size_t)cap * sizeof *s);
                    if (!s) {
                        free(sel);
                        return -1;
                    }
                    sel = s;
                }
                sel[count++] = v;
                break;
            }
        }
    }
    qsort(sel, (size_t)count, sizeof *sel, cmp_int);
    int w = 0;
    for (int k = 0; k < count; ++k)
        if (w == 0 || sel[w - 1] != sel[k]) sel[w++] = sel[k];
    *out = sel;
    return w;
}

int pl_util_select_checked(const pl_component *c, pl_ctx *ctx, const pl_component *state,
                           const pl_doubles *boxes, const pl_ints *indices, int **out)
{
    int n;
    if (pl_util_check_boxes(c, ctx, "box", boxes) != PL_OK) return -1;
    const double *x = pl_util_rest(state, &n);
    for (int k = 0; k < indices->n; ++k)
        if (indices->v[k] < 0 || indices->v[k] >= n) {
            pl_component_error(c, ctx, PL_EINPUT,
                               "indices: %d is out of range (the MechanicalObject has %d vertices)",
                               indices->v[k], n);
            return -1;
        }
    int count = pl_util_select(x, n, boxes, indices, out);
    if (count < 0) pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    return count;
}

int pl_util_check_boxes(const pl_component *c, pl_ctx *ctx, const char *field,
                        const pl_doubles *boxes)
{
    if (boxes->n % 6)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "%s: expected 6 numbers per box (xmin ymin zmin xmax ymax zmax), "
                                  "found %d numbers",
                                  field, boxes->n);
    for (int b = 0; b < boxes->n / 6; ++b) {
        const double *bx = &boxes->v[6 * b];
        if (bx[0] > bx[3] || bx[1] > bx[4] || bx[2] > bx[5])
            return pl_component_error(c, ctx, PL_EINPUT,
                                      "%s: box %d has a min corner above its max corner", field,
                                      b + 1);
    }
    return PL_OK;
}

static void matmul3(const double A[9], const double B[9], double C[9])
{
    double T[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            T[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
    memcpy(C, T, sizeof T);
}

void pl_util_rotation_deg(const double deg[3], double R[9])
{
    static const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
    double Rx[9], Ry[9], Rz[9], T[9];
    pl_util_axis_angle(ex, deg[0] * M_PI / 180.0, Rx);
    pl_util_axis_angle(ey, deg[1] * M_PI / 180.0, Ry);
    pl_util_axis_angle(ez, deg[2] * M_PI / 180.0, Rz);
    /* x first, then y, then z: R = Rz Ry Rx (SOFA's convention) */
    matmul3(Ry, Rx, T);
    matmul3(Rz, T, R);
}

void pl_util_axis_angle(const double a[3], double angle, double R[9])
{
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    double x = a[0], y = a[1], z = a[2];
    R[0] = t * x * x + c;     R[1] = t * x * y - s * z; R[2] = t * x * z + s * y;
    R[3] = t * x * y + s * z; R[4] = t * y * y + c;     R[5] = t * y * z - s * x;
    R[6] = t * x * z - s * y; R[7] = t * y * z + s * x; R[8] = t * z * z + c;
}

pl_component *pl_util_device(const pl_component *c)
{
    pl_component *dev = c && c->node ? pl_node_find_role_up(c->node, PL_ROLE_DEVICE) : NULL;
    const pl_device_ops *ops = dev ? pl_component_role(dev, PL_ROLE_DEVICE) : NULL;
    if (!ops) return NULL;
    if (ops->flags && (ops->flags(dev) & PL_DEVICE_ABSENT)) return NULL;
    return dev;
}
