/* lg_device_fakes.h - test components for the LocalGlobalSolver's device
 * path without a GPU: a device service in host memory ("HostDevice", no
 * graphs; fields profile, loops: its loop runs the body once per
 * iteration with the shared stopping rule), springs on tetrahedron edges ("TestSprings",
 * fields stiffness, deviceOk) and a dense Cholesky global solver
 * ("TestDenseSolver", field deviceOk).  The term and the solver read and
 * write their buffers in place whatever their location says, so the device
 * path runs the same arithmetic as the CPU path. */
#ifndef PLIANT_TESTS_LG_DEVICE_FAKES_H
#define PLIANT_TESTS_LG_DEVICE_FAKES_H

#include "pliant/pliant.h"

extern const pl_type fake_host_device_type;
extern const pl_type fake_host_device_v3_type; /* "HostDeviceV3": device ops version 3 */
extern const pl_type fake_springs_type;
extern const pl_type fake_dense_solver_type;

/* Allocations HostDevice components still held when destroyed (all runs). */
extern long fake_device_leaks;
/* Kernel calls (scale, gather, scatter, sub, gather_sub, residual) made on a HostDevice. */
long fake_device_calls(const pl_component *c);
/* stopping rules the HostDevice's loop applied (0: no device loop ran) */
long fake_device_rules(const pl_component *c);

#endif
