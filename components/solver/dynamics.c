/* dynamics.c - numbering, masses, prescribed DOFs, the constant system and
 * the incremental potential shared by the scene's solvers. */
#include "dynamics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct collect {
    pl_component **items;
    int n, cap;
} collect;

static int push(pl_component *c, void *user)
{
    collect *l = user;
    if (l->n == l->cap) {
        int cap = l->cap ? 2 * l->cap : 8;
        pl_component **items = realloc(l->items, (size_t)cap * sizeof *items);
        if (!items) return 1;
        l->items = items;
        l->cap = cap;
    }
    l->items[l->n++] = c;
    return 0;
}

static int gather_role(pl_node *n, pl_role role, pl_component ***out, int *count)
{
    collect l = {0};
    if (pl_node_visit_role(n, role, push, &l)) {
        free(l.items);
        return -1;
    }
    *out = l.items;
    *count = l.n;
    return 0;
}

static const pl_state_ops *state_ops(const pl_component *s)
{
    return pl_component_role(s, PL_ROLE_STATE);
}

int pl_dynamics_state_offset(const pl_dynamics *d, const pl_component *s)
{
    for (int k = 0; k < d->nstates; ++k)
        if (d->states[k] == s) return state_ops(s)->offset(s);
    return -1;
}

static int number_vertices(pl_dynamics *d, pl_component *owner, pl_ctx *ctx)
{
    d->n = 0;
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = state_ops(d->states[k]);
        ops->set_offset(d->states[k], d->n);
        d->n += ops->count(d->states[k]);
    }
    if (d->n == 0) return pl_component_error(owner, ctx, PL_EINPUT, "no MechanicalObject below it");
    d->mass = calloc((size_t)d->n, sizeof *d->mass);
    d->inertia = calloc((size_t)d->n, sizeof *d->inertia);
    d->gravity = calloc((size_t)d->n * 3, sizeof *d->gravity);
    d->free_index = malloc((size_t)d->n * sizeof *d->free_index);
    if (!d->mass || !d->inertia || !d->gravity || !d->free_index)
        return pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory");
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = state_ops(d->states[k]);
        double g[3];
        pl_node_gravity(d->states[k]->node, g);
        for (int i = ops->offset(d->states[k]), e = i + ops->count(d->states[k]); i < e; ++i)
            memcpy(&d->gravity[3 * i], g, sizeof g);
    }
    return PL_OK;
}

static int add_masses(pl_dynamics *d, pl_component *owner, pl_ctx *ctx)
{
    pl_component **masses;
    int nm;
    if (gather_role(owner->node, PL_ROLE_MASS, &masses, &nm))
        return pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory");
    for (int k = 0; k < nm; ++k) {
        const pl_mass_ops *ops = pl_component_role(masses[k], PL_ROLE_MASS);
        pl_component *s = ops->state(masses[k]);
        int off = s ? pl_dynamics_state_offset(d, s) : -1;
        pl_error err;
        if (off < 0) continue; /* its state is outside this solver's subtree */
        if (ops->add_vertex_masses(masses[k], d->mass + off, state_ops(s)->count(s), &err)) {
            pl_diag_add(ctx->diag, &err);
            free(masses);
            return err.code;
        }
    }
    free(masses);
    return PL_OK;
}

