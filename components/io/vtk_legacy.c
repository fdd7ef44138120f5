/* vtk_legacy.c - legacy VTK files ("# vtk DataFile"), ASCII and BINARY.
 *
 * BINARY data is big-endian and starts right after the newline that ends
 * its keyword line.  UNSTRUCTURED_GRID keeps tetra (type 10) and triangle
 * (type 5) cells; POLYDATA keeps POLYGONS (fan-triangulated when they have
 * more than three points) and TRIANGLE_STRIPS.  Both the classic CELLS
 * layout (count, ids...) and the 5.x OFFSETS/CONNECTIVITY layout are read.
 * Attribute data (POINT_DATA, CELL_DATA) is not needed and ends the read. */
#include "mesh_io.h"

#include "pliant/checked.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct vtk_reader {
    pl_text *t;
    int binary;
    pl_mesh_build b;
    int have_points;
    /* UNSTRUCTURED_GRID cells, kept until CELL_TYPES arrives */
    long long ncells;
    int *off, *conn; /* off[ncells+1] into conn */
    int cells_line;
    int have_types;
    pl_io_skipped skipped;
} vtk_reader;

/* Ends a keyword line: binary data begins on the next byte. */
static int end_header_line(pl_text *t, const char *keyword)
{
    if (!pl_io_at_eol(t)) {
        char tok[64];
        if (pl_io_token(t, tok, sizeof tok, PL_IO_SAME_LINE) < 0) strcpy(tok, "...");
        return pl_io_fail(t, "unexpected '%s' at the end of the %s line", tok, keyword);
    }
    pl_io_next_line(t);
    return PL_OK;
}

/* Advances over a binary block of n bytes, keeping the line count honest. */
static int take_binary(pl_text *t, size_t n, const char *what, const unsigned char **p)
{
    if (n > pl_io_left(t))
        return pl_io_fail(t, "file is truncated: %s needs %zu bytes of binary data, %zu remain",
                          what, n, pl_io_left(t));
    *p = (const unsigned char *)t->buf + t->pos;
    for (size_t i = 0; i < n; ++i) t->line += (*p)[i] == '\n';
    t->pos += n;
    return PL_OK;
}

/* Reads n integers (binary: big-endian, `width` bytes) in 0..INT_MAX. */
static int read_ints(vtk_reader *r, long long n, int width, int *out, const char *what)
{
    pl_text *t = r->t;
    if (!r->binary) {
        for (long long i = 0; i < n; ++i) {
            long long v;
            if (pl_io_read_int_range(t, &v, 0, INT_MAX, what, PL_IO_ANY_LINE)) return PL_EINPUT;
            out[i] = (int)v;
        }
        return PL_OK;
    }
    const unsigned char *p = NULL;
    int line = t->line;
    size_t bytes;
    if (pl_array_bytes((uint64_t)n, (size_t)width, 0, &bytes))
        return pl_io_fail(t, "%s: %lld values of %d bytes overflow", what, n, width);
    if (take_binary(t, bytes, what, &p)) return PL_EINPUT;
    for (long long i = 0; i < n; ++i) {
        long long v = width == 8 ? (long long)pl_io_u64(p + 8 * i, 1)
                                 : (long long)(int32_t)pl_io_u32(p + 4 * i, 1);
        if (v < 0 || v > INT_MAX)
            return pl_io_fail_at(t, line, "%s %lld (value %lld of the block) is out of range 0..%d",
                                 what, v, i, INT_MAX);
        out[i] = (int)v;
    }
    return PL_OK;
}

/* Checks that n values of `width` bytes (binary) or >= 2 chars (ASCII) fit. */
static int check_values(vtk_reader *r, long long n, int width, const char *what, int line)
{
    if (r->binary) return pl_io_check_count(r->t, line, n, pl_io_left(r->t), (size_t)width, what);
    return pl_io_check_count(r->t, line, n, pl_io_left(r->t) + 1, 2, what);
}

