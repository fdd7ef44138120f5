/* gmsh.c - Gmsh .msh ASCII: version 1 ($NOD/$ELM) and 2.x ($MeshFormat
 * 2.2, $Nodes/$Elements); version 4.1 is handed to gmsh4.c once
 * $MeshFormat has been read.  Tetrahedra (type 4) and triangles (type 2)
 * are kept, every other element kind is counted and reported. */
#include "gmsh.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct gmsh_reader {
    pl_text *t;
    pl_mesh_build b;
    gmsh_nodes nodes;
    int have_nodes, have_elements;
    pl_io_skipped skipped;
} gmsh_reader;

/* Fails unless the line ends here (trailing values are a format error). */
static int end_of_record(pl_text *t, const char *what)
{
    if (pl_io_at_eol(t)) return PL_OK;
    char tok[64];
    if (pl_io_token(t, tok, sizeof tok, PL_IO_SAME_LINE) < 0) strcpy(tok, "...");
    return pl_io_fail(t, "unexpected '%s' after %s: expected the end of the line", tok, what);
}

/* "$MeshFormat": version, file-type (0 = ASCII), data-size.  Sets *v4. */
static int read_format(pl_text *t, int *v4)
{
    char ver[32];
    long long ftype, dsize;
    if (pl_io_token(t, ver, sizeof ver, PL_IO_ANY_LINE) <= 0)
        return pl_io_fail(t, "expected the Gmsh format version");
    if (pl_io_read_int(t, &ftype, "the file type (0 = ASCII)", PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &dsize, "the data size", PL_IO_SAME_LINE))
        return PL_EINPUT;
    if (ftype != 0)
        return pl_io_fail(t, "binary Gmsh files (file-type %lld) are not supported: expected an "
                          "ASCII file (file-type 0)", ftype);
    *v4 = strcmp(ver, "4.1") == 0;
    if (!*v4 && ver[0] != '2')
        return pl_io_fail(t, "Gmsh format version %s is not supported: expected 2.x or 4.1 "
                          "(or a version 1 file starting with $NOD)", ver);
    if (end_of_record(t, "the format line") || pl_io_gmsh_expect(t, "EndMeshFormat"))
        return PL_EINPUT;
    return PL_OK;
}

/* "$Nodes"/"$NOD": count, then "tag x y z" lines. */
static int read_nodes(gmsh_reader *r, const char *end)
{
    pl_text *t = r->t;
    long long n;
    if (r->have_nodes) return pl_io_fail(t, "a second node section: expected one");
    r->have_nodes = 1;
    if (pl_io_read_int(t, &n, "the number of nodes", PL_IO_ANY_LINE) ||
        pl_io_check_count(t, 0, n, pl_io_left(t) + 1, 8, "nodes"))
        return PL_EINPUT;
    int line = t->line;
    if (pl_io_reserve(&r->b, n, 0, 0)) return pl_io_nomem(t);
    for (long long i = 0; i < n; ++i) {
        long long tag;
        double x[3];
        if (pl_io_read_int_range(t, &tag, 1, LLONG_MAX, "a node tag", PL_IO_ANY_LINE) ||
            pl_io_read_double(t, &x[0], "the node's x", PL_IO_SAME_LINE) ||
            pl_io_read_double(t, &x[1], "the node's y", PL_IO_SAME_LINE) ||
            pl_io_read_double(t, &x[2], "the node's z", PL_IO_SAME_LINE) ||
            end_of_record(t, "a node's coordinates"))
            return PL_EINPUT;
        if (pl_io_gmsh_add_node(&r->nodes, tag)) return pl_io_nomem(t);
        pl_io_add_vert(&r->b, x[0], x[1], x[2]);
    }
    if (pl_io_gmsh_index(t, &r->nodes, line)) return PL_EINPUT;
    return pl_io_gmsh_expect(t, end);
}

/* Reads the node tags left on an element line into tags (at most cap). */
static int read_element_nodes(pl_text *t, long long *tags, int cap, int *k, long long elem)
{
    *k = 0;
    while (!pl_io_at_eol(t)) {
        long long v;
        if (pl_io_read_int(t, &v, "a node tag", PL_IO_SAME_LINE)) return PL_EINPUT;
        if (*k == cap) return pl_io_fail(t, "element %lld has more than %d nodes", elem, cap);
        tags[(*k)++] = v;
    }
    return PL_OK;
}

/* "$Elements" (v2: tag type ntags tags... nodes...) or "$ELM" (v1: tag type
 * physical elementary nnodes nodes...). */
