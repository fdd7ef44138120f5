/* sofa_lower.c - a SOFA scene's document rewritten into Pliant's components,
 * before the tree is built (scene_xml.c calls pl_sofa_lower).
 *
 * Why a rewrite of the document: the SOFA idioms that Pliant honours are
 * other spellings of Pliant components (MeshVTKLoader is MeshLoader,
 * TetrahedronFEMForceField is Corotational, a BoxROI's indices are a box of
 * the consumer, a cable in a mapped child node is a cable whose points
 * follow the body's tetrahedra), so translating the document keeps one
 * code path for both vocabularies and every error keeps the line of the
 * element the user wrote.  What SOFA does and Pliant does not is refused
 * here, with the line, the component and the closest alternative.
 *
 * Passes: state templates (every scene); then, for a SOFA scene only:
 * RequiredPlugin, Node attributes, mapped child nodes, BoxROI, every
 * element by its entry in the vocabulary (sofa_vocab.c), and last the
 * solvers gathered at the root. */
#include "sofa_lower.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- every scene: state templates ---------------------------------------- */

static int template_ok(const char *t, int *cuda)
{
    static const char *const ok[] = {"Vec3", "Vec3d", "Vec3f", "Vec3Types", "Vec3dTypes",
                                     "Vec3fTypes", NULL};
    for (int k = 0; ok[k]; ++k)
        if (!strcmp(t, ok[k])) return 1;
    if (!strcmp(t, "CudaVec3f") || !strcmp(t, "CudaVec3d")) return *cuda = 1;
    /* linear solvers' matrix types are hints about assembly */
    return !strncmp(t, "CompressedRowSparseMatrix", 25) || !strncmp(t, "FullMatrix", 10) ||
           !strncmp(t, "SparseMatrix", 12) || !strncmp(t, "GraphScattered", 14);
}

static void check_templates(sofa_lower *L, xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next) {
        if (!sofa_is_element(e)) continue;
        if (sofa_is_node(e)) {
            check_templates(L, e);
            continue;
        }
        char *t = sofa_get(e, "template");
        if (!t) continue;
        char *save = NULL, *copy = strdup(t);
        for (char *p = copy ? strtok_r(copy, ", \t", &save) : NULL; p;
             p = strtok_r(NULL, ", \t", &save)) {
            int cuda = 0;
            if (!template_ok(p, &cuda))
                sofa_error(L, e,
                           "template \"%s\": Pliant's states are 3D points only (Vec3, Vec3d, "
                           "Vec3f); %s are not supported yet, and components following such a "
                           "state cannot run",
                           p, !strncmp(p, "Rigid", 5) ? "rigid bodies (Rigid3)" : "such states");
            else if (cuda)
                sofa_note(L, "template-cuda", e,
                          "template \"%s\": Pliant picks the device itself (`pliant run "
                          "--device`, CudaDevice); the state is double precision",
                          p);
        }
        free(copy);
        xmlFree(t);
    }
}

/* ---- is it a SOFA scene? -------------------------------------------------- */

static int sofa_flavoured(sofa_lower *L, xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next) {
        if (!sofa_is_element(e)) continue;
        const char *tag = (const char *)e->name;
        if (sofa_is_node(e)) {
            if (sofa_flavoured(L, e)) return 1;
        } else if (!strcmp(tag, "RequiredPlugin")) {
            char *v = sofa_get(e, "pluginName");
            if (!v) v = sofa_get(e, "name");
            char *save = NULL, *copy = v ? strdup(v) : NULL;
            int sofa = 0;
            for (char *p = copy ? strtok_r(copy, " \t\n,", &save) : NULL; p && !sofa;
                 p = strtok_r(NULL, " \t\n,", &save)) {
                const char *why;
                sofa = pl_sofa_module(p, &why) != 0;
            }
            free(copy);
            xmlFree(v);
            if (sofa) return 1;
        } else {
            const pl_sofa_component *c = pl_sofa_find(tag);
            if (c && c->kind != PL_SOFA_SAME && !pl_registry_find(L->reg, tag)) return 1;
        }
    }
    return 0;
}

