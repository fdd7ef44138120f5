/* gpu_bar.c - the twisting bar system for the GPU programs (gpu_bar.h). */
#include "gpu_bar.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "spinv_testmat.h"

double gpu_rand(unsigned *state)
{
    unsigned x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return x / 4294967296.0 - 0.5;
}

double gpu_rel_diff(const double *a, const double *b, size_t m)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < m; ++i) num += (a[i] - b[i]) * (a[i] - b[i]), den += b[i] * b[i];
    return den > 0.0 ? sqrt(num / den) : sqrt(num);
}

void gpu_bar_free(gpu_bar *b)
{
    free(b->rest);
    free(b->mass);
    for (int m = 0; m < 3; ++m) hyper_elements_free(&b->el[m]);
    sparse_inverse_destroy(b->spinv);
    memset(b, 0, sizeof *b);
}

static int fail(gpu_bar *b, pl_error *err, const char *what)
{
    gpu_bar_free(b);
    return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "gpu bar: %s", what);
}

int gpu_bar_build(gpu_bar *b, int nx, int ny, int nz, pl_error *err)
{
    memset(b, 0, sizeof *b);
    b->nx = nx, b->ny = ny, b->nz = nz, b->n = nx * ny * nz, b->h = 0.01;
    int n = b->n;
    int *tets = spinv_grid_tets(nx, ny, nz, &b->ntets);
    b->rest = malloc((size_t)n * 3 * sizeof *b->rest);
    b->mass = calloc((size_t)n, sizeof *b->mass);
    if (!tets || !b->rest || !b->mass) {
        free(tets);
        return fail(b, err, "out of memory");
    }
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                double *x = b->rest + 3 * (size_t)(i + nx * (j + ny * k));
                x[0] = (double)i / (nx - 1);
                x[1] = 0.25 * j / (ny - 1);
                x[2] = 0.25 * k / (nz - 1);
            }
    const double E = 1e9, nu = 0.45, rho = 1000.0;
    const pl_hyper_material mats[3] = {PL_HYPER_ARAP, PL_HYPER_COROTATIONAL, PL_HYPER_NEOHOOKEAN};
    for (int m = 0; m < 3; ++m) {
        if (hyper_elements_build(&b->el[m], mats[m], 4, tets, b->ntets, b->rest, n, &E, 1, &nu,
                                    1, 0.0, err) != PL_OK) {
            free(tets);
            gpu_bar_free(b);
            return PL_EINTERNAL;
        }
    }
    free(tets);
    const pl_hyper_elements *e = &b->el[0];
    for (int t = 0; t < e->n; ++t)
        for (int c = 0; c < 4; ++c) b->mass[e->verts[4 * t + c]] += rho * e->volume[t] / 4.0;
    pl_triplets T;
    if (pl_triplets_init(&T, n, n, 16 * e->n + n) != PL_OK) return fail(b, err, "out of memory");
    int rc = PL_OK;
    for (int i = 0; i < n && rc == PL_OK; ++i) rc = pl_triplets_add(&T, i, i, b->mass[i]);
    if (rc == PL_OK) rc = hyper_elements_add_matrix(e, 0, b->h * b->h, &T, err);
    pl_csc A;
    if (rc == PL_OK) rc = pl_triplets_to_csc(&T, &A);
    pl_triplets_free(&T);
    if (rc != PL_OK) return fail(b, err, "assembling A");
    pl_spinv_options o = {PL_SPINV_METIS, PL_SPINV_SPARSE, 0};
    b->spinv = sparse_inverse_create(&o);
    rc = b->spinv ? sparse_inverse_factor(b->spinv, &A, err) : PL_EINTERNAL;
    pl_csc_free(&A);
    if (rc != PL_OK) return fail(b, err, "factoring A");
    return PL_OK;
}

void gpu_bar_twist(const gpu_bar *b, double turns, double noise, unsigned seed, double *q)
{
    unsigned st = seed ? seed : 1u;
    for (int v = 0; v < b->n; ++v) {
        const double *x = b->rest + 3 * (size_t)v;
        double ang = 2.0 * M_PI * turns * x[0], cy = x[1] - 0.125, cz = x[2] - 0.125;
        q[3 * v] = x[0] + noise * gpu_rand(&st);
        q[3 * v + 1] = 0.125 + cos(ang) * cy - sin(ang) * cz + noise * gpu_rand(&st);
        q[3 * v + 2] = 0.125 + sin(ang) * cy + cos(ang) * cz + noise * gpu_rand(&st);
    }
}

int gpu_bar_rhs(gpu_bar *b, const double *q, double *rhs, pl_error *err)
{
    for (int v = 0; v < b->n; ++v)
        for (int c = 0; c < 3; ++c) rhs[3 * v + c] = b->mass[v] * q[3 * v + c];
    double *work = malloc(hyper_elements_work_size(&b->el[0]) * sizeof *work);
    if (!work) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    int rc = hyper_elements_project(&b->el[0], 0, b->h * b->h, q, NULL, NULL, work, rhs, NULL, err);
    free(work);
    return rc;
}
