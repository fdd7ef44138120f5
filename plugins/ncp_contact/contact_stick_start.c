/* contact_stick_start.c - the multipliers of contacts that begin a step
 * without force (new contacts; every contact of the first step from rest).
 *
 * Why.  The warm start (contact_warmstart.c) gives a persisting contact last
 * step's force, and the Newton iteration then converges in one or two
 * iterations.  A contact without history starts at lambda = 0, where the
 * friction cone mu lambda_n is empty: the first Newton step treats its
 * friction as inactive (lambda_f stays 0, ncp_eval_friction) and only the
 * normal force appears.  From there the friction force grows by a fixed
 * fraction per iteration (its compliance is frozen in each Newton step and
 * the contact still slips, DERIVATION.md section 6): on a box resting on a
 * 25 degree slope the friction reached 91% of its static value after the 10
 * local-global iterations of the first step and 99% after 100 Newton steps
 * with b fixed.  The missing part leaves a slip velocity (5 mm/s) that the
 * following steps only brake at g cos(theta) (mu - tan theta): near the
 * stick/slip threshold the box then creeps far enough to be counted as
 * sliding (docs/contact.md, "First step of a resting contact").
 *
 * What.  At the first iteration of a step, the contacts without force whose
 * free motion closes them (delta_n < 0 at the linearisation point
 * delta = delta_free + h^2 W lambda) get the forces that hold them still:
 * normal AND friction rows as equalities,
 *     h^2 W_SS dlambda_S = -delta_S        (S: those contacts' rows),
 * solved by conjugate residual (Jacobi-scaled, as the Newton step), then
 * projected onto the cone (lambda_n >= 0, |lambda_f| <= mu lambda_n).  For a
 * contact that sticks this is the solution of the step's constraint
 * problem; for one that slides it puts the friction on the cone against the
 * motion.  The Newton iterations then start next to the solution, as they
 * do from a warm start. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact.h"

typedef struct sub_operator {
    const pl_ncp_operator *W;
    int m, n;
    const int *rows;          /* n: the selected rows */
    const double *d;          /* n: Jacobi scaling (h^2 W_jj)^-1/2 */
    double h2;
    double *x, *y;            /* m: full-size scratch */
} sub_operator;

/* y = D P (h^2 W) P^T D x over the selected rows. */
static int apply_sub(void *user, const double *x, double *y)
{
    sub_operator *o = user;
    memset(o->x, 0, sizeof(double) * (size_t)o->m);
    for (int k = 0; k < o->n; ++k) o->x[o->rows[k]] = o->d[k] * x[k];
    int st = ncp_operator_apply(o->W, o->x, o->y);
    for (int k = 0; k < o->n; ++k) y[k] = o->h2 * o->d[k] * o->y[o->rows[k]];
    return st;
}

/* Normal rows of contacts without force that the free motion closes, with
 * their friction rows: the row list (returns its length).  The friction rows
 * of normal row j are chained from first[j] through next[] (one pass over the
 * rows, not one per contact: the first step of a scene with 9k contacts). */
static int select_rows(const pl_ncpc_rows *r, const double *delta, const double *lambda,
                       int *first, int *next, int *list)
{
    int m = r->m, n = 0;
    for (int j = 0; j < m; ++j) first[j] = -1;
    for (int k = m - 1; k >= 0; --k) /* backwards: each chain in increasing row order */
        if (r->kind[k] == PL_ROW_FRICTION && r->pair[k] >= 0) {
            next[k] = first[r->pair[k]];
            first[r->pair[k]] = k;
        }
    for (int j = 0; j < m; ++j) {
        if (r->kind[j] != PL_ROW_NORMAL || lambda[j] != 0.0 || !(delta[j] < 0.0)) continue;
        int quiet = 1;
        for (int k = first[j]; k >= 0; k = next[k]) quiet &= lambda[k] == 0.0;
        if (!quiet) continue;
        list[n++] = j;
        if (r->mu && r->mu[j] > 0.0)
            for (int k = first[j]; k >= 0; k = next[k]) list[n++] = k;
    }
    return n;
}

/* A contact whose holding force lies outside its cone slides.  Its friction
 * starts strictly inside the cone: on the boundary with no slip (y = 0,
 * |lambda_f| = mu lambda_n) Fischer-Burmeister's friction is 0/0, taken as
 * stick (e = 0), and the Newton steps then push lambda_f outside the cone,
 * whence it returns only slowly (the compliance there is proportional to the
 * excess): a box on a 25 degree slope with mu = tan - 0.002 stayed put.  1%
 * inside, the contact slips a little and the iterations reach the boundary
 * from inside (that box: 9.5 mm in 1 s, 9.0 mm analytic; 0.999 still stuck,
 * 0.95 to 0.995 gave 10.9 to 9.0 mm). */
