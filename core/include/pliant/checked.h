/* checked.h - size arithmetic that cannot wrap.
 *
 * Every size a reader computes from numbers found in a file (counts times
 * widths, block counts times block sizes, sums of announced lengths) goes
 * through these helpers, so a hostile file cannot make a product wrap
 * around to a small, plausible value (a 2^63 block size times 2 is 0).
 * Each returns 0 and stores the exact result, or returns -1 (and stores
 * nothing) when the result does not fit its type.  One place, so that a
 * reviewer checks the arithmetic once. */
#ifndef PLIANT_CHECKED_H
#define PLIANT_CHECKED_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

static inline int pl_add_u64(uint64_t a, uint64_t b, uint64_t *out)
{
    uint64_t r;
    if (__builtin_add_overflow(a, b, &r)) return -1;
    *out = r;
    return 0;
}

static inline int pl_mul_u64(uint64_t a, uint64_t b, uint64_t *out)
{
    uint64_t r;
    if (__builtin_mul_overflow(a, b, &r)) return -1;
    *out = r;
    return 0;
}

/* a * b + c */
static inline int pl_muladd_u64(uint64_t a, uint64_t b, uint64_t c, uint64_t *out)
{
    uint64_t r;
    if (pl_mul_u64(a, b, &r) || pl_add_u64(r, c, &r)) return -1;
    *out = r;
    return 0;
}

static inline int pl_add_size(size_t a, size_t b, size_t *out)
{
    size_t r;
    if (__builtin_add_overflow(a, b, &r)) return -1;
    *out = r;
    return 0;
}

static inline int pl_mul_size(size_t a, size_t b, size_t *out)
{
    size_t r;
    if (__builtin_mul_overflow(a, b, &r)) return -1;
    *out = r;
    return 0;
}

/* Signed counts as files declare them (a negative product is an error too). */
static inline int pl_mul_i64(long long a, long long b, long long *out)
{
    long long r;
    if (__builtin_mul_overflow(a, b, &r)) return -1;
    *out = r;
    return 0;
}

static inline int pl_add_i64(long long a, long long b, long long *out)
{
    long long r;
    if (__builtin_add_overflow(a, b, &r)) return -1;
    *out = r;
    return 0;
}

/* n items of `item` bytes, plus `extra`: the argument of an allocation. */
static inline int pl_array_bytes(uint64_t n, size_t item, size_t extra, size_t *out)
{
    uint64_t r;
    if (pl_muladd_u64(n, (uint64_t)item, (uint64_t)extra, &r) || r > (uint64_t)SIZE_MAX)
        return -1;
    *out = (size_t)r;
    return 0;
}

#ifdef __cplusplus
}
#endif
#endif
