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

int pl_regression_compare(const pl_state_records *ref, const pl_state_records *cur, int nstates,
                          double time_tol, double epsilon, pl_regression_result *res,
                          pl_error *err)
{
    if (!ref || !cur || !res || nstates <= 0 || !(time_tol > 0) || !(epsilon >= 0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "regression comparison needs states, time_tol > 0 and epsilon >= 0");
    pl_regression_result r = {0};
    for (int s = 0; s < nstates; ++s) {
        double by_dof = 0.0, total = 0.0;
        for (int k = 0; k < ref[s].count; ++k) {
            const pl_state_record *a = &ref[s].items[k];
            int j = nearest_record(&cur[s], a->time);
            if (j < 0 || !(fabs(cur[s].items[j].time - a->time) < time_tol)) {
                r.missing++;
                continue;
            }
            const pl_state_record *b = &cur[s].items[j];
            if (a->nx != b->nx)
                return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                    "state %d at T= %g: the reference has %d values, the "
                                    "current run %d",
                                    s, a->time, a->nx, b->nx);
            if (a->nx == 0) continue; /* an empty state has nothing to compare */
            double e = pl_regression_step_error(b->x, a->x, a->nx);
            by_dof += e;
            total += e * a->nx;
            r.compared++;
        }
        r.error_by_dof += by_dof;
        r.total_error += total;
    }
    r.error_by_dof /= nstates;
    r.total_error /= nstates;
    r.passed = r.compared > 0 && r.missing == 0 && isfinite(r.error_by_dof) &&
               r.error_by_dof <= epsilon;
    *res = r;
    return PL_OK;
}
