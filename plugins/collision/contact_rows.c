/* contact_rows.c - the rows of one point-versus-obstacle contact (Appendix A,
 * PAPER_NOTES items 5, 9, 10): a Signorini row along the outward normal and
 * two Coulomb rows along orthonormal tangents, paired, and the contact force
 * recovered from their multipliers. */
#include "collision.h"

static int add_row(pl_rows *rows, const pl_component *owner, pl_row_kind kind, int nv,
                   const int *vertex, const double *weight, const double c[3], double d)
{
    int r = pl_rows_begin(rows, kind, owner);
    if (r < 0) return -1;
    for (int a = 0; a < nv; ++a) {
        double w = weight[a];
        if (pl_rows_add(rows, vertex[a], w * c[0], w * c[1], w * c[2]) != 0) return -1;
    }
    rows->d[r] = d;
    return r;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

int collision_emit_contact(pl_rows *rows, const pl_component *owner, int nv, const int *vertex,
                              const double *weight, const double p[3], const double n[3],
                              const double vs[3], double mu, double contact_distance,
                              double t1[3], double t2[3])
{
    contact_tangents(n, t1, t2);
    /* delta = n . x - (n . p + contactDistance): the gap beyond contactDistance */
    int rn = add_row(rows, owner, PL_ROW_NORMAL, nv, vertex, weight, n,
                     dot3(n, p) + contact_distance);
    if (rn < 0) return -1;
    /* d_f = t . v_s: h dot(delta_f) = H_f (q - q_t) - h d_f is the slip relative
     * to the moving surface */
    int r1 = add_row(rows, owner, PL_ROW_FRICTION, nv, vertex, weight, t1, dot3(t1, vs));
    if (r1 < 0) return -1;
    int r2 = add_row(rows, owner, PL_ROW_FRICTION, nv, vertex, weight, t2, dot3(t2, vs));
    if (r2 < 0) return -1;
    rows->mu[rn] = mu;
    rows->pair[rn] = r1;
    rows->pair[r1] = rn;
    rows->pair[r2] = rn;
    return rn;
}

void collision_contact_forces(pl_obstacle_contact *c, int ncontacts, const double *lambda)
{
    for (int k = 0; k < ncontacts; ++k) {
        const double *l = &lambda[3 * k];
        for (int i = 0; i < 3; ++i) {
            c[k].lambda[i] = l[i];
            c[k].force[i] = l[0] * c[k].normal[i] + l[1] * c[k].t1[i] + l[2] * c[k].t2[i];
        }
    }
}