static int mark_prescribed(pl_dynamics *d, pl_component *owner, pl_ctx *ctx)
{
    for (int i = 0; i < d->n; ++i) d->free_index[i] = 0;
    for (int k = 0; k < d->nprescribed; ++k) {
        const pl_prescribed_ops *ops = pl_component_role(d->prescribed[k], PL_ROLE_PRESCRIBED);
        int off = pl_dynamics_state_offset(d, ops->state(d->prescribed[k]));
        const int *idx;
        int m = ops->indices(d->prescribed[k], &idx);
        for (int j = 0; off >= 0 && j < m; ++j) d->free_index[off + idx[j]] = -1;
    }
    d->nfree = 0;
    for (int i = 0; i < d->n; ++i)
        if (d->free_index[i] == 0) d->free_index[i] = d->nfree++;
    d->free_vertex = malloc((size_t)(d->nfree ? d->nfree : 1) * sizeof *d->free_vertex);
    if (!d->free_vertex) return pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory");
    for (int i = 0; i < d->n; ++i)
        if (d->free_index[i] >= 0) d->free_vertex[d->free_index[i]] = i;
    for (int i = 0; i < d->n; ++i)
        if (d->free_index[i] >= 0 && !(d->mass[i] > 0))
            return pl_component_error(owner, ctx, PL_EINPUT,
                                      "vertex %d has no mass: every free vertex needs one (add a "
                                      "UniformMass or DiagonalMass to its node)",
                                      i);
    return PL_OK;
}

/* diag (may be NULL) + scale * sum w G^T G over all vertices, as CSC. */
static int sum_terms(pl_dynamics *d, pl_component *owner, pl_ctx *ctx, const double *diag,
                     double scale, pl_csc *out)
{
    pl_triplets full;
    pl_error err;
    if (pl_triplets_init(&full, d->n, d->n, 16 * d->n) != PL_OK)
        return pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory");
    for (int i = 0; diag && i < d->n; ++i) pl_triplets_add(&full, i, i, diag[i]);
    for (int k = 0; k < d->nterms; ++k) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[k], PL_ROLE_LOCAL_TERM);
        if (ops->add_matrix(d->terms[k], d->term_offset[k], scale, &full, &err) != PL_OK) {
            pl_diag_add(ctx->diag, &err);
            pl_triplets_free(&full);
            return err.code;
        }
    }
    int rc = pl_triplets_to_csc(&full, out);
    pl_triplets_free(&full);
    return rc ? pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory") : PL_OK;
}

/* A = M' + (h^2 + h rS) sum w G^T G over all vertices (M' the inertia
 * masses), then split into the free x free and free x prescribed blocks;
 * with rS > 0 also L = sum w G^T G. */
static int assemble(pl_dynamics *d, pl_component *owner, pl_ctx *ctx)
{
    pl_triplets ff, fp;
    double rs = d->scheme.rayleigh_stiffness;
    if (rs > 0) {
        int rl = sum_terms(d, owner, ctx, NULL, 1.0, &d->L);
        if (rl) return rl;
    }
    pl_csc a;
    int rc = sum_terms(d, owner, ctx, d->inertia, d->h * d->h + d->h * rs, &a);
    if (rc) return rc;
    rc = pl_triplets_init(&ff, d->nfree, d->nfree, pl_csc_nnz(&a));
    rc |= pl_triplets_init(&fp, d->nfree, d->n, 16);
    for (int j = 0; rc == PL_OK && j < d->n; ++j)
        for (int p = a.p[j]; p < a.p[j + 1]; ++p) {
            int fi = d->free_index[a.i[p]], fj = d->free_index[j];
            if (fi < 0) continue;
            rc |= fj >= 0 ? pl_triplets_add(&ff, fi, fj, a.x[p]) : pl_triplets_add(&fp, fi, j, a.x[p]);
        }
    pl_csc_free(&a);
    if (rc == PL_OK) rc = pl_triplets_to_csc(&ff, &d->A_ff);
    if (rc == PL_OK) rc = pl_triplets_to_csc(&fp, &d->A_fp);
    pl_triplets_free(&ff);
    pl_triplets_free(&fp);
    return rc ? pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory") : PL_OK;
}

