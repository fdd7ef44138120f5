/* sofa_values.c - IndexValueMapper: per-element values (a FEM's
 * youngModulus or poissonRatio) made from BoxROI selections of
 * tetrahedra, as raptor-cpu.scn builds its two-stiffness body:
 *
 *   <BoxROI name="box1" box="..."/>
 *   <IndexValueMapper name="m0" indices="@box0.tetrahedronIndices" value="1e5"/>
 *   <IndexValueMapper name="m1" inputValues="@m0.outputValues"
 *                     indices="@box1.tetrahedronIndices" value="1e6"/>
 *   <TetrahedronFEMForceField youngModulus="@m1.outputValues" .../>
 *
 * SOFA's rules, computed here once at load (the selection is made on rest
 * positions, as BoxROI does at init):
 *  - BoxROI's tetrahedronIndices: the tetrahedra whose four vertices all lie
 *    in a box, bounds included (strict="true", SOFA's default), or whose
 *    centre does (strict="false");
 *  - IndexValueMapper: outputValues = inputValues, grown with defaultValue
 *    (1) up to each index, then value at every index;
 *  - the FEM: element e takes values[e] when there are that many values,
 *    else values[0].
 * The FEM's attribute becomes the explicit list, one value per element
 * (Corotational takes one per element).  The mesh is read from the node's
 * first loader, as Pliant's components will; indices past its elements and
 * value lists longer than its element count are errors (SOFA would ignore
 * them silently: a selection made on another mesh). */
#include "sofa_lower.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/util.h"

typedef struct values {
    double *v;
    int n;
} values;

static int grow(values *o, int n, double fill)
{
    if (n <= o->n) return 0;
    double *v = realloc(o->v, (size_t)n * sizeof *v);
    if (!v) return -1;
    for (int k = o->n; k < n; ++k) v[k] = fill;
    o->v = v, o->n = n;
    return 0;
}

/* Numbers of a list attribute; -1 if one is not a number. */
static int parse_numbers(const char *s, values *out)
{
    const char *p = s;
    char *end;
    out->v = NULL, out->n = 0;
    for (;; p = end) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
        if (!*p) return 0;
        double d = strtod(p, &end);
        if (end == p || grow(out, out->n + 1, d)) return -1;
    }
}

/* ---- the node's mesh ----------------------------------------------------- */

/* The rest mesh the FEM of `node` will use: its first loader's file, or
 * NULL (error given) when that cannot be known here. */
static pl_mesh *node_mesh(sofa_lower *L, xmlNode *user, xmlNode *node, pl_mesh *m)
{
    xmlNode *ld = NULL, *mo = NULL;
    for (xmlNode *e = node->children; e; e = e->next) {
        if (!sofa_is_element(e) || sofa_is_node(e)) continue;
        if (!ld && strstr((const char *)e->name, "Loader")) ld = e;
        if (!mo && sofa_tag_is(e, "MechanicalObject")) mo = e;
    }
    if (!ld) {
        sofa_error(L, user, "per-element values from a BoxROI need the node's mesh from a mesh "
                            "loader in the same node");
        return NULL;
    }
    static const char *const moved[] = {"scale", "scale3d", "rotation", "translation", "dx",
                                        "dy", "dz", "rx", "ry", "rz", NULL};
    for (int k = 0; moved[k]; ++k)
        if (xmlHasProp(ld, (const xmlChar *)moved[k]) ||
            (mo && xmlHasProp(mo, (const xmlChar *)moved[k]))) {
            sofa_error(L, user, "per-element values from a BoxROI on a mesh moved by '%s' are not "
                                "mapped yet; transform the mesh file instead",
                       moved[k]);
            return NULL;
        }
    char *f = sofa_get(ld, "filename"), *only = sofa_get(ld, "onlyAttachedPoints");
    char path[1024], tried[2048];
    int found = f && pl_util_data_file(L->file, f, path, sizeof path, tried, sizeof tried) == 0;
    if (f && !found && !strncmp(f, "mesh/", 5)) /* SOFA's share/ paths (sofa_lower.c) */
        found = pl_util_data_file(L->file, f + 5, path, sizeof path, tried, sizeof tried) == 0;
    pl_mesh_load_options opt = {.drop_unused = sofa_is_true(only)};
    pl_diag d;
    pl_diag_init(&d);
    int ok = found && pl_mesh_load(path, &opt, m, &d) == PL_OK;
    pl_diag_free(&d); /* the loader reports its own file's problems again */
    if (!ok)
        sofa_error(L, user, "per-element values: cannot read the mesh '%s' of the node's loader",
                   f ? f : "");
    xmlFree(f);
    xmlFree(only);
    return ok ? m : NULL;
}