/* Loads the Pliant plugins the scene requires before the vocabulary is
 * consulted, so that a name a required plugin provides (CollisionPipeline of
 * the collision plugin) is Pliant's.  Only plain names; scene_xml.c loads them
 * again (a no-op) and reports what fails or what its policy refuses. */
static void preload_plugins(sofa_lower *L, xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next) {
        if (sofa_is_node(e)) {
            preload_plugins(L, e);
            continue;
        }
        if (!sofa_tag_is(e, "RequiredPlugin")) continue;
        char *v = sofa_get(e, "pluginName");
        if (!v) v = sofa_get(e, "name");
        char *save = NULL, *copy = v ? strdup(v) : NULL;
        for (char *p = copy ? strtok_r(copy, " \t\n,", &save) : NULL; p;
             p = strtok_r(NULL, " \t\n,", &save)) {
            const char *why;
            int plain = 1;
            for (const char *q = p; *q; ++q)
                plain &= isalnum((unsigned char)*q) || *q == '_' || *q == '-';
            pl_error err;
            if (plain && pl_sofa_module(p, &why) == 0) pl_registry_load_plugin(L->reg, p, &err);
        }
        free(copy);
        xmlFree(v);
    }
}

/* ---- Node attributes -------------------------------------------------------- */

static void lower_node_attrs(sofa_lower *L, xmlNode *node)
{
    static const char *const ignored[] = {"tags", "bbox", "multiThreading", NULL};
    for (int k = 0; ignored[k]; ++k)
        if (xmlHasProp(node, (const xmlChar *)ignored[k])) {
            char key[64];
            snprintf(key, sizeof key, "node-%s", ignored[k]);
            sofa_note(L, key, node, "Node attribute '%s' has no Pliant meaning: ignored",
                      ignored[k]);
            sofa_unset(node, ignored[k]);
        }
    char *t = sofa_get(node, "time");
    double v;
    if (t && (!sofa_parse_number(t, &v) || v != 0))
        sofa_error(L, node, "time=\"%s\": scenes start at time 0 in Pliant", t);
    if (t) sofa_unset(node, "time");
    xmlFree(t);
}

/* Drops deactivated nodes; returns 1 when node was removed. */
static int drop_inactive(sofa_lower *L, xmlNode *node)
{
    char *a = sofa_get(node, "activated");
    int off = a && (!strcmp(a, "0") || !strcmp(a, "false") || !strcmp(a, "False"));
    if (a) sofa_unset(node, "activated");
    xmlFree(a);
    if (off) {
        sofa_note(L, "node-activated", node,
                  "a Node with activated=\"false\" is not part of the simulation: dropped");
        sofa_remove(node);
    }
    return off;
}

/* ---- per-component attribute rules -------------------------------------- */

/* Merges SOFA's per-axis attributes (dx dy dz, rx ry rz) into a vec3 field. */
static void merge_axes(sofa_lower *L, xmlNode *e, const char *const axes[3], const char *field)
{
    double v[3] = {0, 0, 0};
    int any = 0;
    char *base = sofa_get(e, field);
    if (base && sscanf(base, "%lf %lf %lf", &v[0], &v[1], &v[2]) != 3) {
        xmlFree(base);
        return; /* the field's own parser reports it */
    }
    xmlFree(base);
    for (int k = 0; k < 3; ++k) {
        char *s = sofa_get(e, axes[k]);
        if (!s) continue;
        double d;
        if (!sofa_parse_number(s, &d))
            sofa_error(L, e, "%s: expected a number, found '%s'", axes[k], s);
        else
            v[k] += d, any = 1;
        sofa_unset(e, axes[k]);
        xmlFree(s);
    }
    if (any) {
        char buf[96];
        snprintf(buf, sizeof buf, "%.17g %.17g %.17g", v[0], v[1], v[2]);
        sofa_set(e, field, buf);
    }
}

