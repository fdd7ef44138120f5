/* scene_xml.c - XML scene -> node tree, with every mistake reported.
 *
 * Security: scenes are parsed by xml_guard.c, with network access off and
 * without entity substitution; a document that declares a DTD is refused
 * as soon as the parser meets it, whatever its encoding. */
#include "scene.h"
#include "sofa.h"
#include "xml_guard.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/tree.h>

/* What every step of building the tree needs. */
typedef struct scene_build {
    const char *file;
    pl_registry *reg;
    pl_diag *diag;
    int flags; /* PL_SCENE_* */
} scene_build;

static const char *const NODE_ATTRS[] = {"name", "dt", "gravity", "animate", NULL};

static int line_of(xmlNode *x)
{
    long l = xmlGetLineNo(x);
    return l > 0 ? (int)l : 0;
}

static pl_node *new_node(pl_node *parent, const char *name, const char *file, int line)
{
    pl_node *n = calloc(1, sizeof *n);
    if (!n) return NULL;
    n->name = strdup(name ? name : "root");
    n->file = strdup(file);
    n->line = line;
    n->parent = parent;
    if (!n->name || !n->file) {
        free(n->name);
        free(n->file);
        free(n);
        return NULL;
    }
    if (parent) {
        if (parent->nchildren == parent->cap_children) {
            int cap = parent->cap_children ? 2 * parent->cap_children : 4;
            pl_node **c = realloc(parent->children, (size_t)cap * sizeof *c);
            if (!c) {
                free(n->name);
                free(n->file);
                free(n);
                return NULL;
            }
            parent->children = c;
            parent->cap_children = cap;
        }
        parent->children[parent->nchildren++] = n;
    }
    return n;
}

static void destroy_component(pl_component *c)
{
    if (c->type->ops.destroy) c->type->ops.destroy(c);
    for (int k = 0; k < c->type->nfields; ++k) pl_field_release(&c->type->fields[k], c);
    free(c->name);
    free(c->file);
    free(c);
}

void pl_scene_free(pl_node *n)
{
    if (!n) return;
    for (int k = 0; k < n->nchildren; ++k) pl_scene_free(n->children[k]);
    /* components in reverse order: later ones may point at earlier ones */
    for (int k = n->ncomponents - 1; k >= 0; --k) destroy_component(n->components[k]);
    free(n->children);
    free(n->components);
    free(n->name);
    free(n->file);
    free(n);
}

void pl_scene_remove_component(pl_node *n, pl_component *c)
{
    for (int k = 0; k < n->ncomponents; ++k)
        if (n->components[k] == c) {
            memmove(n->components + k, n->components + k + 1,
                    sizeof *n->components * (size_t)(n->ncomponents - k - 1));
            n->ncomponents--;
            destroy_component(c);
            return;
        }
}

void pl_scene_move_component_first(pl_node *n, pl_component *c)
{
    for (int k = 0; k < n->ncomponents; ++k)
        if (n->components[k] == c) {
            memmove(n->components + 1, n->components, sizeof *n->components * (size_t)k);
            n->components[0] = c;
            return;
        }
}

static int name_taken(const pl_node *n, const char *name)
{
    for (int k = 0; k < n->ncomponents; ++k)
        if (!strcmp(n->components[k]->name, name)) return 1;
    return 0;
}

