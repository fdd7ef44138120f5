/* local_global_solver.c - LocalGlobalSolver: implicit Euler by local-global
 * iterations (the paper's Algorithms 1-2): each iteration projects every
 * local term in parallel (local step), assembles the right-hand side
 *     b = M sn + h^2 sum w G^T (p - u)  (restricted to the unknowns, - A_fp q_p)
 * and solves the constant system A q = b with the scene's global solver
 * (the sparse inverse S^T S b, or Cholesky).  v = (q - q_t) / h.
 *
 * With constraints (Algorithm 4): once per step every constraint component
 * appends its rows of H; when there are rows, the contact solver builds W
 * and, in each iteration, replaces the plain global solve by the constrained
 * one (lambda update and corrected positions).  The multipliers go back to
 * the components that emitted the rows.
 *
 * device = "cuda" (or "auto" with a CudaDevice in the scene) runs the
 * iterations on the GPU through the device service: local_global_device.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "local_global.h"
#include "solver.h"

static const char *const device_choices[] = {"cpu", "cuda", "auto", NULL};
static const char *const guess_choices[] = {"prediction", "inertia", NULL};
static const char *const residual_choices[] = {"auto", "on", "off", NULL};

static const pl_field FIELDS[] = {
    PL_FIELD(local_global_solver, iterations, "iterations", PL_F_INT, "5",
             "local-global iterations per time step (the maximum when tolerance > 0)", 0),
    PL_FIELD(local_global_solver, tolerance, "tolerance", PL_F_DOUBLE, "0",
             "run to tolerance: stop when the largest position change of an iteration is below "
             "tolerance times the bounding-box diagonal (0: always run `iterations`)",
             PL_FIELD_RUNTIME),
    PL_FIELD(local_global_solver, force_tolerance, "forceTolerance", PL_F_DOUBLE, "0",
             "run to equilibrium: stop when the force residual (the largest norm over free "
             "vertices of m_i (q_i - s_i) / h^2 - f_int,i(q) - (H^T lambda)_i) is below it [N] "
             "(0: not used; with "
             "tolerance > 0 too, both must hold); costs one gradient evaluation per iteration; "
             "the iterations then run on the CPU",
             PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(local_global_solver, compute_residual, "computeResidual", residual_choices,
                  "auto",
                  "record the force residual [N] at the end of each step (series \"force "
                  "residual\" and statistic \"force residual max\" in the timings, phase "
                  "\"Residual\"; one gradient evaluation per step, on the CPU): on, off, or auto "
                  "(on when the iterations run on the CPU and every local term has a gradient; "
                  "off on the device, where that host evaluation would cost more than the frame)",
                  PL_FIELD_RUNTIME),
    PL_FIELD_ENUM(local_global_solver, initial_guess, "initialGuess", guess_choices, "prediction",
                  "q^0 of each step's iterations: prediction (sn = q_t + h v_t + h^2 g, the "
                  "paper's) or inertia (q_t + h v_t: a body held against gravity, e.g. a soft "
                  "robot at rest, is already in equilibrium there: with forceTolerance 1e-3 N the "
                  "resting finger of cable_finger_small.xml took 1 iteration a step instead of "
                  "133, docs/scenes.md)",
                  PL_FIELD_RUNTIME),
    PL_FIELD(local_global_solver, damping, "damping", PL_F_DOUBLE, "0",
             "Rayleigh-style mass damping [1/s]: v <- v / (1 + h damping)", PL_FIELD_INPUT),
    PL_FIELD(local_global_solver, first_order, "firstOrder", PL_F_BOOL, "0",
             "first-order backward Euler, SOFA's EulerImplicitSolver firstOrder: M (q - q_t) / h "
             "= f(q), no velocity carried from step to step (the output velocity is (q - q_t) / "
             "h); the system's mass term becomes h M",
             0),
    PL_FIELD(local_global_solver, rayleigh_stiffness, "rayleighStiffness", PL_F_DOUBLE, "0",
             "Rayleigh stiffness damping rS [s]: the force -rS L v with L = sum w G^T G, the "
             "rest stiffness of the system (SOFA damps with the current tangent K; L also "
             "damps the rigid rotation of a body with no fixed vertex); the system becomes M + "
             "(h^2 + h rS) L",
             0),
    PL_FIELD(local_global_solver, compute_energy, "computeEnergy", PL_F_BOOL, "0",
             "record the incremental potential after each iteration (series \"energy\" in the "
             "timings file; \"energy0\": at the initial guess of each step; costs one energy "
             "evaluation per iteration)",
             PL_FIELD_RUNTIME),
    PL_FIELD(local_global_solver, solver_link, "solver", PL_F_LINK, NULL,
             "the global solver (default: the first one in this node or below)", 0),
    PL_FIELD(local_global_solver, contact_link, "contactSolver", PL_F_LINK, NULL,
             "the constraint solver (default: the first one in this node or below, if any)", 0),
    PL_FIELD_ENUM(local_global_solver, device, "device", device_choices, "auto",
                  "where the iterations run: cpu; cuda (needs <CudaDevice/> in this node or above, "
                  "a global solver and local terms that take device buffers and, with constraints, "
                  "a contact solver with a device path); auto (cuda when all of that holds, else "
                  "cpu: a scene with a CudaDevice runs on the GPU)",
                  0),
};

typedef struct collect {
    pl_component **items;
    int n;
} collect;

static int collect_one(pl_component *c, void *user)
{
    collect *l = user;
    pl_component **items = realloc(l->items, (size_t)(l->n + 1) * sizeof *items);
    if (!items) return 1;
    l->items = items;
    l->items[l->n++] = c;
    return 0;
}

static int find_first(pl_component *c, void *user)
{
    *(pl_component **)user = c;
    return 1;
}

/* L damps rigid rotation (SOFA's tangent K does not): said once per state
 * with no prescribed vertex. */