/* scale="s" -> scale3d="s s s". */
static void lower_scale(sofa_lower *L, xmlNode *e)
{
    char *s = sofa_get(e, "scale");
    if (!s) return;
    double d;
    if (!sofa_parse_number(s, &d)) {
        sofa_error(L, e, "scale: expected one number, found '%s'", s);
    } else if (xmlHasProp(e, (const xmlChar *)"scale3d")) {
        sofa_error(L, e, "scale and scale3d are both given: keep one");
    } else {
        char buf[96];
        snprintf(buf, sizeof buf, "%.17g %.17g %.17g", d, d, d);
        sofa_set(e, "scale3d", buf);
    }
    sofa_unset(e, "scale");
    xmlFree(s);
}

static void lower_state(sofa_lower *L, xmlNode *e)
{
    static const char *const d[3] = {"dx", "dy", "dz"}, *const r[3] = {"rx", "ry", "rz"};
    merge_axes(L, e, d, "translation");
    merge_axes(L, e, r, "rotation");
    lower_scale(L, e);
    char *p = sofa_get(e, "position");
    const char *field;
    if (p && p[0] == '@') {
        xmlNode *src = sofa_data_link(e->parent, p, &field);
        if (!src || strcmp(field, "position"))
            sofa_error(L, e, "position=\"%s\": a link to the positions of a loader of this node or "
                             "above (@loader.position) was expected",
                       p);
        else {
            char buf[300];
            snprintf(buf, sizeof buf, "%.*s", (int)(field - p - 1), p);
            sofa_set(e, "src", buf);
        }
        sofa_unset(e, "position");
    }
    xmlFree(p);
}

/* FEM: method and SOFA's defaults. */
static void lower_fem(sofa_lower *L, xmlNode *e, const char *tag)
{
    char *m = sofa_get(e, "method");
    /* SOFA's default method of the tetrahedral FEMs is "large" */
    if (!m && (!strcmp(tag, "TetrahedronFEMForceField") ||
               !strcmp(tag, "TetrahedralCorotationalFEMForceField")))
        m = (char *)xmlStrdup((const xmlChar *)"large");
    if (m) {
        static const char *const ok[] = {"large", "polar", "svd", "qr", "polar2", NULL};
        int good = 0;
        for (int k = 0; ok[k]; ++k) good |= !strcmp(m, ok[k]);
        if (!good)
            sofa_error(L, e,
                       "method=\"%s\": %s; Pliant's Corotational is the corotational method "
                       "(large, polar, svd)",
                       m,
                       !strcmp(m, "small") || !strcmp(m, "linear")
                           ? "linear FEM without rotations is not in Pliant (it is wrong under "
                             "rotation anyway)"
                           : "an unknown method");
        else if ((!strcmp(m, "large") || !strcmp(m, "qr")) &&
                 !strcmp(tag, "TriangleFEMForceField"))
            sofa_note(L, "fem-large-tri", e,
                      "method=\"%s\": Pliant's Corotational takes each triangle's rotation from "
                      "the polar decomposition (SOFA's 'polar'); SOFA's '%s' frame on the edges "
                      "differs under large shear",
                      m, m);
        else if ((!strcmp(m, "large") || !strcmp(m, "qr")) && L->nlarge < 64 &&
                 !xmlHasProp(e, (const xmlChar *)"rotation"))
            L->large_fem[L->nlarge++] = e; /* the solvers decide (sofa_solvers.c) */
        sofa_unset(e, "method");
        xmlFree(m);
    }
    char *ym = sofa_get(e, "youngModulus");
    if (ym && ym[0] == '@') {
        sofa_error(L, e, "youngModulus=\"%s\": per-element values through a data link are not "
                         "mapped yet; give one value, or one per element",
                   ym);
        sofa_unset(e, "youngModulus");
    }
    xmlFree(ym);
    if (!strcmp(tag, "TriangleFEMForceField")) {
        sofa_set(e, "elements", "triangles");
        if (!xmlHasProp(e, (const xmlChar *)"thickness")) sofa_set(e, "thickness", "1");
    }
}