int pl_dynamics_setup(pl_dynamics *d, pl_component *owner, pl_ctx *ctx, double h, int with_matrix,
                      const pl_dyn_scheme *scheme)
{
    memset(d, 0, sizeof *d);
    d->h = h;
    if (scheme && with_matrix) d->scheme = *scheme;
    pl_node *root = owner->node;
    if (gather_role(root, PL_ROLE_STATE, &d->states, &d->nstates) ||
        gather_role(root, PL_ROLE_PRESCRIBED, &d->prescribed, &d->nprescribed) ||
        gather_role(root, PL_ROLE_LOCAL_TERM, &d->terms, &d->nterms))
        return pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory");
    int rc = number_vertices(d, owner, ctx);
    if (!rc) rc = add_masses(d, owner, ctx);
    if (!rc) rc = mark_prescribed(d, owner, ctx);
    if (rc) return rc;
    for (int i = 0; i < d->n; ++i) d->inertia[i] = (d->scheme.first_order ? h : 1.0) * d->mass[i];
    d->term_offset = malloc((size_t)(d->nterms ? d->nterms : 1) * sizeof *d->term_offset);
    if (!d->term_offset) return pl_component_error(owner, ctx, PL_EINTERNAL, "out of memory");
    for (int k = 0; k < d->nterms; ++k) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[k], PL_ROLE_LOCAL_TERM);
        d->term_offset[k] = pl_dynamics_state_offset(d, ops->state(d->terms[k]));
        if (d->term_offset[k] < 0)
            return pl_component_error(d->terms[k], ctx, PL_EINPUT,
                                      "its MechanicalObject is not below the solver %s",
                                      owner->name);
    }
    /* the contact solver's mass scaling is of the inertia term (W's) */
    d->sys = (pl_system){d->n, d->nfree, d->free_index, d->free_vertex, h, NULL, d->inertia};
    return with_matrix ? assemble(d, owner, ctx) : PL_OK;
}

void pl_dynamics_free(pl_dynamics *d)
{
    free(d->states);
    free(d->terms);
    free(d->term_offset);
    free(d->prescribed);
    free(d->mass);
    free(d->inertia);
    free(d->gravity);
    free(d->free_index);
    free(d->free_vertex);
    pl_csc_free(&d->A_ff);
    pl_csc_free(&d->A_fp);
    pl_csc_free(&d->L);
    memset(d, 0, sizeof *d);
}

int pl_dyn_work_alloc(pl_dyn_work *w, const pl_dynamics *d)
{
    size_t n3 = (size_t)(d->n ? d->n : 1) * 3, f3 = (size_t)(d->nfree ? d->nfree : 1) * 3;
    pl_dyn_work_free(w);
    w->q = calloc(n3, sizeof(double));
    w->q_t = calloc(n3, sizeof(double));
    w->v_t = calloc(n3, sizeof(double));
    w->sn = calloc(n3, sizeof(double));
    w->rhs = calloc(n3, sizeof(double));
    w->qp = calloc(n3, sizeof(double));
    w->b_free = calloc(f3, sizeof(double));
    w->q_free = calloc(f3, sizeof(double));
    if (!w->q || !w->q_t || !w->v_t || !w->sn || !w->rhs || !w->qp || !w->b_free || !w->q_free) {
        pl_dyn_work_free(w);
        return PL_EINTERNAL;
    }
    return PL_OK;
}

void pl_dyn_work_free(pl_dyn_work *w)
{
    double *all[] = {w->q, w->q_t, w->v_t, w->sn, w->rhs, w->qp, w->b_free, w->q_free};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) free(all[k]);
    memset(w, 0, sizeof *w);
}

void pl_dynamics_gather(const pl_dynamics *d, pl_dyn_work *w, const pl_data *data)
{
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = state_ops(d->states[k]);
        pl_buffer x = ops->positions(d->states[k], data), v = ops->velocities(d->states[k], data);
        size_t bytes = x.rows * 3 * sizeof(double);
        int off = ops->offset(d->states[k]);
        memcpy(&w->q_t[3 * off], x.data, bytes);
        memcpy(&w->v_t[3 * off], v.data, bytes);
    }
}

void pl_dynamics_add_Lq(const pl_dynamics *d, const double *q, double scale, double *out)
{
    const pl_csc *L = &d->L;
    if (!L->p) return;
    for (int j = 0; j < L->ncols; ++j)
        for (int p = L->p[j]; p < L->p[j + 1]; ++p) {
            double a = scale * L->x[p];
            for (int c = 0; c < 3; ++c) out[3 * L->i[p] + c] += a * q[3 * j + c];
        }
}