static void warn_unfixed(local_global_solver *s, pl_ctx *ctx)
{
    const pl_dynamics *d = &s->dyn;
    for (int k = 0; k < d->nstates; ++k) {
        const pl_state_ops *ops = pl_component_role(d->states[k], PL_ROLE_STATE);
        int off = ops->offset(d->states[k]), n = ops->count(d->states[k]), fixed = 0;
        for (int i = off; i < off + n && !fixed; ++i) fixed = d->free_index[i] < 0;
        if (!fixed)
            pl_component_warn(&s->base, ctx,
                              "rayleighStiffness: %s has no fixed vertex; the damping matrix "
                              "(the rest stiffness L) also damps its rigid rotation, which "
                              "SOFA's (the current tangent K) does not",
                              d->states[k]->name);
    }
}

static int lg_reinit(pl_component *c, pl_ctx *ctx)
{
    local_global_solver *s = (local_global_solver *)c;
    pl_error err;
    s->ready = 0;
    pl_lg_device_free(s);
    pl_dynamics_free(&s->dyn);
    if (s->iterations < 1) return pl_component_error(c, ctx, PL_EINPUT, "iterations must be >= 1");
    if (s->tolerance < 0) return pl_component_error(c, ctx, PL_EINPUT, "tolerance must be >= 0");
    pl_work_limits lim;
    pl_work_limits_of(ctx->model, c->node, &lim);
    if (pl_work_limit_check(c, ctx, s->iterations, lim.max_iterations,
                            "iterations (per time step)", "maxIterations"))
        return PL_EINPUT;
    if (!(s->force_tolerance >= 0))
        return pl_component_error(c, ctx, PL_EINPUT, "forceTolerance must be >= 0 [N], got %g",
                                  s->force_tolerance);
    free(s->constraints);
    s->constraints = NULL;
    collect cl = {NULL, 0};
    if (pl_node_visit_role(c->node, PL_ROLE_CONSTRAINT, collect_one, &cl))
        return pl_component_error(c, ctx, PL_EINTERNAL, "out of memory");
    s->constraints = cl.items;
    s->nconstraints = cl.n;
    s->contact = s->contact_link.target;
    if (!s->contact) pl_node_visit_role(c->node, PL_ROLE_CONTACT_SOLVER, find_first, &s->contact);
    if (s->contact && !pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER))
        return pl_component_error(c, ctx, PL_EINPUT, "contactSolver: '%s' is not a contact solver",
                                  s->contact->name);
    if (s->nconstraints && !s->contact)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the scene has %d constraint component(s) but no contact solver "
                                  "(add <NonSmoothNewtonContactSolver/> with <RequiredPlugin "
                                  "name=\"ncp_contact\"/>)",
                                  s->nconstraints);
    s->solver = s->solver_link.target;
    if (!s->solver) pl_node_visit_role(c->node, PL_ROLE_GLOBAL_SOLVER, find_first, &s->solver);
    if (!s->solver || !pl_component_role(s->solver, PL_ROLE_GLOBAL_SOLVER))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "needs a global solver (e.g. <SparseInverseSolver/> with "
                                  "<RequiredPlugin name=\"sparse_inverse\"/>)");
    const pl_global_solver_ops *ops = pl_component_role(s->solver, PL_ROLE_GLOBAL_SOLVER);
    char path[256];
    if (s->nconstraints && ops->version >= 4 && ops->approximate && ops->approximate(s->solver))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "the global solver %s (%s) only approximates A^-1 b, and the "
                                  "scene's %d constraint component(s) need W = H A^-1 H^T: use "
                                  "an exact global solver (SparseInverseSolver)",
                                  pl_component_path(s->solver, path, sizeof path),
                                  s->solver->type->name, s->nconstraints);
    if (!(s->rayleigh_stiffness >= 0))
        return pl_component_error(c, ctx, PL_EINPUT, "rayleighStiffness must be >= 0 [s], got %g",
                                  s->rayleigh_stiffness);
    pl_dyn_scheme scheme = {s->first_order, s->rayleigh_stiffness};
    int rc = pl_dynamics_setup(&s->dyn, c, ctx, pl_node_dt(c->node), 1, &scheme);
    if (rc) return rc;
    if (s->rayleigh_stiffness > 0) warn_unfixed(s, ctx);
    s->dyn.sys.global_solver = s->solver;
    if (s->dyn.nfree > 0 && (rc = ops->factor(s->solver, &s->dyn.A_ff, ctx->timers, &err))) {
        pl_diag_add(ctx->diag, &err);
        return rc;
    }
    s->t_local = pl_timer_id(ctx->timers, "Local");
    s->t_assembly = pl_timer_id(ctx->timers, "Assembly");
    s->t_global = pl_timer_id(ctx->timers, "Global");
    s->t_residual = pl_timer_id(ctx->timers, "Residual");
    s->t_rows = s->nconstraints ? pl_timer_id(ctx->timers, "Rows") : -1;
    if ((rc = pl_lg_device_setup(s, ctx))) return rc;
    s->t_queue = s->gpu.dev ? pl_timer_id(ctx->timers, "Device queue") : -1;
    s->t_wait = s->gpu.dev ? pl_timer_id(ctx->timers, "Device wait") : -1;
    /* computeResidual: 0 auto, 1 on, 2 off */
    s->report_residual = s->compute_residual == 1 ||
                         (s->compute_residual == 0 && !s->gpu.dev &&
                          pl_force_residual_possible(&s->dyn));
    if ((s->report_residual || s->force_tolerance > 0) &&
        (rc = pl_force_residual_check(&s->dyn, c, ctx)))
        return rc;
    pl_log_info("LocalGlobalSolver: %d vertices (%d unknowns), %d local terms, %d iterations%s",
                s->dyn.n, s->dyn.nfree, s->dyn.nterms, s->iterations,
                s->gpu.dev ? ", on the device" : "");
    s->ready = 1;
    return PL_OK;
}

