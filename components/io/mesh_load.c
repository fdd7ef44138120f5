/* mesh_load.c - pl_mesh_load: reads a file, recognises its format from the
 * content (never the extension: SOFA ships VTU XML under .vtk names),
 * dispatches to the format reader, then validates, fixes inverted
 * tetrahedra and optionally drops unused vertices. */
#include "mesh_io.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The same numbers as pl_mesh_format (FMT_UNKNOWN = PL_MESH_AUTO). */
typedef enum {
    FMT_UNKNOWN = PL_MESH_AUTO,
    FMT_VTK_LEGACY = PL_MESH_VTK_LEGACY,
    FMT_VTU = PL_MESH_VTU,
    FMT_GMSH = PL_MESH_GMSH,
    FMT_OBJ = PL_MESH_OBJ,
    FMT_STL_ASCII = PL_MESH_STL_ASCII,
    FMT_STL_BINARY = PL_MESH_STL_BINARY
} mesh_format;

static int starts_with(const char *p, size_t n, const char *word)
{
    size_t k = strlen(word);
    return n >= k && memcmp(p, word, k) == 0;
}

/* OBJ has no magic: the first line that is neither blank nor a comment must
 * begin with an OBJ statement, and the start of the file must be text. */
static int looks_like_obj(const char *p, size_t n)
{
    static const char *const words[] = {"v",      "vt", "vn", "vp", "f", "l", "p", "o", "g",
                                        "s",      "mtllib", "usemtl", "cstype", "deg", NULL};
    size_t probe = n < 4096 ? n : 4096;
    if (memchr(p, '\0', probe)) return 0; /* binary bytes */
    size_t i = 0;
    while (i < n) {
        while (i < n && isspace((unsigned char)p[i])) i++;
        if (i >= n) return 0;
        if (p[i] == '#') {
            const char *nl = memchr(p + i, '\n', n - i);
            if (!nl) return 0;
            i = (size_t)(nl - p) + 1;
            continue;
        }
        size_t k = i;
        while (k < n && !isspace((unsigned char)p[k])) k++;
        if (k >= n) return 0;
        for (int w = 0; words[w]; ++w)
            if (k - i == strlen(words[w]) && memcmp(p + i, words[w], k - i) == 0) return 1;
        return 0;
    }
    return 0;
}

static mesh_format sniff(const char *buf, size_t size)
{
    const char *p = buf;
    size_t n = size;
    if (starts_with(p, n, "\xEF\xBB\xBF")) { /* UTF-8 byte order mark */
        p += 3;
        n -= 3;
    }
    /* A binary STL's size is exactly 84 + 50 * (its triangle count); test it
     * before any text magic because many binary headers begin with "solid". */
    if (size >= 84) {
        unsigned long long ntri = pl_io_u32((const unsigned char *)buf + 80, 0);
        if (84 + 50 * ntri == size) return FMT_STL_BINARY;
    }
    while (n > 0 && isspace((unsigned char)*p)) {
        p++;
        n--;
    }
    if (starts_with(p, n, "# vtk DataFile")) return FMT_VTK_LEGACY;
    if (starts_with(p, n, "<?xml") || starts_with(p, n, "<VTKFile")) return FMT_VTU;
    if (starts_with(p, n, "$MeshFormat") || starts_with(p, n, "$NOD") ||
        starts_with(p, n, "$PhysicalNames") || starts_with(p, n, "$Comments"))
        return FMT_GMSH;
    if (starts_with(p, n, "solid") && (n == 5 || isspace((unsigned char)p[5])))
        return FMT_STL_ASCII;
    if (looks_like_obj(p, n)) return FMT_OBJ;
    return FMT_UNKNOWN;
}

/* Says what kind of bytes an unrecognised file starts with, without
 * quoting them: the name of a file that is not a mesh (a scene's
 * filename="/etc/passwd") must not turn the error message into a way to
 * read it. */
