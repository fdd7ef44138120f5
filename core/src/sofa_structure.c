/* sofa_structure.c - the SOFA idioms that change a scene's structure:
 * RequiredPlugin modules, mapped child nodes (a cable's points), BoxROI
 * and the links to its indices, topology containers, rest-shape springs,
 * and the solvers that SOFA puts in each body's node and Pliant runs once
 * at the root.  Part of the lowering (sofa_lower.c). */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- RequiredPlugin ----------------------------------------------------- */

static void lower_required(sofa_lower *L, xmlNode *e, int *nmodules, char *first, size_t size)
{
    const char *attr = xmlHasProp(e, (const xmlChar *)"pluginName") ? "pluginName" : "name";
    char *v = sofa_get(e, attr);
    if (!v) return; /* scene_xml.c reports the missing name */
    char *copy = strdup(v), *save = NULL, kept[1024] = "";
    size_t w = 0;
    for (char *p = copy ? strtok_r(copy, " \t\n,", &save) : NULL; p;
         p = strtok_r(NULL, " \t\n,", &save)) {
        const char *why;
        int kind = pl_sofa_module(p, &why);
        if (kind == 1) {
            if (!(*nmodules)++) snprintf(first, size, "%s", p);
        } else if (kind == 2) {
            L->need |= NEED_CABLE;
            sofa_note(L, "softrobots", e,
                      "SoftRobots: Pliant's cable plugin stands in for it (CableConstraint, "
                      "SurfacePressureConstraint); "
                      "its other components are listed in docs/sofa.md");
        } else if (kind < 0) {
            sofa_error(L, e, "plugin '%s': %s", p, why);
        } else {
            w += (size_t)snprintf(kept + w, w < sizeof kept ? sizeof kept - w : 0, "%s%s",
                                  w ? " " : "", p);
        }
    }
    free(copy);
    xmlFree(v);
    if (w)
        sofa_set(e, attr, kept);
    else
        sofa_remove(e);
}

static void plugins_in(sofa_lower *L, xmlNode *node, int *nmodules, char *first, size_t size,
                       int *line)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e)) {
            plugins_in(L, e, nmodules, first, size, line);
        } else if (sofa_tag_is(e, "RequiredPlugin")) {
            int before = *nmodules;
            if (!*line) *line = sofa_line(e);
            lower_required(L, e, nmodules, first, size);
            (void)before;
        }
    }
}

void sofa_lower_plugins(sofa_lower *L)
{
    int nmodules = 0, line = 0;
    char first[128] = "";
    plugins_in(L, L->root, &nmodules, first, sizeof first, &line);
    if (nmodules)
        pl_diag_warn(L->diag, L->file, line, "RequiredPlugin",
                     "%d SOFA module%s (%s%s): nothing to load, Pliant maps their components "
                     "itself (docs/sofa.md)",
                     nmodules, nmodules > 1 ? "s" : "", first, nmodules > 1 ? ", ..." : "");
}

/* ---- mapped child nodes ------------------------------------------------- */

static xmlNode *first_tag(xmlNode *node, const char *tag)
{
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_tag_is(e, tag)) return e;
    return NULL;
}

/* The n x 3 numbers of a MechanicalObject's position attribute. */
static double *read_points(sofa_lower *L, xmlNode *mo, int *n)
{
    char *v = sofa_get(mo, "position");
    *n = 0;
    if (!v || v[0] == '@') {
        sofa_error(L, mo, "the MechanicalObject of a mapped cable node needs its points as "
                          "numbers (position=\"x y z ...\")%s",
                   v ? "; positions linked from a loader are not mapped yet" : "");
        xmlFree(v);
        return NULL;
    }
    int cap = 16, count = 0;
    double *x = malloc((size_t)cap * sizeof *x);
    char *p = v, *end;
    for (;; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
        if (!*p) break;
        double d = strtod(p, &end);
        if (end == p || !x) {
            sofa_error(L, mo, "position: expected numbers, found '%.20s'", p);
            free(x);
            xmlFree(v);
            return NULL;
        }
        if (count == cap) {
            double *y = realloc(x, (size_t)(cap *= 2) * sizeof *y);
            if (!y) break;
            x = y;
        }
        x[count++] = d;
    }
    xmlFree(v);
    if (count % 3) {
        sofa_error(L, mo, "position: %d numbers, not x y z per point", count);
        free(x);
        return NULL;
    }
    *n = count / 3;
    return x;
}