static void lg_destroy(pl_component *c)
{
    local_global_solver *s = (local_global_solver *)c;
    pl_lg_device_free(s);
    pl_dynamics_free(&s->dyn);
    free(s->constraints);
}

static void lg_workspace_free(const pl_component *c, void *ws)
{
    lg_ws *w = ws;
    (void)c;
    pl_lg_device_ws_free(w);
    pl_dyn_work_free(&w->w);
    pl_rows_free(&w->rows);
    pl_force_residual_free(&w->res);
}

/* This data's workspace, made for the model on first use; NULL with err
 * set when memory runs out. */
static lg_ws *workspace(const local_global_solver *s, pl_data *d, pl_error *err)
{
    lg_ws *ws = pl_data_workspace(d, &s->base);
    if (ws && !ws->ready) {
        if (pl_dyn_work_alloc(&ws->w, &s->dyn) != PL_OK) ws = NULL;
        else if (s->gpu.dev && pl_lg_device_ws_alloc(s, ws, err) != PL_OK) return NULL;
        else ws->ready = 1;
    }
    if (!ws) pl_component_fail(&s->base, err, PL_EINTERNAL, "out of memory (workspace)");
    return ws;
}

/* Rows of every constraint at the start of the step; the contact solver's
 * begin when there are any.  Returns the number of rows (or < 0).  Shared
 * with the device path (local_global.h). */
