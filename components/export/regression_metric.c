/* regression_metric.c - SOFA's regression error measure.
 *
 * For each state, each reference step that the current run also recorded
 * adds ||x - x_ref||_2 / nDoF (nDoF = doubles in the state, 3 per vertex);
 * the sums are averaged over the states and the mean is checked against
 * epsilon (SOFA Regression: StateRegression_test / RegressionSceneData.py,
 * legacy mode, which is how the *.txt.gz references are compared). */
#include <math.h>

#include "export/export.h"

double pl_regression_step_error(const double *x, const double *x_ref, int n)
{
    if (n <= 0) return 0.0;
    /* scaled sum of squares: no overflow or underflow for extreme values */
    double scale = 0.0, ssq = 1.0;
    for (int i = 0; i < n; ++i) {
        double d = fabs(x[i] - x_ref[i]);
        if (d == 0.0) continue;
        if (isnan(d)) return NAN;
        if (scale < d) {
            ssq = 1.0 + ssq * (scale / d) * (scale / d);
            scale = d;
        } else {
            ssq += (d / scale) * (d / scale);
        }
    }
    return scale * sqrt(ssq) / n;
}

/* Index of the record of cur nearest in time to t, or -1 if cur is empty. */
static int nearest_record(const pl_state_records *cur, double t)
{
    int best = -1;
    double best_dt = INFINITY;
    for (int j = 0; j < cur->count; ++j) {
        double dt = fabs(cur->items[j].time - t);
        if (dt < best_dt) {
            best_dt = dt;
            best = j;
        }
    }
    return best;
}

/* Largest vertex distance between x and x_ref (n doubles, 3 per vertex);
 * *vertex: where. */
static double largest_distance(const double *x, const double *x_ref, int n, int *vertex)
{
    double best = 0.0;
    *vertex = 0;
    for (int i = 0; i + 2 < n; i += 3) {
        double d = sqrt((x[i] - x_ref[i]) * (x[i] - x_ref[i]) +
                        (x[i + 1] - x_ref[i + 1]) * (x[i + 1] - x_ref[i + 1]) +
                        (x[i + 2] - x_ref[i + 2]) * (x[i + 2] - x_ref[i + 2]));
        if (d > best || isnan(d)) {
            best = d;
            *vertex = i / 3;
            if (isnan(d)) break;
        }
    }
    return best;
}

/* Diagonal of the bounding box of n doubles (3 per vertex). */
static double box_diagonal(const double *x, int n)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i + 2 < n; i += 3)
        for (int j = 0; j < 3; ++j) lo[j] = fmin(lo[j], x[i + j]), hi[j] = fmax(hi[j], x[i + j]);
    if (n < 3) return 0.0;
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* One state: adds its compared steps to r, and keeps where it is worst. */
static int compare_state(const pl_state_records *ref, const pl_state_records *cur, int s,
                         double time_tol, pl_regression_result *r, pl_regression_detail *w,
                         pl_error *err)
{
    double by_dof = 0.0, total = 0.0, far = -1.0, far_time = 0.0;
    int far_vertex = 0;
    const pl_state_record *last = NULL, *last_cur = NULL;
    for (int k = 0; k < ref->count; ++k) {
        const pl_state_record *a = &ref->items[k];
        int j = nearest_record(cur, a->time);
        if (j < 0 || !(fabs(cur->items[j].time - a->time) < time_tol)) {
            if (r->missing++ == 0) w->missing_state = s, w->missing_time = a->time;
            continue;
        }
        const pl_state_record *b = &cur->items[j];
        if (a->nx != b->nx)
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "state %d at T= %g: the reference has %d values, the "
                                "current run %d",
                                s, a->time, a->nx, b->nx);
        if (a->nx == 0) continue; /* an empty state has nothing to compare */
        double e = pl_regression_step_error(b->x, a->x, a->nx);
        by_dof += e;
        total += e * a->nx;
        r->compared++;
        int v;
        double d = largest_distance(b->x, a->x, a->nx, &v);
        if (d > far || isnan(d)) far = d, far_vertex = v, far_time = a->time;
        if (!last || a->time >= last->time) last = a, last_cur = b;
    }
    r->error_by_dof += by_dof;
    r->total_error += total;
    if (last) {
        int v;
        double diag = box_diagonal(ref->items[0].x, ref->items[0].nx);
        double rel = largest_distance(last_cur->x, last->x, last->nx, &v) / diag;
        /* a state of one point has no box: it has no relative error */
        if (diag > 0 && (isnan(w->last_relative) || rel > w->last_relative || isnan(rel)))
            w->last_relative = rel, w->last_time = last->time;
    }
    if (far >= 0 && (w->worst_state < 0 || by_dof > w->worst_state_error || isnan(by_dof))) {
        w->worst_state = s;
        w->worst_state_error = by_dof;
        w->worst_vertex = far_vertex;
        w->worst_distance = far;
        w->worst_time = far_time;
    }
    return PL_OK;
}

int pl_regression_compare(const pl_state_records *ref, const pl_state_records *cur, int nstates,
                          double time_tol, double epsilon, pl_regression_result *res,
                          pl_error *err)
{
    return pl_regression_compare_detail(ref, cur, nstates, time_tol, epsilon, res, NULL, err);
}

int pl_regression_compare_detail(const pl_state_records *ref, const pl_state_records *cur,
                                 int nstates, double time_tol, double epsilon,
                                 pl_regression_result *res, pl_regression_detail *why,
                                 pl_error *err)
{
    if (!ref || !cur || !res || nstates <= 0 || !(time_tol > 0) || !(epsilon >= 0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "regression comparison needs states, time_tol > 0 and epsilon >= 0");
    pl_regression_result r = {0};
    pl_regression_detail w = {0};
    w.worst_state = w.missing_state = -1;
    w.last_relative = NAN;
    for (int s = 0; s < nstates; ++s) {
        int rc = compare_state(&ref[s], &cur[s], s, time_tol, &r, &w, err);
        if (rc != PL_OK) return rc;
    }
    if (why) *why = w;
    r.error_by_dof /= nstates;
    r.total_error /= nstates;
    r.passed = r.compared > 0 && r.missing == 0 && isfinite(r.error_by_dof) &&
               r.error_by_dof <= epsilon;
    *res = r;
    return PL_OK;
}