/* The cable's points: the mapped points its indices name, in that order. */
static int cable_points(sofa_lower *L, xmlNode *cable, const double *x, int n, char **out)
{
    char *v = sofa_get(cable, "indices");
    if (!v) {
        sofa_error(L, cable, "a cable in a mapped node needs indices (the mapped points it runs "
                             "through, in order from the pull point)");
        return -1;
    }
    size_t cap = 64, w = 0;
    char *buf = malloc(cap), *p = v, *end;
    int count = 0, rc = 0;
    for (; buf; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
        if (!*p) break;
        long i = strtol(p, &end, 10);
        if (end == p || i < 0 || i >= n) {
            sofa_error(L, cable, "indices: '%.20s' is not one of the %d mapped points (0 to %d)",
                       p, n, n - 1);
            rc = -1;
            break;
        }
        if (cap - w < 80) {
            char *b = realloc(buf, cap *= 2);
            if (!b) break;
            buf = b;
        }
        w += (size_t)snprintf(buf + w, cap - w, "%s%.17g %.17g %.17g", count ? "  " : "",
                              x[3 * i], x[3 * i + 1], x[3 * i + 2]);
        ++count;
    }
    xmlFree(v);
    if (rc || !buf || !count) {
        if (!rc && buf) sofa_error(L, cable, "indices: no point given");
        free(buf);
        return -1;
    }
    *out = buf;
    return count;
}

/* Checks the mapping's explicit input and output, if any. */
static int check_mapping(sofa_lower *L, xmlNode *map, xmlNode *parent_mo, xmlNode *mo)
{
    int ok = 1;
    char *in = sofa_get(map, "input"), *out = sofa_get(map, "output"), *mc;
    if (in && (in[0] != '@' || sofa_find(map->parent, in + 1) != parent_mo)) {
        sofa_error(L, map, "input=\"%s\": the mapping must map the parent node's "
                           "MechanicalObject (@../name)",
                   in);
        ok = 0;
    }
    if (out && (out[0] != '@' || sofa_find(map->parent, out + 1) != mo)) {
        sofa_error(L, map, "output=\"%s\": the mapping must drive this node's MechanicalObject",
                   out);
        ok = 0;
    }
    mc = sofa_get(map, "mapConstraints");
    if (mc && !sofa_is_true(mc)) {
        sofa_error(L, map, "mapConstraints=\"%s\": the cable would act on nothing (SOFA does "
                           "not pass its force to the body); remove it",
                   mc);
        ok = 0;
    }
    xmlFree(in);
    xmlFree(out);
    xmlFree(mc);
    return ok;
}

/* Is e something a mapped node may hold without physics? */
static int mapped_harmless(const xmlNode *e)
{
    const char *tag = (const char *)e->name;
    const pl_sofa_component *c = pl_sofa_find(tag);
    /* topology containers and the topological mappings that fill them
     * (Tetra2TriangleTopologicalMapping: a body's surface for drawing)
     * describe the mapped surface: the component using it is the reason */
    return (c && (c->kind == PL_SOFA_VISUAL || c->kind == PL_SOFA_NOTED)) ||
           strstr(tag, "Loader") || strstr(tag, "TopologyContainer") ||
           strstr(tag, "TopologicalMapping") || !strcmp(tag, "MeshTopology");
}