static int read_points(vtk_reader *r)
{
    pl_text *t = r->t;
    long long n;
    char type[32];
    int line = t->line;
    if (r->have_points) return pl_io_fail(t, "a second POINTS section: expected only one");
    if (pl_io_read_int(t, &n, "the number of POINTS", PL_IO_SAME_LINE)) return PL_EINPUT;
    if (pl_io_token(t, type, sizeof type, PL_IO_SAME_LINE) <= 0)
        return pl_io_fail(t, "expected the POINTS data type (float or double)");
    int width = strcasecmp(type, "float") == 0 ? 4 : strcasecmp(type, "double") == 0 ? 8 : 0;
    if (!width)
        return pl_io_fail(t, "POINTS data type '%s' is not supported: expected float or double",
                          type);
    if (n < 0 || n > INT_MAX / 4)
        return pl_io_fail(t, "POINTS count %lld: expected 0..%d", n, INT_MAX / 4);
    if (end_header_line(t, "POINTS") || check_values(r, 3 * n, width, "point coordinates", line))
        return PL_EINPUT;
    if (pl_io_reserve(&r->b, n, 0, 0)) return pl_io_nomem(t);
    r->have_points = 1;
    const unsigned char *p = NULL;
    size_t bytes = 0;
    if (r->binary && pl_array_bytes((uint64_t)n, 3 * (size_t)width, 0, &bytes))
        return pl_io_fail_at(t, line, "POINTS count %lld is too large", n);
    if (r->binary && take_binary(t, bytes, "POINTS", &p)) return PL_EINPUT;
    for (long long i = 0; i < n; ++i) {
        double x[3];
        for (int a = 0; a < 3; ++a) {
            if (!r->binary) {
                if (pl_io_read_double(t, &x[a], "a point coordinate", PL_IO_ANY_LINE))
                    return PL_EINPUT;
                continue;
            }
            const unsigned char *q = p + (size_t)(3 * i + a) * (size_t)width;
            x[a] = width == 4 ? pl_io_f32(q, 1) : pl_io_f64(q, 1);
            if (!isfinite(x[a]))
                return pl_io_fail_at(t, line, "point %lld has a non-finite coordinate: expected "
                                     "finite numbers", i);
        }
        pl_io_add_vert(&r->b, x[0], x[1], x[2]); /* room was reserved */
    }
    return PL_OK;
}

/* Reads "OFFSETS type" or "CONNECTIVITY type" (VTK 5.x) and its values. */
static int read_51_array(vtk_reader *r, const char *name, long long n, int *out)
{
    pl_text *t = r->t;
    char tok[32], type[32];
    if (pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE) <= 0 || strcasecmp(tok, name) != 0)
        return pl_io_fail(t, "expected %s after CELLS (VTK 5 layout)", name);
    if (pl_io_token(t, type, sizeof type, PL_IO_SAME_LINE) <= 0)
        return pl_io_fail(t, "expected the %s data type", name);
    int width = strcasecmp(type, "vtktypeint64") == 0 ? 8
                : strcasecmp(type, "vtktypeint32") == 0 ? 4 : 0;
    if (!width)
        return pl_io_fail(t, "%s type '%s': expected vtktypeint64 or vtktypeint32", name, type);
    int line = t->line;
    if (end_header_line(t, name) || check_values(r, n, width, name, line)) return PL_EINPUT;
    return read_ints(r, n, width, out, name);
}

/* Reads a cell section into offsets + connectivity: either the classic
 * "n size" then (k, ids...) lists, or the 5.x OFFSETS/CONNECTIVITY arrays. */
