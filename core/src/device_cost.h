/* device_cost.h - private: the cost model behind device="auto".
 *
 * A scene that declares no device gets the implicit CudaDevice only when
 * this model predicts its step to be faster on the GPU than on the CPU
 * (sim_device.c asks it after every component's init, when the sizes are
 * known and nothing has yet been put on the device).  The predictions are
 * pure functions of the sizes below and of the constants in device_cost.c
 * (one table, fitted by tests/bench/device_cost_fit.py on runs of every
 * scene of scenes/, docs/benchmarks.md): no timing trial, so the choice is
 * the same on every run of a machine with the same thread count. */
#ifndef PLIANT_DEVICE_COST_H
#define PLIANT_DEVICE_COST_H

#include <stddef.h>

/* Element classes of the local terms, by material law. */
typedef enum pl_cost_law {
    PL_COST_ARAP,     /* ARAP (and the bending terms: no scene measures them) */
    PL_COST_COROT,    /* Corotational */
    PL_COST_NH,       /* NeoHookean */
    PL_COST_NLAWS
} pl_cost_law;

/* What the model reads; gathered from the initialised scene (sim_device.c). */
typedef struct pl_device_sizes {
    int vertices;               /* of all states */
    int tets[PL_COST_NLAWS];    /* elements of the local terms by law: tetrahedra */
    int tris[PL_COST_NLAWS];    /* and triangles (membranes) */
    double s_tet, s_tri;        /* sums over bodies of n^(4/3) (tetrahedra) and
                                 * n log2 n (triangles): nnz(S) ~ S_TET s_tet + S_TRI s_tri */
    int iterations;             /* local-global iterations per step (estimated with
                                 * forceTolerance, see iterations_max) */
    int iterations_max;         /* the field `iterations` */
    int force_tolerance;        /* forceTolerance > 0: the count is not known ahead */
    int constraints;            /* constraint components (contact, cables, pressure) */
    int cr_iterations;          /* the contact solver's crIterations (0: none) */
    int surface_vertices;       /* of the deformable collision models */
    int device_path;            /* 1: the iterations can run on the device; 0: only the
                                 * global solves go there (a term without a device step,
                                 * a CPU contact solver; forceTolerance with a term
                                 * without a device gradient or rayleighStiffness) */
    int sparse_inverse;         /* the global solver is a SparseInverseSolver */
} pl_device_sizes;

typedef struct pl_device_estimate {
    double cpu_ms, gpu_ms;  /* predicted step times */
    double nnz_s;           /* estimated entries of S */
    int gpu;                /* 1: the GPU is predicted faster */
} pl_device_estimate;

/* The iteration count the model assumes for a forceTolerance scene. */
int pl_device_cost_iterations(int iterations_max, int force_tolerance);

/* Predicted times on `threads` CPU threads and on the GPU. */
pl_device_estimate pl_device_cost_predict(const pl_device_sizes *z, int threads);

/* The choice: 1 for the GPU, 0 for the CPU (always 0 when gpu_present is
 * 0); *e gets the predictions and why one sentence for the log: "CPU
 * chosen: predicted 2.1 ms/step on 16 threads vs 5.5 ms on the GPU (3.2k
 * tetrahedra Neo-Hookean, 0.9k vertices, 10 iterations, ...)". */
int pl_device_cost_choose(const pl_device_sizes *z, int threads, int gpu_present,
                          pl_device_estimate *e, char *why, size_t size);

#endif
