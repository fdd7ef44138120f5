/* api.h - symbol visibility and the ABI version (plugin.h says how
 * versions are compared).
 *
 * libpliant is built with hidden visibility: a function is exported only
 * when its declaration in an SDK header carries PL_API, so what a plugin or
 * an embedding program can call is exactly what core/include/pliant
 * declares (tests/sdk/exports.sh checks that both sets are equal).
 * PL_EXPORT marks the one symbol a plugin exports (PL_PLUGIN_DEFINE). */
#ifndef PLIANT_API_H
#define PLIANT_API_H

#if defined(__GNUC__)
#define PL_EXPORT __attribute__((visibility("default")))
#else
#define PL_EXPORT
#endif

#define PL_API PL_EXPORT

#define PL_ABI_MAJOR 5
#define PL_ABI_MINOR 10
/* A plugin built for hosts from minor N on defines PL_ABI_TARGET_MINOR N
 * before including the SDK: what later minors added is then left out. */
#ifndef PL_ABI_TARGET_MINOR
#define PL_ABI_TARGET_MINOR PL_ABI_MINOR
#elif PL_ABI_TARGET_MINOR > PL_ABI_MINOR || PL_ABI_TARGET_MINOR < 0
#error "PL_ABI_TARGET_MINOR: this SDK has minor versions 0 to PL_ABI_MINOR"
#endif
/* One int: major * 1000 + minor. */
#define PL_ABI(major, minor) ((major) * 1000 + (minor))
#define PL_ABI_MAJOR_OF(v) ((v) / 1000)
#define PL_ABI_MINOR_OF(v) ((v) % 1000)
/* What this plugin (or the host) is built for. */
#define PL_ABI_VERSION PL_ABI(PL_ABI_MAJOR, PL_ABI_TARGET_MINOR)

#endif
