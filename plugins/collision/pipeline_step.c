/* pipeline_step.c - the three per-step stages of the CollisionPipeline:
 * model geometry at both ends of the step, detection over the pairs of
 * models, and the rows and records of the proximities found. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision.h"
#include "models.h"
#include "pipeline.h"

/* (Re)allocates a model's per-point arrays when its topology changed. */
static int fit_model(pipe_model *m)
{
    const pl_collision_geometry *g = &m->g;
    if (m->x0 && g->nverts == m->nverts && g->ntris == m->ntris && g->nedges == m->nedges &&
        g->tris == m->tris && g->edges == m->edges)
        return PL_OK;
    coll_mesh_free(&m->mesh);
    coll_mesh_init(&m->mesh);
    free(m->x0);
    free(m->x1);
    free(m->active);
    size_t n = (size_t)(g->nverts ? g->nverts : 1);
    m->x0 = malloc(n * 3 * sizeof *m->x0);
    m->x1 = malloc(n * 3 * sizeof *m->x1);
    m->active = malloc(n);
    m->nverts = g->nverts;
    m->ntris = g->ntris;
    m->nedges = g->nedges;
    m->tris = g->tris;
    m->edges = g->edges;
    return (m->x0 && m->x1 && m->active) ? PL_OK : PL_EINTERNAL;
}

/* x0 / x1 over the step and which points carry a free DOF.  A deformable
 * point is predicted where its inertia and gravity take it, x + h v + h^2 g
 * (the solver's own initial guess): a falling body's motion over the step
 * is then exact until it touches. */
static void fill_positions(pipe_model *m, const pl_system *sys)
{
    const pl_collision_geometry *g = &m->g;
    double h = sys->h, grav[3] = {0.0, 0.0, 0.0};
    if (!g->is_obstacle) pl_node_gravity(m->c->node, grav);
    for (int i = 0; i < g->nverts; ++i) {
        for (int k = 0; k < 3; ++k) {
            double x = g->x[3 * i + k], v = g->v ? g->v[3 * i + k] : 0.0;
            /* obstacles are posed at t + h, deformables given at t */
            m->x0[3 * i + k] = g->is_obstacle ? x - h * v : x;
            m->x1[3 * i + k] = g->is_obstacle ? x : x + h * v + h * h * grav[k];
        }
        unsigned char act = 0;
        for (int a = 0; a < 4 && !g->is_obstacle; ++a) {
            int v = g->map_vertex[4 * i + a];
            if (v >= 0 && v < sys->nverts && (!sys->free_index || sys->free_index[v] >= 0)) act = 1;
        }
        m->active[i] = act;
    }
}

int coll_pipeline_update_models(const collision_pipeline *p, coll_ws *w, pl_ctx *ctx,
                                const pl_system *sys, const pl_buffer *q, pl_error *err)
{
    for (int k = 0; k < p->nmodels; ++k) {
        pipe_model *m = &w->models[k];
        const pl_collision_model_ops *ops = pl_component_role(m->c, PL_ROLE_COLLISION_MODEL);
        memset(&m->g, 0, sizeof m->g);
        int rc = ops->update(m->c, ctx, q, &m->g, err);
        if (rc) return rc;
        if (m->g.nverts > 0 && (!m->g.x || !m->g.map_vertex || !m->g.map_weight))
            return pl_component_fail(&p->base, err, PL_EINTERNAL,
                                     "collision model '%s' gave no positions or mapping",
                                     m->c->name);
        if (fit_model(m)) return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
        fill_positions(m, sys);
    }
    for (int k = 0; k < p->nmodels; ++k) {
        pipe_model *m = &w->models[k];
        pl_coll_mesh *cm = &m->mesh;
        cm->nverts = m->g.nverts;
        cm->ntris = m->g.ntris;
        cm->nedges = m->g.nedges;
        cm->x0 = m->x0;
        cm->x1 = m->x1;
        cm->tris = m->g.tris;
        cm->edges = m->g.edges;
        cm->active = m->active;
        cm->sides = coll_model_sides(m->c);
        /* boxes reach alarm / 2: what the first pass of detection keeps
         * (coll_pipeline_detect widens them for the pairs it measures
         * again).  They were inflated by the largest speed at which another
         * body might strike this one, bounded by the models' velocity
         * spreads: a cookie's arms springing back after a plate's hole
         * (gingerbread_small.xml) made boxes of 86 mm instead of 10, 17x
         * the candidates and 15x the time of detection, in steps where no
         * third body struck anything (docs/benchmarks.md, spikes). */
        pl_error e;
        int rc;
        if ((rc = coll_mesh_prepare(cm, p->alarm, &e)))
            return pl_component_fail(&p->base, err, rc, "collision model '%s': %s", m->c->name,
                                     e.msg);
    }
    return PL_OK;
}

