/* walk.c - traversals, and "node/component.field" paths. */
#include "walk.h"
#include "pliant/input.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int walk_pre(pl_node *n, pl_component_visit fn, void *user)
{
    for (int k = 0; k < n->ncomponents; ++k) {
        int rc = fn(n->components[k], user);
        if (rc) return rc;
    }
    for (int k = 0; k < n->nchildren; ++k) {
        int rc = walk_pre(n->children[k], fn, user);
        if (rc) return rc;
    }
    return 0;
}

int walk_post(pl_node *n, pl_component_visit fn, void *user)
{
    for (int k = 0; k < n->nchildren; ++k) {
        int rc = walk_post(n->children[k], fn, user);
        if (rc) return rc;
    }
    for (int k = 0; k < n->ncomponents; ++k) {
        int rc = fn(n->components[k], user);
        if (rc) return rc;
    }
    return 0;
}

typedef struct by_name {
    const char *name;
    pl_component *found;
    int count;
} by_name;

static int match_name(pl_component *c, void *user)
{
    by_name *b = user;
    if (!strcmp(c->name, b->name)) {
        b->found = c;
        b->count++;
    }
    return 0;
}

static pl_node *child(pl_node *n, const char *name, size_t len)
{
    for (int k = 0; k < n->nchildren; ++k)
        if (strlen(n->children[k]->name) == len && !strncmp(n->children[k]->name, name, len))
            return n->children[k];
    return NULL;
}

/* Resolves a node path; returns the node or NULL. */
static pl_node *walk_nodes(pl_node *root, const char *path)
{
    pl_node *n = root;
    const char *s = path;
    size_t rl = strlen(root->name);
    if (!strncmp(s, root->name, rl) && (s[rl] == '/' || s[rl] == '\0')) {
        s += rl;
        if (*s == '/') s++;
    }
    while (*s && n) {
        const char *slash = strchr(s, '/');
        size_t len = slash ? (size_t)(slash - s) : strlen(s);
        n = child(n, s, len);
        s = slash ? slash + 1 : s + len;
    }
    return n;
}

static pl_component *in_node(pl_node *root, const char *path, const char *slash, pl_error *err)
{
    char nodepath[512], hint[512];
    size_t len = (size_t)(slash - path);
    if (len >= sizeof nodepath) len = sizeof nodepath - 1;
    memcpy(nodepath, path, len);
    nodepath[len] = '\0';
    pl_node *n = walk_nodes(root, nodepath);
    if (!n) {
        if (pl_walk_suggest_node(root, nodepath, hint, sizeof hint))
            pl_error_set(err, PL_EINPUT, NULL, 0, path,
                         "no node '%s' in the scene (did you mean %s/%s?)", nodepath, hint,
                         slash + 1);
        else
            pl_error_set(err, PL_EINPUT, NULL, 0, path, "no node '%s' in the scene", nodepath);
        return NULL;
    }
    for (int k = 0; k < n->ncomponents; ++k)
        if (!strcmp(n->components[k]->name, slash + 1)) return n->components[k];
    const char *best = pl_walk_suggest_component(n, slash + 1);
    if (best)
        pl_error_set(err, PL_EINPUT, NULL, 0, path,
                     "node '%s' has no component '%s' (did you mean %s/%s?)", nodepath,
                     slash + 1, nodepath, best);
    else
        pl_error_set(err, PL_EINPUT, NULL, 0, path, "node '%s' has no component '%s'", nodepath,
                     slash + 1);
    return NULL;
}

pl_component *pl_walk_component(pl_node *root, const char *path, pl_error *err)
{
    if (!root) return NULL;
    const char *slash = strrchr(path, '/');
    if (slash) return in_node(root, path, slash, err);
    by_name b = {path, NULL, 0};
    walk_pre(root, match_name, &b);
    if (b.count == 1) return b.found;
    char hint[512];
    if (b.count > 1)
        pl_error_set(err, PL_EINPUT, NULL, 0, path,
                     "%d components are named '%s': give the node path (node/%s)", b.count, path,
                     path);
    else if (pl_walk_suggest_anywhere(root, path, hint, sizeof hint))
        pl_error_set(err, PL_EINPUT, NULL, 0, path,
                     "no component named '%s' in the scene (did you mean %s?)", path, hint);
    else
        pl_error_set(err, PL_EINPUT, NULL, 0, path, "no component named '%s' in the scene", path);
    return NULL;
}

/* Splits "a/b/comp.field" at the last '.'; returns 0 on success. */
static int split(const char *path, char *obj, size_t size, const char **field)
{
    const char *dot = strrchr(path, '.');
    if (!dot || dot == path || !dot[1] || (size_t)(dot - path) >= size) return -1;
    memcpy(obj, path, (size_t)(dot - path));
    obj[dot - path] = '\0';
    *field = dot + 1;
    return 0;
}

static int set_node_field(pl_node *n, const char *field, const char *value, pl_error *err)
{
    pl_field f;
    if (!strcmp(field, "dt"))
        f = (pl_field){"dt", PL_F_DOUBLE, offsetof(pl_node, dt), NULL, "", 0, NULL, NULL};
    else if (!strcmp(field, "gravity"))
        f = (pl_field){"gravity", PL_F_VEC3, offsetof(pl_node, gravity), NULL, "", 0, NULL, NULL};
    else
        return pl_error_set(err, PL_EINPUT, NULL, 0, n->name,
                            "a Node has the fields dt and gravity, not '%s'", field);
    int rc = pl_field_parse(&f, n, value, err);
    if (rc) return rc;
    if (!strcmp(field, "dt")) {
        if (n->dt <= 0)
            return pl_error_set(err, PL_EINPUT, NULL, 0, n->name, "dt must be positive");
        n->has_dt = 1;
    } else {
        n->has_gravity = 1;
    }
    return PL_OK;
}

