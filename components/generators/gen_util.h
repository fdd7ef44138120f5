/* gen_util.h - helpers shared by the generators (private). */
#ifndef PLIANT_GEN_UTIL_H
#define PLIANT_GEN_UTIL_H

#include "generators.h"

#define PL_GEN_HIDDEN __attribute__((visibility("hidden")))

/* Allocates out's arrays for the given counts (a freed mesh on failure);
 * PL_OK, or PL_EINPUT/PL_EINTERNAL with err set when too large or out of memory. */
PL_GEN_HIDDEN int pl_gen_alloc(pl_mesh *out, long long nverts, long long ntets,
                               long long ntris, pl_error *err);
/* Writes the 6 positively oriented Kuhn tetrahedra (24 ints) of a cell whose
 * corners are corner[x + 2y + 4z]; the shared diagonal runs from corner
 * `mirror` to corner `mirror ^ 7`. */
PL_GEN_HIDDEN void pl_gen_kuhn_cell(const int corner[8], int mirror, int *tets);

#endif