#define INSIDE_CONE 0.99

/* Solves of the active set at most (each drops the contacts pushed apart). */
#define MAX_ROUNDS 4

/* lambda_n >= 0 and |lambda_f| <= mu lambda_n on the selected contacts
 * (INSIDE_CONE of it where the holding force exceeded the cone). */
static void project(const pl_ncpc_rows *r, const int *list, int n, double *lambda)
{
    for (int a = 0; a < n; ++a) {
        int j = list[a];
        if (r->kind[j] != PL_ROW_NORMAL) continue;
        if (lambda[j] < 0.0) lambda[j] = 0.0;
        double cap = r->mu ? r->mu[j] * lambda[j] : 0.0, t2 = 0.0;
        for (int b = a + 1; b < n && r->kind[list[b]] == PL_ROW_FRICTION; ++b)
            t2 += lambda[list[b]] * lambda[list[b]];
        double t = sqrt(t2), f = t > cap ? (t > 0.0 ? INSIDE_CONE * cap / t : 0.0) : 1.0;
        for (int b = a + 1; b < n && r->kind[list[b]] == PL_ROW_FRICTION; ++b) lambda[list[b]] *= f;
    }
}

int ncpc_stick_start(const pl_ncpc_rows *r, const pl_ncp_operator *W, double h,
                        const double *delta_free, double *lambda, int cr_iterations,
                        pl_error *err)
{
    int m = r->m;
    if (m == 0) return 0;
    size_t mm = (size_t)m;
    double *delta = malloc(sizeof(double) * mm), *x = malloc(sizeof(double) * mm),
           *y = malloc(sizeof(double) * mm), *b = malloc(sizeof(double) * mm),
           *z = calloc(mm, sizeof(double)), *d = malloc(sizeof(double) * mm),
           *work = malloc(sizeof(double) * 4 * mm);
    int *list = malloc(sizeof(int) * mm), *first = malloc(sizeof(int) * mm),
        *next = malloc(sizeof(int) * mm), n = 0, st = PL_OK;
    if (!delta || !x || !y || !b || !z || !d || !work || !list || !first || !next) {
        st = pl_error_set(err, PL_EINTERNAL, NULL, 0, "ncp_contact", "out of memory");
        goto done;
    }
    /* the linearisation point of the first Newton step */
    if ((st = ncp_operator_apply(W, lambda, delta)) != PL_OK) goto done;
    for (int j = 0; j < m; ++j) delta[j] = delta_free[j] + h * h * delta[j];
    n = select_rows(r, delta, lambda, first, next, list);
    if (n == 0) goto done;
    /* active set: a contact the others push apart (lambda_n <= 0: a separating
     * contact, or one of two nearly dependent rows, which come with large
     * opposite multipliers) leaves the set, and the rest is solved again */
    int rounds = 0, changed = 1;
    while (n > 0 && changed) {
        if (++rounds > MAX_ROUNDS) {
            n = 0;
            break;
        }
        for (int k = 0; k < n; ++k) {
            double wjj = W->diag ? h * h * W->diag[list[k]] : 0.0;
            d[k] = wjj > 0.0 ? 1.0 / sqrt(wjj) : 1.0;
            b[k] = -d[k] * delta[list[k]];
            z[k] = 0.0;
        }
        sub_operator op = {W, m, n, list, d, h * h, x, y};
        pl_error cr_err;
        if (ncp_cr(n, apply_sub, &op, b, z, cr_iterations, 1e-12, work, NULL, NULL, &cr_err) !=
            PL_OK) {
            n = 0; /* a breakdown: the Newton iterations start from lambda as it is */
            break;
        }
        changed = 0;
        int kept = 0;
        for (int k = 0; k < n;) {
            int e = k + 1; /* the contact's rows: list[k] (normal) .. list[e - 1] */
            while (e < n && r->kind[list[e]] == PL_ROW_FRICTION) ++e;
            int keep = d[k] * z[k] > 0.0;
            changed |= !keep;
            for (int a = k; a < e && keep; ++a) {
                list[kept] = list[a];
                z[kept] = z[a];
                d[kept++] = d[a];
            }
            k = e;
        }
        n = kept;
    }
    for (int k = 0; k < n; ++k) lambda[list[k]] += d[k] * z[k];
    project(r, list, n, lambda);
done:
    free(delta);
    free(x);
    free(y);
    free(b);
    free(z);
    free(d);
    free(work);
    free(list);
    free(first);
    free(next);
    return st == PL_OK ? n : -st;
}