static const char *describe(const char *buf, size_t size)
{
    size_t probe = size < 512 ? size : 512;
    for (size_t i = 0; i < probe; ++i) {
        unsigned char c = (unsigned char)buf[i];
        if (c < 0x20 && c != '\n' && c != '\r' && c != '\t') return "binary data";
    }
    return "text";
}

static int dispatch(mesh_format f, pl_text *t, pl_mesh *out)
{
    switch (f) {
    case FMT_VTK_LEGACY: return pl_io_load_vtk_legacy(t, out);
    case FMT_VTU: return pl_io_load_vtu(t, out);
    case FMT_GMSH: return pl_io_load_gmsh(t, out);
    case FMT_OBJ: return pl_io_load_obj(t, out);
    case FMT_STL_ASCII: return pl_io_load_stl_ascii(t, out);
    case FMT_STL_BINARY: return pl_io_load_stl_binary(t, out);
    default: break;
    }
    char stl[160] = "";
    if (t->size >= 84) { /* a truncated binary STL lands here: give the numbers */
        unsigned long long n = pl_io_u32((const unsigned char *)t->buf + 80, 0);
        snprintf(stl, sizeof stl, " (read as a binary STL it declares %llu triangles, which "
                 "need %llu bytes; the file has %zu)", n, 84 + 50 * n, t->size);
    }
    return pl_io_fail_at(t, 1,
                         "unrecognised mesh format (the file holds %s): expected legacy VTK "
                         "('# vtk DataFile'), VTU XML ('<VTKFile'), Gmsh ('$MeshFormat' or "
                         "'$NOD'), STL ('solid ...' or binary of 84+50n bytes) or OBJ "
                         "('v x y z' / 'f i j k' lines)%s",
                         describe(t->buf, t->size), stl);
}

/* Counts tetrahedra whose volume is negligible against the mesh size:
 * they make element matrices singular, so the user should hear of them. */
static int count_degenerate(const pl_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < m->nverts; ++i)
        for (int a = 0; a < 3; ++a) {
            double x = m->verts[3 * (size_t)i + a];
            lo[a] = x < lo[a] ? x : lo[a];
            hi[a] = x > hi[a] ? x : hi[a];
        }
    double L = 0;
    for (int a = 0; a < 3 && m->nverts; ++a) L = fmax(L, hi[a] - lo[a]);
    double tiny = 1e-14 * L * L * L;
    int n = 0;
    for (int i = 0; i < m->ntets; ++i) {
        const int *t = m->tets + 4 * (size_t)i;
        const double *a = m->verts + 3 * (size_t)t[0];
        double e[3][3];
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) e[k][c] = m->verts[3 * (size_t)t[k + 1] + c] - a[c];
        double v6 = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                    e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                    e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
        if (fabs(v6) <= tiny) n++;
    }
    return n;
}

/* Vertices that no element uses (-1 if out of memory); indices are valid. */
static int count_unused(const pl_mesh *m)
{
    if (m->nverts == 0) return 0;
    char *used = calloc((size_t)m->nverts, 1);
    if (!used) return -1;
    for (size_t k = 0; k < 4 * (size_t)m->ntets; ++k) used[m->tets[k]] = 1;
    for (size_t k = 0; k < 3 * (size_t)m->ntris; ++k) used[m->tris[k]] = 1;
    int n = 0;
    for (int i = 0; i < m->nverts; ++i) n += !used[i];
    free(used);
    return n;
}