/* A child node driven by `map`: cable points, or drawing only. */
static void lower_mapped(sofa_lower *L, xmlNode *node, xmlNode *map)
{
    xmlNode *parent = node->parent, *mo = NULL, *other = NULL;
    int ncables = 0, identity = sofa_tag_is(map, "IdentityMapping");
    for (xmlNode *e = node->children; e; e = e->next) {
        if (!sofa_is_element(e) || e == map) continue;
        if (sofa_tag_is(e, "MechanicalObject") && !mo)
            mo = e;
        else if (sofa_tag_is(e, "CableConstraint") || sofa_tag_is(e, "SurfacePressureConstraint"))
            ++ncables;
        else if (!mapped_harmless(e) && !other)
            other = e;
    }
    char where[160];
    sofa_node_path(node, where, sizeof where);
    if (other) {
        sofa_error(L, other, "%s in the node '%s', which %s maps from its parent: Pliant maps "
                             "the points of cables and pressure cavities only so far (a "
                             "collision surface in a mapped node is not supported yet)",
                   (const char *)other->name, where, (const char *)map->name);
        sofa_remove(node);
        return;
    }
    if (!ncables && mo && sofa_lower_mapped_points(L, node, map, mo, identity)) return;
    if (!ncables) {
        sofa_note(L, "mapped-visual", map,
                  "the node '%s' only follows the body (drawing, nothing acting on it): not "
                  "simulated, dropped", where);
        sofa_remove(node);
        return;
    }
    xmlNode *parent_mo = first_tag(parent, "MechanicalObject");
    if (!mo || !parent_mo) {
        sofa_error(L, map, "%s needs a MechanicalObject in this node and one in its parent",
                   (const char *)map->name);
        sofa_remove(node);
        return;
    }
    if (!check_mapping(L, map, parent_mo, mo)) {
        sofa_remove(node);
        return;
    }
    for (xmlNode *e = node->children; e; e = e->next)
        if (sofa_tag_is(e, "SurfacePressureConstraint")) sofa_lower_cavity(L, node, mo, e, identity);
    int n = 0, cables = 0;
    for (xmlNode *e = node->children; e; e = e->next)
        cables += sofa_tag_is(e, "CableConstraint") && !sofa_is_area_cable(e);
    double *x = identity || !cables ? NULL : read_points(L, mo, &n);
    if (identity && xmlHasProp(mo, (const xmlChar *)"position"))
        sofa_error(L, mo, "under an IdentityMapping the points are the parent's vertices: remove "
                          "position");
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (!sofa_tag_is(e, "CableConstraint")) continue;
        int area = !identity && sofa_is_area_cable(e);
        if (!area && !identity && !x) continue;
        if (!area && xmlHasProp(e, (const xmlChar *)"centers")) {
            sofa_error(L, e, "centers in a mapped node: give indices of the mapped points");
            continue;
        }
        xmlNode *moved = xmlCopyNode(e, 1);
        if (!moved) continue;
        moved->line = e->line;
        xmlAddPrevSibling(node, moved);
        if (area) {
            sofa_lower_area_cable(L, node, e, moved);
        } else if (!identity) {
            char *pts = NULL;
            if (cable_points(L, e, x, n, &pts) < 0) {
                sofa_remove(moved);
                continue;
            }
            sofa_unset(moved, "indices");
            sofa_set(moved, "position", pts);
            free(pts);
        }
        char pp[160];
        sofa_note(L, "mapped-cable", e,
                  "the cable of the mapped node '%s' acts in '%s' (its points follow the %s): "
                  "its path there is %s/<name>",
                  where, sofa_node_path(parent, pp, sizeof pp),
                  identity ? "body's vertices" : "tetrahedra containing them", pp);
    }
    free(x);
    sofa_remove(node);
}

void sofa_lower_mapped_nodes(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    for (xmlNode *c = node->children; c; c = next) {
        next = c->next;
        if (!sofa_is_node(c)) continue;
        xmlNode *map = first_tag(c, "BarycentricMapping");
        if (!map) map = first_tag(c, "IdentityMapping");
        if (!map) {
            sofa_lower_mapped_nodes(L, c);
            continue;
        }
        for (xmlNode *k = c->children; k; k = k->next)
            if (sofa_is_node(k)) {
                sofa_error(L, k, "a node below the mapped node: nested mapped nodes are not "
                                 "supported");
                break;
            }
        lower_mapped(L, c, map);
    }
}

