/* gmsh4.c - Gmsh 4.1 ASCII, read after its $MeshFormat line.
 *
 * Nodes and elements come in entity blocks.  A node block lists its tags
 * first, then the coordinates (plus u/v/w when parametric); tags may be
 * sparse and are mapped to 0-based indices.  An element block has one type;
 * blocks of kinds other than tetrahedra and triangles are skipped whole. */
#include "gmsh.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct gmsh4_reader {
    pl_text *t;
    pl_mesh_build b;
    gmsh_nodes nodes;
    int have_nodes, have_elements;
    pl_io_skipped skipped;
} gmsh4_reader;

static int end_of_record(pl_text *t, const char *what)
{
    if (pl_io_at_eol(t)) return PL_OK;
    return pl_io_fail(t, "unexpected values after %s: expected the end of the line", what);
}

/* "numEntityBlocks numItems minTag maxTag" of $Nodes and $Elements. */
static int read_counts(pl_text *t, long long *nblocks, long long *nitems, const char *what)
{
    long long lo, hi;
    if (pl_io_read_int(t, nblocks, "the number of entity blocks", PL_IO_ANY_LINE) ||
        pl_io_read_int(t, nitems, what, PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &lo, "the minimum tag", PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &hi, "the maximum tag", PL_IO_SAME_LINE) ||
        end_of_record(t, "the section counts"))
        return PL_EINPUT;
    /* each block header needs 8 bytes, each item at least 4 */
    if (pl_io_check_count(t, 0, *nblocks, pl_io_left(t) + 1, 8, "entity blocks") ||
        pl_io_check_count(t, 0, *nitems, pl_io_left(t) + 1, 4, what))
        return PL_EINPUT;
    return PL_OK;
}

static int read_node_block(gmsh4_reader *r, long long total)
{
    pl_text *t = r->t;
    long long dim, entity, parametric, n;
    if (pl_io_read_int_range(t, &dim, 0, 3, "the entity dimension", PL_IO_ANY_LINE) ||
        pl_io_read_int(t, &entity, "the entity tag", PL_IO_SAME_LINE) ||
        pl_io_read_int_range(t, &parametric, 0, 1, "the parametric flag", PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &n, "the number of nodes in the block", PL_IO_SAME_LINE) ||
        end_of_record(t, "a node block header"))
        return PL_EINPUT;
    if (n < 0 || n > total - r->nodes.n)
        return pl_io_fail(t, "node block declares %lld nodes: the section announced %lld in "
                          "all, %d are already read", n, total, r->nodes.n);
    for (long long i = 0; i < n; ++i) {
        long long tag;
        if (pl_io_read_int_range(t, &tag, 1, LLONG_MAX, "a node tag", PL_IO_ANY_LINE) ||
            end_of_record(t, "a node tag"))
            return PL_EINPUT;
        if (pl_io_gmsh_add_node(&r->nodes, tag)) return pl_io_nomem(t);
    }
    for (long long i = 0; i < n; ++i) {
        double x[3], u;
        if (pl_io_read_double(t, &x[0], "a node's x", PL_IO_ANY_LINE) ||
            pl_io_read_double(t, &x[1], "a node's y", PL_IO_SAME_LINE) ||
            pl_io_read_double(t, &x[2], "a node's z", PL_IO_SAME_LINE))
            return PL_EINPUT;
        for (long long p = 0; parametric && p < dim; ++p)
            if (pl_io_read_double(t, &u, "a parametric coordinate", PL_IO_SAME_LINE))
                return PL_EINPUT;
        if (end_of_record(t, "a node's coordinates")) return PL_EINPUT;
        pl_io_add_vert(&r->b, x[0], x[1], x[2]); /* reserved by the caller */
    }
    return PL_OK;
}

static int read_nodes(gmsh4_reader *r)
{
    pl_text *t = r->t;
    long long nblocks, n;
    if (r->have_nodes) return pl_io_fail(t, "a second $Nodes section: expected one");
    r->have_nodes = 1;
    if (read_counts(t, &nblocks, &n, "nodes")) return PL_EINPUT;
    int line = t->line; /* the counts line, named by count errors */
    if (pl_io_reserve(&r->b, n, 0, 0)) return pl_io_nomem(t);
    for (long long b = 0; b < nblocks; ++b)
        if (read_node_block(r, n)) return PL_EINPUT;
    if (r->nodes.n != n)
        return pl_io_fail_at(t, line, "$Nodes announced %lld nodes but its blocks hold %d", n,
                          r->nodes.n);
    if (pl_io_gmsh_index(t, &r->nodes, line)) return PL_EINPUT;
    return pl_io_gmsh_expect(t, "EndNodes");
}