static int any_active(const pipe_model *m)
{
    for (int i = 0; i < m->g.nverts; ++i)
        if (m->active[i]) return 1;
    return 0;
}

/* The sides of the previous step's contacts (in d: exact on restore). */
static int build_hints(const collision_pipeline *p, coll_ws *w, const pl_data *d)
{
    const coll_contact_record *items;
    int n = coll_pipeline_contacts(&p->base, d, &items);
    return side_hints_build_strided(&w->hints, n > 0 ? &items[0].prox : NULL, sizeof *items, n);
}

/* Whether models k and l are a pair to detect. */
static int is_pair(const collision_pipeline *p, const coll_ws *w, int k, int l)
{
    const pipe_model *a = &w->models[k], *b = &w->models[l];
    if (a->g.ntris == 0 && b->g.ntris == 0) return 0; /* points against points */
    if (a->g.is_obstacle && b->g.is_obstacle) return 0;
    if (l == k && (!p->self || a->g.is_obstacle)) return 0;
    if (a->g.groups & b->g.groups) return 0; /* they share a group */
    return any_active(a) || any_active(b);
}

/* The speed at which each model strikes each other one in this step: the
 * largest approach speed -n . (motion_a - motion_b) / h of the closest
 * points of their proximities at the predictions (0 when they only
 * separate).  It is measured where they touch, so a body gripped by
 * another and turning with it is not struck, however fast its rim moves
 * (a bound from the models' velocity spreads made every pair of a turning
 * gripper look struck at the rim speed). */
static void struck_speeds(const collision_pipeline *p, coll_ws *w, double h)
{
    int n = p->nmodels;
    memset(w->struck, 0, (size_t)n * (size_t)n * sizeof *w->struck);
    for (int k = 0; k < w->prox.n; ++k) {
        const pl_proximity *x = &w->prox.items[k];
        const pipe_model *ma = &w->models[x->model_a], *mb = &w->models[x->model_b];
        double u = 0.0;
        for (int i = 0; i < 3; ++i) {
            double m = 0.0;
            for (int j = 0; j < x->na; ++j)
                m += x->wa[j] * (ma->x1[3 * x->a[j] + i] - ma->x0[3 * x->a[j] + i]);
            for (int j = 0; j < x->nb; ++j)
                m -= x->wb[j] * (mb->x1[3 * x->b[j] + i] - mb->x0[3 * x->b[j] + i]);
            u -= x->normal[i] * m / h;
        }
        double *ab = &w->struck[x->model_a * n + x->model_b];
        double *ba = &w->struck[x->model_b * n + x->model_a];
        *ab = fmax(*ab, u);
        *ba = fmax(*ba, u);
    }
}

/* The fastest strike on model k by a model other than k and l [m/s]. */
static double struck_by_third(const coll_ws *w, int n, int k, int l)
{
    double u = 0.0;
    for (int j = 0; j < n; ++j)
        if (j != k && j != l) u = fmax(u, w->struck[k * n + j]);
    return u;
}

/* Pair i of this step is (k, l); PL_OK or PL_EINTERNAL. */
static int push_pair(coll_ws *w, int i, int k, int l)
{
    if (2 * i + 2 > w->cap_pairs) {
        int cap = 2 * i + 16;
        int *x = realloc(w->pairs, (size_t)cap * sizeof *x);
        if (!x) return PL_EINTERNAL;
        w->pairs = x;
        w->cap_pairs = cap;
    }
    w->pairs[2 * i] = k;
    w->pairs[2 * i + 1] = l;
    return PL_OK;
}

/* Drops the proximities between models k and l (order kept). */
static void drop_pair(pl_proximities *px, int k, int l)
{
    int m = 0;
    for (int i = 0; i < px->n; ++i) {
        const pl_proximity *x = &px->items[i];
        if ((x->model_a == k && x->model_b == l) || (x->model_a == l && x->model_b == k)) continue;
        px->items[m++] = *x;
    }
    px->n = m;
}

