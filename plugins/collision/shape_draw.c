/* shape_draw.c - triangles of the analytic shapes, for the visual role:
 * what the viewer shows and VTKExporter writes for an obstacle.  Planes
 * become a finite square patch around a given point.  Each flat face has
 * its own vertices, so that a renderer averaging normals per vertex shades
 * boxes and cylinder caps flat; triangles are counter-clockwise seen from
 * outside. */
#include <math.h>

#include "shape_draw.h"

enum { RING = 32, LAT = 12 };

typedef struct emitter {
    const pl_shape *s;
    pl_draw_part *p;
    int rc;
} emitter;

/* Adds the vertex of local coordinates (a, b, c) (x = center + R l). */
static int vertex(emitter *e, double a, double b, double c)
{
    const double *R = e->s->R, *o = e->s->center;
    double x[3];
    for (int i = 0; i < 3; ++i) x[i] = o[i] + R[3 * i] * a + R[3 * i + 1] * b + R[3 * i + 2] * c;
    int v = pl_draw_vertices(e->p, x, NULL, 1);
    if (v < 0) e->rc = PL_EINTERNAL;
    return v;
}

static void tri(emitter *e, int a, int b, int c)
{
    int t[3] = {a, b, c};
    if (!e->rc && a >= 0 && b >= 0 && c >= 0) e->rc = pl_draw_triangles(e->p, t, 1, 0);
}

static void quad(emitter *e, int a, int b, int c, int d)
{
    tri(e, a, b, c);
    tri(e, a, c, d);
}

/* A lat-long cap or sphere: radius r about local (0, 0, z0), polar angle
 * from th0 to th1 (0 = +z). */
static void sphere_band(emitter *e, double r, double z0, double th0, double th1, int nlat)
{
    int first = e->p->nverts;
    for (int i = 0; i <= nlat; ++i) {
        double th = th0 + (th1 - th0) * i / nlat;
        for (int j = 0; j <= RING; ++j) {
            double ph = 2.0 * M_PI * j / RING;
            vertex(e, r * sin(th) * cos(ph), r * sin(th) * sin(ph), z0 + r * cos(th));
        }
    }
    for (int i = 0; i < nlat; ++i)
        for (int j = 0; j < RING; ++j) {
            int a = first + i * (RING + 1) + j, b = a + RING + 1;
            quad(e, a, b, b + 1, a + 1);
        }
}

/* The side of a cylinder of radius r between local z = -h and +h. */
static void tube(emitter *e, double r, double h)
{
    int first = e->p->nverts;
    for (int j = 0; j <= RING; ++j) {
        double ph = 2.0 * M_PI * j / RING;
        vertex(e, r * cos(ph), r * sin(ph), -h);
        vertex(e, r * cos(ph), r * sin(ph), h);
    }
    for (int j = 0; j < RING; ++j) {
        int a = first + 2 * j;
        quad(e, a, a + 2, a + 3, a + 1);
    }
}

/* A flat disc of radius r at local z, facing +z (up = 1) or -z. */
static void disc(emitter *e, double r, double z, int up)
{
    int c = vertex(e, 0.0, 0.0, z), first = e->p->nverts;
    for (int j = 0; j < RING; ++j) {
        double ph = 2.0 * M_PI * j / RING;
        vertex(e, r * cos(ph), r * sin(ph), z);
    }
    for (int j = 0; j < RING; ++j) {
        int a = first + j, b = first + (j + 1) % RING;
        if (up)
            tri(e, c, a, b);
        else
            tri(e, c, b, a);
    }
}

static void box(emitter *e, const double h[3])
{
    /* per face: the axis it faces, its sign */
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2) {
            int u = (axis + 1) % 3, w = (axis + 2) % 3, v[4];
            static const double cu[4] = {-1, 1, 1, -1}, cw[4] = {-1, -1, 1, 1};
            for (int k = 0; k < 4; ++k) {
                double l[3];
                l[axis] = sign * h[axis];
                l[u] = cu[k] * h[u];
                l[w] = cw[k] * h[w];
                v[k] = vertex(e, l[0], l[1], l[2]);
            }
            if (sign > 0)
                quad(e, v[0], v[1], v[2], v[3]);
            else
                quad(e, v[0], v[3], v[2], v[1]);
        }
}

/* The plane's patch: a square of half side `half` centred on the
 * projection of `around` onto the plane, split in 8 x 8 quads. */
static void patch(emitter *e, const double around[3], double half)
{
    const double *R = e->s->R, *o = e->s->center;
    double d[3] = {around[0] - o[0], around[1] - o[1], around[2] - o[2]};
    double cu = R[0] * d[0] + R[3] * d[1] + R[6] * d[2];
    double cv = R[1] * d[0] + R[4] * d[1] + R[7] * d[2];
    enum { N = 8 };
    int first = e->p->nverts;
    for (int i = 0; i <= N; ++i)
        for (int j = 0; j <= N; ++j)
            vertex(e, cu + half * (2.0 * j / N - 1.0), cv + half * (2.0 * i / N - 1.0), 0.0);
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            int a = first + i * (N + 1) + j;
            quad(e, a, a + 1, a + N + 2, a + N + 1);
        }
}

int coll_shape_draw(const pl_shape *s, const double around[3], double half, pl_draw_part *p)
{
    emitter e = {s, p, PL_OK};
    double hz = s->half[2];
    switch (s->kind) {
    case PL_SHAPE_PLANE: patch(&e, around, half); break;
    case PL_SHAPE_SPHERE: sphere_band(&e, s->radius, 0.0, 0.0, M_PI, LAT); break;
    case PL_SHAPE_BOX: box(&e, s->half); break;
    case PL_SHAPE_CAPSULE:
        tube(&e, s->radius, hz);
        sphere_band(&e, s->radius, hz, 0.0, 0.5 * M_PI, LAT / 2);
        sphere_band(&e, s->radius, -hz, 0.5 * M_PI, M_PI, LAT / 2);
        break;
    case PL_SHAPE_CYLINDER:
        tube(&e, s->radius, hz);
        disc(&e, s->radius, hz, 1);
        disc(&e, s->radius, -hz, 0);
        break;
    }
    return e.rc;
}