/* ---- BoxROI's tetrahedronIndices ----------------------------------------- */

static int in_box(const double *b, const double *p)
{
    for (int j = 0; j < 3; ++j) {
        double lo = b[j] < b[j + 3] ? b[j] : b[j + 3], hi = b[j] < b[j + 3] ? b[j + 3] : b[j];
        if (!(p[j] >= lo && p[j] <= hi)) return 0;
    }
    return 1;
}

static int in_boxes(const values *b, const double *p)
{
    for (int k = 0; k + 6 <= b->n; k += 6)
        if (in_box(b->v + k, p)) return 1;
    return 0;
}

/* The tetrahedra of m that the BoxROI selects, as values (indices). */
static int roi_tetrahedra(sofa_lower *L, xmlNode *roi, const pl_mesh *m, values *out)
{
    char *box = sofa_get(roi, "box"), *strict = sofa_get(roi, "strict");
    values b = {NULL, 0};
    int rc = box && parse_numbers(box, &b) == 0 && b.n > 0 && b.n % 6 == 0 ? 0 : -1;
    if (rc) sofa_error(L, roi, "box=\"%s\": expected 6 numbers per box", box ? box : "");
    int all = !strict || sofa_is_true(strict);
    out->v = NULL, out->n = 0;
    for (int t = 0; !rc && t < m->ntets; ++t) {
        const int *v = m->tets + 4 * t;
        int inside = 1;
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
            const double *p = m->verts + 3 * v[k];
            if (all) inside &= in_boxes(&b, p);
            for (int j = 0; j < 3; ++j) c[j] += 0.25 * p[j];
        }
        if (!all) inside = in_boxes(&b, c);
        if (inside && grow(out, out->n + 1, t)) rc = -1;
    }
    if (!rc) {
        sofa_set(roi, "pliant-used", "1");
        sofa_unset(roi, "strict"); /* honoured here */
    }
    free(b.v);
    xmlFree(box);
    xmlFree(strict);
    return rc;
}

/* ---- IndexValueMapper ------------------------------------------------------ */

static int number_attr(sofa_lower *L, xmlNode *e, const char *name, double def, double *v)
{
    char *s = sofa_get(e, name);
    int ok = !s ? (*v = def, 1) : sofa_parse_number(s, v);
    if (!ok) sofa_error(L, e, "%s=\"%s\": expected one number", name, s);
    xmlFree(s);
    return ok ? 0 : -1;
}

/* outputValues of the mapper `m` over the elements of mesh; depth guards cycles. */
static int mapper_values(sofa_lower *L, xmlNode *m, const pl_mesh *mesh, int depth, values *out)
{
    out->v = NULL, out->n = 0;
    if (depth > 16) {
        sofa_error(L, m, "IndexValueMapper: its inputValues lead back to itself");
        return -1;
    }
    double value, fill;
    if (!xmlHasProp(m, (const xmlChar *)"value")) {
        sofa_error(L, m, "IndexValueMapper needs value (the value given at its indices)");
        return -1;
    }
    if (number_attr(L, m, "value", 0, &value) || number_attr(L, m, "defaultValue", 1, &fill))
        return -1;
    char *in = sofa_get(m, "inputValues"), *ix = sofa_get(m, "indices");
    const char *field = NULL;
    int rc = 0;
    if (in && in[0] == '@') {
        xmlNode *src = sofa_data_link(m->parent, in, &field);
        if (!src || !sofa_tag_is(src, "IndexValueMapper") || strcmp(field, "outputValues")) {
            sofa_error(L, m, "inputValues=\"%s\": only another IndexValueMapper's outputValues "
                             "(or numbers) can be linked here", in);
            rc = -1;
        } else {
            rc = mapper_values(L, src, mesh, depth + 1, out);
        }
    } else if (in && parse_numbers(in, out)) {
        sofa_error(L, m, "inputValues=\"%s\": expected numbers", in);
        rc = -1;
    }
    values idx = {NULL, 0};
    if (!rc && ix && ix[0] == '@') {
        xmlNode *roi = sofa_data_link(m->parent, ix, &field);
        if (!roi || !sofa_tag_is(roi, "BoxROI") || strcmp(field, "tetrahedronIndices")) {
            sofa_error(L, m, "indices=\"%s\": only a BoxROI's tetrahedronIndices (or numbers) "
                             "can be linked here", ix);
            rc = -1;
        } else if (roi->parent != m->parent) {
            sofa_error(L, m, "indices=\"%s\": the BoxROI must be in this node (it selects this "
                             "node's tetrahedra)", ix);
            rc = -1;
        } else {
            rc = roi_tetrahedra(L, roi, mesh, &idx);
        }
    } else if (!rc && (!ix || parse_numbers(ix, &idx))) {
        sofa_error(L, m, "indices=\"%s\": expected element indices or @roi.tetrahedronIndices",
                   ix ? ix : "");
        rc = -1;
    }
    for (int k = 0; !rc && k < idx.n; ++k) {
        double i = idx.v[k];
        if (!(i >= 0 && i < mesh->ntets && i == (int)i)) {
            sofa_error(L, m, "indices: %g is not an element of the node's mesh (%d tetrahedra)",
                       i, mesh->ntets);
            rc = -1;
        } else if (grow(out, (int)i + 1, fill)) {
            rc = -1;
        } else {
            out->v[(int)i] = value;
        }
    }
    if (!rc) sofa_set(m, "pliant-used", "1");
    free(idx.v);
    xmlFree(in);
    xmlFree(ix);
    return rc;
}

