/* diagonal_mass.c - DiagonalMass: masses lumped from a density over the
 * mesh, a quarter of each tetrahedron's mass to each of its vertices (a
 * third of each triangle's for surfaces, with a thickness). */
#include <math.h>
#include <stdlib.h>

#include "pliant/util.h"
#include "mass.h"

typedef struct diagonal_mass {
    pl_component base;
    double density, thickness;
    pl_link src;
    pl_component *state;
    double *m;      /* per vertex [kg] */
    int n;
    double total;
} diagonal_mass;

static const pl_field FIELDS[] = {
    PL_FIELD(diagonal_mass, density, "massDensity", PL_F_DOUBLE, NULL,
             "density [kg/m^3]", PL_FIELD_REQUIRED),
    PL_FIELD(diagonal_mass, thickness, "thickness", PL_F_DOUBLE, "0.001",
             "thickness of a surface (triangle) mesh [m]: area density = massDensity * thickness",
             0),
    PL_FIELD(diagonal_mass, src, "src", PL_F_LINK, NULL,
             "the mesh to integrate over (default: the node's first loader or generator)", 0),
};

static double tet_volume(const double *x, const int *t)
{
    const double *a = &x[3 * t[0]], *b = &x[3 * t[1]], *c = &x[3 * t[2]], *d = &x[3 * t[3]];
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = d[k] - a[k];
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
}

static double tri_area(const double *x, const int *t)
{
    const double *a = &x[3 * t[0]], *b = &x[3 * t[1]], *c = &x[3 * t[2]];
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
    double n0 = u[1] * v[2] - u[2] * v[1], n1 = u[2] * v[0] - u[0] * v[2],
           n2 = u[0] * v[1] - u[1] * v[0];
    return 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
}

static int dm_bind(pl_component *c, pl_ctx *ctx)
{
    diagonal_mass *m = (diagonal_mass *)c;
    if (!(m->density > 0)) return pl_component_error(c, ctx, PL_EINPUT, "massDensity must be > 0");
    if (!(m->thickness > 0)) return pl_component_error(c, ctx, PL_EINPUT, "thickness must be > 0");
    m->state = pl_util_state(c, ctx, 1);
    const pl_mesh *mesh = pl_util_topology(c, &m->src, ctx, 1);
    if (!m->state || !mesh) return PL_EINPUT;
    /* integrate over the state's rest positions (they include its transform) */
    const double *x = pl_util_rest(m->state, &m->n);
    if (m->n != mesh->nverts)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the mesh has %d vertices but the MechanicalObject has %d",
                                  mesh->nverts, m->n);
    m->m = calloc((size_t)m->n, sizeof *m->m);
    if (!m->m) return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    m->total = 0;
    if (mesh->ntets) {
        for (int e = 0; e < mesh->ntets; ++e) {
            double share = m->density * fabs(tet_volume(x, &mesh->tets[4 * e])) / 4.0;
            for (int a = 0; a < 4; ++a) m->m[mesh->tets[4 * e + a]] += share;
        }
    } else if (mesh->ntris) {
        for (int e = 0; e < mesh->ntris; ++e) {
            double share = m->density * m->thickness * tri_area(x, &mesh->tris[3 * e]) / 3.0;
            for (int a = 0; a < 3; ++a) m->m[mesh->tris[3 * e + a]] += share;
        }
    } else {
        return pl_component_error(c, ctx, PL_EINPUT, "the mesh has no tetrahedra or triangles");
    }
    int orphans = 0;
    for (int i = 0; i < m->n; ++i) {
        m->total += m->m[i];
        if (m->m[i] <= 0) orphans++;
    }
    if (orphans)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "%d vertices belong to no element and would have no mass "
                                  "(drop them with the loader's onlyAttachedPoints=\"1\")",
                                  orphans);
    pl_log_debug("DiagonalMass %s: total %g kg", c->name, m->total);
    return PL_OK;
}

static void dm_destroy(pl_component *c) { free(((diagonal_mass *)c)->m); }

static pl_component *dm_state(const pl_component *c) { return ((const diagonal_mass *)c)->state; }

static int dm_add(const pl_component *c, double *mass, int n, pl_error *err)
{
    const diagonal_mass *m = (const diagonal_mass *)c;
    if (n != m->n) return pl_component_fail(c, err, PL_EINTERNAL, "size mismatch");
    for (int i = 0; i < n; ++i) mass[i] += m->m[i];
    return PL_OK;
}

static const pl_mass_ops MASS_OPS = {
    .version = PL_MASS_OPS_VERSION, .state = dm_state, .add_vertex_masses = dm_add};

const pl_type pl_diagonal_mass_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "DiagonalMass",
    .help = "Lumped masses from a density: a quarter of each tetrahedron (a third of each "
            "triangle times thickness) per vertex.",
    .size = sizeof(diagonal_mass),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.bind = dm_bind, .destroy = dm_destroy},
    .roles = {[PL_ROLE_MASS] = &MASS_OPS},
};