/* A vertex selection given as a link that survived the BoxROI pass. */
static void check_selection_link(sofa_lower *L, xmlNode *e, const char *attr)
{
    char *v = sofa_get(e, attr);
    if (v && v[0] == '@')
        sofa_error(L, e, "%s=\"%s\": only the indices of a BoxROI of this node or above can be "
                         "linked here",
                   attr, v);
    xmlFree(v);
}

/* SOFA's data-repository paths ("mesh/liver.msh", resolved by SOFA against
 * its share/ folder): when the scene's folder has no such file, the name
 * without "mesh/" is looked up by MeshLoader's own rule (the scene's folder,
 * the working directory, PLIANT_DATA_PATH). */
void sofa_lower_mesh_path(sofa_lower *L, xmlNode *e)
{
    char *f = sofa_get(e, "filename");
    if (f && !strncmp(f, "mesh/", 5)) {
        char path[1024];
        const char *slash = strrchr(L->file, '/');
        snprintf(path, sizeof path, "%.*s%s", slash ? (int)(slash - L->file + 1) : 0, L->file, f);
        if (access(path, F_OK) != 0) {
            sofa_note(L, "mesh-path", e,
                      "filename \"%s\": a SOFA share/ path, looked up as \"%s\" in the scene's "
                      "folder, the working directory and PLIANT_DATA_PATH",
                      f, f + 5);
            sofa_set(e, "filename", f + 5);
        }
    }
    xmlFree(f);
}

static void lower_component_attrs(sofa_lower *L, xmlNode *e, const char *tag)
{
    if (!strcmp(tag, "MechanicalObject")) lower_state(L, e);
    if (strstr(tag, "Loader")) lower_scale(L, e), sofa_lower_mesh_path(L, e);
    if (strstr(tag, "FEMForceField") || !strcmp(tag, "FastTetrahedralCorotationalForceField"))
        lower_fem(L, e, tag);
    if (!strcmp(tag, "DiagonalMass") || !strcmp(tag, "MeshMatrixMass")) {
        if (!xmlHasProp(e, (const xmlChar *)"thickness")) sofa_set(e, "thickness", "1");
        if (!strcmp(tag, "MeshMatrixMass"))
            sofa_note(L, "meshmatrixmass", e,
                      "MeshMatrixMass: Pliant lumps the mass (DiagonalMass); SOFA's default is "
                      "the consistent mass matrix");
    }
    if (!strcmp(tag, "ConstantForceField")) {
        char *f = sofa_get(e, "force");
        if (f) {
            if (xmlHasProp(e, (const xmlChar *)"forces"))
                sofa_error(L, e, "force and forces are both given: keep one");
            else
                sofa_set(e, "forces", f);
            sofa_unset(e, "force");
            xmlFree(f);
        }
        check_selection_link(L, e, "indices");
        if (!xmlHasProp(e, (const xmlChar *)"indices") && !xmlHasProp(e, (const xmlChar *)"box"))
            sofa_set(e, "box", "-1e300 -1e300 -1e300 1e300 1e300 1e300"); /* every point */
    }
    if (!strcmp(tag, "FixedConstraint") || !strcmp(tag, "FixedProjectiveConstraint"))
        check_selection_link(L, e, "indices");
    if (!strcmp(tag, "CableConstraint")) {
        char *m = sofa_get(e, "method");
        if (m && strcmp(m, "point") && strcmp(m, "sphere") && strcmp(m, "geodesic"))
            sofa_error(L, e, "method=\"%s\": expected point, sphere or geodesic", m);
        xmlFree(m);
    }
}

