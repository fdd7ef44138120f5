/* sofa_grid.c - SOFA's RegularGridTopology split into tetrahedra by a
 * Hexa2TetraTopologicalMapping, as fallingBeamLagrangianCollision.scn
 * builds its beam:
 *
 *   <Node name="BEAMVOLUME">
 *     <RegularGridTopology name="HexaTop" n="25 5 5" min="0 0 0" max="0.5 0.1 0.1"/>
 *     <TetrahedronSetTopologyContainer name="Container" position="@HexaTop.position"/>
 *     <Hexa2TetraTopologicalMapping input="@HexaTop" output="@Container"/>
 *   </Node>
 *   <Node name="FEM"> ...
 *     <TetrahedronSetTopologyContainer name="Container"
 *         position="@../BEAMVOLUME/HexaTop.position"
 *         tetrahedra="@../BEAMVOLUME/Container.tetrahedra"/>
 *     <MechanicalObject src="@Container"/> ...
 *
 * The container a body's node uses becomes Pliant's RegularGridTetrahedra
 * (same n, min, max) under the container's name: the same vertices in the
 * same order (x fastest, then y, then z, as SOFA numbers a grid), each cell
 * split into 6 tetrahedra (Pliant's split along the cell's main diagonal;
 * SOFA's Hexa2Tetra alternates its diagonals from cell to cell: the same
 * vertices, slightly different elements).  The grid, the mapping and the
 * containers that only fed it are dropped; a node left holding nothing else
 * goes with them. */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Exactly `count` numbers in attribute `name` of e; 0 (error given) if not. */
static int numbers(sofa_lower *L, xmlNode *e, const char *name, double *v, int count,
                   const char *what)
{
    char *s = sofa_get(e, name), *p = s, *end;
    int n = 0;
    for (; p && n <= count; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == ',') ++p;
        if (!*p) break;
        double d = strtod(p, &end);
        if (end == p) {
            n = -1;
            break;
        }
        if (n < count) v[n] = d;
        ++n;
    }
    int ok = n == count;
    if (!ok) sofa_error(L, e, "%s=\"%s\": expected %s", name, s ? s : "", what);
    xmlFree(s);
    return ok;
}

/* Checks the grid's n, min and max; writes them into out (RegularGridTetrahedra). */
static int grid_fields(sofa_lower *L, xmlNode *grid, xmlNode *out)
{
    double n[3], lo[3], hi[3];
    if (!numbers(L, grid, "n", n, 3, "three vertex counts (nx ny nz)") ||
        !numbers(L, grid, "min", lo, 3, "three numbers (x y z)") ||
        !numbers(L, grid, "max", hi, 3, "three numbers (x y z)"))
        return 0;
    for (int a = 0; a < 3; ++a) {
        if (!(n[a] >= 2 && n[a] <= 1e6 && n[a] == (int)n[a])) {
            sofa_error(L, grid, "n: %g vertices along %c: a grid split into tetrahedra needs a "
                                "whole number >= 2 on every axis",
                       n[a], "xyz"[a]);
            return 0;
        }
        if (!(hi[a] > lo[a])) {
            sofa_error(L, grid, "min %g and max %g along %c: max must be above min", lo[a], hi[a],
                       "xyz"[a]);
            return 0;
        }
    }
    char buf[200];
    snprintf(buf, sizeof buf, "%d %d %d", (int)n[0], (int)n[1], (int)n[2]);
    sofa_set(out, "n", buf);
    snprintf(buf, sizeof buf, "%.17g %.17g %.17g", lo[0], lo[1], lo[2]);
    sofa_set(out, "min", buf);
    snprintf(buf, sizeof buf, "%.17g %.17g %.17g", hi[0], hi[1], hi[2]);
    sofa_set(out, "max", buf);
    return 1;
}

/* The element a link attribute names ("@path" or "@path.field"), or NULL. */
static xmlNode *linked(xmlNode *e, const char *attr)
{
    char *v = sofa_get(e, attr);
    xmlNode *t = NULL;
    if (v && v[0] == '@') {
        const char *field;
        t = sofa_data_link(e->parent, v, &field);
        if (!t) t = sofa_find(e->parent, v + 1);
    }
    xmlFree(v);
    return t;
}

