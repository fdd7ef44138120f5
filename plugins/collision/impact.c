/* impact.c - how far a collision model may move beyond its prediction in a
 * step.  A body's points are predicted at x + h v + h^2 g, which is exact
 * while nothing touches it; a body struck in this step by another (a ball
 * dropped on a resting one, a moving obstacle) is pushed by up to their
 * relative speed times h more than predicted, and its points near a third
 * surface must already have rows there.  The CollisionPipeline measures
 * that speed at the proximities of the struck pair (pipeline_step.c); an
 * analytic obstacle, which sees the other models only as boxes, takes the
 * difference of their mean velocities (this file). */
#include <math.h>
#include <string.h>

#include "collision.h"

/* The box and mean velocity in locals, min and max by comparison: fmin and
 * fmax are calls, and stores into r every vertex made a chain through
 * memory (a 3.3k-vertex model: about 200 us, now about 30; the same values
 * for finite coordinates but for the sign of a zero bound, which the box
 * tests do not see; the sums in the same order). */
void reach_of(const double *x, const double *v, int n, int is_obstacle, unsigned groups,
                 double h, const double grav[3], pl_reach *r)
{
    memset(r, 0, sizeof *r);
    r->groups = groups;
    r->n = n;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double mean[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double p = x[3 * i + k], u = v ? v[3 * i + k] : 0.0;
            /* obstacles are posed at t + h, bodies given at t */
            double a = is_obstacle ? p - h * u : p;
            double b = is_obstacle ? p : p + h * u + h * h * grav[k];
            double mn = a < b ? a : b, mx = a > b ? a : b;
            lo[k] = mn < lo[k] ? mn : lo[k];
            hi[k] = mx > hi[k] ? mx : hi[k];
            mean[k] += u / n;
        }
    for (int k = 0; k < 3; ++k) r->box.lo[k] = lo[k], r->box.hi[k] = hi[k], r->v[k] = mean[k];
}

/* Whether the boxes come within d of each other. */
static int near(const pl_aabb *a, const pl_aabb *b, double d)
{
    for (int k = 0; k < 3; ++k)
        if (a->lo[k] > b->hi[k] + d || b->lo[k] > a->hi[k] + d) return 0;
    return 1;
}

double hit_speed(const pl_reach *r, int n, int k, int except, double alarm)
{
    double u = 0.0;
    if (r[k].n == 0) return 0.0;
    for (int j = 0; j < n; ++j) {
        if (j == k || j == except || r[j].n == 0 || (r[j].groups & r[k].groups)) continue;
        if (!near(&r[j].box, &r[k].box, alarm)) continue;
        double d2 = 0.0;
        for (int i = 0; i < 3; ++i) d2 += (r[j].v[i] - r[k].v[i]) * (r[j].v[i] - r[k].v[i]);
        u = fmax(u, sqrt(d2));
    }
    return u;
}