/* Validation and clean-up shared by every format. */
static int finish(const char *path, const pl_mesh_load_options *opt, pl_mesh *m, pl_diag *diag)
{
    if (pl_mesh_validate(m, path, diag)) return PL_EINPUT;
    if (m->ntets == 0 && m->ntris == 0)
        return pl_diag_error(diag, PL_EINPUT, path, 0, NULL,
                             "the file holds %d vertices but no tetrahedra or triangles: "
                             "expected a volume or surface mesh",
                             m->nverts);
    if (!opt || !opt->keep_inverted) {
        int flipped = pl_mesh_fix_inverted(m);
        if (flipped)
            pl_diag_warn(diag, path, 0, NULL,
                         "%d of %d tetrahedra were inverted (negative volume) and have been "
                         "flipped",
                         flipped, m->ntets);
    }
    int degenerate = count_degenerate(m);
    if (degenerate)
        pl_diag_warn(diag, path, 0, NULL, "%d tetrahedra have (nearly) zero volume",
                     degenerate);
    if (opt && opt->drop_unused) {
        if (pl_mesh_drop_unused(m) < 0)
            return pl_diag_error(diag, PL_EINTERNAL, path, 0, NULL,
                                 "out of memory dropping unused vertices");
        return PL_OK;
    }
    int unused = count_unused(m);
    if (unused < 0) return pl_diag_error(diag, PL_EINTERNAL, path, 0, NULL, "out of memory");
    if (unused)
        pl_diag_warn(diag, path, 0, NULL,
                     "%d of %d vertices belong to no element (they need a mass or a fixed "
                     "constraint; the drop_unused option removes them)",
                     unused, m->nverts);
    return PL_OK;
}

/* Reads buf (size bytes, buf[size] == '\0') as a mesh named `name`. */
static int load_text(const char *name, const char *buf, size_t size,
                     const pl_mesh_load_options *opt, pl_mesh *out, pl_diag *diag)
{
    if (size == 0)
        return pl_diag_error(diag, PL_EINPUT, name, 0, NULL,
                             "empty file: expected a mesh (VTK, VTU, Gmsh, OBJ or STL)");
    pl_text t;
    pl_io_text_init(&t, name, buf, size, 1, diag);
    pl_mesh m;
    pl_mesh_init(&m);
    if (opt && (opt->format < PL_MESH_AUTO || opt->format > PL_MESH_STL_BINARY))
        return pl_diag_error(diag, PL_EINTERNAL, name, 0, NULL, "unknown mesh format %d",
                             (int)opt->format);
    mesh_format f = opt && opt->format ? (mesh_format)opt->format : sniff(buf, size);
    int rc = dispatch(f, &t, &m);
    if (rc == PL_OK) rc = finish(name, opt, &m, diag);
    if (rc) {
        pl_mesh_free(&m);
        return rc;
    }
    *out = m;
    return PL_OK;
}

int pl_mesh_load(const char *path, const pl_mesh_load_options *opt, pl_mesh *out, pl_diag *diag)
{
    if (!out) return pl_diag_error(diag, PL_EINTERNAL, path, 0, NULL, "no output mesh given");
    pl_mesh_init(out);
    if (!path || !*path)
        return pl_diag_error(diag, PL_EINPUT, NULL, 0, NULL, "no mesh file name given");
    char *buf;
    size_t size;
    int rc = pl_io_read_file(path, &buf, &size, diag);
    if (rc) return rc;
    rc = load_text(path, buf, size, opt, out, diag);
    free(buf);
    return rc;
}

int pl_mesh_load_buffer(const char *name, const void *buf, size_t size,
                        const pl_mesh_load_options *opt, pl_mesh *out, pl_diag *diag)
{
    if (!out) return pl_diag_error(diag, PL_EINTERNAL, name, 0, NULL, "no output mesh given");
    pl_mesh_init(out);
    if (!buf && size) return pl_diag_error(diag, PL_EINTERNAL, name, 0, NULL, "no buffer given");
    if (size > PL_IO_MAX_FILE)
        return pl_diag_error(diag, PL_EINPUT, name, 0, NULL, "mesh of %zu bytes is too large: "
                             "meshes up to %zu bytes are read", size, (size_t)PL_IO_MAX_FILE);
    char *copy = malloc(size + 1); /* the readers rely on a terminating NUL */
    if (!copy) return pl_diag_error(diag, PL_EINTERNAL, name, 0, NULL, "out of memory");
    if (size) memcpy(copy, buf, size);
    copy[size] = '\0';
    int rc = load_text(name ? name : "<buffer>", copy, size, opt, out, diag);
    free(copy);
    return rc;
}