/* The Hexa2TetraTopologicalMapping whose output is `container`, or NULL. */
static xmlNode *mapping_into(xmlNode *container)
{
    for (xmlNode *e = container->parent->children; e; e = e->next)
        if (sofa_tag_is(e, "Hexa2TetraTopologicalMapping") && linked(e, "output") == container)
            return e;
    return NULL;
}

static int has_state(xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_tag_is(e, "MechanicalObject")) return 1;
    return 0;
}

/* The container c of a body's node, if its tetrahedra come from a grid:
 * replaced by RegularGridTetrahedra. */
static void lower_grid_container(sofa_lower *L, xmlNode *c)
{
    xmlNode *source = linked(c, "tetrahedra"); /* another node's container */
    if (!source) source = c;
    if (!strstr((const char *)source->name, "TopologyContainer")) return;
    xmlNode *map = mapping_into(source);
    if (!map) return;
    xmlNode *grid = linked(map, "input");
    if (!grid || !sofa_tag_is(grid, "RegularGridTopology")) {
        sofa_error(L, map, "Hexa2TetraTopologicalMapping: its input must be a "
                           "RegularGridTopology (input=\"@grid\"); other hexahedra are not "
                           "mapped");
        return;
    }
    xmlNode *pos = linked(c, "position");
    if (pos && pos != grid && pos != source) {
        sofa_error(L, c, "position: the tetrahedra come from the grid '%s' but the positions "
                         "from elsewhere; link the grid's position",
                   (const char *)grid->name);
        return;
    }
    xmlNode *g = sofa_new_before(L, c, "RegularGridTetrahedra", sofa_line(grid));
    char *nm = sofa_get(c, "name");
    if (nm) sofa_set(g, "name", nm);
    xmlFree(nm);
    if (!grid_fields(L, grid, g)) {
        sofa_remove(g);
        return;
    }
    sofa_set(grid, "pliant-used", "1");
    sofa_set(map, "pliant-used", "1");
    sofa_set(source, "pliant-used", "1");
    sofa_note(L, "grid-tetra", map,
              "RegularGridTopology + Hexa2TetraTopologicalMapping: Pliant's "
              "RegularGridTetrahedra (the same vertices, numbered as SOFA's grid; each cell "
              "split into 6 tetrahedra along its main diagonal, where SOFA alternates the "
              "diagonals)");
    sofa_remove(c);
}

static void containers(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e))
            containers(L, e);
        else if (sofa_tag_is(e, "TetrahedronSetTopologyContainer") && has_state(node))
            lower_grid_container(L, e);
    }
}

/* Is e what only fed a grid (or a modifier of such a container)? */
static int grid_part(xmlNode *e)
{
    char *used = sofa_get(e, "pliant-used");
    int hit = used != NULL;
    xmlFree(used);
    return hit || strstr((const char *)e->name, "TopologyModifier");
}

static void drop_used(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    int used = 0, other = 0;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e)) {
            drop_used(L, e);
            ++other;
        } else if (sofa_is_element(e)) {
            int part = grid_part(e);
            char *u = sofa_get(e, "pliant-used");
            if (u) sofa_remove(e), ++used;
            else if (!part) ++other;
            xmlFree(u);
        }
    }
    if (used && !other && node != L->root) {
        char path[160];
        sofa_note(L, "grid-node", node, "the node '%s' only built a grid's tetrahedra for "
                                        "another node: dropped",
                  sofa_node_path(node, path, sizeof path));
        sofa_remove(node);
    }
}

/* A RegularGridTopology nobody split into tetrahedra. */
static void unused_grids(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e)) {
            unused_grids(L, e);
        } else if (sofa_tag_is(e, "RegularGridTopology") ||
                   sofa_tag_is(e, "Hexa2TetraTopologicalMapping")) {
            sofa_error(L, e, "%s: only a grid split into the tetrahedra of a body's "
                             "TetrahedronSetTopologyContainer (Hexa2TetraTopologicalMapping, "
                             "in the body's node or linked by tetrahedra=\"@...\") is mapped; "
                             "closest: RegularGridTetrahedra (n, min, max)",
                       (const char *)e->name);
            sofa_remove(e);
        }
    }
}

void sofa_lower_grids(sofa_lower *L)
{
    containers(L, L->root);
    drop_used(L, L->root);
    unused_grids(L, L->root);
}