/* ---- BoxROI -------------------------------------------------------------- */

/* The ROI's boxes, min and max sorted per axis as SOFA does; 0 if malformed. */
static int roi_boxes(sofa_lower *L, xmlNode *roi, char *out, size_t size)
{
    char *v = sofa_get(roi, "box");
    double b[6 * 32];
    int n = 0;
    char *p = v, *end;
    for (; p && n < 6 * 32; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == ',') ++p;
        if (!*p) break;
        b[n] = strtod(p, &end);
        if (end == p) break;
        ++n;
    }
    int ok = v && n > 0 && n % 6 == 0 && p && !*p;
    if (!ok)
        sofa_error(L, roi, "box=\"%s\": expected 6 numbers per box (xmin ymin zmin xmax ymax "
                           "zmax)",
                   v ? v : "");
    xmlFree(v);
    if (!ok) return 0;
    size_t w = 0;
    for (int k = 0; k < n; k += 6)
        for (int j = 0; j < 6; ++j) {
            double lo = b[k + j % 3], hi = b[k + 3 + j % 3];
            double s = j < 3 ? (lo < hi ? lo : hi) : (lo < hi ? hi : lo);
            w += (size_t)snprintf(out + w, w < size ? size - w : 0, "%s%.17g", w ? " " : "", s);
        }
    return w < size;
}

/* Replaces attr="@roi.indices" of e by boxes; returns 1 if it named a BoxROI. */
static int link_roi(sofa_lower *L, xmlNode *e, const char *attr)
{
    char *v = sofa_get(e, attr);
    const char *field;
    xmlNode *roi = sofa_data_link(e->parent, v, &field);
    int done = 0;
    if (roi && sofa_tag_is(roi, "BoxROI")) {
        char boxes[4096];
        if (strcmp(field, "indices"))
            sofa_error(L, e, "%s=\"%s\": only a BoxROI's point indices are mapped (not %s)", attr,
                       v, field);
        else if (roi_boxes(L, roi, boxes, sizeof boxes)) {
            char *old = sofa_get(e, "box"), all[8192];
            snprintf(all, sizeof all, "%s%s%s", old ? old : "", old ? " " : "", boxes);
            sofa_set(e, "box", all);
            xmlFree(old);
            sofa_set(roi, "pliant-used", "1");
        }
        sofa_unset(e, attr);
        done = 1;
    }
    xmlFree(v);
    return done;
}

static void rois_link(sofa_lower *L, xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next) {
        if (sofa_is_node(e))
            rois_link(L, e);
        else if (sofa_is_element(e)) {
            link_roi(L, e, "indices");
            link_roi(L, e, "points");
        }
    }
}

/* BoxROI position="@dofs.rest_position" (SoftRobots' idiom): the rest
 * positions of its node's MechanicalObject, or the positions of a loader of
 * its node, are what Pliant's boxes select from anyway; any other points
 * would select other vertices: refused. */
static void roi_position(sofa_lower *L, xmlNode *roi)
{
    char *v = sofa_get(roi, "position");
    if (!v) return;
    const char *field = NULL;
    xmlNode *src = sofa_data_link(roi->parent, v, &field);
    int same_node = src && src->parent == roi->parent;
    int ok = same_node && ((sofa_tag_is(src, "MechanicalObject") &&
                            (!strcmp(field, "rest_position") || !strcmp(field, "position"))) ||
                           (strstr((const char *)src->name, "Loader") && !strcmp(field, "position")));
    if (ok)
        sofa_note(L, "roi-position", roi,
                  "position=\"%s\": the rest positions of this node's body, which BoxROI selects "
                  "from in Pliant", v);
    else
        sofa_error(L, roi, "position=\"%s\": BoxROI selects from the rest positions of its "
                           "node's MechanicalObject in Pliant (position=\"@dofs.rest_position\" "
                           "or a loader of this node); other points are not mapped", v);
    xmlFree(v);
}

