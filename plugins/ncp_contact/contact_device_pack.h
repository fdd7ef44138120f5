/* contact_device_pack.h - the device path's step inputs (contact_device.c):
 * the rows, their transpose, the scaling and the warm start packed into one
 * device arena, each array at a 16-byte aligned offset, so that one copy
 * from one page-locked buffer sends them all. */
#ifndef PLIANT_CONTACT_DEVICE_PACK_H
#define PLIANT_CONTACT_DEVICE_PACK_H

#include <stddef.h>

#include "contact_device.h"
#include "ncp_cuda.h"

typedef struct ncpc_pack {
    size_t at;                   /* bytes laid out so far */
    char *host;                  /* NULL: only measure */
    char *dev;                   /* the arena's device address (NULL: only measure) */
    double *lambda, *lambda_all; /* where the warm start went (device) */
} ncpc_pack;

/* Lays out (and, when k->host is set, fills) the inputs, setting R's device
 * pointers (R itself goes at offset 0); tr is ncpc_pack_transpose's array;
 * jacobian: the free vertices are needed (not full_force). */
void ncpc_pack_layout(pl_ncp_cuda_rows *R, int jacobian, const pl_ncpc_device_step *st,
                      const pl_system *sys, const int *kind, const int *tr, ncpc_pack *k);

/* The transpose of the free entries: per unknown, its entries in increasing
 * order, and each entry's row (tptr, tent, erow: nfree + 1, nfe, nfe ints in
 * one malloc'd array), or NULL when out of memory. */
int *ncpc_pack_transpose(const pl_ncpc_rows *r, int nfree);

#endif