static int read_cell_lists(vtk_reader *r, const char *kw, long long *ncells, int **off,
                           int **conn)
{
    pl_text *t = r->t;
    long long n, size;
    int header = t->line;
    if (pl_io_read_int(t, &n, "the number of cells", PL_IO_SAME_LINE) ||
        pl_io_read_int(t, &size, "the size of the cell list", PL_IO_SAME_LINE) ||
        end_header_line(t, kw))
        return PL_EINPUT;
    pl_text probe = *t;
    char tok[32];
    int v5 = pl_io_token(&probe, tok, sizeof tok, PL_IO_ANY_LINE) > 0 &&
             strcasecmp(tok, "OFFSETS") == 0;
    long long nc = v5 ? n - 1 : n, nconn = v5 ? size : size - n;
    if (n < 0 || size < 0 || nc < 0 || nconn < 0)
        return pl_io_fail_at(t, header, "%s counts %lld %lld are inconsistent", kw, n, size);
    if (check_values(r, size, 4, "cell integers", header) || check_values(r, n, 4, "cells", header))
        return PL_EINPUT;
    size_t off_bytes, conn_bytes;
    if (pl_array_bytes((uint64_t)nc + 1, sizeof(int), 0, &off_bytes) ||
        pl_array_bytes((uint64_t)size, sizeof(int), 1, &conn_bytes))
        return pl_io_fail_at(t, header, "%s counts %lld %lld are too large", kw, n, size);
    *off = malloc(off_bytes);
    *conn = malloc(conn_bytes);
    if (!*off || !*conn) return pl_io_nomem(t);
    *ncells = nc;
    if (v5) {
        if (read_51_array(r, "OFFSETS", n, *off) || read_51_array(r, "CONNECTIVITY", size, *conn))
            return PL_EINPUT;
        int bad = (*off)[0] != 0 || (*off)[nc] != size;
        for (long long i = 0; i < nc && !bad; ++i) bad = (*off)[i] > (*off)[i + 1];
        if (bad) return pl_io_fail(t, "%s OFFSETS are not increasing from 0 to %lld", kw, size);
        return PL_OK;
    }
    /* classic layout: read everything, then split the counts out in place */
    int line = t->line;
    if (read_ints(r, size, 4, *conn, "a cell entry")) return PL_EINPUT;
    long long p = 0, q = 0;
    for (long long i = 0; i < n; ++i) {
        if (p >= size)
            return pl_io_fail_at(t, line, "%s declares %lld cells in %lld integers but the list "
                                 "ends after cell %lld", kw, n, size, i);
        long long k = (*conn)[p++];
        if (k > size - p)
            return pl_io_fail_at(t, line, "cell %lld of %s declares %lld points but only %lld "
                                 "integers remain", i, kw, k, size - p);
        (*off)[i] = (int)q;
        memmove(*conn + q, *conn + p, (size_t)k * sizeof(int));
        p += k;
        q += k;
    }
    (*off)[n] = (int)q;
    if (p != size)
        return pl_io_fail_at(t, line, "%s declares a list of %lld integers but its %lld cells use "
                             "%lld", kw, size, n, p);
    return PL_OK;
}

/* Adds cell c (nodes ids[0..k)) of VTK type `type` to the mesh. */
static int add_cell(vtk_reader *r, int type, const int *ids, int k, long long c)
{
    int need = type == 10 ? 4 : type == 5 ? 3 : -1;
    if (need < 0) {
        pl_io_skip_cell(&r->skipped, type);
        return PL_OK;
    }
    if (k != need)
        return pl_io_fail_at(r->t, r->cells_line, "cell %lld is a %s (type %d) with %d points: "
                             "expected %d", c, pl_io_vtk_cell_name(type), type, k, need);
    for (int j = 0; j < k; ++j)
        if (ids[j] >= r->b.m->nverts)
            return pl_io_fail_at(r->t, r->cells_line, "cell %lld uses point %d: expected an "
                                 "index in 0..%d", c, ids[j], r->b.m->nverts - 1);
    int rc = need == 4 ? pl_io_add_tet(&r->b, ids[0], ids[1], ids[2], ids[3])
                       : pl_io_add_tri(&r->b, ids[0], ids[1], ids[2]);
    return rc ? pl_io_nomem(r->t) : PL_OK;
}

static int read_cell_types(vtk_reader *r)
{
    pl_text *t = r->t;
    long long n;
    int line = t->line;
    if (pl_io_read_int(t, &n, "the number of CELL_TYPES", PL_IO_SAME_LINE)) return PL_EINPUT;
    if (!r->off) return pl_io_fail(t, "CELL_TYPES before CELLS: expected CELLS first");
    if (r->have_types) return pl_io_fail(t, "a second CELL_TYPES section: expected only one");
    if (!r->have_points) return pl_io_fail(t, "CELL_TYPES before POINTS: expected POINTS first");
    if (n != r->ncells)
        return pl_io_fail(t, "CELL_TYPES declares %lld cells but CELLS declared %lld", n,
                          r->ncells);
    if (end_header_line(t, "CELL_TYPES") || check_values(r, n, 4, "cell types", line))
        return PL_EINPUT;
    r->have_types = 1;
    size_t bytes;
    int *types = pl_array_bytes((uint64_t)n, sizeof(int), 1, &bytes) ? NULL : malloc(bytes);
    if (!types) return pl_io_nomem(t);
    int rc = read_ints(r, n, 4, types, "a cell type");
    for (long long c = 0; c < n && rc == PL_OK; ++c)
        rc = add_cell(r, types[c], r->conn + r->off[c], r->off[c + 1] - r->off[c], c);
    free(types);
    return rc;
}