static void rois_drop(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e)) {
            rois_drop(L, e);
            continue;
        }
        if (!sofa_tag_is(e, "BoxROI") || pl_registry_find(L->reg, "BoxROI")) continue;
        for (xmlAttr *a = e->properties; a; a = a->next) {
            const pl_sofa_attr *r = pl_sofa_find_attr("BoxROI", (const char *)a->name);
            if (r && r->kind == PL_SOFA_A_REFUSE)
                sofa_error(L, e, "'%s' is not supported: %s", (const char *)a->name, r->note);
        }
        roi_position(L, e);
        char *used = sofa_get(e, "pliant-used");
        if (!used)
            sofa_note(L, "roi-unused", e, "no component links to this BoxROI's indices: ignored");
        xmlFree(used);
        sofa_remove(e);
    }
}

void sofa_lower_rois(sofa_lower *L, xmlNode *node)
{
    rois_link(L, node);
    rois_drop(L, node);
}

/* ---- topology containers ------------------------------------------------- */

void sofa_lower_container(sofa_lower *L, xmlNode *e)
{
    char *src = sofa_get(e, "src"), *pos = sofa_get(e, "position");
    const char *field = NULL;
    xmlNode *loader = NULL;
    if (src && src[0] == '@')
        loader = sofa_find(e->parent, src + 1);
    else if (pos && pos[0] == '@')
        loader = sofa_data_link(e->parent, pos, &field);
    const char *tag = (const char *)e->name;
    if (!src && (!pos || pos[0] != '@')) {
        sofa_error(L, e, "%s without a loader (src=\"@loader\" or position=\"@loader.position\"): "
                         "inline meshes and meshes made by topological mappings are not mapped "
                         "yet; load the mesh from a file",
                   tag);
    } else if (!loader || !strstr((const char *)loader->name, "Loader")) {
        sofa_error(L, e, "%s: '%s' names no mesh loader", tag, src ? src : pos);
    } else if (loader->parent != e->parent) {
        sofa_error(L, e, "%s: its loader is in another node; Pliant's components use the mesh of "
                         "their own node, so put the loader in this node",
                   tag);
    } else {
        for (xmlNode *k = e->parent->children; k != loader; k = k->next)
            if (sofa_is_element(k) && strstr((const char *)k->name, "Loader")) {
                sofa_error(L, e, "%s: Pliant's components use the first loader of a node; put "
                                 "the one it names first",
                           tag);
                break;
            }
        sofa_note(L, "container", e, "%s: Pliant's components use the mesh of the node's loader "
                                     "directly: dropped",
                  tag);
    }
    xmlFree(src);
    xmlFree(pos);
    sofa_remove(e);
}

/* ---- RestShapeSpringsForceField ----------------------------------------- */

