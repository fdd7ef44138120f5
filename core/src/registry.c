/* registry.c - component types by name; plugins loaded with dlopen. */
#include "pliant/registry.h"
#include "pliant/log.h"
#include "pliant/plugin.h"

#include <dirent.h>
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct plugin {
    char *name;
    char *path;
    void *handle;
} plugin;

struct pl_registry {
    const pl_type **types;
    int ntypes, cap_types;
    plugin *plugins;
    int nplugins, cap_plugins;
    char **dirs;
    int ndirs;
    const char *loading;  /* plugin being registered, stamped on its types */
    pl_error last;
};

pl_registry *pl_registry_create(void)
{
    pl_registry *r = calloc(1, sizeof *r);
    return r;
}

void pl_registry_free(pl_registry *r)
{
    if (!r) return;
    for (int k = 0; k < r->ntypes; ++k) free((void *)r->types[k]);
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

int pl_registry_add(pl_registry *r, const pl_type *t, pl_error *err)
{
    if (!t || !t->name) {
        pl_error_set(&r->last, PL_EINPUT, NULL, 0, NULL, "a component type without a name");
        if (err) *err = r->last;
        return PL_EINPUT;
    }
    if (t->abi_version != PL_ABI_VERSION) {
        pl_error_set(&r->last, PL_EINPUT, NULL, 0, NULL,
                     "component type '%s' was built for ABI version %d, this Pliant has ABI "
                     "version %d",
                     t->name, t->abi_version, PL_ABI_VERSION);
        if (err) *err = r->last;
        return PL_EINPUT;
    }
    if (pl_registry_find(r, t->name)) {
        pl_error_set(&r->last, PL_EINPUT, NULL, 0, NULL,
                     "component type '%s' is registered twice (by %s and by %s)", t->name,
                     pl_registry_find(r, t->name)->plugin, r->loading ? r->loading : "builtin");
        if (err) *err = r->last;
        return PL_EINPUT;
    }
    if (t->size < sizeof(pl_component)) {
        pl_error_set(&r->last, PL_EINPUT, NULL, 0, NULL,
                     "component type '%s' is smaller than pl_component", t->name);
        if (err) *err = r->last;
        return PL_EINPUT;
    }
    if (r->ntypes == r->cap_types) {
        int cap = r->cap_types ? 2 * r->cap_types : 32;
        const pl_type **types = realloc(r->types, (size_t)cap * sizeof *types);
        if (!types) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        r->types = types;
        r->cap_types = cap;
    }
    /* keep our own copy so the plugin field can be stamped */
    pl_type *copy = malloc(sizeof *copy);
    if (!copy) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    *copy = *t;
    copy->plugin = r->loading ? r->loading : "builtin";
    r->types[r->ntypes++] = copy;
    return PL_OK;
}

const pl_type *pl_registry_find(const pl_registry *r, const char *name)
{
    for (int k = 0; k < r->ntypes; ++k)
        if (!strcmp(r->types[k]->name, name)) return r->types[k];
    return NULL;
}

const char *pl_registry_suggest(const pl_registry *r, const char *name)
{
    const char *best = NULL;
    int bestd = 1 << 30;
    for (int k = 0; k < r->ntypes; ++k) {
        int d = pl_edit_distance(name, r->types[k]->name);
        if (d < bestd) bestd = d, best = r->types[k]->name;
    }
    /* close enough: a few edits, relative to the name's length */
    if (best && bestd <= 2 + (int)strlen(name) / 4) return best;
    return NULL;
}

int pl_registry_count(const pl_registry *r) { return r->ntypes; }
const pl_type *pl_registry_type(const pl_registry *r, int i) { return r->types[i]; }
int pl_registry_plugin_count(const pl_registry *r) { return r->nplugins; }
const char *pl_registry_plugin_name(const pl_registry *r, int i) { return r->plugins[i].name; }
const char *pl_registry_plugin_path(const pl_registry *r, int i) { return r->plugins[i].path; }

int pl_registry_add_plugin_dir(pl_registry *r, const char *dir)
{
    char **dirs = realloc(r->dirs, (size_t)(r->ndirs + 1) * sizeof *dirs);
    if (!dirs) return PL_EINTERNAL;
    r->dirs = dirs;
    if (!(r->dirs[r->ndirs] = strdup(dir))) return PL_EINTERNAL;
    r->ndirs++;
    return PL_OK;
}

static int try_file(char *buf, size_t size, const char *dir, const char *name)
{
    snprintf(buf, size, "%s/lib%s.so", dir, name);
    if (access(buf, R_OK) == 0) return 1;
    snprintf(buf, size, "%s/%s.so", dir, name);
    return access(buf, R_OK) == 0;
}

/* Searches the plugin folders in order; fills `searched` for the message. */
static int find_plugin(const pl_registry *r, const char *name, char *path, size_t size,
                       char *searched, size_t ssize)
{
    size_t n = 0;
    searched[0] = '\0';
#define SEARCH(dir)                                                                  \
    do {                                                                             \
        if (try_file(path, size, (dir), name)) return 1;                            \
        if (n < ssize) n += (size_t)snprintf(searched + n, ssize - n, "%s%s", n ? ", " : "", (dir)); \
    } while (0)
    for (int k = 0; k < r->ndirs; ++k) SEARCH(r->dirs[k]);
    const char *env = getenv("PLIANT_PLUGIN_PATH");
    if (env && *env) {
        char *copy = strdup(env), *save = NULL;
        if (copy) {
            for (char *d = strtok_r(copy, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
                if (try_file(path, size, d, name)) {
                    free(copy);
                    return 1;
                }
                if (n < ssize)
                    n += (size_t)snprintf(searched + n, ssize - n, "%s%s", n ? ", " : "", d);
            }
            free(copy);
        }
    }
    SEARCH(PL_BUILD_PLUGIN_DIR);
    SEARCH(PL_INSTALL_PLUGIN_DIR);
#undef SEARCH
    return 0;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

int pl_registry_load_plugin(pl_registry *r, const char *name_or_path, pl_error *err)
{
    char path[1024], searched[2048], name[1024];
    if (strchr(name_or_path, '/')) {
        snprintf(path, sizeof path, "%s", name_or_path);
        /* libfoo.so -> foo */
        const char *b = base_name(path);
        if (!strncmp(b, "lib", 3)) b += 3;
        snprintf(name, sizeof name, "%s", b);
        char *dot = strstr(name, ".so");
        if (dot) *dot = '\0';
    } else {
        snprintf(name, sizeof name, "%s", name_or_path);
        if (!find_plugin(r, name, path, sizeof path, searched, sizeof searched))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "plugin '%s' not found (looked for lib%s.so in: %s; set "
                                "PLIANT_PLUGIN_PATH to add folders)",
                                name, name, searched);
    }
    for (int k = 0; k < r->nplugins; ++k)
        if (!strcmp(r->plugins[k].name, name)) return PL_OK;

    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h)
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "plugin '%s' cannot be loaded: %s",
                            name, dlerror());
    pl_plugin_entry entry;
    *(void **)&entry = dlsym(h, PL_PLUGIN_ENTRY_NAME);
    if (!entry) {
        dlclose(h);
        return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                            "'%s' is not a Pliant plugin: it exports no %s()", path,
                            PL_PLUGIN_ENTRY_NAME);
    }
    if (r->nplugins == r->cap_plugins) {
        int cap = r->cap_plugins ? 2 * r->cap_plugins : 8;
        plugin *p = realloc(r->plugins, (size_t)cap * sizeof *p);
        if (!p) {
            dlclose(h);
            return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        }
        r->plugins = p;
        r->cap_plugins = cap;
    }
    plugin *p = &r->plugins[r->nplugins];
    p->name = strdup(name);
    p->path = strdup(path);
    p->handle = h;
    if (!p->name || !p->path) {
        free(p->name);
        free(p->path);
        dlclose(h);
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    }
    int before = r->ntypes;
    r->loading = p->name;
    pl_error_clear(&r->last);
    int abi = entry(r, PL_ABI_VERSION);
    r->loading = NULL;
    if (abi != PL_ABI_VERSION) {
        int code;
        if (abi < 0)
            code = pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "plugin '%s' (%s) failed to register its components: %s", name,
                                path, r->last.msg);
        else
            code = pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "plugin '%s' (%s) was built for ABI version %d, but this Pliant "
                                "has ABI version %d: rebuild the plugin against this SDK",
                                name, path, abi, PL_ABI_VERSION);
        /* forget the types it may have added before failing */
        for (int k = before; k < r->ntypes; ++k) free((void *)r->types[k]);
        r->ntypes = before;
        free(p->name);
        free(p->path);
        dlclose(h);
        return code;
    }
    r->nplugins++;
    pl_log_debug("loaded plugin %s from %s (%d types)", name, path, r->ntypes - before);
    return PL_OK;
}