int coll_pipeline_detect(const collision_pipeline *p, coll_ws *w, const pl_data *d, double h,
                         pl_error *err)
{
    w->prox.n = 0;
    w->last_overlaps = w->counts.candidates; /* PLIANT_DETECT=auto's rule */
    memset(&w->counts, 0, sizeof w->counts);
    w->margin_max = 0.0;
    if (build_hints(p, w, d))
        return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
    pl_detect_params prm = detect_defaults(p->alarm);
    prm.contact = p->contact;
    prm.hints = &w->hints;
    prm.vertex_face = p->vertex_face;
    prm.edge_edge = p->edge_edge;
    prm.max_per_vertex = p->max_per_vertex;
    prm.counts = &w->counts;
    /* every pair at its prediction */
    prm.margin = 0.0;
    int n = 0;
    for (int k = 0; k < p->nmodels; ++k)
        for (int l = k; l < p->nmodels; ++l)
            if (is_pair(p, w, k, l) && push_pair(w, n++, k, l))
                return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
    int rc = coll_detect_pairs(p, w, n, w->pairs, &prm, err);
    if (rc) return rc;
    /* a model struck by a third one in this step may be pushed up to that
     * speed times h beyond its prediction: its pairs again, that much
     * farther */
    struck_speeds(p, w, h);
    for (int k = 0; k < p->nmodels; ++k)
        for (int l = k; l < p->nmodels; ++l) {
            if (!is_pair(p, w, k, l)) continue;
            prm.margin = h * fmax(struck_by_third(w, p->nmodels, k, l),
                                  struck_by_third(w, p->nmodels, l, k));
            if (!(prm.margin > 0.0)) continue;
            /* a pair is kept when it comes within alarm + margin during the
             * step: boxes inflated by half that each overlap then */
            coll_mesh_inflate(&w->models[k].mesh, p->alarm + prm.margin);
            coll_mesh_inflate(&w->models[l].mesh, p->alarm + prm.margin);
            w->margin_max = fmax(w->margin_max, prm.margin);
            drop_pair(&w->prox, k, l);
            if ((rc = coll_detect_models(p, w, k, l, &prm, err))) return rc;
        }
    return PL_OK;
}

static double pair_mu(const collision_pipeline *p, double a, double b)
{
    if (a < 0.0 && b < 0.0) return p->mu;
    if (a < 0.0) return b;
    if (b < 0.0) return a;
    switch (p->rule) {
    case COLL_RULE_MAX: return a > b ? a : b;
    case COLL_RULE_MEAN: return 0.5 * (a + b);
    case COLL_RULE_PRODUCT: return a * b;
    default: return a < b ? a : b;
    }
}

/* One side of a proximity: the DOF entries of its points (mapped through the
 * model) and the fixed part of the points without DOFs; point = the closest
 * point at the start of the step. */
static int make_side(const pipe_model *m, int nv, const int *v, const double *w,
                     pl_contact_side *s, double point[3])
{
    memset(s, 0, sizeof *s);
    point[0] = point[1] = point[2] = 0.0;
    for (int j = 0; j < nv; ++j) {
        int i = v[j];
        for (int k = 0; k < 3; ++k) point[k] += w[j] * m->x0[3 * i + k];
        int has_dof = 0;
        for (int a = 0; a < 4 && !m->g.is_obstacle; ++a) {
            int g = m->g.map_vertex[4 * i + a];
            if (g < 0) continue;
            has_dof = 1;
            double wg = w[j] * m->g.map_weight[4 * i + a];
            int e = 0;
            while (e < s->n && s->vertex[e] != g) e++;
            if (e == s->n) {
                if (s->n == PL_CONTACT_SIDE_MAX) return PL_EINTERNAL;
                s->vertex[s->n] = g;
                s->weight[s->n++] = 0.0;
            }
            s->weight[e] += wg;
        }
        if (!has_dof)
            for (int k = 0; k < 3; ++k) {
                s->fixed[k] += w[j] * m->x1[3 * i + k];
                s->fixed_v[k] += w[j] * (m->g.v ? m->g.v[3 * i + k] : 0.0);
            }
    }
    return PL_OK;
}

/* Room for `more` records after the w->nwork kept. */
static int fit_records(coll_ws *w, int more)
{
    if (w->nwork + more <= w->capwork) return 0;
    int cap = w->capwork ? 2 * w->capwork : 256;
    while (cap < w->nwork + more) cap *= 2;
    coll_contact_record *grown = realloc(w->work, (size_t)cap * sizeof *grown);
    if (!grown) return 1;
    w->work = grown;
    w->capwork = cap;
    return 0;
}

/* What emit_prepare found for a contact. */
enum { EMIT_ROWS = 0, EMIT_NONE = -2 /* nothing movable (collision_pair_prepare) */,
       EMIT_TOO_MANY = 1 /* more DOFs than a side holds */, EMIT_OUTSIDE = 2 /* a bad vertex */ };

/* A contact prepared by a thread (emit_prepare) for the ordered append. */
typedef struct emit_item {
    pl_pair_rows pr;
    double pa[3], pb[3];
    int status;                /* EMIT_* */
    int bad_model, bad_vertex; /* EMIT_OUTSIDE's */
    int nent;                  /* EMIT_ROWS': its rows' entries (collision_pair_entries) */
    int row, entry, record;    /* EMIT_ROWS': where its rows and record go */
} emit_item;

