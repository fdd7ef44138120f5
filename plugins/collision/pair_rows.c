/* pair_rows.c - the rows of a contact between two collision models (both
 * deformable, or one an obstacle): one Signorini row along the normal and
 * two Coulomb rows along the tangents, over the DOFs of both sides with
 * opposite signs (PAPER_NOTES items 5, 9, 10). */
#include <math.h>

#include "collision.h"

/* The merged coefficient of every vertex: +w on side a, -w on side b. */
typedef struct merged {
    int n;
    int vertex[2 * PL_CONTACT_SIDE_MAX];
    double coef[2 * PL_CONTACT_SIDE_MAX];
} merged;

static void merge_side(merged *m, const pl_contact_side *s, double sign)
{
    for (int a = 0; a < s->n; ++a) {
        int k = 0;
        while (k < m->n && m->vertex[k] != s->vertex[a]) k++;
        if (k == m->n) {
            m->vertex[m->n] = s->vertex[a];
            m->coef[m->n++] = 0.0;
        }
        m->coef[k] += sign * s->weight[a];
    }
}

/* Largest |coefficient| first (ties: lower vertex): a row's first entry is
 * its dominant vertex, which is what warm starts key on. */
static void sort_merged(merged *m)
{
    for (int i = 1; i < m->n; ++i) {
        int v = m->vertex[i];
        double c = m->coef[i];
        int j = i - 1;
        while (j >= 0 && (fabs(m->coef[j]) < fabs(c) ||
                          (fabs(m->coef[j]) == fabs(c) && m->vertex[j] > v))) {
            m->vertex[j + 1] = m->vertex[j];
            m->coef[j + 1] = m->coef[j];
            j--;
        }
        m->vertex[j + 1] = v;
        m->coef[j + 1] = c;
    }
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int add_row(pl_rows *rows, const pl_component *owner, pl_row_kind kind, const merged *m,
                   const double c[3], double d)
{
    int r = pl_rows_begin(rows, kind, owner);
    if (r < 0) return -1;
    for (int k = 0; k < m->n; ++k) {
        double w = m->coef[k];
        if (w == 0.0) continue;
        if (pl_rows_add(rows, m->vertex[k], w * c[0], w * c[1], w * c[2]) != 0) return -1;
    }
    rows->d[r] = d;
    return r;
}

int collision_emit_pair(pl_rows *rows, const pl_component *owner, const pl_contact_side *a,
                           const pl_contact_side *b, const double n[3], double mu,
                           double contact_distance, double t1[3], double t2[3])
{
    merged m = {0};
    merge_side(&m, a, 1.0);
    merge_side(&m, b, -1.0);
    double total = 0.0;
    for (int k = 0; k < m.n; ++k) total += fabs(m.coef[k]);
    if (!(total > 1e-12)) return -2;
    sort_merged(&m);
    contact_tangents(n, t1, t2);
    double fx[3], fv[3];
    for (int k = 0; k < 3; ++k) {
        fx[k] = b->fixed[k] - a->fixed[k];
        fv[k] = b->fixed_v[k] - a->fixed_v[k];
    }
    int rn = add_row(rows, owner, PL_ROW_NORMAL, &m, n, contact_distance + dot3(n, fx));
    if (rn < 0) return -1;
    int r1 = add_row(rows, owner, PL_ROW_FRICTION, &m, t1, dot3(t1, fv));
    if (r1 < 0) return -1;
    int r2 = add_row(rows, owner, PL_ROW_FRICTION, &m, t2, dot3(t2, fv));
    if (r2 < 0) return -1;
    rows->mu[rn] = mu;
    rows->pair[rn] = r1;
    rows->pair[r1] = rn;
    rows->pair[r2] = rn;
    return rn;
}
