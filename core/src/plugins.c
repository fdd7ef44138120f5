/* plugins.c - plugin files: found in the plugin folders as
 * libpliant_<name>.so, loaded with dlopen, their entry point called with
 * the host's ABI version.  libpliant's own plugin folder is found relative
 * to the library, so that an install can be moved. */
#include "registry_internal.h"

#include "pliant/log.h"
#include "pliant/plugin.h"

#include <dirent.h>
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define FILE_PREFIX "libpliant_"
#define FILE_SUFFIX ".so"

int pl_registry_add_plugin_dir(pl_registry *r, const char *dir)
{
    char **dirs = realloc(r->dirs, (size_t)(r->ndirs + 1) * sizeof *dirs);
    if (!dirs) return PL_EINTERNAL;
    r->dirs = dirs;
    if (!(r->dirs[r->ndirs] = strdup(dir))) return PL_EINTERNAL;
    r->ndirs++;
    return PL_OK;
}

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int pl_registry_default_plugin_dir(char *buf, size_t size)
{
    Dl_info info;
    char lib[PATH_MAX];
    /* the file this function was loaded from: libpliant.so (or a program
     * linking libpliant's objects) */
    if (!dladdr((void *)pl_registry_default_plugin_dir, &info) || !info.dli_fname ||
        !realpath(info.dli_fname, lib)) {
        snprintf(buf, size, "lib/pliant/plugins");
        return PL_EINPUT;
    }
    char *slash = strrchr(lib, '/');
    if (slash) *slash = '\0'; /* its folder: <prefix>/lib or <build>/lib */
    /* an install keeps plugins below the library's folder */
    snprintf(buf, size, "%s/pliant/plugins", lib);
    if (is_dir(buf)) return PL_OK;
    /* a build tree beside it: <build>/lib and <build>/plugins */
    slash = strrchr(lib, '/');
    if (slash) {
        char tree[PATH_MAX + 16];
        snprintf(tree, sizeof tree, "%.*s/plugins", (int)(slash - lib), lib);
        if (is_dir(tree)) {
            snprintf(buf, size, "%s", tree);
            return PL_OK;
        }
    }
    snprintf(buf, size, "%s/pliant/plugins", lib);
    return PL_EINPUT;
}

/* The folders searched, in order: dirs[0..n-1] point into the registry's
 * folders, env (a copy of PLIANT_PLUGIN_PATH cut at its colons) and own
 * (libpliant's folder); at most 64. */
typedef struct search_path {
    const char *dirs[64];
    int n;
    char *env;
    char own[PATH_MAX + 32];
} search_path;

static void search_path_init(const pl_registry *r, search_path *sp)
{
    sp->n = 0;
    for (int k = 0; k < r->ndirs && sp->n < 64; ++k) sp->dirs[sp->n++] = r->dirs[k];
    const char *env = getenv("PLIANT_PLUGIN_PATH");
    sp->env = env && *env ? strdup(env) : NULL;
    char *save = NULL;
    for (char *d = sp->env ? strtok_r(sp->env, ":", &save) : NULL; d && sp->n < 63;
         d = strtok_r(NULL, ":", &save))
        sp->dirs[sp->n++] = d;
    pl_registry_default_plugin_dir(sp->own, sizeof sp->own);
    sp->dirs[sp->n++] = sp->own;
}

static void search_path_free(search_path *sp)
{
    free(sp->env);
}

static int find_plugin(const pl_registry *r, const char *name, char *path, size_t size,
                       char *searched, size_t ssize)
{
    search_path sp;
    search_path_init(r, &sp);
    size_t n = 0;
    searched[0] = '\0';
    int found = 0;
    for (int k = 0; k < sp.n && !found; ++k) {
        snprintf(path, size, "%s/" FILE_PREFIX "%s" FILE_SUFFIX, sp.dirs[k], name);
        found = access(path, R_OK) == 0;
        if (!found && n < ssize)
            n += (size_t)snprintf(searched + n, ssize - n, "%s%s", n ? ", " : "", sp.dirs[k]);
    }
    search_path_free(&sp);
    return found;
}

/* The plugin name of a file: libpliant_foo.so -> foo (else the file name
 * without lib and .so). */
static void name_of_file(const char *path, char *name, size_t size)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    if (!strncmp(b, FILE_PREFIX, strlen(FILE_PREFIX)))
        b += strlen(FILE_PREFIX);
    else if (!strncmp(b, "lib", 3))
        b += 3;
    snprintf(name, size, "%s", b);
    char *dot = strstr(name, FILE_SUFFIX);
    if (dot) *dot = '\0';
}

static int loaded(const pl_registry *r, const char *name)
{
    for (int k = 0; k < r->nplugins; ++k)
        if (!strcmp(r->plugins[k].name, name)) return 1;
    return 0;
}