pl_component *pl_scene_new_component(pl_node *n, const pl_type *t, const char *name,
                                     const char *file, int line, pl_diag *diag)
{
    char buf[128];
    if (!name) {
        /* SOFA's default name: the type name with a lower-case initial */
        snprintf(buf, sizeof buf, "%s", t->name);
        buf[0] = (char)tolower((unsigned char)buf[0]);
        for (int k = 2; name_taken(n, buf); ++k) {
            snprintf(buf, sizeof buf, "%s%d", t->name, k);
            buf[0] = (char)tolower((unsigned char)buf[0]);
        }
        name = buf;
    } else if (name_taken(n, name)) {
        char np[160];
        pl_diag_error(diag, PL_EINPUT, file, line, pl_node_path(n, np, sizeof np),
                      "two components are named '%s' in this node", name);
        return NULL;
    }
    pl_component *c = calloc(1, t->size);
    if (!c) return NULL;
    c->type = t;
    c->node = n;
    c->line = line;
    c->name = strdup(name);
    c->file = strdup(file);
    if (!c->name || !c->file) goto oom;
    for (int k = 0; k < t->nfields; ++k) {
        const pl_field *f = &t->fields[k];
        if (!f->def) continue;
        pl_error e;
        if (pl_field_parse(f, c, f->def, &e) != PL_OK) {
            /* a bad default is a bug in the component, not the user's fault */
            pl_diag_error(diag, PL_EINTERNAL, file, line, t->name, "bad default for %s: %s",
                          f->name, e.msg);
        }
    }
    if (n->ncomponents == n->cap_components) {
        int cap = n->cap_components ? 2 * n->cap_components : 8;
        pl_component **cs = realloc(n->components, (size_t)cap * sizeof *cs);
        if (!cs) goto oom;
        n->components = cs;
        n->cap_components = cap;
    }
    n->components[n->ncomponents++] = c;
    return c;
oom:
    free(c->name);
    free(c->file);
    free(c);
    return NULL;
}

/* Best field name for a misspelled attribute. */
static const char *suggest_field(const pl_type *t, const char *attr)
{
    const char *best = NULL;
    int bestd = 1 << 30;
    for (int k = 0; k < t->nfields; ++k) {
        int d = pl_edit_distance(attr, t->fields[k].name);
        if (d < bestd) bestd = d, best = t->fields[k].name;
    }
    return (best && bestd <= 2 + (int)strlen(attr) / 4) ? best : NULL;
}

static void parse_attributes(pl_component *c, xmlNode *x, const char *file, pl_diag *diag)
{
    char where[192], path[160];
    snprintf(where, sizeof where, "%s %s", c->type->name, pl_component_path(c, path, sizeof path));
    for (xmlAttr *a = x->properties; a; a = a->next) {
        const char *an = (const char *)a->name;
        if (!strcmp(an, "name") || !strcmp(an, "template")) continue; /* template: a hint */
        xmlChar *v = xmlNodeListGetString(x->doc, a->children, 1);
        const pl_field *f = pl_component_field(c, an);
        if (!f) {
            const char *s = suggest_field(c->type, an);
            pl_diag_error(diag, PL_EINPUT, file, line_of(x), where,
                          s ? "unknown attribute '%s' (did you mean %s?)"
                            : "unknown attribute '%s'%s",
                          an, s ? s : " (run `pliant list` for the fields of each component)");
        } else if (f->flags & PL_FIELD_OUTPUT) {
            pl_diag_error(diag, PL_EINPUT, file, line_of(x), where,
                          "'%s' is an output of %s and cannot be set", an, c->type->name);
        } else {
            pl_error e;
            if (pl_field_parse(f, c, v ? (const char *)v : "", &e) != PL_OK)
                pl_diag_error(diag, e.code, file, line_of(x), where, "%s", e.msg);
        }
        xmlFree(v);
    }
    for (int k = 0; k < c->type->nfields; ++k) {
        const pl_field *f = &c->type->fields[k];
        if ((f->flags & PL_FIELD_REQUIRED) && !xmlHasProp(x, (const xmlChar *)f->name) &&
            !(f->alias && xmlHasProp(x, (const xmlChar *)f->alias)))
            pl_diag_error(diag, PL_EINPUT, file, line_of(x), where,
                          "missing required attribute '%s' (%s)", f->name, f->help);
    }
}

/* A plugin name names a file of the plugin path (lib<name>.so): letters,
 * digits, '_', '-' and '.', never a path.  A scene is data: it must not be
 * able to make the program map and run an arbitrary shared object (its
 * constructors run on dlopen, before any check), so a path is accepted only
 * when the user running the scene allows it. */
static int is_plain_plugin_name(const char *p)
{
    if (!*p || strstr(p, "..")) return 0;
    for (; *p; ++p)
        if (!isalnum((unsigned char)*p) && *p != '_' && *p != '-' && *p != '.') return 0;
    return 1;
}