/* Applies the attribute table to e: renames, drops, refusals. */
static void apply_attr_rules(sofa_lower *L, xmlNode *e, const char *tag)
{
    char *names[128];
    int n = 0;
    for (xmlAttr *a = e->properties; a && n < 128; a = a->next)
        names[n++] = strdup((const char *)a->name);
    for (int k = 0; k < n; ++k) {
        const pl_sofa_attr *r = names[k] ? pl_sofa_find_attr(tag, names[k]) : NULL;
        if (!r || r->kind == PL_SOFA_A_LOWERED) {
            free(names[k]);
            continue;
        }
        char key[160];
        snprintf(key, sizeof key, "attr-%s-%s", r->component, r->sofa);
        if (r->kind == PL_SOFA_A_IGNORE) {
            sofa_note(L, key, e, "'%s' is ignored: %s", names[k], r->note);
            sofa_unset(e, names[k]);
        } else if (r->kind == PL_SOFA_A_REFUSE) {
            sofa_error(L, e, "'%s' is not supported: %s", names[k], r->note);
            sofa_unset(e, names[k]);
        } else if (r->kind == PL_SOFA_A_RENAME) {
            char *v = sofa_get(e, names[k]);
            sofa_unset(e, names[k]);
            if (v) sofa_set(e, r->pliant, v);
            xmlFree(v);
        }
        free(names[k]);
    }
    sofa_unset(e, "template"); /* checked by check_templates */
}

static unsigned plugin_bit(const char *plugin)
{
    if (!plugin) return 0;
    if (!strcmp(plugin, "hyperelastic")) return NEED_HYPERELASTIC;
    if (!strcmp(plugin, "sparse_inverse")) return NEED_SPARSE_INVERSE;
    if (!strcmp(plugin, "ncp_contact")) return NEED_NCP_CONTACT;
    if (!strcmp(plugin, "cable")) return NEED_CABLE;
    return 0;
}

/* One element by its vocabulary entry. */
static void lower_element(sofa_lower *L, xmlNode *e)
{
    const char *tag = (const char *)e->name;
    const pl_sofa_component *c = pl_sofa_find(tag);
    if (!c) return; /* a Pliant component, or unknown: scene_xml.c says so */
    if (c->kind != PL_SOFA_SAME && pl_registry_find(L->reg, tag)) return; /* Pliant's own */
    char key[160];
    snprintf(key, sizeof key, "comp-%s", tag);
    switch (c->kind) {
    case PL_SOFA_VISUAL:
        sofa_note(L, key, e, "%s is a visual component: ignored", tag);
        sofa_remove(e);
        return;
    case PL_SOFA_NOTED:
        sofa_note(L, key, e, "%s: ignored, %s", tag, c->note);
        sofa_remove(e);
        return;
    case PL_SOFA_REFUSED:
        sofa_error(L, e, "%s (SOFA) is not supported: %s", tag, c->note);
        sofa_remove(e);
        return;
    case PL_SOFA_LOWERED:
        if (strstr(tag, "TopologyContainer") || !strcmp(tag, "MeshTopology"))
            sofa_lower_container(L, e);
        else if (!strcmp(tag, "RestShapeSpringsForceField"))
            sofa_lower_springs(L, e);
        else if (strstr(tag, "Mapping"))
            sofa_error(L, e, "%s outside a child node that carries a cable: %s", tag, c->note);
        else if (strstr(tag, "Solver") || strstr(tag, "AnimationLoop") || strstr(tag, "LDLT") ||
                 strstr(tag, "LLT"))
            sofa_gather_solver(L, e, c);
        else {
            sofa_error(L, e, "%s here: %s", tag, c->note); /* a BoxROI nobody could use */
            sofa_remove(e);
        }
        return;
    case PL_SOFA_SAME:
    case PL_SOFA_RENAME:
        L->need |= plugin_bit(c->plugin);
        lower_component_attrs(L, e, tag);
        apply_attr_rules(L, e, tag);
        if (!strcmp(c->pliant, "CableConstraint") ||
            !strcmp(c->pliant, "SurfacePressureConstraint")) {
            if (!L->nconstraints++)
                L->constraint_line = sofa_line(e), L->constraint_type = c->sofa; /* static */
        }
        if (c->kind == PL_SOFA_RENAME) xmlNodeSetName(e, (const xmlChar *)c->pliant);
        return;
    }
}

