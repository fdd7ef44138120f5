/* stl.c - STL, ASCII ("solid ... facet ... endsolid") and binary (80-byte
 * header, little-endian triangle count, 50 bytes per triangle).
 *
 * STL stores three positions per triangle and no connectivity, so
 * identical positions are welded into one vertex (exact comparison, with
 * -0 equal to +0).  Triangles that collapse when welded are dropped and
 * reported. */
#include "mesh_io.h"

#include "pliant/checked.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static uint64_t hash_point(const double *p)
{
    uint64_t h = 1469598103934665603ULL;
    for (int a = 0; a < 3; ++a) {
        uint64_t u;
        memcpy(&u, &p[a], sizeof u);
        h = (h ^ u) * 1099511628211ULL;
        h ^= h >> 29;
    }
    return h;
}

/* Welds ntri*3 corner positions into out's vertices and triangles. */
static int weld(pl_text *t, double *corners, long long ntri, pl_mesh *out)
{
    long long ncorner = 3 * ntri;
    size_t cap = 16;
    while (cap < 2 * (size_t)ncorner) cap *= 2;
    int *slot = malloc(cap * sizeof *slot);
    pl_mesh_build b;
    pl_io_build_init(&b, out);
    if (!slot || pl_io_reserve(&b, 0, 0, ntri)) {
        free(slot);
        return pl_io_nomem(t);
    }
    memset(slot, 0xff, cap * sizeof *slot); /* -1: empty */
    int *corner_vert = malloc((size_t)ncorner * sizeof *corner_vert + 1);
    if (!corner_vert) {
        free(slot);
        return pl_io_nomem(t);
    }
    for (long long c = 0; c < ncorner; ++c) {
        double *p = corners + 3 * c;
        for (int a = 0; a < 3; ++a) p[a] += 0.0; /* -0 + 0 == +0: one key for both zeros */
        size_t h = (size_t)hash_point(p) & (cap - 1);
        while (slot[h] >= 0 && memcmp(out->verts + 3 * (size_t)slot[h], p, 3 * sizeof *p))
            h = (h + 1) & (cap - 1);
        if (slot[h] < 0) {
            slot[h] = out->nverts;
            if (pl_io_add_vert(&b, p[0], p[1], p[2])) {
                free(slot);
                free(corner_vert);
                return pl_io_nomem(t);
            }
        }
        corner_vert[c] = slot[h];
    }
    long long dropped = 0;
    for (long long f = 0; f < ntri; ++f) {
        const int *v = corner_vert + 3 * f;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) dropped++;
        else pl_io_add_tri(&b, v[0], v[1], v[2]); /* reserved above */
    }
    free(slot);
    free(corner_vert);
    if (dropped)
        pl_diag_warn(t->diag, t->path, 0, NULL, "dropped %lld of %lld triangles whose corners "
                     "coincide", dropped, ntri);
    return PL_OK;
}

int pl_io_load_stl_binary(pl_text *t, pl_mesh *out)
{
    const unsigned char *p = (const unsigned char *)t->buf;
    if (t->size < 84) /* the count sits at bytes 80..83 */
        return pl_io_fail_at(t, 0, "binary STL of %zu bytes: expected at least the 84-byte "
                             "header", t->size);
    uint64_t ntri = pl_io_u32(p + 80, 0), want;
    if (pl_muladd_u64(50, ntri, 84, &want) || want != (uint64_t)t->size)
        return pl_io_fail_at(t, 0, "binary STL of %zu bytes declares %llu triangles: expected "
                             "84 + 50 * count bytes", t->size, (unsigned long long)ntri);
    size_t bytes;
    if (ntri > INT_MAX / 12 || pl_array_bytes(ntri, 9 * sizeof(double), 1, &bytes))
        return pl_io_fail_at(t, 0, "too many triangles (%llu)", (unsigned long long)ntri);
    double *corners = malloc(bytes);
    if (!corners) return pl_io_nomem(t);
    for (long long f = 0; f < (long long)ntri; ++f) {
        const unsigned char *q = p + 84 + 50 * f + 12; /* skip the facet normal */
        for (int k = 0; k < 9; ++k) {
            double x = pl_io_f32(q + 4 * k, 0);
            if (!isfinite(x)) {
                free(corners);
                return pl_io_fail_at(t, 0, "triangle %lld has a non-finite coordinate: expected "
                                     "finite numbers", f);
            }
            corners[9 * f + k] = x;
        }
    }
    int rc = weld(t, corners, (long long)ntri, out);
    free(corners);
    return rc;
}

