/* incidence.h - vertex -> slot incidence (internal).  A term's parallel loop
 * writes one 3-vector per slot (an element corner, a stencil entry); a
 * gather over vertices then sums each vertex's slots in increasing order,
 * so the result is deterministic and no two threads write one vertex. */
#ifndef PLIANT_HYPER_INCIDENCE_H
#define PLIANT_HYPER_INCIDENCE_H

/* Builds *vptr (nverts + 1) and *vinc (nslots): the slots s with
 * vert[s] == v are vinc[vptr[v] .. vptr[v+1]-1], increasing.  vert values
 * must lie in [0, nverts).  Returns 0, or -1 on allocation failure. */
int hyper_incidence_build(int nverts, int nslots, const int *vert, int **vptr, int **vinc);

/* out[offset + v] += sum of the 3-vectors vals[s] over v's slots. */
void hyper_incidence_gather(int nverts, const int *vptr, const int *vinc, const double *vals,
                            int offset, double *out);

#endif