static void load_required_plugins(xmlNode *x, const scene_build *b)
{
    xmlChar *v = xmlGetProp(x, (const xmlChar *)"pluginName");
    if (!v) v = xmlGetProp(x, (const xmlChar *)"name");
    if (!v) {
        pl_diag_error(b->diag, PL_EINPUT, b->file, line_of(x), "RequiredPlugin",
                      "missing attribute 'name' (the plugin to load)");
        return;
    }
    char *list = strdup((const char *)v), *save = NULL;
    xmlFree(v);
    if (!list) return;
    for (char *p = strtok_r(list, " \t\n,", &save); p; p = strtok_r(NULL, " \t\n,", &save)) {
        pl_error e;
        int is_path = strchr(p, '/') || strstr(p, "..");
        if (!is_plain_plugin_name(p) && !(is_path && (b->flags & PL_SCENE_ALLOW_PLUGIN_PATH))) {
            pl_diag_error(b->diag, PL_EINPUT, b->file, line_of(x), "RequiredPlugin",
                          is_path ? "'%s' is a path: a scene names plugins, which are loaded from "
                                    "the plugin path only (PLIANT_PLUGIN_PATH and the built-in "
                                    "folders); `pliant run --allow-plugin-path` lets a scene you "
                                    "trust load a file"
                                  : "'%s' is not a plugin name (letters, digits, '_', '-', '.')",
                          p);
            continue;
        }
        if (pl_registry_load_plugin(b->reg, p, &e) != PL_OK)
            pl_diag_error(b->diag, e.code, b->file, line_of(x), "RequiredPlugin", "%s", e.msg);
    }
    free(list);
}

static void parse_node_attrs(pl_node *n, xmlNode *x, const char *file, pl_diag *diag)
{
    char np[160];
    pl_node_path(n, np, sizeof np);
    for (xmlAttr *a = x->properties; a; a = a->next) {
        const char *an = (const char *)a->name;
        xmlChar *v = xmlNodeListGetString(x->doc, a->children, 1);
        const char *s = v ? (const char *)v : "";
        pl_error e;
        pl_field f = {0};
        if (!strcmp(an, "dt")) {
            f = (pl_field){"dt", PL_F_DOUBLE, offsetof(pl_node, dt), NULL, "", 0, NULL, NULL};
            if (pl_field_parse(&f, n, s, &e) != PL_OK || n->dt <= 0)
                pl_diag_error(diag, PL_EINPUT, file, line_of(x), np,
                              "dt: expected a positive time step [s], found '%s'", s);
            n->has_dt = 1;
        } else if (!strcmp(an, "gravity")) {
            f = (pl_field){"gravity", PL_F_VEC3, offsetof(pl_node, gravity), NULL, "", 0, NULL,
                           NULL};
            if (pl_field_parse(&f, n, s, &e) != PL_OK)
                pl_diag_error(diag, PL_EINPUT, file, line_of(x), np, "%s", e.msg);
            n->has_gravity = 1;
        } else if (strcmp(an, "name") && strcmp(an, "animate")) {
            const char *best = NULL;
            int bestd = 1 << 30;
            for (int k = 0; NODE_ATTRS[k]; ++k) {
                int d = pl_edit_distance(an, NODE_ATTRS[k]);
                if (d < bestd) bestd = d, best = NODE_ATTRS[k];
            }
            if (bestd <= 2)
                pl_diag_error(diag, PL_EINPUT, file, line_of(x), np,
                              "unknown Node attribute '%s' (did you mean %s?)", an, best);
            else
                pl_diag_error(diag, PL_EINPUT, file, line_of(x), np,
                              "unknown Node attribute '%s' (a Node takes name, dt, gravity)", an);
        }
        xmlFree(v);
    }
}

