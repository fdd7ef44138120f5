/* elements_step.c - what a FEM term does with positions: the local step
 * (ARAP projection or ADMM-PD prox + dual update), the energy, its gradient
 * and its Hessian.  Element loops run in parallel, each element writing its
 * own slot; vertices then gather their slots in a fixed order. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include "hyperelastic.h"
#include "incidence.h"
#include "small_matrix.h"

/* F = X D for element i from global positions q. */
static void deformation_gradient(const pl_hyper_elements *e, int i, int offset, const double *q,
                                 double *F)
{
    const int k = e->k, d = e->d;
    const double *D = e->D + (size_t)i * k * d;
    const int *v = e->verts + (size_t)i * k;
    for (int a = 0; a < 3 * d; ++a) F[a] = 0.0;
    for (int c = 0; c < k; ++c) {
        const double *x = q + 3 * ((size_t)offset + v[c]);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < d; ++b) F[a * d + b] += x[a] * D[c * d + b];
    }
}

/* slot[c] (3-vector per corner c) = scale * M D^T for a 3 x d matrix M. */
static void spread(const pl_hyper_elements *e, int i, double scale, const double *M, double *slot)
{
    const int k = e->k, d = e->d;
    const double *D = e->D + (size_t)i * k * d;
    for (int c = 0; c < k; ++c)
        for (int a = 0; a < 3; ++a) {
            double s = 0.0;
            for (int b = 0; b < d; ++b) s += M[a * d + b] * D[c * d + b];
            slot[3 * c + a] = scale * s;
        }
}

size_t hyper_elements_work_size(const pl_hyper_elements *e)
{
    return (size_t)(e->n > 0 ? e->n : 1) * 3 * (size_t)e->k;
}

int hyper_elements_project(const pl_hyper_elements *e, int offset, double h2, const double *q,
                              double *dual, double *warm, double *work, double *rhs,
                              hyper_prox_stats *stats, pl_error *err)
{
    return hyper_elements_project_relaxed(e, offset, h2, q, dual, warm, 1.0, NULL, work, rhs, stats,
                                          err);
}

int hyper_elements_project_relaxed(const pl_hyper_elements *e, int offset, double h2,
                                   const double *q, double *dual, double *warm, double alpha,
                                   double *prev, double *work, double *rhs,
                                   hyper_prox_stats *stats, pl_error *err)
{
    const int d = e->d, nd = 3 * d, k = e->k;
    if (e->material != PL_HYPER_ARAP && !dual)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "the ADMM-PD local step needs its dual variables");
    int first_bad = INT_MAX, max_it = 0;
    long long missed = 0, newton = 0, halvings = 0, hist[HYPER_PROX_HIST] = {0};
#pragma omp parallel for schedule(static) reduction(min : first_bad) reduction(max : max_it) \
    reduction(+ : missed, newton, halvings, hist[:HYPER_PROX_HIST])
    for (int i = 0; i < e->n; ++i) {
        double F[9], z[9], p[9];
        deformation_gradient(e, i, offset, q, F);
        pl_hyper_law law = hyper_elements_law(e, i);
        double *u = dual && e->material != PL_HYPER_ARAP ? dual + (size_t)i * nd : NULL;
        double *pp = u && prev ? prev + (size_t)i * nd : NULL;
        /* over-relaxed ADMM: alpha G q + (1 - alpha) p_prev stands for G q
         * in the prox and in the dual update */
        if (pp && alpha != 1.0)
            for (int a = 0; a < nd; ++a) F[a] = alpha * F[a] + (1.0 - alpha) * pp[a];
        for (int a = 0; a < nd; ++a) z[a] = u ? F[a] + u[a] : F[a];
        int nhalf = 0;
        int it = hyper_local_solve_warm(&law, e->weight_scale * hyper_law_weight(&law), z, p,
                                        warm ? warm + (size_t)i * HM_WARM_LEN(d) : NULL, &nhalf);
        halvings += nhalf;
        int finite = 1;
        for (int a = 0; a < nd; ++a) finite &= isfinite(p[a]);
        if (!finite) {
            if (i < first_bad) first_bad = i;
            continue;
        }
        if (it < 0) {
            ++missed;
        } else {
            newton += it;
            ++hist[it < HYPER_PROX_HIST - 1 ? it : HYPER_PROX_HIST - 1];
            if (it > max_it) max_it = it;
        }
        if (u) {
            /* scaled dual ascent, then the right-hand side uses p - u */
            for (int a = 0; a < nd; ++a) {
                if (pp) pp[a] = p[a];
                u[a] += F[a] - p[a];
                p[a] -= u[a];
            }
        }
        spread(e, i, h2 * e->w[i], p, work + (size_t)i * 3 * k);
    }
    if (stats) {
        stats->solves += e->n;
        stats->newton += newton;
        stats->halvings += halvings;
        stats->capped += missed;
        for (int b = 0; b < HYPER_PROX_HIST; ++b) stats->hist[b] += hist[b];
        if (max_it > stats->max_iterations) stats->max_iterations = max_it;
    }
    if (first_bad != INT_MAX)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                            "element %d: non-finite deformation gradient in the local step",
                            first_bad);
    hyper_incidence_gather(e->nverts, e->vptr, e->vinc, work, offset, rhs);
    return PL_OK;
}

