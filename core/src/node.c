/* node.c - the scene tree: inherited context, role lookup, link resolution. */
#include "pliant/node.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

double pl_node_dt(const pl_node *n)
{
    for (; n; n = n->parent)
        if (n->has_dt) return n->dt;
    return 0.01;
}

void pl_node_gravity(const pl_node *n, double g[3])
{
    for (; n; n = n->parent)
        if (n->has_gravity) {
            memcpy(g, n->gravity, 3 * sizeof *g);
            return;
        }
    g[0] = 0.0;
    g[1] = -9.81;
    g[2] = 0.0;
}

const char *pl_node_path(const pl_node *n, char *buf, size_t size)
{
    if (!n) {
        snprintf(buf, size, "%s", "");
        return buf;
    }
    if (!n->parent) {
        snprintf(buf, size, "%s", n->name ? n->name : "root");
        return buf;
    }
    char up[160];
    pl_node_path(n->parent, up, sizeof up);
    /* a path for messages: cut when longer than buf */
    if (snprintf(buf, size, "%s/%s", up, n->name ? n->name : "?") >= (int)size && size > 3)
        memcpy(buf + size - 4, "...", 4);
    return buf;
}

pl_component *pl_node_find_role(const pl_node *n, pl_role role)
{
    if (!n) return NULL;
    for (int k = 0; k < n->ncomponents; ++k)
        if (pl_component_role(n->components[k], role)) return n->components[k];
    return NULL;
}

pl_component *pl_node_find_role_up(const pl_node *n, pl_role role)
{
    for (; n; n = n->parent) {
        pl_component *c = pl_node_find_role(n, role);
        if (c) return c;
    }
    return NULL;
}

int pl_node_visit_role(pl_node *n, pl_role role, pl_component_visit fn, void *user)
{
    for (int k = 0; k < n->ncomponents; ++k)
        if (pl_component_role(n->components[k], role)) {
            int rc = fn(n->components[k], user);
            if (rc) return rc;
        }
    for (int k = 0; k < n->nchildren; ++k) {
        int rc = pl_node_visit_role(n->children[k], role, fn, user);
        if (rc) return rc;
    }
    return 0;
}

int pl_node_count_role(const pl_node *n, pl_role role)
{
    int count = 0;
    for (int k = 0; k < n->ncomponents; ++k)
        if (pl_component_role(n->components[k], role)) count++;
    for (int k = 0; k < n->nchildren; ++k) count += pl_node_count_role(n->children[k], role);
    return count;
}

static pl_component *find_in_node(const pl_node *n, const char *name, size_t len)
{
    for (int k = 0; k < n->ncomponents; ++k) {
        const char *cn = n->components[k]->name;
        if (cn && strlen(cn) == len && !strncmp(cn, name, len)) return n->components[k];
    }
    return NULL;
}

static pl_node *child_named(const pl_node *n, const char *name, size_t len)
{
    for (int k = 0; k < n->nchildren; ++k) {
        const char *cn = n->children[k]->name;
        if (cn && strlen(cn) == len && !strncmp(cn, name, len)) return n->children[k];
    }
    return NULL;
}

/* Walks "a/b/c": every segment but the last is a node ("..", "." allowed),
 * the last a component. */
static pl_component *walk(const pl_node *n, const char *path)
{
    const char *s = path;
    while (n) {
        const char *slash = strchr(s, '/');
        size_t len = slash ? (size_t)(slash - s) : strlen(s);
        if (!slash) return find_in_node(n, s, len);
        if (len == 2 && !strncmp(s, "..", 2))
            n = n->parent;
        else if (!(len == 1 && s[0] == '.') && len > 0)
            n = child_named(n, s, len);
        s = slash + 1;
    }
    return NULL;
}

pl_component *pl_node_resolve(const pl_component *from, const char *path)
{
    if (!from || !path || !path[0]) return NULL;
    const pl_node *n = from->node;
    if (!strcmp(path, "[-1]")) {
        for (int k = 1; k < n->ncomponents; ++k)
            if (n->components[k] == from) return n->components[k - 1];
        return NULL;
    }
    if (path[0] == '/') {
        const pl_node *root = n;
        while (root->parent) root = root->parent;
        const char *rest = path + 1;
        /* "/root/bar/x" and "/bar/x" both name from the root */
        size_t rl = root->name ? strlen(root->name) : 0;
        if (rl && !strncmp(rest, root->name, rl) && rest[rl] == '/') rest += rl + 1;
        return walk(root, rest);
    }
    if (strchr(path, '/')) return walk(n, path);
    /* a bare name: this node, then up the tree (SOFA's context lookup) */
    for (; n; n = n->parent) {
        pl_component *c = find_in_node(n, path, strlen(path));
        if (c) return c;
    }
    return NULL;
}
