/* vtu.c - VTK XML unstructured grids (<VTKFile type="UnstructuredGrid">).
 *
 * Parsed by core/src/xml_guard.c: network access off, no entity
 * substitution, and a <!DOCTYPE> refused as soon as the parser meets it
 * (VTU never needs one; refusing it stops entity-expansion bombs and
 * external entities in any encoding).  Every <Piece> is read and appended
 * (vertex indices offset). */
#include "vtu_data.h"
#include "xml_guard.h"

#include <libxml/parser.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static int is_element(xmlNode *n, const char *name)
{
    return n && n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

static xmlNode *child(xmlNode *parent, const char *name)
{
    for (xmlNode *c = parent ? parent->children : NULL; c; c = c->next)
        if (is_element(c, name)) return c;
    return NULL;
}

/* The <DataArray> child of `parent` with Name=name (any name when NULL). */
static xmlNode *data_array(xmlNode *parent, const char *name)
{
    for (xmlNode *c = parent ? parent->children : NULL; c; c = c->next) {
        if (!is_element(c, "DataArray")) continue;
        if (!name) return c;
        xmlChar *n = xmlGetProp(c, (const xmlChar *)"Name");
        int match = n && strcmp((const char *)n, name) == 0;
        xmlFree(n);
        if (match) return c;
    }
    return NULL;
}

/* Copies attribute `name` into buf ("" when absent). */
static void attr(xmlNode *n, const char *name, char *buf, size_t cap)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)name);
    snprintf(buf, cap, "%s", v ? (const char *)v : "");
    xmlFree(v);
}

/* Reads an integer attribute in [lo, hi]. */
static int int_attr(pl_text *t, xmlNode *n, const char *name, long long lo, long long hi,
                    long long *v)
{
    char buf[64];
    attr(n, name, buf, sizeof buf);
    int line = (int)xmlGetLineNo(n);
    if (!buf[0])
        return pl_io_fail_at(t, line, "<%s> lacks the %s attribute", (const char *)n->name, name);
    if (pl_io_parse_int(buf, v) || *v < lo || *v > hi)
        return pl_io_fail_at(t, line, "%s=\"%s\": expected an integer in %lld..%lld", name, buf,
                             lo, hi);
    return PL_OK;
}

static int read_format(pl_text *t, xmlNode *root, vtu_format *f)
{
    char buf[64];
    int line = (int)xmlGetLineNo(root);
    attr(root, "type", buf, sizeof buf);
    if (strcmp(buf, "UnstructuredGrid") != 0)
        return pl_io_fail_at(t, line, "<VTKFile type=\"%s\">: expected type=\"UnstructuredGrid\"",
                             buf);
    attr(root, "byte_order", buf, sizeof buf);
    f->big_endian = strcmp(buf, "BigEndian") == 0;
    if (!f->big_endian && buf[0] && strcmp(buf, "LittleEndian") != 0)
        return pl_io_fail_at(t, line, "byte_order=\"%s\": expected LittleEndian or BigEndian",
                             buf);
    attr(root, "header_type", buf, sizeof buf);
    f->header64 = strcmp(buf, "UInt64") == 0;
    if (!f->header64 && buf[0] && strcmp(buf, "UInt32") != 0)
        return pl_io_fail_at(t, line, "header_type=\"%s\": expected UInt32 or UInt64", buf);
    attr(root, "compressor", buf, sizeof buf);
    f->zlib = strcmp(buf, "vtkZLibDataCompressor") == 0;
    if (!f->zlib && buf[0])
        return pl_io_fail_at(t, line, "compressor=\"%s\" is not supported: expected "
                             "vtkZLibDataCompressor or no compressor", buf);
    return PL_OK;
}

/* Checks offsets (increasing, from above 0) and adds the kept cells. */
static int add_cells(pl_text *t, int line, pl_mesh_build *b, int base, long long npts,
                     long long ncells, const long long *off, const long long *conn,
                     const long long *type, pl_io_skipped *skipped)
{
    for (long long c = 0; c < ncells; ++c) {
        long long start = c ? off[c - 1] : 0, k = off[c] - start;
        int need = type[c] == 10 ? 4 : type[c] == 5 ? 3 : -1;
        if (need < 0) {
            pl_io_skip_cell(skipped, type[c]);
            continue;
        }
        if (k != need)
            return pl_io_fail_at(t, line, "cell %lld is a %s (type %lld) with %lld points: "
                                 "expected %d", c, pl_io_vtk_cell_name((int)type[c]), type[c], k,
                                 need);
        int ids[4];
        for (int j = 0; j < need; ++j) {
            long long v = conn[start + j];
            if (v < 0 || v >= npts)
                return pl_io_fail_at(t, line, "cell %lld uses point %lld: expected an index in "
                                     "0..%lld", c, v, npts - 1);
            ids[j] = base + (int)v;
        }
        int rc = need == 4 ? pl_io_add_tet(b, ids[0], ids[1], ids[2], ids[3])
                           : pl_io_add_tri(b, ids[0], ids[1], ids[2]);
        if (rc) return pl_io_nomem(t);
    }
    return PL_OK;
}

