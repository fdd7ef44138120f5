/* gmsh.h - pieces shared by the Gmsh v1/v2 and v4.1 readers (private). */
#ifndef PLIANT_IO_GMSH_H
#define PLIANT_IO_GMSH_H

#include "mesh_io.h"

/* Node tags are arbitrary positive integers, not necessarily contiguous:
 * this maps them to 0-based vertex indices. */
typedef struct gmsh_nodes {
    long long *tags;  /* tag of vertex i, in file order */
    int *order;       /* vertex indices sorted by tag */
    int n, cap;
} gmsh_nodes;

PL_IO_HIDDEN int pl_io_gmsh_add_node(gmsh_nodes *g, long long tag);
/* Sorts the tags and rejects duplicates (error at `line`). */
PL_IO_HIDDEN int pl_io_gmsh_index(pl_text *t, gmsh_nodes *g, int line);
/* The vertex index of a tag, or -1. */
PL_IO_HIDDEN int pl_io_gmsh_find(const gmsh_nodes *g, long long tag);
PL_IO_HIDDEN void pl_io_gmsh_nodes_free(gmsh_nodes *g);
/* Node count of a Gmsh element type we keep: 3 (triangle, 2), 4 (tetra, 4). */
PL_IO_HIDDEN int pl_io_gmsh_kept_nodes(long long type);
PL_IO_HIDDEN const char *pl_io_gmsh_type_name(int type);
/* Reads the remaining tokens of a "$Section" header line and skips the
 * section up to its "$End..." line. */
PL_IO_HIDDEN int pl_io_gmsh_skip_section(pl_text *t, const char *name);
/* Adds a kept element whose node tags are given; maps and checks them. */
PL_IO_HIDDEN int pl_io_gmsh_add_element(pl_text *t, pl_mesh_build *b, const gmsh_nodes *g,
                                        long long type, const long long *tags, int k,
                                        long long elem_tag);
/* Expects the line "$<name>". */
PL_IO_HIDDEN int pl_io_gmsh_expect(pl_text *t, const char *name);

#endif