/* POLYDATA sections: VERTICES and LINES are skipped, POLYGONS fanned,
 * TRIANGLE_STRIPS unrolled with alternating winding. */
static int read_poly_section(vtk_reader *r, const char *kw)
{
    long long n;
    int *off = NULL, *conn = NULL, rc;
    r->cells_line = r->t->line;
    rc = read_cell_lists(r, kw, &n, &off, &conn);
    int is_strip = strcasecmp(kw, "TRIANGLE_STRIPS") == 0;
    int is_poly = strcasecmp(kw, "POLYGONS") == 0;
    for (long long c = 0; c < n && rc == PL_OK; ++c) {
        const int *ids = conn + off[c];
        int k = off[c + 1] - off[c];
        if (!is_poly && !is_strip) {
            pl_io_skip_cell(&r->skipped, strcasecmp(kw, "LINES") == 0 ? 3 : 1);
            continue;
        }
        if (k < 3) {
            rc = pl_io_fail_at(r->t, r->cells_line, "%s cell %lld has %d points: expected at "
                               "least 3", kw, c, k);
            break;
        }
        for (int j = 0; j + 2 < k && rc == PL_OK; ++j) {
            int fan[3] = {ids[0], ids[j + 1], ids[j + 2]};
            /* strip triangle j is (j, j+1, j+2), every odd one reversed to keep the winding */
            int strip[3] = {ids[j + (j & 1)], ids[j + 1 - (j & 1)], ids[j + 2]};
            rc = add_cell(r, 5, is_strip ? strip : fan, 3, c);
        }
    }
    free(off);
    free(conn);
    return rc;
}

/* FIELD data: "FIELD name n" then n arrays "name ncomp ntuples type". */
static int skip_field(vtk_reader *r)
{
    pl_text *t = r->t;
    char tok[256];
    long long narrays, ncomp, ntup;
    if (pl_io_token(t, tok, sizeof tok, PL_IO_SAME_LINE) <= 0 ||
        pl_io_read_int_range(t, &narrays, 0, 1 << 20, "the number of FIELD arrays",
                             PL_IO_SAME_LINE))
        return pl_io_fail(t, "expected 'FIELD name count'");
    for (long long a = 0; a < narrays; ++a) {
        char type[64];
        if (pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE) <= 0 ||
            pl_io_read_int_range(t, &ncomp, 0, INT_MAX, "components", PL_IO_SAME_LINE) ||
            pl_io_read_int_range(t, &ntup, 0, INT_MAX, "tuples", PL_IO_SAME_LINE) ||
            pl_io_token(t, type, sizeof type, PL_IO_SAME_LINE) <= 0 ||
            end_header_line(t, "FIELD array"))
            return pl_io_fail(t, "expected a FIELD array header 'name ncomp ntuples type'");
        long long n;
        if (pl_mul_i64(ncomp, ntup, &n))
            return pl_io_fail(t, "FIELD array of %lld x %lld values is too large", ncomp, ntup);
        int width = strstr(type, "double") || strstr(type, "long") ? 8
                    : strstr(type, "short") ? 2 : strstr(type, "char") || strstr(type, "bit") ? 1
                    : 4;
        if (check_values(r, n, width, "FIELD values", 0)) return PL_EINPUT;
        const unsigned char *p;
        size_t bytes = 0;
        if (r->binary && pl_array_bytes((uint64_t)n, (size_t)width, 0, &bytes))
            return pl_io_fail(t, "FIELD array of %lld values is too large", n);
        if (r->binary && take_binary(t, bytes, "a FIELD array", &p)) return PL_EINPUT;
        for (long long i = 0; !r->binary && i < n; ++i)
            if (pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE) <= 0)
                return pl_io_fail(t, "FIELD array ends early: expected %lld values", n);
    }
    return PL_OK;
}

/* METADATA blocks end at the first empty line. */
static void skip_metadata(pl_text *t)
{
    pl_io_next_line(t);
    while (t->pos < t->size && !pl_io_at_eol(t)) pl_io_next_line(t);
}