void pl_dynamics_motion(const pl_dynamics *d, const pl_dyn_work *w, double *out)
{
    double h = d->h;
    if (d->scheme.first_order) /* M (q - q_t) / h = f: no velocity, gravity's impulse h g */
        for (int i = 0; i < 3 * d->n; ++i) out[i] = w->q_t[i] + h * d->gravity[i];
    else
        for (int i = 0; i < 3 * d->n; ++i)
            out[i] = w->q_t[i] + h * w->v_t[i] + h * h * d->gravity[i];
}

/* With Rayleigh stiffness damping, sn += h rS M'^-1 L q_t: the damping's
 * right-hand side h rS L q_t (vertices without mass are prescribed: their
 * rows are not solved). */
static void add_damping_prediction(const pl_dynamics *d, pl_dyn_work *w)
{
    double h = d->h, rs = d->scheme.rayleigh_stiffness;
    if (!(rs > 0)) return;
    memset(w->rhs, 0, (size_t)d->n * 3 * sizeof(double));
    pl_dynamics_add_Lq(d, w->q_t, h * rs, w->rhs);
    for (int i = 0; i < d->n; ++i)
        if (d->inertia[i] > 0)
            for (int c = 0; c < 3; ++c) w->sn[3 * i + c] += w->rhs[3 * i + c] / d->inertia[i];
}

void pl_dynamics_predict(const pl_dynamics *d, pl_dyn_work *w)
{
    pl_dynamics_motion(d, w, w->sn);
    add_damping_prediction(d, w);
}

void pl_dynamics_begin(const pl_dynamics *d, pl_dyn_work *w, const pl_data *data, int guess)
{
    const double h = d->h, hv = d->scheme.first_order ? 0.0 : h;
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = state_ops(d->states[k]);
        pl_buffer x = ops->positions(d->states[k], data), v = ops->velocities(d->states[k], data);
        size_t base = 3 * (size_t)ops->offset(d->states[k]), cnt = 3 * x.rows;
        if (!cnt) continue;
        const double *px = x.data, *pv = v.data, *g = &d->gravity[base]; /* one g a state */
        double *qt = w->q_t + base, *vt = w->v_t + base, *sn = w->sn + base, *q = w->q + base;
        /* pl_dynamics_motion's expressions, term by term (bitwise the same) */
        double hg[3], h2g[3];
        for (int c = 0; c < 3; ++c) hg[c] = h * g[c], h2g[c] = h * h * g[c];
        for (size_t i = 0; i < cnt; i += 3)
            for (int c = 0; c < 3; ++c) {
                double xi = px[i + c], vi = pv[i + c];
                double m = d->scheme.first_order ? xi + hg[c] : xi + h * vi + h2g[c];
                qt[i + c] = xi, vt[i + c] = vi, sn[i + c] = m;
                q[i + c] = guess ? xi + hv * vi : m;
            }
    }
    add_damping_prediction(d, w); /* q_t is complete now */
}

int pl_dynamics_prescribe(const pl_dynamics *d, pl_dyn_work *w, const pl_data *data, double t,
                          double *q, pl_error *err)
{
    for (int k = 0; k < d->nprescribed; ++k) {
        const pl_prescribed_ops *ops = pl_component_role(d->prescribed[k], PL_ROLE_PRESCRIBED);
        int off = pl_dynamics_state_offset(d, ops->state(d->prescribed[k]));
        const int *idx;
        int m = ops->indices(d->prescribed[k], &idx);
        if (off < 0 || m == 0) continue;
        /* qp is scratch big enough for every vertex */
        int rc = ops->positions_at(d->prescribed[k], data, t, w->qp, err);
        if (rc) return rc;
        for (int j = 0; j < m; ++j) memcpy(&q[3 * (off + idx[j])], &w->qp[3 * j], 3 * sizeof(double));
    }
    return PL_OK;
}