/* Reads the next keyword and checks it is `want`. */
static int expect(pl_text *t, const char *want, const char *context)
{
    char tok[64];
    int n = pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE);
    if (n > 0 && strcasecmp(tok, want) == 0) return PL_OK;
    return pl_io_fail(t, "expected '%s' %s, found '%s'", want, context,
                      n > 0 ? tok : n == 0 ? "end of file" : "an overlong token");
}

/* One "facet normal n n n outer loop vertex x3 endloop endfacet". */
static int read_facet(pl_text *t, double *corner)
{
    double nrm;
    if (expect(t, "normal", "after 'facet'")) return PL_EINPUT;
    for (int a = 0; a < 3; ++a)
        if (pl_io_read_double(t, &nrm, "a normal component", PL_IO_SAME_LINE)) return PL_EINPUT;
    if (expect(t, "outer", "to open the facet's loop") || expect(t, "loop", "after 'outer'"))
        return PL_EINPUT;
    for (int k = 0; k < 3; ++k) {
        if (expect(t, "vertex", k ? "(a facet has three vertices)" : "in the loop"))
            return PL_EINPUT;
        for (int a = 0; a < 3; ++a)
            if (pl_io_read_double(t, &corner[3 * k + a], "a vertex coordinate", PL_IO_SAME_LINE))
                return PL_EINPUT;
    }
    if (expect(t, "endloop", "after three vertices") || expect(t, "endfacet", "after 'endloop'"))
        return PL_EINPUT;
    return PL_OK;
}

int pl_io_load_stl_ascii(pl_text *t, pl_mesh *out)
{
    double *corners = NULL;
    long long ntri = 0, cap = 0;
    int rc = PL_OK, in_solid = 0;
    char tok[64];
    for (;;) {
        int n = pl_io_token(t, tok, sizeof tok, PL_IO_ANY_LINE);
        if (n == 0) break;
        if (!in_solid && n > 0 && strcasecmp(tok, "solid") == 0) {
            in_solid = 1;
            pl_io_next_line(t); /* the solid's name */
        } else if (in_solid && n > 0 && strcasecmp(tok, "endsolid") == 0) {
            in_solid = 0;
            pl_io_next_line(t);
        } else if (in_solid && n > 0 && strcasecmp(tok, "facet") == 0) {
            if (ntri == cap) {
                cap = cap ? 2 * cap : 256;
                double *c = cap <= INT_MAX / 12 ? realloc(corners, (size_t)cap * 9 * sizeof *c)
                                                : NULL;
                if (!c) {
                    rc = pl_io_nomem(t);
                    break;
                }
                corners = c;
            }
            if ((rc = read_facet(t, corners + 9 * ntri))) break;
            ntri++;
        } else {
            rc = pl_io_fail(t, "expected %s, found '%s'",
                            in_solid ? "'facet' or 'endsolid'" : "'solid' or the end of the file",
                            n > 0 ? tok : "an overlong token");
            break;
        }
    }
    if (rc == PL_OK && in_solid) rc = pl_io_fail(t, "unexpected end of file: expected 'endsolid'");
    if (rc == PL_OK) rc = weld(t, corners, ntri, out);
    free(corners);
    return rc;
}