int pl_lg_begin_constraints(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    pl_rows_clear(&ws->rows);
    pl_buffer qt = pl_buffer_host_f64(ws->w.q_t, (size_t)d->n, 3);
    pl_timer_start(ctx->timers, s->t_rows);
    for (int k = 0; k < s->nconstraints; ++k) {
        const pl_constraint_ops *ops = pl_component_role(s->constraints[k], PL_ROLE_CONSTRAINT);
        int rc = ops->build_rows(s->constraints[k], ctx, &d->sys, &qt, &ws->rows, err);
        if (rc) return -rc;
    }
    pl_timer_stop(ctx->timers, s->t_rows);
    if (ws->rows.n == 0) return 0;
    const pl_contact_solver_ops *cs = pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER);
    int rc = cs->begin(s->contact, ctx, &d->sys, &ws->rows, &qt, err);
    return rc ? -rc : ws->rows.n;
}

/* Hands every constraint component the multipliers of its own rows. */
void pl_lg_end_constraints(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx)
{
    const pl_contact_solver_ops *cs = pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER);
    const pl_rows *rows = &ws->rows;
    int count = 0;
    const double *lambda = cs->multipliers(s->contact, ctx->data, &count);
    if (!lambda || count != rows->n) return;
    pl_dynamics_store_forces(&s->dyn, &ws->w, ctx->data, rows, lambda);
    for (int first = 0; first < rows->n;) {
        int last = first;
        while (last + 1 < rows->n && rows->owner[last + 1] == rows->owner[first]) last++;
        const pl_component *owner = rows->owner[first];
        const pl_constraint_ops *ops = owner ? pl_component_role(owner, PL_ROLE_CONSTRAINT) : NULL;
        if (ops && ops->accept_multipliers)
            ops->accept_multipliers(owner, ctx->data, rows, lambda, first, last - first + 1);
        first = last + 1;
    }
}

/* One local step: rhs <- M' sn + h^2 sum w G^T (p - u) (M' the inertia
 * masses, dynamics.h). */
static int local_step(const local_global_solver *s, pl_dyn_work *w, pl_ctx *ctx, pl_error *err)
{
    const pl_dynamics *d = &s->dyn;
    for (int i = 0; i < d->n; ++i)
        for (int k = 0; k < 3; ++k) w->rhs[3 * i + k] = d->inertia[i] * w->sn[3 * i + k];
    pl_buffer qb = pl_buffer_host_f64(w->q, (size_t)d->n, 3);
    pl_buffer rb = pl_buffer_host_f64(w->rhs, (size_t)d->n, 3);
    for (int t = 0; t < d->nterms; ++t) {
        const pl_local_term_ops *ops = pl_component_role(d->terms[t], PL_ROLE_LOCAL_TERM);
        int rc = ops->project(d->terms[t], ctx->data, d->term_offset[t], d->h * d->h, &qb, &rb, err);
        if (rc) return rc;
    }
    return PL_OK;
}