void pl_dynamics_scatter(const pl_dynamics *d, const pl_dyn_work *w, pl_data *data,
                         const double *q, double damping)
{
    double scale = 1.0 / (1.0 + d->h * damping);
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = state_ops(d->states[k]);
        pl_buffer x = ops->positions(d->states[k], data), v = ops->velocities(d->states[k], data);
        double *px = pl_buffer_f64(&x), *pv = pl_buffer_f64(&v);
        int off = ops->offset(d->states[k]);
        for (size_t i = 0; i < 3 * x.rows; ++i) {
            size_t g = 3 * (size_t)off + i;
            pv[i] = scale * (q[g] - w->q_t[g]) / d->h;
            px[i] = q[g];
        }
    }
}

double pl_dynamics_energy(const pl_dynamics *d, const pl_dyn_work *w, const pl_data *data,
                          const double *q)
{
    double e = 0.0, h2 = d->h * d->h;
    const double *sn = w->sn;
    for (int i = 0; i < d->n; ++i) {
        if (d->free_index[i] < 0) continue;
        double dx = q[3 * i] - sn[3 * i], dy = q[3 * i + 1] - sn[3 * i + 1],
               dz = q[3 * i + 2] - sn[3 * i + 2];
        e += 0.5 * d->inertia[i] * (dx * dx + dy * dy + dz * dz) / h2;
    }
    if (d->L.p) { /* (rS/(2h)) q^T L q: the dissipation potential, less a constant */
        double qlq = 0.0;
        for (int j = 0; j < d->L.ncols; ++j)
            for (int p = d->L.p[j]; p < d->L.p[j + 1]; ++p) {
                const double *a = &q[3 * d->L.i[p]], *b = &q[3 * j];
                qlq += d->L.x[p] * (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
            }
        e += 0.5 * d->scheme.rayleigh_stiffness / d->h * qlq;
    }
    pl_buffer qb = pl_buffer_host_f64((double *)q, (size_t)d->n, 3);
    for (int k = 0; k < d->nterms; ++k) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[k], PL_ROLE_LOCAL_TERM);
        e += ops->energy(d->terms[k], data, d->term_offset[k], &qb);
    }
    return e;
}

void pl_dynamics_reduce_rhs(const pl_dynamics *d, pl_dyn_work *w, const double *rhs,
                            const double *q)
{
    for (int f = 0; f < d->nfree; ++f)
        memcpy(&w->b_free[3 * f], &rhs[3 * d->free_vertex[f]], 3 * sizeof(double));
    /* - A_fp q_p: columns of A_fp are global vertices, non-empty only when prescribed */
    for (int j = 0; j < d->n; ++j)
        for (int p = d->A_fp.p[j]; p < d->A_fp.p[j + 1]; ++p) {
            int f = d->A_fp.i[p];
            for (int c = 0; c < 3; ++c) w->b_free[3 * f + c] -= d->A_fp.x[p] * q[3 * j + c];
        }
}

double pl_dynamics_bbox_diagonal(const double *q, int n)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], q[3 * i + k]);
            hi[k] = fmax(hi[k], q[3 * i + k]);
        }
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return d2 > 0 ? sqrt(d2) : 1.0;
}

void pl_dynamics_store_forces(const pl_dynamics *d, pl_dyn_work *w, pl_data *data,
                              const pl_rows *rows, const double *lambda)
{
    memset(w->rhs, 0, (size_t)d->n * 3 * sizeof(double));
    if (rows && lambda && rows->n) pl_rows_add_transpose(rows, lambda, 1.0, w->rhs);
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = state_ops(d->states[k]);
        if (!ops->constraint_forces) continue;
        pl_buffer f = ops->constraint_forces(d->states[k], data);
        double *pf = pl_buffer_f64(&f);
        if (pf) memcpy(pf, &w->rhs[3 * ops->offset(d->states[k])], f.rows * 3 * sizeof(double));
    }
}
