/* sofa_cable_area.c - SoftRobots' surface cable in a mapped child node:
 * a CableConstraint with centers, radii, method="sphere"|"geodesic" and
 * surfaceTopology, in a node holding a loader of the surface's triangles
 * (often through a MeshTopology src="@loader"), a MechanicalObject whose
 * points come from that topology, and a BarycentricMapping to the body's
 * tetrahedra.  Pliant moves the constraint into the body's node and the
 * loader beside the body's as <node>_<loader>, named by the cable's
 * `surface`: the cable plugin takes the pulled areas from its triangles
 * and maps their points into the tetrahedra (plugins/cable/cable_area.c).
 * Part of the lowering (sofa_structure.c calls it for each such cable). */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sofa_is_area_cable(xmlNode *e)
{
    char *m = sofa_get(e, "method");
    int area = m && (!strcmp(m, "geodesic") || !strcmp(m, "sphere"));
    xmlFree(m);
    return area;
}

/* The loader that surfaceTopology names: the loader itself, or a topology
 * of the node filled from a loader of the node (src="@loader"). */
static xmlNode *surface_loader(sofa_lower *L, xmlNode *node, xmlNode *e)
{
    char *v = sofa_get(e, "surfaceTopology");
    xmlNode *t = v && v[0] == '@' ? sofa_find(node, v + 1) : NULL;
    if (t && t->parent == node && !strstr((const char *)t->name, "Loader")) {
        char *src = sofa_get(t, "src");
        xmlNode *l = src && src[0] == '@' ? sofa_find(node, src + 1) : NULL;
        int own = xmlHasProp(t, (const xmlChar *)"triangles") ||
                  xmlHasProp(t, (const xmlChar *)"position");
        t = l && l->parent == node && !own ? l : NULL;
        xmlFree(src);
    }
    if (!t || t->parent != node || !strstr((const char *)t->name, "Loader")) {
        char *m = sofa_get(e, "method");
        sofa_error(L, e, "surfaceTopology=\"%s\": a surface cable (method=\"%s\") needs a link "
                         "to a loader of its node, or to a MeshTopology of its node filled from "
                         "one (src=\"@loader\")",
                   v ? v : "", m ? m : "");
        xmlFree(m);
    }
    xmlFree(v);
    return t && t->parent == node && strstr((const char *)t->name, "Loader") ? t : NULL;
}

void sofa_lower_area_cable(sofa_lower *L, xmlNode *node, xmlNode *e, xmlNode *moved)
{
    xmlNode *loader = surface_loader(L, node, e);
    if (!loader) {
        sofa_remove(moved);
        return;
    }
    char *nn = sofa_get(node, "name"), *ln = sofa_get(loader, "name"), name[256], link[260];
    snprintf(name, sizeof name, "%s_%s", nn ? nn : "cable", ln ? ln : "loader");
    xmlFree(nn);
    xmlFree(ln);
    xmlNode *copy = xmlCopyNode(loader, 1);
    if (!copy) {
        sofa_remove(moved);
        return;
    }
    copy->line = loader->line;
    xmlAddPrevSibling(node, copy);
    sofa_set(copy, "name", name);
    snprintf(link, sizeof link, "@%s", name);
    sofa_unset(moved, "surfaceTopology");
    sofa_set(moved, "surface", link);
}