static int read_element_block(gmsh4_reader *r, long long total, long long *done)
{
    pl_text *t = r->t;
    long long dim, entity, type, n;
    if (pl_io_read_int_range(t, &dim, 0, 3, "the entity dimension", PL_IO_ANY_LINE) ||
        pl_io_read_int(t, &entity, "the entity tag", PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &type, "the element type", PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &n, "the number of elements in the block", PL_IO_SAME_LINE) ||
        end_of_record(t, "an element block header"))
        return PL_EINPUT;
    if (n < 0 || n > total - *done)
        return pl_io_fail(t, "element block declares %lld elements: the section announced "
                          "%lld in all, %lld are already read", n, total, *done);
    *done += n;
    int k = pl_io_gmsh_kept_nodes(type);
    for (long long e = 0; e < n; ++e) {
        if (!k) { /* a kind we skip: one element per line */
            if (pl_io_at_eof(t))
                return pl_io_fail(t, "unexpected end of file inside an element block");
            pl_io_skip_cell(&r->skipped, type);
            pl_io_next_line(t);
            continue;
        }
        long long tag, tags[4];
        if (pl_io_read_int(t, &tag, "an element tag", PL_IO_ANY_LINE)) return PL_EINPUT;
        for (int j = 0; j < k; ++j)
            if (pl_io_read_int(t, &tags[j], "a node tag", PL_IO_SAME_LINE)) return PL_EINPUT;
        if (end_of_record(t, "an element's nodes") ||
            pl_io_gmsh_add_element(t, &r->b, &r->nodes, type, tags, k, tag))
            return PL_EINPUT;
    }
    return PL_OK;
}

static int read_elements(gmsh4_reader *r)
{
    pl_text *t = r->t;
    long long nblocks, n, done = 0;
    if (!r->have_nodes) return pl_io_fail(t, "$Elements before $Nodes: expected $Nodes first");
    if (r->have_elements) return pl_io_fail(t, "a second $Elements section: expected one");
    r->have_elements = 1;
    if (read_counts(t, &nblocks, &n, "elements")) return PL_EINPUT;
    int line = t->line;
    for (long long b = 0; b < nblocks; ++b)
        if (read_element_block(r, n, &done)) return PL_EINPUT;
    if (done != n)
        return pl_io_fail_at(t, line, "$Elements announced %lld elements but its blocks hold %lld", n,
                          done);
    return pl_io_gmsh_expect(t, "EndElements");
}

int pl_io_load_gmsh4(pl_text *t, pl_mesh *out)
{
    gmsh4_reader *r = calloc(1, sizeof *r);
    if (!r) return pl_io_nomem(t);
    r->t = t;
    pl_io_build_init(&r->b, out);
    int rc = PL_OK;
    char tok[80];
    for (;;) {
        int n = pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE);
        if (n == 0) break;
        if (n < 0 || tok[0] != '$') {
            rc = pl_io_fail(t, "expected a $Section header, found '%s'",
                            n < 0 ? "an overlong token" : tok);
            break;
        }
        if (strcasecmp(tok, "$Nodes") == 0) rc = read_nodes(r);
        else if (strcasecmp(tok, "$Elements") == 0) rc = read_elements(r);
        else if (strcasecmp(tok, "$MeshFormat") == 0)
            rc = pl_io_fail(t, "a second $MeshFormat: expected one");
        else if (strncasecmp(tok, "$End", 4) == 0)
            rc = pl_io_fail(t, "unexpected %s without its opening section", tok);
        else rc = pl_io_gmsh_skip_section(t, tok + 1); /* $Entities, $PhysicalNames, ... */
        if (rc) break;
    }
    if (rc == PL_OK && !r->have_nodes) rc = pl_io_fail(t, "no $Nodes section");
    else if (rc == PL_OK && !r->have_elements) rc = pl_io_fail(t, "no $Elements section");
    if (rc == PL_OK) pl_io_report_skipped(t, &r->skipped, "Gmsh", pl_io_gmsh_type_name, out);
    pl_io_gmsh_nodes_free(&r->nodes);
    free(r);
    return rc;
}