/* attr="@mapper.outputValues" of the FEM e becomes one value per element. */
static void lower_fem_values(sofa_lower *L, xmlNode *e, const char *attr)
{
    char *v = sofa_get(e, attr);
    const char *field = NULL;
    xmlNode *m = v && v[0] == '@' ? sofa_data_link(e->parent, v, &field) : NULL;
    if (!m || !sofa_tag_is(m, "IndexValueMapper")) {
        xmlFree(v);
        return; /* numbers, or a link sofa_lower.c refuses */
    }
    pl_mesh mesh;
    pl_mesh_init(&mesh);
    values out = {NULL, 0};
    sofa_unset(e, attr); /* the values, or an error here: not the link */
    if (strcmp(field, "outputValues")) {
        sofa_error(L, e, "%s=\"%s\": an IndexValueMapper's values are its outputValues", attr, v);
    } else if (node_mesh(L, e, e->parent, &mesh) &&
               mapper_values(L, m, &mesh, 0, &out) == 0) {
        if (out.n > mesh.ntets || out.n == 0) {
            sofa_error(L, e, "%s=\"%s\": %d values for the %d tetrahedra of the node's mesh",
                       attr, v, out.n, mesh.ntets);
        } else {
            /* SOFA: elements past the list take its first value */
            if (out.n < mesh.ntets) grow(&out, mesh.ntets, out.v[0]);
            size_t cap = (size_t)out.n * 26 + 1, w = 0;
            char *text = malloc(cap);
            for (int k = 0; text && k < out.n; ++k)
                w += (size_t)snprintf(text + w, cap - w, "%s%.17g", k ? " " : "", out.v[k]);
            if (text) sofa_set(e, attr, text);
            free(text);
            sofa_note(L, "index-value-mapper", e,
                      "%s=\"%s\": one value per tetrahedron, from SOFA's BoxROI and "
                      "IndexValueMapper rules evaluated on the rest mesh",
                      attr, v);
        }
    }
    free(out.v);
    pl_mesh_free(&mesh);
    xmlFree(v);
}

static void fems(sofa_lower *L, xmlNode *node)
{
    for (xmlNode *e = node->children; e; e = e->next) {
        if (sofa_is_node(e)) {
            fems(L, e);
        } else if (sofa_is_element(e)) {
            lower_fem_values(L, e, "youngModulus");
            lower_fem_values(L, e, "poissonRatio");
        }
    }
}

static void drop_mappers(sofa_lower *L, xmlNode *node)
{
    xmlNode *next;
    for (xmlNode *e = node->children; e; e = next) {
        next = e->next;
        if (sofa_is_node(e)) {
            drop_mappers(L, e);
        } else if (sofa_tag_is(e, "IndexValueMapper")) {
            char *used = sofa_get(e, "pliant-used");
            if (!used)
                sofa_note(L, "mapper-unused", e,
                          "IndexValueMapper: no FEM's youngModulus or poissonRatio links to its "
                          "outputValues: ignored");
            xmlFree(used);
            sofa_remove(e);
        }
    }
}

void sofa_lower_value_mappers(sofa_lower *L)
{
    fems(L, L->root);
    drop_mappers(L, L->root);
}