static void build_node(pl_node *n, xmlNode *x, const scene_build *b)
{
    const char *file = b->file;
    pl_diag *diag = b->diag;
    parse_node_attrs(n, x, file, diag);
    /* plugins first, wherever they appear in the node, so order does not matter */
    for (xmlNode *k = x->children; k; k = k->next)
        if (k->type == XML_ELEMENT_NODE && !strcmp((const char *)k->name, "RequiredPlugin"))
            load_required_plugins(k, b);
    for (xmlNode *k = x->children; k; k = k->next) {
        if (k->type != XML_ELEMENT_NODE) continue;
        const char *tag = (const char *)k->name;
        char np[160];
        pl_node_path(n, np, sizeof np);
        if (!strcmp(tag, "RequiredPlugin")) continue;
        if (!strcmp(tag, "Node")) {
            xmlChar *nm = xmlGetProp(k, (const xmlChar *)"name");
            pl_node *child = new_node(n, nm ? (const char *)nm : "node", file, line_of(k));
            xmlFree(nm);
            if (!child) {
                pl_diag_error(diag, PL_EINTERNAL, file, line_of(k), np, "out of memory");
                return;
            }
            build_node(child, k, b);
            continue;
        }
        const pl_type *t = pl_registry_find(b->reg, tag);
        if (!t) {
            const char *s = pl_registry_suggest(b->reg, tag);
            char plugin[128];
            if (pl_registry_plugin_providing(b->reg, tag, plugin, sizeof plugin))
                pl_diag_error(diag, PL_EINPUT, file, line_of(k), np,
                              "unknown component type '%s': the plugin '%s' provides it; add "
                              "<RequiredPlugin name=\"%s\"/>",
                              tag, plugin, plugin);
            else if (s)
                pl_diag_error(diag, PL_EINPUT, file, line_of(k), np,
                              "unknown component type '%s' (did you mean %s?)", tag, s);
            else
                pl_diag_error(diag, PL_EINPUT, file, line_of(k), np,
                              "unknown component type '%s' (is a <RequiredPlugin name=\"...\"/> "
                              "missing? `pliant list` shows the known types)",
                              tag);
            continue;
        }
        xmlChar *nm = xmlGetProp(k, (const xmlChar *)"name");
        pl_component *c = pl_scene_new_component(n, t, (const char *)nm, file, line_of(k), diag);
        xmlFree(nm);
        if (c) parse_attributes(c, k, file, diag);
    }
}

pl_component *pl_node_add_component(pl_node *n, const pl_registry *reg, const char *type,
                                    const char *name, pl_diag *diag)
{
    const pl_type *t = pl_registry_find(reg, type);
    if (!t) {
        char np[160];
        pl_diag_error(diag, PL_EINPUT, n->file ? n->file : "<scene>", 0,
                      pl_node_path(n, np, sizeof np), "no component type '%s' is registered",
                      type);
        return NULL;
    }
    pl_component *c = pl_scene_new_component(n, t, name, n->file ? n->file : "<scene>", 0, diag);
    if (!c && !diag->nerrors)
        pl_diag_error(diag, PL_EINTERNAL, n->file ? n->file : "<scene>", 0, type, "out of memory");
    return c;
}

pl_node *pl_scene_build(const char *xml, size_t len, const char *file, pl_registry *reg,
                        int flags, pl_diag *diag)
{
    scene_build b = {file, reg, diag, flags};
    if (len == 0) {
        pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "the scene is empty");
        return NULL;
    }
    if (len > (size_t)1 << 30) {
        pl_diag_error(diag, PL_EINPUT, file, 0, NULL, "the scene is larger than 1 GiB");
        return NULL;
    }
    pl_error e;
    xmlDoc *doc = pl_xml_read_untrusted(xml, len, file, "scenes", XML_PARSE_BIG_LINES, &e);
    if (!doc) {
        pl_diag_add(diag, &e);
        return NULL;
    }
    xmlNode *x = xmlDocGetRootElement(doc);
    pl_node *root = NULL;
    if (!x || strcmp((const char *)x->name, "Node") != 0) {
        pl_diag_error(diag, PL_EINPUT, file, x ? line_of(x) : 0, NULL,
                      "the root element must be <Node>, found <%s>",
                      x ? (const char *)x->name : "nothing");
    } else {
        xmlChar *nm = xmlGetProp(x, (const xmlChar *)"name");
        root = new_node(NULL, nm ? (const char *)nm : "root", file, line_of(x));
        xmlFree(nm);
        /* SOFA's vocabulary and idioms become Pliant components (sofa_lower.c) */
        pl_sofa_lower(doc, file, reg, diag);
        if (root) build_node(root, x, &b);
    }
    xmlFreeDoc(doc);
    return root;
}
