/* contact_device_pack.c - a step's rows packed into one device arena (see
 * contact_device_pack.h). */
#include "contact_device_pack.h"

#include <stdlib.h>
#include <string.h>

static void *put(ncpc_pack *k, const void *src, size_t bytes)
{
    size_t at = k->at;
    k->at = (at + bytes + 15) & ~(size_t)15;
    if (k->host && src && bytes) memcpy(k->host + at, src, bytes);
    return k->dev ? k->dev + at : NULL;
}

void ncpc_pack_layout(pl_ncp_cuda_rows *R, int jacobian, const pl_ncpc_device_step *st,
                      const pl_system *sys, const int *kind, const int *tr, ncpc_pack *k)
{
    const pl_ncpc_rows *r = st->rows;
    int m = r->m, nc = st->work->nc, nfe = r->fstart[m], npe = r->pstart[m], nf = sys->nfree;
    put(k, NULL, sizeof *R); /* the device copy of R, at offset 0 (filled by upload) */
    R->m = m, R->nc = nc, R->nall = st->nall, R->nfree = nf;
    R->kind = put(k, kind, sizeof(int) * (size_t)m);
    R->contact = put(k, st->work->contact, sizeof(int) * 3 * (size_t)nc);
    R->full = put(k, r->full, sizeof(int) * (size_t)m);
    R->fstart = put(k, r->fstart, sizeof(int) * ((size_t)m + 1));
    R->fcol = put(k, r->fcol, sizeof(int) * (size_t)nfe);
    R->pstart = put(k, r->pstart, sizeof(int) * ((size_t)m + 1));
    R->pvert = put(k, r->pvert, sizeof(int) * (size_t)npe);
    R->tptr = put(k, tr, sizeof(int) * ((size_t)nf + 1));
    R->tent = put(k, tr ? tr + nf + 1 : NULL, sizeof(int) * (size_t)nfe);
    R->erow = put(k, tr ? tr + nf + 1 + nfe : NULL, sizeof(int) * (size_t)nfe);
    R->fvert = jacobian ? put(k, sys->free_vertex, sizeof(int) * (size_t)nf) : NULL;
    R->fcoef = put(k, r->fcoef, sizeof(double) * 3 * (size_t)nfe);
    R->pcoef = put(k, r->pcoef, sizeof(double) * 3 * (size_t)npe);
    size_t mb = sizeof(double) * (size_t)m;
    R->offset = put(k, r->offset, mb);
    R->mu = put(k, r->mu, mb);
    R->compliance = put(k, r->compliance, mb);
    R->lo = put(k, r->lo, mb);
    R->hi = put(k, r->hi, mb);
    R->r = put(k, st->r, mb);
    R->wdiag = put(k, st->D->diag, mb);
    /* the warm start, copied into the work vectors by upload */
    k->lambda = put(k, st->lambda, mb);
    k->lambda_all = put(k, st->lambda_all, sizeof(double) * (size_t)st->nall);
}

int *ncpc_pack_transpose(const pl_ncpc_rows *r, int nfree)
{
    int m = r->m, nfe = r->fstart[m];
    int *t = calloc((size_t)nfree + 1 + 2 * (size_t)nfe + 1, sizeof(int));
    int *next = malloc(sizeof(int) * ((size_t)nfree + 1));
    if (!t || !next) return free(t), free(next), NULL;
    int *tptr = t, *tent = t + nfree + 1, *erow = tent + nfe;
    for (int e = 0; e < nfe; ++e) tptr[r->fcol[e] + 1]++;
    for (int f = 0; f < nfree; ++f) tptr[f + 1] += tptr[f];
    memcpy(next, tptr, sizeof(int) * (size_t)nfree);
    for (int j = 0; j < m; ++j)
        for (int e = r->fstart[j]; e < r->fstart[j + 1]; ++e) {
            tent[next[r->fcol[e]]++] = e;
            erow[e] = j;
        }
    free(next);
    return t;
}