double hyper_elements_energy(const pl_hyper_elements *e, int offset, const double *q)
{
    double *en = malloc((size_t)(e->n > 0 ? e->n : 1) * sizeof *en);
    if (!en) return NAN;
#pragma omp parallel for schedule(static)
    for (int i = 0; i < e->n; ++i) {
        double F[9];
        deformation_gradient(e, i, offset, q, F);
        pl_hyper_law law = hyper_elements_law(e, i);
        en[i] = hyper_psi(&law, F) * e->volume[i];
    }
    double sum = 0.0; /* fixed order: deterministic */
    for (int i = 0; i < e->n; ++i) sum += en[i];
    free(en);
    return sum;
}

int hyper_elements_add_gradient(const pl_hyper_elements *e, int offset, const double *q,
                                   double *grad, pl_error *err)
{
    const int k = e->k;
    double *slots = malloc((size_t)(e->n > 0 ? e->n : 1) * 3 * k * sizeof *slots);
    if (!slots)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (gradient)");
#pragma omp parallel for schedule(static)
    for (int i = 0; i < e->n; ++i) {
        double F[9], P[9];
        deformation_gradient(e, i, offset, q, F);
        pl_hyper_law law = hyper_elements_law(e, i);
        if (e->edge_rotation)
            hyper_edge_piola(&law, F, e->D + (size_t)i * k * e->d, P);
        else
            hyper_piola(&law, F, P);
        spread(e, i, e->volume[i], P, slots + (size_t)i * 3 * k); /* dE/dx_c = V P D^T */
    }
    hyper_incidence_gather(e->nverts, e->vptr, e->vinc, slots, offset, grad);
    free(slots);
    return PL_OK;
}

/* The element's 3k x 3k vertex Hessian: V sum_bb' D_cb H_(a b),(a' b') D_c'b'. */
static void element_hessian(const pl_hyper_elements *e, int i, int offset, const double *q,
                            int psd, double *He)
{
    const int k = e->k, d = e->d, nd = 3 * d, n = 3 * k;
    const double *D = e->D + (size_t)i * k * d;
    double F[9], H[81];
    deformation_gradient(e, i, offset, q, F);
    pl_hyper_law law = hyper_elements_law(e, i);
    if (e->edge_rotation) /* SOFA's R K0 R^T, whatever psd asks: there is no energy */
        hyper_edge_dPdF(&law, F, D, H);
    else
        pl_hyper_dPdF(&law, F, psd, H);
    for (int c = 0; c < k; ++c)
        for (int a = 0; a < 3; ++a)
            for (int c2 = 0; c2 < k; ++c2)
                for (int a2 = 0; a2 < 3; ++a2) {
                    double s = 0.0;
                    for (int b = 0; b < d; ++b)
                        for (int b2 = 0; b2 < d; ++b2)
                            s += D[c * d + b] * H[(a * d + b) * nd + (a2 * d + b2)] * D[c2 * d + b2];
                    He[(3 * c + a) * n + (3 * c2 + a2)] = e->volume[i] * s;
                }
}

int hyper_elements_add_hessian(const pl_hyper_elements *e, int offset, const double *q,
                                  int psd, pl_triplets *H, pl_error *err)
{
    const int k = e->k, n = 3 * k;
    const int chunk = 512; /* bounds the scratch (512 x 144 doubles), reused per chunk */
    double *blocks = malloc((size_t)chunk * n * n * sizeof *blocks);
    if (!blocks) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory (Hessian)");
    for (int start = 0; start < e->n; start += chunk) {
        int end = start + chunk < e->n ? start + chunk : e->n;
#pragma omp parallel for schedule(static)
        for (int i = start; i < end; ++i)
            element_hessian(e, i, offset, q, psd, blocks + (size_t)(i - start) * n * n);
        for (int i = start; i < end; ++i) {
            const double *He = blocks + (size_t)(i - start) * n * n;
            const int *v = e->verts + (size_t)i * k;
            for (int r = 0; r < n; ++r)
                for (int c = 0; c < n; ++c) {
                    int gr = 3 * (offset + v[r / 3]) + r % 3, gc = 3 * (offset + v[c / 3]) + c % 3;
                    if (pl_triplets_add(H, gr, gc, He[r * n + c]) != PL_OK) {
                        free(blocks);
                        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                            "out of memory assembling the Hessian");
                    }
                }
        }
    }
    free(blocks);
    return PL_OK;
}