static void lower_tree(sofa_lower *L, xmlNode *node)
{
    lower_node_attrs(L, node);
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (!sofa_is_element(e)) continue;
        if (sofa_is_node(e)) {
            if (!drop_inactive(L, e)) lower_tree(L, e);
        } else if (sofa_tag_is(e, "include")) {
            sofa_error(L, e, "<include> is not supported: write the included components in the "
                             "scene");
            sofa_remove(e);
        } else if (!sofa_tag_is(e, "RequiredPlugin")) {
            lower_element(L, e);
        }
    }
}

/* The closest SOFA name of the table, or NULL. */
static const char *suggest_sofa(const char *tag)
{
    const char *best = NULL;
    int bestd = 1 << 30;
    for (const pl_sofa_component *c = pl_sofa_components(); c->sofa; ++c) {
        int d = pl_edit_distance(tag, c->sofa);
        if (d < bestd) bestd = d, best = c->sofa;
    }
    return bestd <= 2 + (int)strlen(tag) / 4 ? best : NULL;
}

/* Names neither Pliant nor the table knows, in a SOFA scene. */
static void check_unknown(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (!sofa_is_element(e) || sofa_tag_is(e, "RequiredPlugin")) continue;
        if (sofa_is_node(e)) {
            check_unknown(L, e);
            continue;
        }
        const char *tag = (const char *)e->name;
        if (pl_registry_find(L->reg, tag) || pl_sofa_find(tag)) continue;
        const char *p = pl_registry_suggest(L->reg, tag), *s = suggest_sofa(tag);
        char hint[256] = "";
        if (p && s)
            snprintf(hint, sizeof hint, " (did you mean %s, or SOFA's %s?)", p, s);
        else if (p || s)
            snprintf(hint, sizeof hint, " (did you mean %s%s?)", p ? "" : "SOFA's ", p ? p : s);
        sofa_error(L, e, "unknown component type '%s': neither a Pliant component nor a SOFA "
                         "component Pliant knows (docs/sofa-vocabulary.md lists them)%s",
                   tag, hint);
        sofa_remove(e);
    }
}

void pl_sofa_lower(xmlDoc *doc, const char *file, pl_registry *reg, pl_diag *diag)
{
    sofa_lower L = {0};
    L.doc = doc;
    L.root = xmlDocGetRootElement(doc);
    L.file = file;
    L.reg = reg;
    L.diag = diag;
    if (!sofa_is_node(L.root)) return;
    check_templates(&L, L.root);
    preload_plugins(&L, L.root);
    if (!sofa_flavoured(&L, L.root)) return;
    sofa_lower_plugins(&L);
    sofa_lower_lonely_collision(&L);
    sofa_lower_grids(&L);
    sofa_lower_collision(&L);
    sofa_lower_mapped_nodes(&L, L.root);
    sofa_lower_value_mappers(&L);
    sofa_lower_rois(&L, L.root);
    lower_tree(&L, L.root);
    if (L.need & NEED_COLLISION) {
        pl_error err; /* MappedPoints' plugin, now that SOFA's names are lowered */
        pl_registry_load_plugin(L.reg, "collision", &err);
    }
    sofa_emit_solvers(&L);
    check_unknown(&L, L.root);
    for (int k = 0; k < L.nnoted; ++k) free(L.noted[k]);
    xmlFree(L.ode_name);
    xmlFree(L.cg_iter);
    xmlFree(L.cg_tol);
    xmlFree(L.cg_thr);
    xmlFree(L.lin_name);
    xmlFree(L.con_name);
}
