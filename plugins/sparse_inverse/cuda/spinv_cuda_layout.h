/* spinv_cuda_layout.h - the device layout of S = L^-1 and the work lists of
 * the two product kernels, built on the host (plain C, testable without a
 * GPU).  Internal to the CUDA backend.
 *
 * Values: row i of S is stored for the columns f0 .. e, f0 = first[i]
 * rounded down and e = i rounded up to whole blocks of 8 columns, the
 * padding zero; S(i, j) = val[meta[i].vbase + j].  Every row starts on a
 * multiple of 8 values, so a 16-byte vector of columns c .. c+vc-1 (vc = 4
 * in float32, 2 in float64, c a multiple of vc) is aligned and lies either
 * wholly inside [f0, e] or wholly outside.
 *
 * y = S a, items of kind ROWS: one warp takes the blocks lo .. hi-1 (from
 * their common f0) of the pad rows idx .. idx+pad-1, consecutive rows with
 * one padded first column (an etree chain: a separator), at most `group`:
 * each 16-byte piece of a is read once for all of them, which cuts the
 * traffic for a by the group size.  A group longer than one item is split;
 * its parts are summed by the last warp to finish.  Kind SHORT: lane l of
 * one warp takes the whole row short_rows[idx + l], l < lo (rows of at
 * most SHORT_BLOCKS blocks).
 *
 * z = S^T y, items of kind TILE, one thread block each (its 8 warps split
 * the rows): the columns idx*tile .. idx*tile+tile-1, rows tilerows[lo ..
 * hi-1]; a tile with more rows is split, its parts summed by the last
 * block to finish.  A tile's row list is its own rows then the etree
 * ancestors of its last column: exactly the rows that meet it.  Each entry
 * carries the row's metadata, so a warp needs one load per row before it
 * can load the row's values. */
#ifndef PLIANT_SPINV_CUDA_LAYOUT_H
#define PLIANT_SPINV_CUDA_LAYOUT_H

#include <stdint.h>
#include <stddef.h>
#include "pliant/error.h"
#include "sparse_inverse.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PL_SPINV_CUDA_BLOCK 8          /* columns per padding block */
#define PL_SPINV_CUDA_SHORT_BLOCKS 4   /* rows of <= 4 blocks go one per lane */
#define PL_SPINV_CUDA_GROUP_MAX 8      /* rows of S one ROWS item may take (1, 2, 4 or 8) */
#define PL_SPINV_CUDA_ITEM_BYTES 4096  /* default: bytes of each row a ROWS item reads */
#define PL_SPINV_CUDA_TILE_ROWS 128    /* rows one block (8 warps) takes per tile item */

enum { PL_SPINV_ITEM_ROWS = 0, PL_SPINV_ITEM_SHORT = 1, PL_SPINV_ITEM_TILE = 2 };

/* One warp's (ROWS, SHORT) or one block's (TILE) work, 32 bytes.  part: this item's
 * partial-sum slot, -1 when the row or tile is not split; part0 .. part0 +
 * nparts - 1: the slots of its row or tile, summed in that order. */
typedef struct pl_spinv_cuda_item {
    int32_t kind, idx, lo, hi, part, part0, nparts, pad;
} pl_spinv_cuda_item;

/* Row metadata (16 bytes, one vector load). */
typedef struct pl_spinv_cuda_rowmeta {
    int64_t vbase; /* S(i, j) = val[vbase + j] for f0 <= j <= e */
    int32_t f0, e;
} pl_spinv_cuda_rowmeta;

/* One row of a tile's list: the row's metadata inline (e = row | 7). */
typedef struct pl_spinv_cuda_tilerow {
    int64_t vbase;
    int32_t f0, row;
} pl_spinv_cuda_tilerow;

typedef struct pl_spinv_cuda_layout {
    int n, npad;          /* npad: n rounded up to a block (rows of the a buffer) */
    int vc;               /* columns per 16-byte vector: 4 (float32) or 2 (float64) */
    int tile;             /* columns per S^T tile: 32 * vc */
    int ntiles;
    int64_t nval;         /* padded values */
    pl_spinv_cuda_rowmeta *meta;   /* n */
    pl_spinv_cuda_item *items_S;   /* nitems_S: ROWS and SHORT items */
    int nitems_S, nparts_S;        /* a part slot holds group x 4 values */
    int group;                     /* rows per ROWS item at most: 1, 2, 4 or 8 */
    int item_blocks;               /* blocks (of the group's columns) per ROWS item */
    int *short_rows;               /* nshort rows, in row order */
    int nshort;
    pl_spinv_cuda_item *items_ST;  /* nitems_ST: TILE items */
    int nitems_ST, nparts_ST;
    pl_spinv_cuda_tilerow *rowlist; /* nrowlist rows of the tiles */
    int64_t nrowlist;
} pl_spinv_cuda_layout;

/* Builds the layout for values of elem_size bytes (8 or 4), with groups of
 * at most `group` rows (1, 2, 4, 8; 0: the default) and ROWS items of
 * item_blocks blocks (0: ITEM_BYTES of one row).  PL_EINTERNAL on
 * allocation failure or when ST does not list ancestor paths; PL_EINPUT
 * on a bad group. */
int spinv_cuda_layout_build(const pl_spinv_profile *S, const pl_spinv_runs *ST,
                               int elem_size, int group, int item_blocks,
                               pl_spinv_cuda_layout *L, pl_error *err);
/* The default group size: pairs of rows were fastest on an H100 in both
 * precisions (1, 2, 4, 8 measured: docs/benchmarks.md, GPU section). */
#define PL_SPINV_CUDA_GROUP_DEFAULT 2
/* The padded values (nval) in float64 or float32. */
void spinv_cuda_layout_fill_f64(const pl_spinv_cuda_layout *L, const pl_spinv_profile *S,
                                   double *val);
void spinv_cuda_layout_fill_f32(const pl_spinv_cuda_layout *L, const pl_spinv_profile *S,
                                   float *val);
void spinv_cuda_layout_free(pl_spinv_cuda_layout *L);

/* The single-block solve of small systems (spinv_cuda_small.cu) is used
 * when n <= SMALL_N, S's padded values take <= SMALL_BYTES, no row of S is
 * split (nparts_S = 0) and its shared memory (spinv_cuda_small_shmem: a, y
 * and the tile sums) is at most shmem_max, the device's per-block limit.
 * SMALL_BYTES: one block reads the values twice a solve; on the H100 a solve
 * in a graph chain took 5.4 / 6.1 / 11.5 us as one block against 8.6 / 8.2
 * / 9.9 us as three launches with 19 / 43 / 110 KB of values (float64;
 * gpu_bench chain, docs/benchmarks.md): the crossing is near 80 KB. */
#define PL_SPINV_CUDA_SMALL_N 512
#define PL_SPINV_CUDA_SMALL_BYTES (64 * 1024)
#define PL_SPINV_CUDA_SMALL_RED_BYTES (4 * 8 * 32 * 48) /* 4 groups of 8 warps, 48 B a lane */
size_t spinv_cuda_small_shmem(int n, int elem_size);
int spinv_cuda_small_fits(int n, int64_t nval, int nparts_S, int elem_size, int shmem_max);

#ifdef __cplusplus
}
#endif
#endif
