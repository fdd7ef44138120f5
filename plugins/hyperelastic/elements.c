/* elements.c - a FEM term's element set: shape matrices, volumes, Lame
 * parameters and PD weights, built once from the rest state; and its
 * contribution h2 * w D D^T to the scalar system matrix. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hyperelastic.h"
#include "incidence.h"

void hyper_elements_free(pl_hyper_elements *e)
{
    if (!e) return;
    free(e->verts);
    free(e->D);
    free(e->volume);
    free(e->mu);
    free(e->lambda);
    free(e->w);
    free(e->vptr);
    free(e->vinc);
    memset(e, 0, sizeof *e);
}

static int fail(pl_hyper_elements *e, pl_error *err, int code, const char *msg, int i)
{
    hyper_elements_free(e);
    if (i >= 0) return pl_error_set(err, code, NULL, 0, NULL, "element %d: %s", i, msg);
    return pl_error_set(err, code, NULL, 0, NULL, "%s", msg);
}

/* Shape matrix and volume of element i from the rest positions. */
static int element_shape(pl_hyper_elements *e, int i, const double *rest, double thickness)
{
    const int k = e->k;
    double x[12];
    for (int c = 0; c < k; ++c)
        for (int r = 0; r < 3; ++r) x[3 * c + r] = rest[3 * (size_t)e->verts[i * k + c] + r];
    double *D = e->D + (size_t)i * k * e->d;
    if (k == 4) return hyper_tet_shape(x, D, &e->volume[i]);
    int rc = hyper_tri_shape(x, D, &e->volume[i]);
    e->volume[i] *= thickness;
    return rc;
}

int hyper_elements_build(pl_hyper_elements *e, pl_hyper_material material, int k,
                            const int *elems, int nelem, const double *rest, int nverts,
                            const double *E, int nE, const double *nu, int nnu,
                            double thickness, pl_error *err)
{
    memset(e, 0, sizeof *e);
    if (k != 3 && k != 4) return fail(e, err, PL_EINPUT, "elements must have 3 or 4 vertices", -1);
    if (nelem < 0 || nverts < 0) return fail(e, err, PL_EINPUT, "negative element count", -1);
    if (!(nE == 1 || nE == nelem) || !(nnu == 1 || nnu == nelem)) {
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "youngModulus and poissonRatio need 1 or %d values (one per element), "
                     "got %d and %d", nelem, nE, nnu);
        return PL_EINPUT;
    }
    if (k == 3 && !(thickness > 0.0 && isfinite(thickness)))
        return fail(e, err, PL_EINPUT, "thickness must be positive [m]", -1);
    e->material = material;
    e->k = k;
    e->d = k - 1;
    e->n = nelem;
    e->nverts = nverts;
    size_t n = (size_t)(nelem > 0 ? nelem : 1);
    e->verts = malloc(n * k * sizeof *e->verts);
    e->D = malloc(n * k * e->d * sizeof *e->D);
    e->volume = malloc(n * sizeof *e->volume);
    e->mu = malloc(n * sizeof *e->mu);
    e->lambda = malloc(n * sizeof *e->lambda);
    e->w = malloc(n * sizeof *e->w);
    if (!e->verts || !e->D || !e->volume || !e->mu || !e->lambda || !e->w)
        return fail(e, err, PL_EINTERNAL, "out of memory building the elements", -1);
    for (int i = 0; i < nelem * k; ++i) {
        if (elems[i] < 0 || elems[i] >= nverts) {
            pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                         "element %d: vertex index %d out of range [0, %d)", i / k, elems[i],
                         nverts);
            hyper_elements_free(e);
            return PL_EINPUT;
        }
        e->verts[i] = elems[i];
    }
    for (int i = 0; i < nelem; ++i) {
        if (element_shape(e, i, rest, thickness) != PL_OK)
            return fail(e, err, PL_EINPUT, "degenerate (zero volume or area)", i);
        pl_error lame_err;
        int rc = hyper_lame(E[nE == 1 ? 0 : i], nu[nnu == 1 ? 0 : i], k == 3, &e->mu[i],
                               &e->lambda[i], &lame_err);
        if (rc != PL_OK) return fail(e, err, rc, lame_err.msg, i);
        pl_hyper_law law = hyper_elements_law(e, i);
        e->w[i] = hyper_law_weight(&law) * e->volume[i];
    }
    e->weight_scale = 1.0;
    if (hyper_incidence_build(nverts, nelem * k, e->verts, &e->vptr, &e->vinc) != 0)
        return fail(e, err, PL_EINTERNAL, "out of memory building the incidence", -1);
    return PL_OK;
}

pl_hyper_law hyper_elements_law(const pl_hyper_elements *e, int i)
{
    pl_hyper_law law = {e->material, e->d, e->mu[i], e->lambda[i]};
    return law;
}

int hyper_elements_dual_size(const pl_hyper_elements *e)
{
    return e->material == PL_HYPER_ARAP ? 0 : 3 * e->d;
}

int hyper_elements_add_matrix(const pl_hyper_elements *e, int offset, double h2,
                                 pl_triplets *A, pl_error *err)
{
    const int k = e->k, d = e->d;
    for (int i = 0; i < e->n; ++i) {
        const double *D = e->D + (size_t)i * k * d;
        const int *v = e->verts + (size_t)i * k;
        for (int a = 0; a < k; ++a)
            for (int b = 0; b < k; ++b) {
                double s = 0.0;
                for (int c = 0; c < d; ++c) s += D[a * d + c] * D[b * d + c];
                if (pl_triplets_add(A, offset + v[a], offset + v[b], h2 * e->w[i] * s) != PL_OK)
                    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                        "out of memory assembling the system matrix");
            }
    }
    return PL_OK;
}
