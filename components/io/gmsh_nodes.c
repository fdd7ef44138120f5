/* gmsh_nodes.c - node-tag map, element kinds and section skipping shared by
 * the Gmsh readers. */
#include "gmsh.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "pliant/checked.h"

int pl_io_gmsh_add_node(gmsh_nodes *g, long long tag)
{
    if (g->n == g->cap) {
        if (g->cap > INT_MAX / 2) return PL_EINTERNAL;
        int cap = g->cap ? 2 * g->cap : 256;
        size_t bytes;
        long long *t = pl_array_bytes((uint64_t)cap, sizeof *t, 0, &bytes) ? NULL
                                                                           : realloc(g->tags, bytes);
        if (!t) return PL_EINTERNAL;
        g->tags = t;
        g->cap = cap;
    }
    g->tags[g->n++] = tag;
    return PL_OK;
}

/* qsort has no context argument: sort (tag, index) pairs instead. */
typedef struct tag_index {
    long long tag;
    int index;
} tag_index;

static int cmp_tag(const void *a, const void *b)
{
    const tag_index *x = a, *y = b;
    return (x->tag > y->tag) - (x->tag < y->tag);
}

int pl_io_gmsh_index(pl_text *t, gmsh_nodes *g, int line)
{
    free(g->order);
    size_t ob, pb;
    int bad = pl_array_bytes((uint64_t)g->n, sizeof *g->order, 1, &ob) ||
              pl_array_bytes((uint64_t)g->n, sizeof(tag_index), 1, &pb);
    g->order = bad ? NULL : malloc(ob);
    tag_index *p = bad ? NULL : malloc(pb);
    if (!g->order || !p) {
        free(p);
        return pl_io_nomem(t);
    }
    for (int i = 0; i < g->n; ++i) p[i] = (tag_index){g->tags[i], i};
    qsort(p, (size_t)g->n, sizeof *p, cmp_tag);
    for (int i = 0; i < g->n; ++i) {
        if (i && p[i].tag == p[i - 1].tag) {
            long long dup = p[i].tag;
            free(p);
            return pl_io_fail_at(t, line, "node tag %lld appears twice: expected unique tags",
                                 dup);
        }
        g->order[i] = p[i].index;
    }
    free(p);
    return PL_OK;
}

int pl_io_gmsh_find(const gmsh_nodes *g, long long tag)
{
    int lo = 0, hi = g->n - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        long long m = g->tags[g->order[mid]];
        if (m == tag) return g->order[mid];
        if (m < tag) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

void pl_io_gmsh_nodes_free(gmsh_nodes *g)
{
    free(g->tags);
    free(g->order);
    memset(g, 0, sizeof *g);
}

int pl_io_gmsh_kept_nodes(long long type)
{
    return type == 4 ? 4 : type == 2 ? 3 : 0;
}

const char *pl_io_gmsh_type_name(int type)
{
    switch (type) {
    case 1: return "line";
    case 2: return "triangle";
    case 3: return "quadrangle";
    case 4: return "tetrahedron";
    case 5: return "hexahedron";
    case 6: return "prism";
    case 7: return "pyramid";
    case 8: return "second-order line";
    case 9: return "second-order triangle";
    case 10: return "second-order quadrangle";
    case 11: return "second-order tetrahedron";
    case 15: return "point";
    default: return "element";
    }
}

int pl_io_gmsh_expect(pl_text *t, const char *name)
{
    char tok[64];
    int n = pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE);
    if (n <= 0 || tok[0] != '$' || strcasecmp(tok + 1, name) != 0)
        return pl_io_fail(t, "expected $%s, found '%s'", name,
                          n > 0 ? tok : n == 0 ? "end of file" : "an overlong token");
    return PL_OK;
}

int pl_io_gmsh_skip_section(pl_text *t, const char *name)
{
    int line = t->line;
    char end[80];
    snprintf(end, sizeof end, "$End%s", name);
    pl_io_next_line(t);
    while (t->pos < t->size) {
        char tok[80];
        int n = pl_io_token(t, tok, sizeof tok, PL_IO_SAME_LINE);
        /* v1 ends $NOD/$ELM with $ENDNOD/$ENDELM: compare case-insensitively */
        if (n > 0 && strcasecmp(tok, end) == 0) {
            pl_io_next_line(t);
            return PL_OK;
        }
        pl_io_next_line(t);
    }
    return pl_io_fail_at(t, line, "section $%s is not closed: expected %s", name, end);
}

int pl_io_gmsh_add_element(pl_text *t, pl_mesh_build *b, const gmsh_nodes *g, long long type,
                           const long long *tags, int k, long long elem_tag)
{
    int need = pl_io_gmsh_kept_nodes(type), ids[4];
    if (k != need)
        return pl_io_fail(t, "element %lld is a %s (type %lld) with %d nodes: expected %d",
                          elem_tag, pl_io_gmsh_type_name((int)type), type, k, need);
    for (int j = 0; j < k; ++j) {
        ids[j] = pl_io_gmsh_find(g, tags[j]);
        if (ids[j] < 0)
            return pl_io_fail(t, "element %lld uses node %lld, which is not in the node list",
                              elem_tag, tags[j]);
    }
    int rc = need == 4 ? pl_io_add_tet(b, ids[0], ids[1], ids[2], ids[3])
                       : pl_io_add_tri(b, ids[0], ids[1], ids[2]);
    return rc ? pl_io_nomem(t) : PL_OK;
}