/* The force residual [N] at the current iterate w.q with the contact
 * solver's current multipliers (cs NULL: no constraint force); timed as
 * "Residual".  Shared with the device path (local_global.h). */
int pl_lg_residual(const local_global_solver *s, lg_ws *ws, pl_ctx *ctx,
                   const pl_contact_solver_ops *cs, double *out, pl_error *err)
{
    int count = 0;
    const double *lambda = cs ? cs->multipliers(s->contact, ctx->data, &count) : NULL;
    if (lambda && count != ws->rows.n) lambda = NULL;
    pl_timer_start(ctx->timers, s->t_residual);
    int rc = pl_force_residual_eval(&ws->res, &s->dyn, &ws->w, ctx->data, ws->w.q,
                                    lambda ? &ws->rows : NULL, lambda, out, err);
    pl_timer_stop(ctx->timers, s->t_residual);
    return rc;
}

/* The step's residual into the timings ("force residual" per step, its
 * maximum) and, when iterations stop on a tolerance, the iterations done. */
void pl_lg_record_residual(const local_global_solver *s, pl_ctx *ctx, double residual,
                           int iterations)
{
    if (!isnan(residual)) {
        pl_series_push(ctx->timers, "force residual", residual);
        pl_stat_max(ctx->timers, "force residual max", residual);
    }
    if (s->tolerance > 0 || s->force_tolerance > 0)
        pl_series_push(ctx->timers, "iterations", iterations);
}

