/* pair_rows.c - the rows of a contact between two collision models (both
 * deformable, or one an obstacle): one Signorini row along the normal and
 * two Coulomb rows along the tangents, over the DOFs of both sides with
 * opposite signs (PAPER_NOTES items 5, 9, 10). */
#include <math.h>

#include "collision.h"

/* Adds side s's entries to the merged coefficients of m's vertices (+w on
 * side a, -w on side b). */
static void merge_side(pl_pair_rows *m, const pl_contact_side *s, double sign)
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
static void sort_merged(pl_pair_rows *m)
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

/* Row r of kind `kind` along c from entry *e on (room reserved): m's
 * nonzero coefficients in their order. */
static void write_row(pl_rows *rows, const pl_component *owner, pl_row_kind kind,
                      const pl_pair_rows *m, const double c[3], double d, int r, int *e)
{
    pl_rows_put(rows, r, kind, owner, *e);
    for (int k = 0; k < m->n; ++k) {
        double w = m->coef[k];
        if (w == 0.0) continue;
        rows->vertex[*e] = m->vertex[k];
        rows->coef[3 * *e] = w * c[0];
        rows->coef[3 * *e + 1] = w * c[1];
        rows->coef[3 * *e + 2] = w * c[2];
        ++*e;
    }
    rows->d[r] = d;
}

int collision_pair_prepare(pl_pair_rows *pr, const pl_contact_side *a, const pl_contact_side *b,
                           const double n[3], double contact_distance)
{
    pr->n = 0;
    merge_side(pr, a, 1.0);
    merge_side(pr, b, -1.0);
    double total = 0.0;
    for (int k = 0; k < pr->n; ++k) total += fabs(pr->coef[k]);
    if (!(total > 1e-12)) return -2;
    sort_merged(pr);
    contact_tangents(n, pr->t1, pr->t2);
    double fx[3], fv[3];
    for (int k = 0; k < 3; ++k) {
        pr->normal[k] = n[k];
        fx[k] = b->fixed[k] - a->fixed[k];
        fv[k] = b->fixed_v[k] - a->fixed_v[k];
    }
    pr->d[0] = contact_distance + dot3(n, fx);
    pr->d[1] = dot3(pr->t1, fv);
    pr->d[2] = dot3(pr->t2, fv);
    return 0;
}

int collision_pair_entries(const pl_pair_rows *pr)
{
    int n = 0;
    for (int k = 0; k < pr->n; ++k) n += pr->coef[k] != 0.0;
    return 3 * n;
}

void collision_pair_write(pl_rows *rows, const pl_component *owner, const pl_pair_rows *pr,
                          double mu, int rn, int e)
{
    write_row(rows, owner, PL_ROW_NORMAL, pr, pr->normal, pr->d[0], rn, &e);
    write_row(rows, owner, PL_ROW_FRICTION, pr, pr->t1, pr->d[1], rn + 1, &e);
    write_row(rows, owner, PL_ROW_FRICTION, pr, pr->t2, pr->d[2], rn + 2, &e);
    rows->mu[rn] = mu;
    rows->pair[rn] = rn + 1;
    rows->pair[rn + 1] = rn;
    rows->pair[rn + 2] = rn;
}

int collision_pair_append(pl_rows *rows, const pl_component *owner, const pl_pair_rows *pr,
                          double mu)
{
    int ne = collision_pair_entries(pr), rn = rows->n;
    if (pl_rows_reserve(rows, 3, ne)) return -1;
    collision_pair_write(rows, owner, pr, mu, rn, rows->nent);
    rows->n += 3;
    rows->nent += ne;
    rows->start[rows->n] = rows->nent;
    return rn;
}

int collision_emit_pair(pl_rows *rows, const pl_component *owner, const pl_contact_side *a,
                           const pl_contact_side *b, const double n[3], double mu,
                           double contact_distance, double t1[3], double t2[3])
{
    pl_pair_rows pr;
    if (collision_pair_prepare(&pr, a, b, n, contact_distance)) return -2;
    for (int k = 0; k < 3; ++k) t1[k] = pr.t1[k], t2[k] = pr.t2[k];
    return collision_pair_append(rows, owner, &pr, mu);
}
