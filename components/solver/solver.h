/* solver.h - animation loops (the local-global solver, the Newton reference,
 * SOFA's linearised implicit Euler) and the built-in global solver
 * JacobiSolver (the paper's baseline). */
#ifndef PLIANT_SOLVER_H
#define PLIANT_SOLVER_H

#include "pliant/pliant.h"

extern const pl_type pl_local_global_solver_type;
extern const pl_type pl_newton_solver_type;
extern const pl_type pl_linearized_euler_solver_type;
extern const pl_type pl_jacobi_solver_type;

#endif
