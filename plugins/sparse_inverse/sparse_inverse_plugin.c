/* sparse_inverse_plugin.c - the plugin's entry point: registers
 * SparseInverseSolver. */
#include "pliant/plugin.h"

extern const pl_type pl_sparse_inverse_solver_type;

static const pl_type *const sparse_inverse_types[] = {&pl_sparse_inverse_solver_type};
PL_PLUGIN_DEFINE(sparse_inverse_types)