/* Calls the entry point; on refusal forgets what the plugin registered. */
static int register_plugin(pl_registry *r, plugin *p, pl_plugin_entry entry, pl_error *err)
{
    int before = r->ntypes;
    r->loading = p->name;
    pl_error_clear(&r->last);
    int abi = entry(r, PL_ABI_VERSION);
    r->loading = NULL;
    if (abi >= 0 && PL_ABI_COMPATIBLE(PL_ABI_VERSION, abi)) return PL_OK;
    if (abi < 0)
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "plugin '%s' (%s) failed to register its components: %s", p->name, p->path,
                     r->last.msg[0] ? r->last.msg : "its entry point returned an error");
    else {
        char built[32];
        pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                     "plugin '%s' (%s) was built for ABI version %s, but this Pliant has ABI "
                     "version %d.%d (it runs plugins of %d.0 to %d.%d): rebuild the plugin "
                     "against this SDK",
                     p->name, p->path, abi_text(abi, built, sizeof built), PL_ABI_MAJOR,
                     PL_ABI_MINOR, PL_ABI_MAJOR, PL_ABI_MAJOR, PL_ABI_MINOR);
    }
    r->ntypes = before;
    return PL_EINPUT;
}

static int open_plugin(pl_registry *r, const char *name, const char *path, pl_error *err)
{
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
    int rc = p->name && p->path ? register_plugin(r, p, entry, err)
                                : pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    if (rc != PL_OK) {
        free(p->name);
        free(p->path);
        dlclose(h);
        return rc;
    }
    r->nplugins++;
    pl_log_debug("loaded plugin %s from %s", name, path);
    return PL_OK;
}

int pl_registry_load_plugin(pl_registry *r, const char *name_or_path, pl_error *err)
{
    char path[PATH_MAX], searched[2048], name[256];
    if (strchr(name_or_path, '/')) {
        snprintf(path, sizeof path, "%s", name_or_path);
        name_of_file(path, name, sizeof name);
    } else {
        snprintf(name, sizeof name, "%s", name_or_path);
        if (!find_plugin(r, name, path, sizeof path, searched, sizeof searched))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL,
                                "plugin '%s' not found (looked for " FILE_PREFIX "%s" FILE_SUFFIX
                                " in: %s; set PLIANT_PLUGIN_PATH to add folders)",
                                name, name, searched);
    }
    if (loaded(r, name)) return PL_OK;
    return open_plugin(r, name, path, err);
}

/* Loads every libpliant_*.so of dir; warns when dir is missing or has none. */
static void load_dir(pl_registry *r, const char *dir, pl_diag *diag)
{
    DIR *d = opendir(dir);
    if (!d) {
        pl_diag_warn(diag, dir, 0, NULL, "plugin folder missing (or not readable)");
        return;
    }
    struct dirent *e;
    int files = 0;
    size_t lp = strlen(FILE_PREFIX), ls = strlen(FILE_SUFFIX);
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len <= lp + ls || strncmp(e->d_name, FILE_PREFIX, lp) ||
            strcmp(e->d_name + len - ls, FILE_SUFFIX))
            continue;
        char path[PATH_MAX], name[256];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        name_of_file(path, name, sizeof name);
        files++;
        pl_error err;
        if (!loaded(r, name) && pl_registry_load_plugin(r, path, &err) != PL_OK)
            pl_diag_add(diag, &err);
    }
    closedir(d);
    if (files == 0) pl_diag_warn(diag, dir, 0, NULL, "plugin folder holds no " FILE_PREFIX "*.so");
}

int pl_registry_load_all(pl_registry *r, pl_diag *diag)
{
    search_path sp;
    search_path_init(r, &sp);
    for (int k = 0; k < sp.n; ++k) load_dir(r, sp.dirs[k], diag);
    search_path_free(&sp);
    return pl_diag_status(diag);
}

int pl_registry_plugin_count(const pl_registry *r) { return r->nplugins; }
const char *pl_registry_plugin_name(const pl_registry *r, int i) { return r->plugins[i].name; }
const char *pl_registry_plugin_path(const pl_registry *r, int i) { return r->plugins[i].path; }

int pl_registry_plugin_providing(const pl_registry *r, const char *type, char *buf, size_t size)
{
    /* a scratch registry over the same folders: the scene's stays as it is */
    pl_registry *probe = pl_registry_create();
    if (!probe || !type) {
        pl_registry_free(probe);
        return 0;
    }
    for (int k = 0; k < r->ndirs; ++k) pl_registry_add_plugin_dir(probe, r->dirs[k]);
    pl_diag d;
    pl_diag_init(&d);
    pl_registry_load_all(probe, &d);
    pl_diag_free(&d);
    const pl_type *t = pl_registry_find(probe, type);
    const char *p = t ? pl_registry_type_plugin(probe, t) : NULL;
    int found = p && strcmp(p, "builtin") != 0;
    if (found) snprintf(buf, size, "%s", p);
    pl_registry_free(probe);
    return found;
}
