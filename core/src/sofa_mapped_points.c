/* sofa_mapped_points.c - a mapped child node that only follows its body
 * (no cable, no cavity acting in it) but whose MechanicalObject has points:
 * SOFA's WriteState and regression lists record such states (mapped 1), so
 * the node keeps them as the collision plugin's MappedPoints, named as the
 * MechanicalObject.  Its points: the MechanicalObject's numbers, or the
 * sphere centres of a SphereLoader it links (the liver's collision spheres)
 * under a BarycentricMapping; the body's vertices under an IdentityMapping
 * (a collision surface's points).  Part of the lowering (sofa_structure.c). */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static xmlNode *first_tag(xmlNode *node, const char *tag)
{
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_tag_is(e, tag)) return e;
    return NULL;
}

/* The collision plugin (MappedPoints), required once at the root. */
static void require_collision(sofa_lower *L, int line)
{
    for (xmlNode *e = L->root->children; e; e = e->next)
        if (sofa_tag_is(e, "RequiredPlugin")) {
            char *nm = sofa_get(e, "name");
            int found = nm && !strcmp(nm, "collision");
            xmlFree(nm);
            if (found) return;
        }
    xmlNode *first = L->root->children;
    while (first && !sofa_is_element(first)) first = first->next;
    xmlNode *req = first ? sofa_new_before(L, first, "RequiredPlugin", line)
                         : xmlNewChild(L->root, NULL, (const xmlChar *)"RequiredPlugin", NULL);
    if (!req) return;
    sofa_set(req, "name", "collision");
    /* loaded after the lowering of SOFA's names (its CollisionPipeline is
     * SOFA's until then): pl_sofa_lower */
    L->need |= NEED_COLLISION;
}

/* The SphereLoader whose positions the MechanicalObject links
 * (position="@[-1].position" or "@loader.position"), or NULL. */
static xmlNode *sphere_source(xmlNode *node, xmlNode *mo, const char *pos)
{
    const char *field = NULL;
    xmlNode *src = NULL;
    if (!strncmp(pos, "@[-", 3)) { /* SOFA's "the k-th component before this one" */
        int k = atoi(pos + 3);
        for (src = mo->prev; src && k > 0; src = src->prev)
            if (sofa_is_element(src) && --k == 0) break;
    } else {
        src = sofa_data_link(node, pos, &field);
    }
    return src && sofa_tag_is(src, "SphereLoader") ? src : NULL;
}

/* Does the mapping map the parent's MechanicalObject onto mo (when it says)? */
static int maps_onto(xmlNode *map, xmlNode *parent_mo, xmlNode *mo)
{
    char *in = sofa_get(map, "input"), *out = sofa_get(map, "output");
    int ok = (!in || (in[0] == '@' && sofa_find(map->parent, in + 1) == parent_mo)) &&
             (!out || (out[0] == '@' && sofa_find(map->parent, out + 1) == mo));
    xmlFree(in);
    xmlFree(out);
    return ok;
}

int sofa_lower_mapped_points(sofa_lower *L, xmlNode *node, xmlNode *map, xmlNode *mo,
                             int identity)
{
    xmlNode *parent_mo = first_tag(node->parent, "MechanicalObject");
    if (!mo || !parent_mo || !maps_onto(map, parent_mo, mo)) return 0;
    char *pos = sofa_get(mo, "position"), *name = sofa_get(mo, "name");
    xmlNode *sph = pos && pos[0] == '@' ? sphere_source(node, mo, pos) : NULL;
    char *file = sph ? sofa_get(sph, "filename") : NULL;
    int keep = identity ? !pos : (pos && pos[0] != '@') || file;
    if (keep) {
        int line = sofa_line(map); /* map goes below */
        xmlNode *mp = sofa_new_before(L, mo, "MappedPoints", sofa_line(mo));
        sofa_set(mp, "name", name ? name : "mapped");
        if (!identity && file) {
            sofa_set(mp, "filename", file);
            sofa_lower_mesh_path(L, mp);
        } else if (!identity) {
            sofa_set(mp, "position", pos);
        }
        xmlNode *next;
        for (xmlNode *e = node->children; e; e = next) {
            next = e->next;
            if (e != mp && (sofa_is_element(e) || sofa_is_node(e))) sofa_remove(e);
        }
        require_collision(L, line);
        char where[160];
        sofa_note(L, "mapped-points", mp,
                  "the node '%s' only follows the body: its MechanicalObject '%s' is kept as "
                  "MappedPoints (%s), recorded by pliant regress with mapped 1; the rest of the "
                  "node is dropped",
                  sofa_node_path(node, where, sizeof where), name ? name : "mapped",
                  identity ? "the body's vertices" : "barycentric in the body's tetrahedra");
    }
    xmlFree(pos);
    xmlFree(name);
    xmlFree(file);
    return keep;
}