static int read_elements(gmsh_reader *r, int v1, const char *end)
{
    pl_text *t = r->t;
    long long n;
    if (!r->have_nodes) return pl_io_fail(t, "elements before nodes: expected the node section first");
    if (r->have_elements) return pl_io_fail(t, "a second element section: expected one");
    r->have_elements = 1;
    if (pl_io_read_int(t, &n, "the number of elements", PL_IO_ANY_LINE) ||
        pl_io_check_count(t, 0, n, pl_io_left(t) + 1, 8, "elements"))
        return PL_EINPUT;
    for (long long e = 0; e < n; ++e) {
        long long tag, type, ntags, skip, nn = -1, tags[64];
        int k;
        if (pl_io_read_int(t, &tag, "an element tag", PL_IO_ANY_LINE) ||
            pl_io_read_int(t, &type, "the element type", PL_IO_SAME_LINE))
            return PL_EINPUT;
        if (v1) { /* physical and elementary region, then the node count */
            if (pl_io_read_int(t, &skip, "the physical region", PL_IO_SAME_LINE) ||
                pl_io_read_int(t, &skip, "the elementary region", PL_IO_SAME_LINE) ||
                pl_io_read_int_range(t, &nn, 0, 64, "the node count", PL_IO_SAME_LINE))
                return PL_EINPUT;
        } else {
            if (pl_io_read_int_range(t, &ntags, 0, 64, "the number of tags", PL_IO_SAME_LINE))
                return PL_EINPUT;
            for (long long j = 0; j < ntags; ++j)
                if (pl_io_read_int(t, &skip, "an element tag value", PL_IO_SAME_LINE))
                    return PL_EINPUT;
        }
        if (read_element_nodes(t, tags, 64, &k, tag)) return PL_EINPUT;
        if (v1 && k != nn)
            return pl_io_fail(t, "element %lld declares %lld nodes but lists %d", tag, nn, k);
        if (!pl_io_gmsh_kept_nodes(type)) {
            pl_io_skip_cell(&r->skipped, type);
            continue;
        }
        if (pl_io_gmsh_add_element(t, &r->b, &r->nodes, type, tags, k, tag)) return PL_EINPUT;
    }
    return pl_io_gmsh_expect(t, end);
}

int pl_io_load_gmsh(pl_text *t, pl_mesh *out)
{
    gmsh_reader *r = calloc(1, sizeof *r);
    if (!r) return pl_io_nomem(t);
    r->t = t;
    pl_io_build_init(&r->b, out);
    int rc = PL_OK, seen_format = 0, v4 = 0;
    char tok[80];
    for (;;) {
        int n = pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE);
        if (n == 0) break;
        if (n < 0 || tok[0] != '$') {
            rc = pl_io_fail(t, "expected a $Section header, found '%s'",
                            n < 0 ? "an overlong token" : tok);
            break;
        }
        const char *s = tok + 1;
        if (strcasecmp(s, "MeshFormat") == 0) {
            rc = seen_format ? pl_io_fail(t, "a second $MeshFormat") : read_format(t, &v4);
            seen_format = 1;
            if (rc == PL_OK && v4) {
                rc = pl_io_load_gmsh4(t, out);
                break;
            }
        } else if (strcasecmp(s, "NOD") == 0) rc = read_nodes(r, "ENDNOD");
        else if (strcasecmp(s, "Nodes") == 0) rc = read_nodes(r, "EndNodes");
        else if (strcasecmp(s, "ELM") == 0) rc = read_elements(r, 1, "ENDELM");
        else if (strcasecmp(s, "Elements") == 0) rc = read_elements(r, 0, "EndElements");
        else if (strncasecmp(s, "End", 3) == 0)
            rc = pl_io_fail(t, "unexpected %s without its opening section", tok);
        else rc = pl_io_gmsh_skip_section(t, s); /* $PhysicalNames, $NodeData, ... */
        if (rc) break;
    }
    if (rc == PL_OK && !v4) { /* gmsh4.c checks and reports its own sections */
        if (!r->have_nodes) rc = pl_io_fail(t, "no node section: expected $Nodes (or $NOD)");
        else if (!r->have_elements)
            rc = pl_io_fail(t, "no element section: expected $Elements (or $ELM)");
        else pl_io_report_skipped(t, &r->skipped, "Gmsh", pl_io_gmsh_type_name, out);
    }
    pl_io_gmsh_nodes_free(&r->nodes);
    free(r);
    return rc;
}