/* A path "node.dt" whose node is misspelled: suggest the node, not a component. */
static pl_component *component_or_node_hint(pl_node *root, const char *obj, const char *field,
                                            pl_error *err)
{
    pl_component *c = pl_walk_component(root, obj, err);
    char hint[512];
    if (!c && (!strcmp(field, "dt") || !strcmp(field, "gravity")) &&
        pl_walk_suggest_node(root, obj, hint, sizeof hint))
        pl_error_set(err, PL_EINPUT, NULL, 0, obj, "no node '%s' in the scene (did you mean %s?)",
                     obj, hint);
    return c;
}

int pl_walk_set_runtime(pl_node *root, pl_data *d, const char *path, const char *value,
                        int *runtime, pl_error *err)
{
    char obj[512];
    const char *field;
    *runtime = 0;
    if (split(path, obj, sizeof obj, &field) != 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, path,
                            "expected component.field (e.g. bar/arap.youngModulus)");
    pl_node *n = walk_nodes(root, obj);
    if (n && (!strcmp(field, "dt") || !strcmp(field, "gravity")))
        return set_node_field(n, field, value, err);
    pl_component *c = component_or_node_hint(root, obj, field, err);
    if (!c) return PL_EINPUT;
    const pl_field *f = pl_component_field(c, field);
    if (!f) {
        const char *best = NULL;
        int bestd = 1 << 30;
        for (int k = 0; k < c->type->nfields; ++k) {
            int d = pl_edit_distance(field, c->type->fields[k].name);
            if (d < bestd) bestd = d, best = c->type->fields[k].name;
        }
        if (best && bestd <= 3)
            return pl_error_set(err, PL_EINPUT, NULL, 0, path,
                                "%s has no field '%s' (did you mean %s?)", c->type->name, field,
                                best);
        return pl_error_set(err, PL_EINPUT, NULL, 0, path, "%s has no field '%s'", c->type->name,
                            field);
    }
    if (f->flags & PL_FIELD_OUTPUT)
        return pl_error_set(err, PL_EINPUT, NULL, 0, path, "'%s' is an output and cannot be set",
                            field);
    /* an input field's value lives in the data (the component keeps the scene's) */
    int input = d && (f->flags & PL_FIELD_INPUT);
    int rc = input ? pl_input_set_text(d, c, f, value, err) : pl_field_parse(f, c, value, err);
    if (rc) {
        snprintf(err->where, sizeof err->where, "%s", path);
        return rc;
    }
    *runtime = (f->flags & (PL_FIELD_RUNTIME | PL_FIELD_INPUT)) != 0;
    return PL_OK;
}

int pl_walk_set(pl_node *root, const char *path, const char *value, pl_error *err)
{
    int runtime;
    return pl_walk_set_runtime(root, NULL, path, value, &runtime, err);
}

int pl_walk_get(pl_node *root, const pl_data *d, const char *path, char *buf, size_t size,
                pl_error *err)
{
    char obj[512];
    const char *field;
    if (split(path, obj, sizeof obj, &field) != 0)
        return pl_error_set(err, PL_EINPUT, NULL, 0, path, "expected component.field");
    pl_node *n = walk_nodes(root, obj);
    if (n && !strcmp(field, "dt")) {
        snprintf(buf, size, "%.17g", pl_node_dt(n));
        return PL_OK;
    }
    if (n && !strcmp(field, "gravity")) {
        double g[3];
        pl_node_gravity(n, g);
        snprintf(buf, size, "%.17g %.17g %.17g", g[0], g[1], g[2]);
        return PL_OK;
    }
    pl_component *c = component_or_node_hint(root, obj, field, err);
    if (!c) return PL_EINPUT;
    if (c->type->ops.get && d) {
        /* PL_EINPUT: not a field it serves; anything else: it serves it but the
         * text did not fit (falling through would give the scene's value, not
         * the state: a MechanicalObject's position read as "" for a mesh) */
        int grc = c->type->ops.get(c, d, field, buf, size);
        if (grc == PL_OK) return PL_OK;
        if (grc != PL_EINPUT)
            return pl_error_set(err, PL_EINPUT, NULL, 0, path,
                                "the value does not fit in %zu bytes", size);
    }
    const pl_field *f = pl_component_field(c, field);
    if (!f)
        return pl_error_set(err, PL_EINPUT, NULL, 0, path, "%s has no field '%s'", c->type->name,
                            field);
    if (d && (f->flags & PL_FIELD_INPUT) && pl_input_slot(d->model, c, f) >= 0) {
        if (pl_input_format(d, c, f, buf, size) != PL_OK)
            return pl_error_set(err, PL_EINPUT, NULL, 0, path,
                                "the value does not fit in %zu bytes", size);
        return PL_OK;
    }
    if (pl_field_format(f, c, buf, size) != PL_OK)
        return pl_error_set(err, PL_EINPUT, NULL, 0, path, "the value does not fit in %zu bytes",
                            size);
    return PL_OK;
}
