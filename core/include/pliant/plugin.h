/* plugin.h - what a plugin .so exports, and the ABI versions.
 *
 * Exactly one entry point:
 *
 *     int pl_plugin_register(pl_registry *reg, int host_abi);
 *
 * It returns the ABI version the plugin was compiled with (PL_ABI_VERSION).
 * When the host cannot run it (another major version, or an older minor
 * than the plugin's) it must return at once without touching the registry;
 * the host then refuses the plugin, naming both versions.  Otherwise it
 * registers its types with pl_registry_add and returns PL_ABI_VERSION (or a
 * negative value if a registration failed).  PL_PLUGIN_DEFINE writes that
 * boilerplate:
 *
 *     static const pl_type *const types[] = {&arap_type, &neohookean_type};
 *     PL_PLUGIN_DEFINE(types)
 *
 * ABI versions are major.minor, as SQLite's iVersion rule: a minor version
 * only adds (a member at the end of a versioned role table, a role in a free
 * slot of pl_type.roles, a function, a flag), so a host of minor m runs
 * plugins built for any minor <= m of its major: it reads only what their
 * tables have (role tables start with their version, checked by callers and
 * by the registry).  Anything else (a struct layout, a member's meaning)
 * bumps the major version, and plugins of another major are refused.
 * A plugin may define PL_ABI_TARGET_MINOR before including the SDK to be
 * built for hosts from that minor on: the headers then leave out what later
 * minors added (each addition sits in #if PL_ABI_TARGET_MINOR >= m, a role
 * table's new members and its raised version too).
 *
 * History: 3 and before: one number.  4.0: the detector role and
 * pl_contacts removed, pl_type registered by pointer (its plugin name is the
 * registry's), roles in PL_ROLE_MAX reserved slots, ABI major.minor.
 * 4.1: PL_DEVICE_ABSENT, pl_mesh_boundary_triangles, pl_util_data_file.
 * 5.0: the model const in step callbacks (pl_ctx.model const, pl_ctx.build
 * while building), per-data workspaces (pl_type.workspace_size,
 * pl_lifecycle.workspace_free), input fields, fixed and variable state
 * slots with restore checks (pl_type's layout changed: a major version).
 * 5.1: 4.1's additions again, as a minor of 5 (a plugin may target 5.0
 * without them).
 * 5.2: the visual role (PL_ROLE_VISUAL, pl_visual_ops, draw.h) and the event
 * role (PL_ROLE_EVENT, pl_event_ops, pl_sim_send_event) in free role slots;
 * pl_node_add_component, pl_sim_load_file_prepared / _string_prepared,
 * pl_vtu_write_cells, pl_pvd_append_part.
 * 5.3: pl_sofa_write_vocabulary (sofa.h).
 * 5.4: pl_registry_plugin_providing, pl_regression_compare_detail and
 * pl_regression_detail, PL_HESSIAN_FIXED_ROTATION (add_hessian's psd = 2;
 * a term built for an older minor reads it as psd != 0: projected).
 * 5.5: device ops version 3 (pl_device_ops.loop, PL_DEVICE_LOOPS,
 * device_loop.h: an iteration loop kept on the device).
 * 5.6: device ops version 4 (pl_device_ops.scale_rows_zero and
 * residual_max_csr: two launches fewer in a device iteration).
 * 5.7: pl_timer_watch (timer.h: a phase's off-CPU time, page faults and
 * preemptions per frame).
 * 5.8: device ops version 5 (pl_device_ops.branch, PL_DEVICE_BRANCHES:
 * independent work, such as the local steps of different bodies, queued
 * side by side).
 * 5.9: pl_rows_reserve and pl_rows_put (rows.h: rows written by threads at
 * offsets an ordered pass gave them).
 * 5.10: slot versions (model.h: pl_data_slot_version, pl_data_slot_touch,
 * pl_data_slot_writers; pl_data's slot_version and slot_writers at its end):
 * an owner keeping a device copy of its slot knows, without reading it,
 * that nobody else wrote it; device ops version 6 (pl_device_ops.step_begin,
 * step_end: a time step's start and end on the device). */
#ifndef PLIANT_PLUGIN_H
#define PLIANT_PLUGIN_H

#include "registry.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Whether a host of ABI `host` runs code built for ABI `built`. */
#define PL_ABI_COMPATIBLE(host, built)                 \
    (PL_ABI_MAJOR_OF(host) == PL_ABI_MAJOR_OF(built) && \
     PL_ABI_MINOR_OF(built) <= PL_ABI_MINOR_OF(host))

#define PL_PLUGIN_ENTRY_NAME "pl_plugin_register"
typedef int (*pl_plugin_entry)(pl_registry *reg, int host_abi);

#define PL_PLUGIN_DEFINE(types_array)                                              \
    PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi);              \
    PL_EXPORT int pl_plugin_register(pl_registry *reg, int host_abi)               \
    {                                                                              \
        if (!PL_ABI_COMPATIBLE(host_abi, PL_ABI_VERSION)) return PL_ABI_VERSION;   \
        for (size_t k_ = 0; k_ < sizeof(types_array) / sizeof(types_array[0]); ++k_) { \
            pl_error e_;                                                           \
            if (pl_registry_add(reg, types_array[k_], &e_) != PL_OK) return -1;    \
        }                                                                          \
        return PL_ABI_VERSION;                                                     \
    }

#ifdef __cplusplus
}
#endif
#endif
