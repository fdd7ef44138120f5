/* walk_suggest.c - "did you mean" for the node and component names of a
 * path (`--set`, pl_sim_set/get), as the scene reader does for fields. */
#include "walk.h"

#include "pliant/field.h"

#include <stdio.h>
#include <string.h>

/* A name is close when a few edits make it, fewer edits than it has letters. */
static int close_enough(int d, const char *word) { return d <= 3 && d < (int)strlen(word); }

static pl_node *closest_child(const pl_node *n, const char *seg, size_t len)
{
    char word[256];
    snprintf(word, sizeof word, "%.*s", (int)len, seg);
    pl_node *best = NULL;
    int bestd = 1 << 30;
    for (int k = 0; k < n->nchildren; ++k) {
        const char *name = n->children[k]->name;
        if (!name) continue;
        if (strlen(name) == len && !strncmp(name, seg, len)) return n->children[k];
        int d = pl_edit_distance(word, name);
        if (d < bestd) bestd = d, best = n->children[k];
    }
    return best && close_enough(bestd, word) ? best : NULL;
}

int pl_walk_suggest_node(pl_node *root, const char *path, char *buf, size_t size)
{
    const char *s = path;
    size_t rl = strlen(root->name), used = 0;
    if (!strncmp(s, root->name, rl) && (s[rl] == '/' || s[rl] == '\0')) {
        s += rl;
        if (*s == '/') s++;
    }
    buf[0] = '\0';
    pl_node *n = root;
    while (*s) {
        const char *slash = strchr(s, '/');
        size_t len = slash ? (size_t)(slash - s) : strlen(s);
        n = closest_child(n, s, len);
        if (!n) return 0;
        used += (size_t)snprintf(buf + used, used < size ? size - used : 0, "%s%s",
                                 used ? "/" : "", n->name);
        s = slash ? slash + 1 : s + len;
    }
    return used > 0 && used < size;
}

const char *pl_walk_suggest_component(const pl_node *n, const char *name)
{
    const char *best = NULL;
    int bestd = 1 << 30;
    for (int k = 0; k < n->ncomponents; ++k) {
        const char *cn = n->components[k]->name;
        int d = cn ? pl_edit_distance(name, cn) : bestd;
        if (d < bestd) bestd = d, best = cn;
    }
    return best && close_enough(bestd, name) ? best : NULL;
}

typedef struct closest {
    const char *name;
    const pl_component *best;
    int bestd, ties;
} closest;

static int visit(pl_component *c, void *user)
{
    closest *w = user;
    int d = c->name ? pl_edit_distance(w->name, c->name) : 1 << 30;
    if (d < w->bestd) w->bestd = d, w->best = c, w->ties = 0;
    else if (d == w->bestd && w->best && c->name && !strcmp(c->name, w->best->name)) w->ties++;
    return 0;
}

int pl_walk_suggest_anywhere(pl_node *root, const char *name, char *buf, size_t size)
{
    closest w = {name, NULL, 1 << 30, 0};
    walk_pre(root, visit, &w);
    if (!w.best || !close_enough(w.bestd, name)) return 0;
    if (w.ties == 0) /* a unique name may stand alone */
        snprintf(buf, size, "%s", w.best->name);
    else {
        char node[384];
        pl_node_path(w.best->node, node, sizeof node);
        snprintf(buf, size, "%s/%s", node, w.best->name);
    }
    return 1;
}
