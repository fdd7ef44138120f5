/* obj.c - Wavefront OBJ: "v x y z" vertices and "f" faces whose corners
 * may be i, i/t, i//n or i/t/n, with 1-based or negative (relative)
 * indices.  Quads and polygons are fan-triangulated.  Texture coordinates,
 * normals, groups and materials are not needed and are ignored; lines and
 * points are counted and reported. */
#include "mesh_io.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct obj_reader {
    pl_text *t;
    pl_mesh_build b;
    long long max_index; /* largest positive index seen, with its line */
    int max_line;
    long long lines, points, unknown;
    int unknown_line;
    char unknown_word[32];
} obj_reader;

static int read_vertex(obj_reader *r)
{
    double x[3];
    pl_text *t = r->t;
    if (pl_io_read_double(t, &x[0], "the vertex x", PL_IO_SAME_LINE) ||
        pl_io_read_double(t, &x[1], "the vertex y", PL_IO_SAME_LINE) ||
        pl_io_read_double(t, &x[2], "the vertex z", PL_IO_SAME_LINE))
        return PL_EINPUT;
    if (r->b.m->nverts >= INT_MAX / 4) return pl_io_fail(t, "too many vertices");
    /* a w component or vertex colours may follow: not needed */
    return pl_io_add_vert(&r->b, x[0], x[1], x[2]) ? pl_io_nomem(t) : PL_OK;
}

/* Parses one face corner "i[/t][/n]" into a 0-based vertex index. */
static int read_corner(obj_reader *r, const char *tok, int *index)
{
    pl_text *t = r->t;
    char head[64];
    size_t n = strcspn(tok, "/");
    memcpy(head, tok, n);
    head[n] = '\0';
    long long i;
    if (pl_io_parse_int(head, &i))
        return pl_io_fail(t, "face corner '%s': expected a vertex index such as 3, 3/1, 3//2 "
                          "or -1", tok);
    long long nv = r->b.m->nverts;
    if (i == 0) return pl_io_fail(t, "face uses vertex index 0: OBJ indices start at 1");
    if (i < 0) {
        if (-i > nv)
            return pl_io_fail(t, "face uses relative index %lld but only %lld vertices are "
                              "defined so far", i, nv);
        i = nv + i;
    } else {
        if (i > INT_MAX / 4) return pl_io_fail(t, "face uses vertex %lld: out of range", i);
        if (i > r->max_index) { /* a forward reference is checked at the end */
            r->max_index = i;
            r->max_line = t->line;
        }
        i -= 1;
    }
    *index = (int)i;
    return PL_OK;
}

static int read_face(obj_reader *r)
{
    pl_text *t = r->t;
    char tok[64];
    int first = -1, prev = -1, k = 0, len;
    while ((len = pl_io_token(t, tok, sizeof tok, PL_IO_SAME_LINE)) != 0) {
        int v = -1;
        if (len < 0) return pl_io_fail(t, "overlong face corner");
        if (tok[0] == '#') { /* a trailing comment ends the face */
            while (t->pos < t->size && t->buf[t->pos] != '\n') t->pos++;
            break;
        }
        if (read_corner(r, tok, &v)) return PL_EINPUT;
        if (k == 0) first = v;
        else if (k >= 2 && pl_io_add_tri(&r->b, first, prev, v)) return pl_io_nomem(t);
        prev = v;
        k++;
    }
    if (k < 3) return pl_io_fail(t, "face with %d corners: expected at least 3", k);
    return PL_OK;
}

/* Dispatches one statement; t is right after its keyword. */
static int statement(obj_reader *r, const char *kw)
{
    if (strcmp(kw, "v") == 0) return read_vertex(r);
    if (strcmp(kw, "f") == 0) return read_face(r);
    if (strcmp(kw, "l") == 0) r->lines++;
    else if (strcmp(kw, "p") == 0) r->points++;
    else if (strcmp(kw, "vt") && strcmp(kw, "vn") && strcmp(kw, "vp") && strcmp(kw, "o") &&
             strcmp(kw, "g") && strcmp(kw, "s") && strcmp(kw, "usemtl") &&
             strcmp(kw, "mtllib") && strcmp(kw, "mg") && strcmp(kw, "lod")) {
        if (!r->unknown++) {
            r->unknown_line = r->t->line;
            snprintf(r->unknown_word, sizeof r->unknown_word, "%s", kw);
        }
    }
    return PL_OK;
}

int pl_io_load_obj(pl_text *t, pl_mesh *out)
{
    obj_reader r;
    memset(&r, 0, sizeof r);
    r.t = t;
    pl_io_build_init(&r.b, out);
    char kw[32];
    while (!pl_io_at_eof(t)) {
        if (t->buf[t->pos] == '#') { /* a comment line */
            pl_io_next_line(t);
            continue;
        }
        int n = pl_io_token(t, kw, sizeof kw, PL_IO_SAME_LINE);
        if (n > 0 && statement(&r, kw)) return PL_EINPUT;
        if (n < 0 && !r.unknown++) {
            r.unknown_line = t->line;
            strcpy(r.unknown_word, "(overlong)");
        }
        pl_io_next_line(t);
    }
    if (r.max_index > out->nverts)
        return pl_io_fail_at(t, r.max_line, "face uses vertex %lld but the file defines only %d "
                             "vertices", r.max_index, out->nverts);
    if (r.lines || r.points)
        pl_diag_warn(t->diag, t->path, 0, NULL, "skipped %lld line and %lld point statements; "
                     "kept %d triangles", r.lines, r.points, out->ntris);
    if (r.unknown)
        pl_diag_warn(t->diag, t->path, r.unknown_line, NULL, "ignored %lld statements of "
                     "unknown kinds, the first being '%s'", r.unknown, r.unknown_word);
    return PL_OK;
}