/* Contact k's sides and rows, prepared without touching anything shared. */
static void emit_prepare(const collision_pipeline *p, const coll_ws *w, const pl_system *sys,
                         int k, emit_item *e)
{
    const pl_proximity *x = &w->prox.items[k];
    const pipe_model *ma = &w->models[x->model_a], *mb = &w->models[x->model_b];
    pl_contact_side sa, sb;
    e->status = EMIT_ROWS;
    if (make_side(ma, x->na, x->a, x->wa, &sa, e->pa) || make_side(mb, x->nb, x->b, x->wb, &sb, e->pb)) {
        e->status = EMIT_TOO_MANY;
        return;
    }
    const pl_contact_side *side[2] = {&sa, &sb};
    for (int s = 0; s < 2; ++s)
        for (int a = 0; a < side[s]->n; ++a)
            if (side[s]->vertex[a] >= sys->nverts) {
                e->status = EMIT_OUTSIDE, e->bad_model = s ? x->model_b : x->model_a;
                e->bad_vertex = side[s]->vertex[a];
                return;
            }
    e->status = collision_pair_prepare(&e->pr, &sa, &sb, x->normal, p->contact);
    e->nent = e->status == EMIT_ROWS ? collision_pair_entries(&e->pr) : 0;
}

/* Contacts emitted by one thread below this many (waking the team costs
 * more than preparing them). */
#define EMIT_PAR_MIN 2048

/* A contact's rows and record (x its proximity), written where the ordered
 * pass put them. */
static void emit_write(const collision_pipeline *p, coll_ws *w, const emit_item *e,
                       const pl_proximity *x, pl_rows *rows)
{
    const pipe_model *ma = &w->models[x->model_a], *mb = &w->models[x->model_b];
    collision_pair_write(rows, &p->base, &e->pr, pair_mu(p, ma->g.mu, mb->g.mu), e->row,
                         e->entry);
    coll_contact_record *r = &w->work[e->record];
    memset(r, 0, sizeof *r);
    r->prox = *x;
    memcpy(r->point_a, e->pa, sizeof e->pa);
    memcpy(r->point_b, e->pb, sizeof e->pb);
    memcpy(r->t1, e->pr.t1, sizeof e->pr.t1);
    memcpy(r->t2, e->pr.t2, sizeof e->pr.t2);
}

/* The contacts' rows and records: prepared by the threads; then one pass in
 * the contacts' order gives each its rows, entries and record (and stops
 * at the first bad one); then the threads write them there.  The rows are
 * the serial append's, in its order (collision_pair_append), bitwise. */
int coll_pipeline_emit(const collision_pipeline *p, coll_ws *w, const pl_system *sys,
                       pl_rows *rows, pl_error *err)
{
    int n = w->prox.n;
    if (n > w->capemit) {
        emit_item *e = realloc(w->emit, (size_t)n * sizeof *e);
        if (!e) return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
        w->emit = e;
        w->capemit = n;
    }
    emit_item *items = w->emit;
#pragma omp parallel for schedule(dynamic, 64) if (n > EMIT_PAR_MIN)
    for (int k = 0; k < n; ++k) emit_prepare(p, w, sys, k, &items[k]);
    int row = rows->n, entry = rows->nent, record = w->nwork;
    for (int k = 0; k < n; ++k) {
        emit_item *e = &items[k];
        if (e->status == EMIT_TOO_MANY)
            return pl_component_fail(&p->base, err, PL_EINTERNAL,
                                     "a contact touches more than %d DOFs", PL_CONTACT_SIDE_MAX);
        if (e->status == EMIT_OUTSIDE)
            return pl_component_fail(&p->base, err, PL_EINTERNAL,
                                     "collision model '%s' maps to vertex %d outside the "
                                     "system (%d vertices)",
                                     w->models[e->bad_model].c->name, e->bad_vertex, sys->nverts);
        if (e->status == EMIT_NONE) continue;
        e->row = row, e->entry = entry, e->record = record++;
        row += 3;
        entry += e->nent;
    }
    if (pl_rows_reserve(rows, row - rows->n, entry - rows->nent) ||
        fit_records(w, record - w->nwork))
        return pl_component_fail(&p->base, err, PL_EINTERNAL, "out of memory");
#pragma omp parallel for schedule(dynamic, 64) if (n > EMIT_PAR_MIN)
    for (int k = 0; k < n; ++k)
        if (items[k].status == EMIT_ROWS) emit_write(p, w, &items[k], &w->prox.items[k], rows);
    rows->n = row;
    rows->nent = entry;
    if (rows->start) rows->start[row] = entry; /* no start: no row was ever reserved */
    w->nwork = record;
    return PL_OK;
}
