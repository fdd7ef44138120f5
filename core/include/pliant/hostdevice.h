/* hostdevice.h - one source for a numerical kernel on the CPU and on a CUDA
 * device.
 *
 * A header of small kernels (an SVD, a material law, an NCP function) marks
 * each function PL_HD and is included by C files and by .cu files alike:
 *   - in C11 (gcc, clang) PL_HD is `static inline`;
 *   - under nvcc it is `static __host__ __device__ inline`, so kernels call
 *     the very same definition.
 * Such headers include only the C library (math.h) and plain C types.
 *
 * Registers.  A kernel keeps a small local array (double F[9]) in
 * registers only when every index into it is known at compile time;
 * otherwise it lives in slow local memory.  So write these functions with
 * their sizes as parameters that every device caller passes as literal
 * constants (PL_HD functions are inlined, the constants propagate), mark
 * their loops PL_UNROLL (unrolled by nvcc; nothing in C), and never index
 * a small array with a value computed at run time (test `best == j` for
 * each constant j instead of indexing with best). */
#ifndef PLIANT_HOSTDEVICE_H
#define PLIANT_HOSTDEVICE_H

#ifdef __CUDACC__
#define PL_HD static __host__ __device__ inline
#define PL_UNROLL _Pragma("unroll")
#else
#define PL_HD static inline
#define PL_UNROLL
#endif

#endif
