/* registry.c - component types by name.  A type is kept by pointer (a
 * component's c->type is its type's own definition) with the name of the
 * plugin that registered it; plugins.c finds and loads plugin files. */
#include "registry_internal.h"

#include "pliant/plugin.h"
#include "pliant/roles.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

pl_registry *pl_registry_create(void)
{
    pl_registry *r = calloc(1, sizeof *r);
    return r;
}

void pl_registry_free(pl_registry *r)
{
    if (!r) return;
    free(r->types);
    for (int k = 0; k < r->nplugins; ++k) {
        /* Under AddressSanitizer, unloading hides the plugin's frames in leak
         * reports; keeping it mapped until exit costs nothing. */
        free(r->plugins[k].name);
        free(r->plugins[k].path);
    }
    free(r->plugins);
    for (int k = 0; k < r->ndirs; ++k) free(r->dirs[k]);
    free(r->dirs);
    free(r);
}

const pl_error *pl_registry_last_error(const pl_registry *r)
{
    return &r->last;
}

/* The newest version of each role table this host reads (roles.h).  It
 * reads every version from 1 on: a caller checks ops->version before using
 * a member added later.  A table changed incompatibly would bump the major
 * ABI version instead. */
static const int ROLE_VERSION[PL_ROLE_COUNT] = {
    [PL_ROLE_STATE] = PL_STATE_OPS_VERSION,
    [PL_ROLE_MASS] = PL_MASS_OPS_VERSION,
    [PL_ROLE_TOPOLOGY] = PL_TOPOLOGY_OPS_VERSION,
    [PL_ROLE_LOCAL_TERM] = PL_LOCAL_TERM_OPS_VERSION,
    [PL_ROLE_GLOBAL_SOLVER] = PL_GLOBAL_SOLVER_OPS_VERSION,
    [PL_ROLE_CONSTRAINT] = PL_CONSTRAINT_OPS_VERSION,
    [PL_ROLE_CONTACT_SOLVER] = PL_CONTACT_SOLVER_OPS_VERSION,
    [PL_ROLE_COLLISION_MODEL] = PL_COLLISION_MODEL_OPS_VERSION,
    [PL_ROLE_EXPORTER] = PL_EXPORTER_OPS_VERSION,
    [PL_ROLE_CONTROLLER] = PL_CONTROLLER_OPS_VERSION,
    [PL_ROLE_PRESCRIBED] = PL_PRESCRIBED_OPS_VERSION,
    [PL_ROLE_ANIMATION_LOOP] = PL_ANIMATION_LOOP_OPS_VERSION,
    [PL_ROLE_DEVICE] = PL_DEVICE_OPS_VERSION,
    [PL_ROLE_VISUAL] = PL_VISUAL_OPS_VERSION,
    [PL_ROLE_EVENT] = PL_EVENT_OPS_VERSION,
};

/* Records a refusal in r->last and err; returns PL_EINPUT. */
static int refuse(pl_registry *r, pl_error *err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int refuse(pl_registry *r, pl_error *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    pl_error_vset(&r->last, PL_EINPUT, NULL, 0, NULL, fmt, ap);
    va_end(ap);
    if (err) *err = r->last;
    return PL_EINPUT;
}

/* The type's ABI and every role table it fills are ones this host reads. */
static int check_versions(pl_registry *r, const pl_type *t, pl_error *err)
{
    char built[32];
    if (!PL_ABI_COMPATIBLE(PL_ABI_VERSION, t->abi_version))
        return refuse(r, err,
                      "component type '%s' was built for ABI version %s, this Pliant has ABI "
                      "version %d.%d (it runs %d.0 to %d.%d): rebuild it against this SDK",
                      t->name, abi_text(t->abi_version, built, sizeof built), PL_ABI_MAJOR,
                      PL_ABI_MINOR, PL_ABI_MAJOR, PL_ABI_MAJOR, PL_ABI_MINOR);
    for (int k = 0; k < PL_ROLE_MAX; ++k) {
        if (!t->roles[k]) continue;
        if (k >= PL_ROLE_COUNT)
            return refuse(r, err, "component type '%s' plays role %d, which this Pliant does not "
                          "know", t->name, k);
        /* every role table starts with its int version */
        int rv = *(const int *)t->roles[k];
        if (rv < 1 || rv > ROLE_VERSION[k])
            return refuse(r, err,
                          "component type '%s': its %s table has version %d, this Pliant reads "
                          "versions 1 to %d",
                          t->name, pl_role_name(k), rv, ROLE_VERSION[k]);
    }
    return PL_OK;
}

int pl_registry_add(pl_registry *r, const pl_type *t, pl_error *err)
{
    if (!t || !t->name) return refuse(r, err, "a component type without a name");
    int rc = check_versions(r, t, err);
    if (rc != PL_OK) return rc;
    const pl_type *old = pl_registry_find(r, t->name);
    if (old)
        return refuse(r, err, "component type '%s' is registered twice (by %s and by %s)", t->name,
                      pl_registry_type_plugin(r, old), r->loading ? r->loading : "builtin");
    if (t->size < sizeof(pl_component))
        return refuse(r, err, "component type '%s' is smaller than pl_component", t->name);
    if (t->nfields < 0 || (t->nfields > 0 && !t->fields))
        return refuse(r, err, "component type '%s' has %d fields but no field table", t->name,
                      t->nfields);
    if (r->ntypes == r->cap_types) {
        int cap = r->cap_types ? 2 * r->cap_types : 32;
        type_entry *types = realloc(r->types, (size_t)cap * sizeof *types);
        if (!types) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        r->types = types;
        r->cap_types = cap;
    }
    r->types[r->ntypes].type = t;
    r->types[r->ntypes].plugin = r->loading ? r->loading : "builtin";
    r->ntypes++;
    return PL_OK;
}

const pl_type *pl_registry_find(const pl_registry *r, const char *name)
{
    for (int k = 0; k < r->ntypes; ++k)
        if (!strcmp(r->types[k].type->name, name)) return r->types[k].type;
    return NULL;
}

const char *pl_registry_type_plugin(const pl_registry *r, const pl_type *t)
{
    for (int k = 0; k < r->ntypes; ++k)
        if (r->types[k].type == t) return r->types[k].plugin;
    return NULL;
}

const char *pl_registry_suggest(const pl_registry *r, const char *name)
{
    const char *best = NULL;
    int bestd = 1 << 30;
    for (int k = 0; k < r->ntypes; ++k) {
        int d = pl_edit_distance(name, r->types[k].type->name);
        if (d < bestd) bestd = d, best = r->types[k].type->name;
    }
    /* close enough: a few edits, relative to the name's length */
    if (best && bestd <= 2 + (int)strlen(name) / 4) return best;
    return NULL;
}

int pl_registry_count(const pl_registry *r) { return r->ntypes; }
const pl_type *pl_registry_type(const pl_registry *r, int i) { return r->types[i].type; }
