/* ncp_operator.c - the W operator (dense or matrix-free) and the
 * complementarity scaling r of Section 5.4. */
#include "ncp.h"

#include <math.h>

int ncp_operator_apply(const pl_ncp_operator *W, const double *x, double *y)
{
    int m = W->m;
    if (!W->dense)
        return W->apply ? W->apply(W->user, x, y) : PL_EINPUT;
    /* Rows are independent: each thread writes its own y[i] (deterministic). */
#pragma omp parallel for schedule(static) if (m >= 512)
    for (int i = 0; i < m; ++i) {
        const double *row = W->dense + (size_t)i * (size_t)m;
        double s = 0.0;
        for (int j = 0; j < m; ++j)
            s += row[j] * x[j];
        y[i] = s;
    }
    return PL_OK;
}

int ncp_scaling(const pl_ncp_work *w, const double *diag, double h, double *r, pl_error *err)
{
    if (!(h > 0.0))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_scaling", "time step h = %g must be > 0", h);
    for (int j = 0; j < w->m; ++j) {
        pl_row_kind k = w->rows.kind[j];
        if (k != PL_ROW_BILATERAL && !(diag[j] > 0.0 && isfinite(diag[j])))
            return pl_error_set(err, PL_EINPUT, NULL, 0, "ncp_scaling",
                                "row %d: diagonal %g must be finite and > 0", j, diag[j]);
        r[j] = h * h * diag[j];
    }
    /* One friction scaling per contact (PAPER_NOTES 9): h times the mean of
     * its tangent diagonals, on both rows. */
    for (int c = 0; c < w->nc; ++c) {
        const int *ct = w->contact + 3 * c;
        int nt = 0;
        double sum = 0.0;
        for (int i = 1; i <= 2; ++i)
            if (ct[i] >= 0) {
                sum += diag[ct[i]];
                ++nt;
            }
        for (int i = 1; i <= 2; ++i)
            if (ct[i] >= 0)
                r[ct[i]] = h * sum / nt;
    }
    return PL_OK;
}