static void load_dir(pl_registry *r, const char *dir, pl_diag *diag)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len < 7 || strncmp(e->d_name, "lib", 3) || strcmp(e->d_name + len - 3, ".so")) continue;
        char path[2048], name[256];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        snprintf(name, sizeof name, "%.*s", (int)(len - 6), e->d_name + 3);
        int loaded = 0;
        for (int k = 0; k < r->nplugins; ++k)
            if (!strcmp(r->plugins[k].name, name)) loaded = 1;
        pl_error err;
        if (!loaded && pl_registry_load_plugin(r, path, &err) != PL_OK)
            pl_diag_add(diag, &err);
    }
    closedir(d);
}

int pl_registry_load_all(pl_registry *r, pl_diag *diag)
{
    for (int k = 0; k < r->ndirs; ++k) load_dir(r, r->dirs[k], diag);
    const char *env = getenv("PLIANT_PLUGIN_PATH");
    if (env && *env) {
        char *copy = strdup(env), *save = NULL;
        if (copy)
            for (char *d = strtok_r(copy, ":", &save); d; d = strtok_r(NULL, ":", &save))
                load_dir(r, d, diag);
        free(copy);
    }
    load_dir(r, PL_BUILD_PLUGIN_DIR, diag);
    load_dir(r, PL_INSTALL_PLUGIN_DIR, diag);
    return pl_diag_status(diag);
}
