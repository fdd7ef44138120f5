/* sofa_dom.c - the small document helpers the SOFA lowering shares
 * (sofa_lower.h): attributes, new and removed elements, paths for messages,
 * notes given once, and SOFA's link paths (@name, @../name, @x.field)
 * resolved among the elements of the document. */
#include "sofa_lower.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sofa_line(xmlNode *e)
{
    long l = xmlGetLineNo(e);
    return l > 0 ? (int)l : 0;
}

int sofa_is_element(const xmlNode *e) { return e && e->type == XML_ELEMENT_NODE; }
int sofa_tag_is(const xmlNode *e, const char *tag)
{
    return sofa_is_element(e) && !strcmp((const char *)e->name, tag);
}
int sofa_is_node(const xmlNode *e) { return sofa_tag_is(e, "Node"); }

char *sofa_get(xmlNode *e, const char *name)
{
    return (char *)xmlGetProp(e, (const xmlChar *)name);
}

void sofa_set(xmlNode *e, const char *name, const char *value)
{
    xmlSetProp(e, (const xmlChar *)name, (const xmlChar *)value);
}

void sofa_unset(xmlNode *e, const char *name) { xmlUnsetProp(e, (const xmlChar *)name); }

xmlNode *sofa_new_before(sofa_lower *L, xmlNode *before, const char *tag, int line)
{
    xmlNode *n = xmlNewDocNode(L->doc, NULL, (const xmlChar *)tag, NULL);
    if (!n) return NULL;
    n->line = (unsigned short)(line > 0 && line < 65535 ? line : 65535);
    if (before)
        xmlAddPrevSibling(before, n);
    else
        xmlAddChild(L->root, n);
    return n;
}

void sofa_remove(xmlNode *e)
{
    xmlUnlinkNode(e);
    xmlFreeNode(e);
}

const char *sofa_node_path(xmlNode *node, char *buf, size_t size)
{
    const char *names[32];
    int n = 0;
    for (xmlNode *p = node; sofa_is_node(p) && n < 32; p = p->parent) {
        char *nm = sofa_get(p, "name");
        names[n++] = nm ? nm : NULL;
    }
    size_t w = 0;
    buf[0] = '\0';
    for (int k = n - 1; k >= 0; --k) {
        w += (size_t)snprintf(buf + w, w < size ? size - w : 0, "%s%s", k == n - 1 ? "" : "/",
                              names[k] ? names[k] : (k == n - 1 ? "root" : "node"));
        xmlFree((xmlChar *)names[k]);
    }
    return buf;
}

const char *sofa_where(xmlNode *e, char *buf, size_t size)
{
    char np[160];
    char *nm = sofa_get(e, "name");
    sofa_node_path(e->parent, np, sizeof np);
    snprintf(buf, size, "%s %s/%s", (const char *)e->name, np, nm ? nm : (const char *)e->name);
    xmlFree(nm);
    return buf;
}

void sofa_note(sofa_lower *L, const char *key, xmlNode *e, const char *fmt, ...)
{
    for (int k = 0; k < L->nnoted; ++k)
        if (!strcmp(L->noted[k], key)) return;
    if (L->nnoted < SOFA_MAX_NOTES) L->noted[L->nnoted++] = strdup(key);
    char msg[1024], where[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    pl_diag_warn(L->diag, L->file, sofa_line(e), sofa_where(e, where, sizeof where), "%s", msg);
}

void sofa_error(sofa_lower *L, xmlNode *e, const char *fmt, ...)
{
    char msg[1024], where[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    pl_diag_error(L->diag, PL_EINPUT, L->file, sofa_line(e), sofa_where(e, where, sizeof where),
                  "%s", msg);
}

static xmlNode *named_in(xmlNode *node, const char *name, size_t len)
{
    for (xmlNode *k = node ? node->children : NULL; k; k = k->next) {
        if (!sofa_is_element(k)) continue;
        char *nm = sofa_get(k, "name");
        int hit = nm && strlen(nm) == len && !strncmp(nm, name, len);
        xmlFree(nm);
        if (hit) return k;
    }
    return NULL;
}

xmlNode *sofa_find(xmlNode *node, const char *path)
{
    int bare = 1;
    for (;;) {
        if (!strncmp(path, "./", 2)) {
            path += 2, bare = 0;
        } else if (!strncmp(path, "../", 3)) {
            path += 3, bare = 0;
            node = node ? node->parent : NULL;
            if (!sofa_is_node(node)) return NULL;
        } else {
            break;
        }
    }
    const char *slash;
    while ((slash = strchr(path, '/'))) { /* child/child/name */
        xmlNode *child = named_in(node, path, (size_t)(slash - path));
        if (!sofa_is_node(child)) return NULL;
        node = child, path = slash + 1, bare = 0;
    }
    for (; sofa_is_node(node); node = bare ? node->parent : NULL) {
        xmlNode *e = named_in(node, path, strlen(path));
        if (e && !sofa_is_node(e)) return e;
        if (!bare) break;
    }
    return NULL;
}

xmlNode *sofa_data_link(xmlNode *node, const char *value, const char **field)
{
    if (!value || value[0] != '@') return NULL;
    const char *dot = strrchr(value, '.');
    if (!dot || dot == value + 1 || dot[1] == '/' || dot[-1] == '.') return NULL;
    char path[256];
    size_t len = (size_t)(dot - value - 1);
    if (len >= sizeof path) return NULL;
    memcpy(path, value + 1, len);
    path[len] = '\0';
    *field = dot + 1;
    return sofa_find(node, path);
}

int sofa_parse_number(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    while (*end == ' ' || *end == '\t' || *end == '\n') ++end;
    return end != s && !*end;
}

int sofa_is_true(const char *s)
{
    return s && (!strcmp(s, "1") || !strcmp(s, "true") || !strcmp(s, "True"));
}