void sofa_lower_springs(sofa_lower *L, xmlNode *e)
{
    char *k = sofa_get(e, "stiffness"), *pts = sofa_get(e, "points");
    if (!pts) pts = sofa_get(e, "indices");
    double stiff = 0;
    int boxed = xmlHasProp(e, (const xmlChar *)"box") != NULL;
    for (xmlAttr *a = e->properties; a; a = a->next) {
        const pl_sofa_attr *r =
            pl_sofa_find_attr("RestShapeSpringsForceField", (const char *)a->name);
        if (r && r->kind == PL_SOFA_A_REFUSE)
            sofa_error(L, e, "'%s' is not supported: %s", (const char *)a->name, r->note);
    }
    if (!k || !sofa_parse_number(k, &stiff) || stiff <= 0) {
        sofa_error(L, e, "stiffness=\"%s\": one positive stiffness [N/m] is expected",
                   k ? k : "");
    } else if (pts && pts[0] == '@') {
        sofa_error(L, e, "points=\"%s\": only the indices of a BoxROI of this node or above can "
                         "be linked here",
                   pts);
    } else if (stiff >= 1e9) {
        xmlNode *f = sofa_new_before(L, e, "FixedConstraint", sofa_line(e));
        char *nm = sofa_get(e, "name");
        if (nm) sofa_set(f, "name", nm);
        xmlFree(nm);
        if (pts) sofa_set(f, "indices", pts);
        char *box = sofa_get(e, "box");
        if (box) sofa_set(f, "box", box);
        xmlFree(box);
        if (!pts && !boxed) sofa_set(f, "fixAll", "1");
        sofa_note(L, "springs-fixed", e,
                  "stiffness %g >= 1e9: the points are held exactly at their rest positions "
                  "(FixedConstraint); stiff springs and exact fixing differ by force/stiffness",
                  stiff);
    } else if (boxed || !pts) {
        sofa_error(L, e, "springs of stiffness %g on %s: soft rest-shape springs take explicit "
                         "indices in Pliant (PositionTarget); or use stiffness >= 1e9 to hold "
                         "the points exactly",
                   stiff, boxed ? "a BoxROI selection" : "every point");
    } else {
        xmlNode *f = sofa_new_before(L, e, "PositionTarget", sofa_line(e));
        char *nm = sofa_get(e, "name");
        if (nm) sofa_set(f, "name", nm);
        xmlFree(nm);
        sofa_set(f, "indices", pts);
        sofa_set(f, "stiffness", k);
        L->need |= NEED_HYPERELASTIC;
    }
    xmlFree(k);
    xmlFree(pts);
    sofa_remove(e);
}

/* ---- collision models that cannot touch anything ------------------------- */

int sofa_is_collision_model(sofa_lower *L, const xmlNode *e)
{
    const char *tag = (const char *)e->name;
    static const char *const old[] = {"TriangleModel", "LineModel", "PointModel", "SphereModel",
                                      NULL};
    int hit = strstr(tag, "CollisionModel") != NULL;
    for (int k = 0; old[k]; ++k) hit |= !strcmp(tag, old[k]);
    return hit && !pl_registry_find(L->reg, tag);
}

/* Counts SOFA collision models; *node: the one node holding them all (NULL
 * if they sit in several); *self: one of them collides with its own body. */
static int collision_models(sofa_lower *L, xmlNode *node, xmlNode **holder, int *several,
                            int *self)
{
    int n = 0;
    for (xmlNode *e = node->children; e; e = e->next) {
        if (sofa_is_node(e)) {
            n += collision_models(L, e, holder, several, self);
        } else if (sofa_is_element(e) && sofa_is_collision_model(L, e)) {
            char *sc = sofa_get(e, "selfCollision");
            *self |= sofa_is_true(sc);
            xmlFree(sc);
            if (*holder && *holder != node) *several = 1;
            *holder = node;
            ++n;
        }
    }
    return n;
}

void sofa_lower_lonely_collision(sofa_lower *L)
{
    xmlNode *holder = NULL;
    int several = 0, self = 0;
    if (!collision_models(L, L->root, &holder, &several, &self) || several || self) return;
    xmlNode *next;
    char np[160];
    sofa_node_path(holder, np, sizeof np);
    for (xmlNode *e = holder->children; e; e = next) {
        next = e->next;
        if (!sofa_is_element(e) || !sofa_is_collision_model(L, e)) continue;
        sofa_note(L, "lonely-collision", e,
                  "the scene's only collision models are those of '%s', which do not collide "
                  "with each other (no selfCollision): SOFA finds no contact, so they are "
                  "ignored",
                  np);
        sofa_remove(e);
    }
    /* what only fed them (SOFA's SphereLoader) goes with them, unless the
     * node is mapped: its MechanicalObject may stay (sofa_mapped_points.c) */
    if (first_tag(holder, "BarycentricMapping")) return;
    for (xmlNode *e = holder->children; e; e = next) {
        next = e->next;
        if (sofa_tag_is(e, "SphereLoader")) sofa_remove(e);
    }
}