/* Reads the cells of a piece: offsets first, they size connectivity. */
static int read_cells(pl_text *t, const vtu_format *f, xmlNode *piece, long long npts,
                      long long ncells, int base, pl_mesh_build *b, pl_io_skipped *skipped)
{
    xmlNode *cells = child(piece, "Cells");
    int line = (int)xmlGetLineNo(piece);
    if (ncells == 0) return PL_OK;
    if (!cells) return pl_io_fail_at(t, line, "<Piece> has cells but no <Cells> element");
    xmlNode *aconn = data_array(cells, "connectivity"), *aoff = data_array(cells, "offsets");
    xmlNode *atype = data_array(cells, "types");
    if (!aconn || !aoff || !atype)
        return pl_io_fail_at(t, (int)xmlGetLineNo(cells), "<Cells> needs DataArrays named "
                             "connectivity, offsets and types");
    long long *off = NULL, *type = NULL, *conn = NULL;
    int rc = pl_io_vtu_array(t, f, aoff, ncells, 1, (void **)&off);
    if (rc == PL_OK) rc = pl_io_vtu_array(t, f, atype, ncells, 1, (void **)&type);
    line = (int)xmlGetLineNo(aoff);
    for (long long c = 0; rc == PL_OK && c < ncells; ++c)
        if (off[c] < (c ? off[c - 1] : 0) || off[c] > (long long)INT_MAX)
            rc = pl_io_fail_at(t, line, "offsets value %lld (cell %lld) is below the previous "
                               "one or out of range: expected increasing offsets", off[c], c);
    long long nconn = rc == PL_OK ? off[ncells - 1] : 0;
    if (rc == PL_OK) rc = pl_io_vtu_array(t, f, aconn, nconn, 1, (void **)&conn);
    if (rc == PL_OK)
        rc = add_cells(t, (int)xmlGetLineNo(aconn), b, base, npts, ncells, off, conn, type,
                       skipped);
    free(off);
    free(type);
    free(conn);
    return rc;
}

static int read_piece(pl_text *t, const vtu_format *f, xmlNode *piece, pl_mesh_build *b,
                      pl_io_skipped *skipped)
{
    long long npts, ncells;
    if (int_attr(t, piece, "NumberOfPoints", 0, INT_MAX / 4 - b->m->nverts, &npts) ||
        int_attr(t, piece, "NumberOfCells", 0, INT_MAX / 4, &ncells))
        return PL_EINPUT;
    int line = (int)xmlGetLineNo(piece);
    xmlNode *points = child(piece, "Points"), *arr = data_array(points, NULL);
    if (npts > 0 && !arr)
        return pl_io_fail_at(t, line, "<Piece> lacks <Points><DataArray>: expected the point "
                             "coordinates");
    if (arr) {
        long long nc = 3;
        char buf[32];
        attr(arr, "NumberOfComponents", buf, sizeof buf);
        if (buf[0] && (pl_io_parse_int(buf, &nc) || nc != 3))
            return pl_io_fail_at(t, (int)xmlGetLineNo(arr), "Points NumberOfComponents=\"%s\": "
                                 "expected 3", buf);
    }
    int base = b->m->nverts;
    double *xyz = NULL;
    int rc = npts ? pl_io_vtu_array(t, f, arr, 3 * npts, 0, (void **)&xyz) : PL_OK;
    if (rc == PL_OK && pl_io_reserve(b, npts, 0, 0)) rc = pl_io_nomem(t);
    for (long long i = 0; rc == PL_OK && i < npts; ++i)
        pl_io_add_vert(b, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    free(xyz);
    if (rc == PL_OK) rc = read_cells(t, f, piece, npts, ncells, base, b, skipped);
    return rc;
}

static int read_document(pl_text *t, xmlDoc *doc, pl_mesh *out, pl_io_skipped *skipped)
{
    xmlNode *root = xmlDocGetRootElement(doc);
    if (!is_element(root, "VTKFile"))
        return pl_io_fail_at(t, root ? (int)xmlGetLineNo(root) : 1,
                             "root element <%s>: expected <VTKFile>",
                             root ? (const char *)root->name : "(none)");
    vtu_format f;
    if (read_format(t, root, &f)) return PL_EINPUT;
    xmlNode *grid = child(root, "UnstructuredGrid");
    if (!grid)
        return pl_io_fail_at(t, (int)xmlGetLineNo(root), "<VTKFile> lacks <UnstructuredGrid>");
    pl_mesh_build b;
    pl_io_build_init(&b, out);
    int npieces = 0;
    for (xmlNode *p = grid->children; p; p = p->next) {
        if (!is_element(p, "Piece")) continue;
        npieces++;
        if (read_piece(t, &f, p, &b, skipped)) return PL_EINPUT;
    }
    if (!npieces)
        return pl_io_fail_at(t, (int)xmlGetLineNo(grid), "<UnstructuredGrid> has no <Piece>");
    return PL_OK;
}

int pl_io_load_vtu(pl_text *t, pl_mesh *out)
{
    pl_error e;
    xmlDoc *doc = pl_xml_read_untrusted(t->buf, t->size, t->path, "VTU files",
                                        XML_PARSE_BIG_LINES | XML_PARSE_NOCDATA, &e);
    int rc;
    if (!doc) {
        rc = e.code == PL_EINPUT ? pl_io_fail_at(t, e.line, "%s", e.msg) : pl_io_nomem(t);
    } else {
        pl_io_skipped *skipped = calloc(1, sizeof *skipped);
        rc = skipped ? read_document(t, doc, out, skipped) : pl_io_nomem(t);
        if (rc == PL_OK) pl_io_report_skipped(t, skipped, "VTK", pl_io_vtk_cell_name, out);
        free(skipped);
        xmlFreeDoc(doc);
    }
    return rc;
}
