/* export_path.c - output paths: folders created on demand, --out-dir
 * redirection, XML attribute escaping, and naming the component in errors. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
#include <sys/stat.h>

#include "export/export_internal.h"

int pl_export_make_dirs(const char *dir, pl_error *err)
{
    size_t n = strlen(dir);
    char *p = malloc(n + 1);
    if (!p) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    memcpy(p, dir, n + 1);
    while (n > 1 && p[n - 1] == '/') p[--n] = '\0';
    /* Walk the prefixes "a", "a/b", ... so that every missing level is made. */
    for (size_t i = 1; i <= n; ++i) {
        if (p[i] != '/' && p[i] != '\0') continue;
        char save = p[i];
        p[i] = '\0';
        struct stat st;
        if (mkdir(p, 0777) != 0 && errno != EEXIST) {
            int e = errno;
            pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "cannot create folder '%s': %s", p,
                         strerror(e));
            free(p);
            return PL_EINPUT;
        }
        if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)) {
            pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "'%s' exists and is not a folder", p);
            free(p);
            return PL_EINPUT;
        }
        p[i] = save;
    }
    free(p);
    return PL_OK;
}

int pl_export_make_parent_dirs(const char *path, pl_error *err)
{
    const char *slash = strrchr(path, '/');
    if (!slash || slash == path) return PL_OK; /* bare name or a file in "/" */
    size_t n = (size_t)(slash - path);
    char *dir = malloc(n + 1);
    if (!dir) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
    memcpy(dir, path, n);
    dir[n] = '\0';
    int rc = pl_export_make_dirs(dir, err);
    free(dir);
    return rc;
}

const char *pl_export_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

char *pl_export_output_path(const char *out_dir, const char *path)
{
    if (!out_dir || !*out_dir) return strdup(path);
    const char *base = pl_export_basename(path);
    size_t nd = strlen(out_dir), nb = strlen(base);
    int slash = out_dir[nd - 1] != '/';
    char *s = malloc(nd + (size_t)slash + nb + 1);
    if (!s) return NULL;
    memcpy(s, out_dir, nd);
    if (slash) s[nd] = '/';
    memcpy(s + nd + slash, base, nb + 1);
    return s;
}

int pl_export_xml_attr(FILE *f, const char *s)
{
    for (; *s; ++s) {
        const char *rep = NULL;
        switch (*s) {
        case '&': rep = "&amp;"; break;
        case '<': rep = "&lt;"; break;
        case '>': rep = "&gt;"; break;
        case '"': rep = "&quot;"; break;
        case '\'': rep = "&apos;"; break;
        default: break;
        }
        if (rep ? fputs(rep, f) < 0 : fputc(*s, f) == EOF) return PL_EINTERNAL;
    }
    return PL_OK;
}

int pl_export_blame(const pl_component *c, pl_error *err)
{
    if (!err->where[0]) {
        char path[160];
        snprintf(err->where, sizeof err->where, "%s %s", c->type->name,
                 pl_component_path(c, path, sizeof path));
    }
    return err->code;
}