static int lg_step(const pl_component *c, pl_ctx *ctx, double dt, pl_error *err)
{
    const local_global_solver *s = (const local_global_solver *)c;
    const pl_dynamics *d = &s->dyn;
    if (!s->ready) return pl_component_fail(c, err, PL_EINTERNAL, "not initialised");
    if (fabs(dt - d->h) > 1e-15 * d->h)
        return pl_component_fail(c, err, PL_EINPUT,
                                 "dt changed from %g to %g s: the system must be refactored "
                                 "(set dt before loading)",
                                 d->h, dt);
    lg_ws *ws = workspace(s, ctx->data, err);
    if (!ws) return err->code;
    if (s->gpu.dev) return pl_lg_device_step(s, ws, ctx, err);
    pl_dyn_work *w = &ws->w;
    const pl_global_solver_ops *gs = pl_component_role(s->solver, PL_ROLE_GLOBAL_SOLVER);
    pl_dynamics_begin(d, w, ctx->data, s->initial_guess); /* gather, predict, first guess */
    int rc = pl_dynamics_prescribe(d, w, ctx->data, ctx->data->time + d->h, w->q, err);
    if (rc) return rc;
    int nrows = 0;
    if (s->nconstraints) {
        nrows = pl_lg_begin_constraints(s, ws, ctx, err);
        if (nrows < 0) return -nrows;
    }
    const pl_contact_solver_ops *cs =
        nrows ? pl_component_role(s->contact, PL_ROLE_CONTACT_SOLVER) : NULL;
    pl_buffer qk = pl_buffer_host_f64(w->q, (size_t)d->n, 3);
    double scale = s->tolerance > 0 ? pl_dynamics_bbox_diagonal(w->q_t, d->n) : 1.0;
    if (s->compute_energy)
        pl_series_push(ctx->timers, "energy0", pl_dynamics_energy(d, w, ctx->data, w->q));
    pl_buffer bb = pl_buffer_host_f64(w->b_free, (size_t)d->nfree, 3);
    pl_buffer xb = pl_buffer_host_f64(w->q_free, (size_t)d->nfree, 3);
    /* an iterative global solver starts from the current iterate */
    int from_iterate = gs->version >= 4 && gs->solve_from;
    for (int f = 0; from_iterate && f < d->nfree; ++f)
        memcpy(&w->q_free[3 * f], &w->q[3 * d->free_vertex[f]], 3 * sizeof(double));
    int done = 0;
    double residual = NAN;
    for (int it = 0; it < s->iterations; ++it) {
        pl_timer_start(ctx->timers, s->t_local);
        rc = local_step(s, w, ctx, err);
        pl_timer_stop(ctx->timers, s->t_local);
        if (rc) return rc;
        pl_timer_start(ctx->timers, s->t_assembly);
        pl_dynamics_reduce_rhs(d, w, w->rhs, w->q);
        pl_timer_stop(ctx->timers, s->t_assembly);
        if (cs) {
            /* Algorithm 4: lambda update and corrected global step (timed inside) */
            rc = d->nfree ? cs->iterate(s->contact, ctx, &d->sys, &qk, &bb, &xb, err) : PL_OK;
        } else {
            pl_timer_start(ctx->timers, s->t_global);
            if (d->nfree)
                rc = from_iterate ? gs->solve_from(s->solver, &bb, &xb, it, err)
                                  : gs->solve(s->solver, &bb, &xb, err);
            pl_timer_stop(ctx->timers, s->t_global);
        }
        if (rc) return rc;
        double change = 0.0;
        for (int f = 0; f < d->nfree; ++f)
            for (int k = 0; k < 3; ++k) {
                double *qi = &w->q[3 * d->free_vertex[f] + k], nv = w->q_free[3 * f + k];
                if (!isfinite(nv))
                    return pl_component_fail(c, err, PL_EINTERNAL,
                                             "the solution became NaN/inf at iteration %d of "
                                             "step %ld (vertex %d)",
                                             it + 1, ctx->data->step + 1, d->free_vertex[f]);
                double delta = fabs(nv - *qi);
                if (delta > change) change = delta;
                *qi = nv;
            }
        if (s->compute_energy)
            pl_series_push(ctx->timers, "energy", pl_dynamics_energy(d, w, ctx->data, w->q));
        done = it + 1;
        residual = NAN;
        if (s->force_tolerance > 0 && (rc = pl_lg_residual(s, ws, ctx, cs, &residual, err)))
            return rc;
        if (!(s->tolerance > 0 || s->force_tolerance > 0)) continue;
        if ((s->tolerance <= 0 || change < s->tolerance * scale) &&
            (s->force_tolerance <= 0 || residual < s->force_tolerance))
            break;
    }
    if (s->report_residual && isnan(residual) &&
        (rc = pl_lg_residual(s, ws, ctx, cs, &residual, err)))
        return rc;
    pl_lg_record_residual(s, ctx, residual, done);
    if (cs)
        pl_lg_end_constraints(s, ws, ctx);
    else if (s->nconstraints)
        pl_dynamics_store_forces(d, w, ctx->data, NULL, NULL); /* no contact this step */
    pl_dynamics_scatter(d, w, ctx->data, w->q, pl_input_double(ctx->data, c, &s->damping));
    return PL_OK;
}

static const pl_animation_loop_ops LOOP = {.version = PL_ANIMATION_LOOP_OPS_VERSION,
                                           .step = lg_step};

const pl_type pl_local_global_solver_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "LocalGlobalSolver",
    .help = "Implicit Euler by local-global iterations (Projective Dynamics / ADMM-PD) over the "
            "bodies below it, with a constant system solved by the scene's global solver.",
    .size = sizeof(local_global_solver),
    .workspace_size = sizeof(lg_ws),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.reinit = lg_reinit, .destroy = lg_destroy, .workspace_free = lg_workspace_free},
    .roles = {[PL_ROLE_ANIMATION_LOOP] = &LOOP},
};