static int read_header(vtk_reader *r, int *polydata)
{
    pl_text *t = r->t;
    char tok[64];
    pl_io_next_line(t); /* "# vtk DataFile Version x.y" */
    pl_io_next_line(t); /* title */
    if (pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE) <= 0)
        return pl_io_fail(t, "expected ASCII or BINARY on line 3");
    if (strcasecmp(tok, "BINARY") == 0) r->binary = 1;
    else if (strcasecmp(tok, "ASCII") != 0)
        return pl_io_fail(t, "expected ASCII or BINARY, found '%s'", tok);
    if (pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE) <= 0 || strcasecmp(tok, "DATASET") != 0)
        return pl_io_fail(t, "expected 'DATASET UNSTRUCTURED_GRID' or 'DATASET POLYDATA'");
    if (pl_io_token(t, tok, sizeof tok, PL_IO_SAME_LINE) <= 0)
        strcpy(tok, "(nothing)");
    *polydata = strcasecmp(tok, "POLYDATA") == 0;
    if (!*polydata && strcasecmp(tok, "UNSTRUCTURED_GRID") != 0)
        return pl_io_fail(t, "DATASET %s is not supported: expected UNSTRUCTURED_GRID or "
                          "POLYDATA", tok);
    return end_header_line(t, "DATASET");
}

static int read_sections(vtk_reader *r, int polydata)
{
    pl_text *t = r->t;
    char kw[64];
    for (;;) {
        int len = pl_io_token(t, kw, sizeof kw, PL_IO_ANY_LINE);
        if (len == 0) return PL_OK;
        if (len < 0) return pl_io_fail(t, "expected a VTK keyword, found an overlong token");
        int rc;
        if (strcasecmp(kw, "POINTS") == 0) rc = read_points(r);
        else if (strcasecmp(kw, "FIELD") == 0) rc = skip_field(r);
        else if (strcasecmp(kw, "METADATA") == 0) skip_metadata(t), rc = PL_OK;
        else if (strcasecmp(kw, "POINT_DATA") == 0 || strcasecmp(kw, "CELL_DATA") == 0)
            return PL_OK; /* attributes follow: nothing the mesh needs */
        else if (!polydata && strcasecmp(kw, "CELLS") == 0) {
            if (r->off) return pl_io_fail(t, "a second CELLS section: expected only one");
            r->cells_line = t->line;
            rc = read_cell_lists(r, "CELLS", &r->ncells, &r->off, &r->conn);
        } else if (!polydata && strcasecmp(kw, "CELL_TYPES") == 0) rc = read_cell_types(r);
        else if (polydata && (strcasecmp(kw, "VERTICES") == 0 || strcasecmp(kw, "LINES") == 0 ||
                              strcasecmp(kw, "POLYGONS") == 0 ||
                              strcasecmp(kw, "TRIANGLE_STRIPS") == 0)) {
            if (!r->have_points) return pl_io_fail(t, "%s before POINTS: expected POINTS first", kw);
            rc = read_poly_section(r, kw);
        } else
            return pl_io_fail(t, "unexpected '%s': expected POINTS, %s, POINT_DATA or CELL_DATA",
                              kw, polydata ? "VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS"
                                           : "CELLS, CELL_TYPES");
        if (rc) return rc;
    }
}

int pl_io_load_vtk_legacy(pl_text *t, pl_mesh *out)
{
    vtk_reader *r = calloc(1, sizeof *r); /* pl_io_skipped is a few kB: keep it off the stack */
    if (!r) return pl_io_nomem(t);
    r->t = t;
    pl_io_build_init(&r->b, out);
    int polydata = 0;
    int rc = read_header(r, &polydata);
    if (rc == PL_OK) rc = read_sections(r, polydata);
    if (rc == PL_OK && !r->have_points) rc = pl_io_fail(t, "no POINTS section found");
    if (rc == PL_OK && !polydata && r->off && !r->have_types)
        rc = pl_io_fail(t, "CELLS without CELL_TYPES: expected a CELL_TYPES section");
    if (rc == PL_OK) pl_io_report_skipped(t, &r->skipped, "VTK", pl_io_vtk_cell_name, out);
    free(r->off);
    free(r->conn);
    free(r);
    return rc;
}
