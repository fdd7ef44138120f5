/* sofa_cavity.c - SoftRobots' pressure cavity in a mapped child node: a
 * node holding the cavity's surface (a loader, a MechanicalObject, a
 * SurfacePressureConstraint, often VolumeFromTriangles) and a
 * BarycentricMapping to the body's tetrahedra.  Pliant moves the
 * constraint into the body's node: its points are the mapped node's
 * points (inline positions with `triangles`), or the node's loader, moved
 * beside the body's as <node>_<loader> and named by `surface`; each point
 * follows the tetrahedron containing it (cable plugin, surface_pressure.c).
 * `triangles` linking the loader's (directly or through a MeshTopology filled
 * from it) mean the loader's.  Under an IdentityMapping `triangles` index the
 * body's vertices.  Part of
 * the lowering (sofa_structure.c calls it for each such constraint). */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static xmlNode *node_loader(xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_is_element(e) && strstr((const char *)e->name, "Loader")) return e;
    return NULL;
}

/* Copies the mapped node's loader beside the body's (before `node`);
 * returns its new name (caller frees) or NULL after an error. */
static char *move_loader(sofa_lower *L, xmlNode *node, xmlNode *e)
{
    xmlNode *loader = node_loader(node);
    if (!loader) {
        sofa_error(L, e, "the cavity has no triangles: give a loader in its node, or triangles "
                         "(with the MechanicalObject's position)");
        return NULL;
    }
    char *nn = sofa_get(node, "name"), *ln = sofa_get(loader, "name"), name[256];
    snprintf(name, sizeof name, "%s_%s", nn ? nn : "cavity", ln ? ln : "loader");
    xmlFree(nn);
    xmlFree(ln);
    xmlNode *copy = xmlCopyNode(loader, 1);
    if (!copy) return NULL;
    copy->line = loader->line;
    xmlAddPrevSibling(node, copy);
    sofa_set(copy, "name", name);
    return strdup(name);
}

static xmlNode *topological_mapping(xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_is_element(e) && strstr((const char *)e->name, "TopologicalMapping")) return e;
    return NULL;
}

/* 1 when e's triangles/quads link the node's own loader's (triangles="@topo.triangles"
 * with <MeshTopology name="topo" src="@loader"/>, or "@loader.triangles"): SoftRobots'
 * scripts write them out, and they are what the loader path takes anyway. */
static int links_to_loader(xmlNode *node, xmlNode *e, xmlNode *loader)
{
    static const char *const ATTRS[] = {"triangles", "quads"};
    int any = 0;
    for (int k = 0; k < 2; ++k) {
        char *v = sofa_get(e, ATTRS[k]);
        if (!v) continue;
        const char *field = NULL;
        xmlNode *t = loader ? sofa_data_link(node, v, &field) : NULL;
        int ok = t && t->parent == node && !strcmp(field, ATTRS[k]);
        if (ok && t != loader) { /* a topology: filled from the loader, nothing of its own */
            char *src = sofa_get(t, "src");
            ok = src && src[0] == '@' && sofa_find(node, src + 1) == loader &&
                 !xmlHasProp(t, (const xmlChar *)"triangles") &&
                 !xmlHasProp(t, (const xmlChar *)"quads") &&
                 !xmlHasProp(t, (const xmlChar *)"position");
            xmlFree(src);
        }
        xmlFree(v);
        if (!ok) return 0;
        any = 1;
    }
    return any;
}

void sofa_lower_cavity(sofa_lower *L, xmlNode *node, xmlNode *mo, xmlNode *e, int identity)
{
    xmlNode *parent = node->parent;
    char *pos = mo ? sofa_get(mo, "position") : NULL;
    int tris = xmlHasProp(e, (const xmlChar *)"triangles") || xmlHasProp(e, (const xmlChar *)"quads");
    int inline_points = pos && pos[0] != '@';
    xmlNode *moved = xmlCopyNode(e, 1);
    if (!moved) {
        xmlFree(pos);
        return;
    }
    moved->line = e->line;
    xmlAddPrevSibling(node, moved);
    xmlNode *tmap = topological_mapping(node);
    if (tmap) {
        /* SoftRobots would take the cavity from the topology that mapping fills
         * (the body's surface), not from a loader: refused, never misread */
        sofa_error(L, tmap, "%s in the cavity's node: Pliant takes a cavity from a loader, "
                            "triangles or box, not from a topological mapping; give the "
                            "cavity's surface by a loader (MeshOBJLoader) in this node",
                   (const char *)tmap->name);
        sofa_remove(moved);
        xmlFree(pos);
        return;
    }
    if (tris && !identity && !inline_points && links_to_loader(node, e, node_loader(node))) {
        sofa_unset(moved, "triangles"); /* the loader's, taken through `surface` below */
        sofa_unset(moved, "quads");
        tris = 0;
    }
    if (identity && inline_points) {
        sofa_error(L, mo, "under an IdentityMapping the points are the parent's vertices: remove "
                          "position");
    } else if (tris && (identity || inline_points)) {
        if (!identity) sofa_set(moved, "position", pos);
    } else if (tris) {
        sofa_error(L, e, "triangles of points that the node's loader gives: give the points as "
                         "numbers (MechanicalObject position) or drop triangles to use the "
                         "loader's");
    } else {
        char *name = move_loader(L, node, e);
        if (name) {
            char link[260];
            snprintf(link, sizeof link, "@%s", name);
            sofa_set(moved, "surface", link);
            free(name);
        } else {
            sofa_remove(moved);
        }
    }
    xmlFree(pos);
    char where[160], pp[160];
    sofa_node_path(node, where, sizeof where);
    sofa_note(L, "mapped-cavity", e,
              "the cavity of the mapped node '%s' acts in '%s' (its points follow the %s): its "
              "path there is %s/<name>",
              where, sofa_node_path(parent, pp, sizeof pp),
              identity ? "body's vertices" : "tetrahedra containing them", pp);
}
