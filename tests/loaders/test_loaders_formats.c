/* test_loaders_formats.c - format variants the shipped meshes do not cover,
 * written by the test itself from a generated box and read back: the
 * loaded mesh must equal the one written (bit for bit where the format
 * stores doubles).  Covers VTK 5.x OFFSETS/CONNECTIVITY, POLYDATA polygons
 * and strips, VTU binary (both header layouts, UInt32/UInt64, both byte
 * orders, zlib blocks, several pieces), Gmsh v1/v2/v4.1 with sparse node
 * tags, OBJ corner forms, STL ASCII and binary. */
#include "loader_test_util.h"

#include <stdarg.h>
#include <stdint.h>
#include <zlib.h>

#include "generators/generators.h"

/* A growing string. */
typedef struct sbuf {
    char *p;
    size_t n, cap;
} sbuf;

static void sb_add(sbuf *s, const void *data, size_t n)
{
    if (s->n + n + 1 > s->cap) {
        s->cap = 2 * (s->n + n + 1);
        s->p = realloc(s->p, s->cap);
        ck_assert_ptr_nonnull(s->p);
    }
    memcpy(s->p + s->n, data, n);
    s->n += n;
    s->p[s->n] = '\0';
}

static void sb_printf(sbuf *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void sb_printf(sbuf *s, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    ck_assert(n >= 0 && (size_t)n < sizeof tmp);
    sb_add(s, tmp, (size_t)n);
}

static pl_mesh box(int n)
{
    pl_mesh m;
    const int dims[3] = {n, n + 1, n};
    const double lo[3] = {-1, 0, 0.25}, hi[3] = {1, 3, 0.75};
    ck_assert_int_eq(pl_generate_box_tets(dims, lo, hi, &m, NULL), PL_OK);
    return m;
}

static pl_mesh load(const char *path, pl_diag *d)
{
    pl_mesh m;
    pl_diag_init(d);
    int rc = pl_mesh_load(path, NULL, &m, d);
    if (rc) pl_diag_print(d, stderr);
    ck_assert_int_eq(rc, PL_OK);
    return m;
}

/* Same counts, same connectivity, coordinates within tol. */
static void assert_same(const pl_mesh *a, const pl_mesh *b, double tol)
{
    ck_assert_int_eq(a->nverts, b->nverts);
    ck_assert_int_eq(a->ntets, b->ntets);
    ck_assert_int_eq(a->ntris, b->ntris);
    for (int i = 0; i < 3 * a->nverts; ++i)
        ck_assert_msg(fabs(a->verts[i] - b->verts[i]) <= tol, "coordinate %d: %.17g vs %.17g", i,
                      a->verts[i], b->verts[i]);
    if (a->ntets) ck_assert_int_eq(memcmp(a->tets, b->tets, 16 * (size_t)a->ntets), 0);
    if (a->ntris) ck_assert_int_eq(memcmp(a->tris, b->tris, 12 * (size_t)a->ntris), 0);
}

static void put_uint(unsigned char *dst, uint64_t v, int size, int big)
{
    for (int k = 0; k < size; ++k) dst[big ? size - 1 - k : k] = (unsigned char)(v >> (8 * k));
}

static void b64(sbuf *s, const unsigned char *p, size_t n)
{
    static const char *abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)p[i] << 16 | (i + 1 < n ? (unsigned)p[i + 1] << 8 : 0) |
                     (i + 2 < n ? p[i + 2] : 0);
        char q[4] = {abc[v >> 18], abc[(v >> 12) & 63], i + 1 < n ? abc[(v >> 6) & 63] : '=',
                     i + 2 < n ? abc[v & 63] : '='};
        sb_add(s, q, 4);
    }
}

typedef struct vtu_style {
    int big, header64, separate, zlib_block; /* zlib_block > 0: compress in blocks of that size */
} vtu_style;

/* Writes one binary DataArray body (raw bytes already in file byte order). */
static void vtu_binary(sbuf *s, const vtu_style *st, const unsigned char *raw, size_t n)
{
    int hs = st->header64 ? 8 : 4;
    if (!st->zlib_block) {
        unsigned char *all = malloc(n + 8);
        put_uint(all, n, hs, st->big);
        memcpy(all + hs, raw, n);
        if (st->separate) {
            b64(s, all, (size_t)hs);
            b64(s, raw, n);
        } else
            b64(s, all, n + (size_t)hs);
        free(all);
        return;
    }
    size_t bs = (size_t)st->zlib_block, nb = (n + bs - 1) / bs;
    unsigned char *head = calloc(3 + nb, 8), *data = malloc(nb * compressBound(bs) + 1);
    size_t used = 0;
    put_uint(head, nb, hs, st->big);
    put_uint(head + hs, bs, hs, st->big);
    put_uint(head + 2 * hs, n % bs, hs, st->big);
    for (size_t b = 0; b < nb; ++b) {
        uLongf cl = compressBound(bs);
        size_t len = b + 1 < nb || n % bs == 0 ? bs : n % bs;
        ck_assert_int_eq(compress2(data + used, &cl, raw + b * bs, len, 6), Z_OK);
        put_uint(head + (3 + b) * hs, cl, hs, st->big);
        used += cl;
    }
    if (st->separate) {
        b64(s, head, (3 + nb) * hs);
        b64(s, data, used);
    } else {
        unsigned char *all = malloc((3 + nb) * hs + used);
        memcpy(all, head, (3 + nb) * hs);
        memcpy(all + (3 + nb) * hs, data, used);
        b64(s, all, (3 + nb) * hs + used);
        free(all);
    }
    free(head);
    free(data);
}

/* A binary DataArray of n values of `size` bytes; values as uint64 bit patterns. */
static void vtu_array(sbuf *s, const vtu_style *st, const char *type, const char *name, int ncomp,
                      const uint64_t *vals, size_t n, int size)
{
    unsigned char *raw = malloc(n * (size_t)size + 1);
    for (size_t i = 0; i < n; ++i) put_uint(raw + i * (size_t)size, vals[i], size, st->big);
    sb_printf(s, "<DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"binary\">\n",
              type, name, ncomp);
    vtu_binary(s, st, raw, n * (size_t)size);
    sb_printf(s, "\n</DataArray>\n");
    free(raw);
}

static void vtu_piece(sbuf *s, const vtu_style *st, const pl_mesh *m)
{
    size_t nv = 3 * (size_t)m->nverts, nc = 4 * (size_t)m->ntets;
    uint64_t *v = malloc((nv + nc + 1) * sizeof *v);
    sb_printf(s, "<Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n<Points>\n", m->nverts,
              m->ntets);
    for (size_t i = 0; i < nv; ++i) memcpy(&v[i], &m->verts[i], 8);
    vtu_array(s, st, "Float64", "Points", 3, v, nv, 8);
    sb_printf(s, "</Points>\n<Cells>\n");
    for (size_t i = 0; i < nc; ++i) v[i] = (uint64_t)m->tets[i];
    vtu_array(s, st, "Int64", "connectivity", 1, v, nc, 8);
    for (int c = 0; c < m->ntets; ++c) v[c] = 4 * (uint64_t)(c + 1);
    vtu_array(s, st, "Int32", "offsets", 1, v, (size_t)m->ntets, 4);
    for (int c = 0; c < m->ntets; ++c) v[c] = 10;
    vtu_array(s, st, "UInt8", "types", 1, v, (size_t)m->ntets, 1);
    sb_printf(s, "</Cells>\n</Piece>\n");
    free(v);
}

START_TEST(vtu_binary_variants_read_back_exactly)
{
    static const vtu_style styles[] = {
        {0, 0, 0, 0}, {1, 0, 1, 0}, {0, 1, 0, 0}, {1, 1, 1, 0},
        {0, 0, 1, 256}, {1, 1, 1, 100}, {0, 1, 0, 64}, {1, 0, 0, 1 << 20}};
    pl_mesh m = box(4);
    for (size_t k = 0; k < sizeof styles / sizeof *styles; ++k) {
        const vtu_style *st = &styles[k];
        sbuf s = {0};
        sb_printf(&s, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                      "byte_order=\"%s\" header_type=\"%s\"%s>\n<UnstructuredGrid>\n",
                  st->big ? "BigEndian" : "LittleEndian", st->header64 ? "UInt64" : "UInt32",
                  st->zlib_block ? " compressor=\"vtkZLibDataCompressor\"" : "");
        vtu_piece(&s, st, &m);
        sb_printf(&s, "</UnstructuredGrid>\n</VTKFile>\n");
        pl_diag d;
        pl_mesh r = load(tu_write("box.vtu", s.p, s.n), &d);
        assert_same(&m, &r, 0);
        ck_assert_int_eq(d.count, 0);
        pl_mesh_free(&r);
        pl_diag_free(&d);
        free(s.p);
    }
    pl_mesh_free(&m);
    tu_cleanup();
}
END_TEST

START_TEST(vtu_written_by_vtk9_with_information_keys)
{
    /* What VTK 9's vtkXMLUnstructuredGridWriter writes for a unit square of two
     * triangles (zlib, header and blocks base64-encoded separately, and an
     * <InformationKey> with numbers of its own nested in the Points array). */
    const char *vtu =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">\n"
        "<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">\n<PointData>\n"
        "</PointData>\n<CellData>\n</CellData>\n<Points>\n<DataArray type=\"Float32\" "
        "Name=\"Points\" NumberOfComponents=\"3\" format=\"binary\" RangeMin=\"0\" "
        "RangeMax=\"1.4142135623730951\">\nAQAAAACAAAAwAAAAFQAAAA==eAFjYEAGDfYIHoiNzmdgAAA65AL9\n"
        "<InformationKey name=\"L2_NORM_RANGE\" location=\"vtkDataArray\" length=\"2\">\n"
        "<Value index=\"0\">\n0\n</Value>\n<Value index=\"1\">\n1.4142135624\n</Value>\n"
        "</InformationKey>\n</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" "
        "Name=\"connectivity\" format=\"binary\" RangeMin=\"0\" RangeMax=\"3\">\n"
        "AQAAAACAAAAwAAAAFQAAAA==eAFjYIAARijNhEYzQ/kwCgAA+AAJ\n</DataArray>\n"
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\" RangeMin=\"3\" "
        "RangeMax=\"6\">\nAQAAAACAAAAQAAAADgAAAA==eAFjZoAANigNAABwAAo=\n</DataArray>\n"
        "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\" RangeMin=\"5\" "
        "RangeMax=\"5\">\nAQAAAACAAAACAAAACgAAAA==eAFjZQUAABEACw==\n</DataArray>\n</Cells>\n"
        "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    pl_diag d;
    pl_mesh m = load(tu_write_str("vtk9.vtu", vtu), &d);
    const double square[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const int tris[6] = {0, 1, 2, 2, 3, 0};
    ck_assert_int_eq(m.nverts, 4);
    ck_assert_int_eq(m.ntris, 2);
    ck_assert_int_eq(memcmp(m.verts, square, sizeof square), 0);
    ck_assert_int_eq(memcmp(m.tris, tris, sizeof tris), 0);
    pl_mesh_free(&m);
    pl_diag_free(&d);
    tu_cleanup();
}
END_TEST

START_TEST(vtu_pieces_are_concatenated)
{
    pl_mesh a = box(2), b = box(3);
    vtu_style st = {0, 0, 0, 0};
    sbuf s = {0};
    sb_printf(&s, "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\n");
    vtu_piece(&s, &st, &a);
    vtu_piece(&s, &st, &b);
    sb_printf(&s, "</UnstructuredGrid></VTKFile>\n");
    pl_diag d;
    pl_mesh r = load(tu_write("two.vtu", s.p, s.n), &d);
    ck_assert_int_eq(r.nverts, a.nverts + b.nverts);
    ck_assert_int_eq(r.ntets, a.ntets + b.ntets);
    for (int i = 0; i < 4 * b.ntets; ++i) ck_assert_int_eq(r.tets[4 * a.ntets + i], b.tets[i] + a.nverts);
    ck_assert_double_eq_tol(tu_total_volume(&r, NULL), 2 * 6.0 * 0.5, 1e-12);
    pl_mesh_free(&a);
    pl_mesh_free(&b);
    pl_mesh_free(&r);
    pl_diag_free(&d);
    free(s.p);
    tu_cleanup();
}
END_TEST

START_TEST(legacy_vtk_5_offsets_layout_ascii_and_binary)
{
    pl_mesh m = box(3);
    sbuf s = {0};
    sb_printf(&s, "# vtk DataFile Version 5.1\nbox\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                  "FIELD FieldData 1\nTIME 1 1 double\n0.5\nPOINTS %d double\n", m.nverts);
    for (int i = 0; i < 3 * m.nverts; ++i) sb_printf(&s, "%.17g%c", m.verts[i], i % 3 == 2 ? '\n' : ' ');
    sb_printf(&s, "METADATA\nINFORMATION 0\n\nCELLS %d %d\nOFFSETS vtktypeint64\n", m.ntets + 1,
              4 * m.ntets);
    for (int c = 0; c <= m.ntets; ++c) sb_printf(&s, "%d\n", 4 * c);
    sb_printf(&s, "CONNECTIVITY vtktypeint64\n");
    for (int i = 0; i < 4 * m.ntets; ++i) sb_printf(&s, "%d ", m.tets[i]);
    sb_printf(&s, "\nCELL_TYPES %d\n", m.ntets);
    for (int c = 0; c < m.ntets; ++c) sb_printf(&s, "10\n");
    sb_printf(&s, "CELL_DATA %d\nSCALARS id int 1\nLOOKUP_TABLE default\n", m.ntets);
    pl_diag d;
    pl_mesh r = load(tu_write("v5.vtk", s.p, s.n), &d);
    assert_same(&m, &r, 0);
    pl_mesh_free(&r);
    pl_diag_free(&d);

    /* the same in BINARY: big-endian doubles and 64-bit integers */
    s.n = 0;
    sb_printf(&s, "# vtk DataFile Version 5.1\nbox\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
                  "POINTS %d double\n", m.nverts);
    unsigned char w[8];
    for (int i = 0; i < 3 * m.nverts; ++i) {
        uint64_t u;
        memcpy(&u, &m.verts[i], 8);
        put_uint(w, u, 8, 1);
        sb_add(&s, w, 8);
    }
    sb_printf(&s, "\nCELLS %d %d\nOFFSETS vtktypeint64\n", m.ntets + 1, 4 * m.ntets);
    for (int c = 0; c <= m.ntets; ++c) put_uint(w, 4 * (uint64_t)c, 8, 1), sb_add(&s, w, 8);
    sb_printf(&s, "\nCONNECTIVITY vtktypeint64\n");
    for (int i = 0; i < 4 * m.ntets; ++i) put_uint(w, (uint64_t)m.tets[i], 8, 1), sb_add(&s, w, 8);
    sb_printf(&s, "\nCELL_TYPES %d\n", m.ntets);
    for (int c = 0; c < m.ntets; ++c) put_uint(w, 10, 4, 1), sb_add(&s, w, 4);
    sb_printf(&s, "\n");
    r = load(tu_write("v5b.vtk", s.p, s.n), &d);
    assert_same(&m, &r, 0);
    pl_mesh_free(&r);
    pl_diag_free(&d);
    pl_mesh_free(&m);
    free(s.p);
    tu_cleanup();
}
END_TEST

START_TEST(polydata_polygons_and_strips_become_consistent_triangles)
{
    /* a unit square as a quad, and a strip of 4 triangles over [1,3]x[0,1] in z = 0 */
    const char *vtk = "# vtk DataFile Version 3.0\npoly\nASCII\nDATASET POLYDATA\n"
                      "POINTS 10 float\n0 0 0 1 0 0 1 1 0 0 1 0\n"
                      "1 0 0 1 1 0 2 0 0 2 1 0 3 0 0 3 1 0\n"
                      "VERTICES 1 2\n1 0\nLINES 1 3\n2 0 1\n"
                      "POLYGONS 1 5\n4 0 1 2 3\nTRIANGLE_STRIPS 1 7\n6 5 4 7 6 9 8\n"
                      "POINT_DATA 10\n";
    pl_diag d;
    pl_mesh m = load(tu_write_str("poly.vtk", vtk), &d);
    ck_assert_int_eq(m.ntris, 2 + 4);
    ck_assert_double_eq_tol(tu_surface_area(m.verts, m.tris, m.ntris), 1 + 2, 1e-12);
    for (int f = 0; f < m.ntris; ++f) { /* every triangle faces +z, as the quad does */
        const double *a = m.verts + 3 * m.tris[3 * f], *b = m.verts + 3 * m.tris[3 * f + 1];
        const double *c = m.verts + 3 * m.tris[3 * f + 2];
        double nz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        ck_assert_msg(nz > 0, "triangle %d faces -z", f);
    }
    ck_assert_ptr_nonnull(tu_find(&d, PL_OK, "1 vertex (VTK type 1), 1 line (VTK type 3)"));
    pl_mesh_free(&m);
    pl_diag_free(&d);
    tu_cleanup();
}
END_TEST

START_TEST(gmsh_sparse_node_tags_are_mapped)
{
    /* one tetrahedron (0,0,0) (2,0,0) (0,3,0) (0,0,4), volume 4, with tags 70, 5, 1000, 12 */
    const char *v4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                     "$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n"
                     "$Entities\n0 0 0 1\n1 0 0 0 2 3 4 0 0\n$EndEntities\n"
                     "$Nodes\n3 4 5 1000\n0 1 0 1\n70\n0 0 0\n1 2 1 2\n5\n1000\n2 0 0 0.5\n0 3 0 0.25\n"
                     "3 1 0 1\n12\n0 0 4\n$EndNodes\n"
                     "$Elements\n2 2 1 2\n2 1 2 1\n1 70 5 1000\n3 1 4 1\n2 70 5 1000 12\n"
                     "$EndElements\n$NodeData\n1\n\"t\"\n$EndNodeData\n";
    const char *v2 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n70 0 0 0\n5 2 0 0\n"
                     "1000 0 3 0\n12 0 0 4\n$EndNodes\n$Elements\n2\n1 15 2 0 1 70\n"
                     "2 4 2 0 1 70 5 1000 12\n$EndElements\n";
    const char *v1 = "$NOD\n4\n70 0 0 0\n5 2 0 0\n1000 0 3 0\n12 0 0 4\n$ENDNOD\n$ELM\n1\n"
                     "1 4 1 1 4 70 5 1000 12\n$ENDELM\n";
    const char *files[3] = {v4, v2, v1};
    for (int k = 0; k < 3; ++k) {
        pl_diag d;
        pl_mesh m = load(tu_write_str("sparse.msh", files[k]), &d);
        ck_assert_int_eq(m.nverts, 4);
        ck_assert_int_eq(m.ntets, 1);
        ck_assert_int_eq(m.ntris, k == 0 ? 1 : 0);
        ck_assert_double_eq_tol(tu_tet_volume(&m, 0), 4.0, 1e-12);
        /* vertices keep file order: tag 1000 is vertex 2 at (0,3,0) */
        ck_assert_double_eq(m.verts[3 * 2 + 1], 3.0);
        ck_assert_int_eq(m.tets[2], 2);
        pl_mesh_free(&m);
        pl_diag_free(&d);
    }
    tu_cleanup();
}
END_TEST

START_TEST(obj_corner_forms_negative_indices_and_polygons)
{
    const char *obj = "# a pentagon and a triangle\nmtllib x.mtl\no thing\n"
                      "v 0 0 0 1\nv 2 0 0\nv 3 2 0\nv 1 3 0\nv -1 2 0\n"
                      "vt 0 0\nvn 0 0 1\ng pentagon\nusemtl red\ns off\n"
                      "f 1/1/1 2/1/1 3//1 4/1 5 # corners in every form\n"
                      "v 0 0 1\nf -6 -5 -1\nl 1 2\n";
    pl_diag d;
    pl_mesh m = load(tu_write_str("forms.obj", obj), &d);
    ck_assert_int_eq(m.nverts, 6);
    ck_assert_int_eq(m.ntris, 3 + 1);
    int last[3] = {0, 1, 5};
    ck_assert_int_eq(memcmp(m.tris + 9, last, sizeof last), 0);
    /* the pentagon's area by the shoelace formula: 16 / 2 */
    ck_assert_double_eq_tol(tu_surface_area(m.verts, m.tris, 3), 8.0, 1e-12);
    ck_assert_ptr_nonnull(tu_find(&d, PL_OK, "skipped 1 line"));
    pl_mesh_free(&m);
    pl_diag_free(&d);
    tu_cleanup();
}
END_TEST

START_TEST(stl_ascii_and_binary_weld_to_the_box_surface)
{
    pl_mesh m = box(3);
    int *tris, ntris;
    ck_assert_int_eq(pl_mesh_boundary_triangles(&m, &tris, &ntris), PL_OK);
    int nsurf = 0; /* vertices on the box surface */
    char *on = calloc((size_t)m.nverts, 1);
    for (int i = 0; i < 3 * ntris; ++i) nsurf += !on[tris[i]]++;
    sbuf a = {0}, b = {0};
    unsigned char head[84] = "solid binary header that starts like ASCII";
    put_uint(head + 80, (uint64_t)ntris, 4, 0);
    sb_add(&b, head, 84);
    sb_printf(&a, "solid box\n");
    for (int f = 0; f < ntris; ++f) {
        unsigned char rec[50] = {0};
        sb_printf(&a, "  facet normal 0 0 0\n    outer loop\n");
        for (int k = 0; k < 3; ++k) {
            const double *p = m.verts + 3 * tris[3 * f + k];
            sb_printf(&a, "      vertex %.9g %.9g %.9g\n", p[0], p[1], p[2]);
            for (int c = 0; c < 3; ++c) {
                float x = (float)p[c];
                uint32_t u;
                memcpy(&u, &x, 4);
                put_uint(rec + 12 + 12 * k + 4 * c, u, 4, 0);
            }
        }
        sb_printf(&a, "    endloop\n  endfacet\n");
        sb_add(&b, rec, 50);
    }
    sb_printf(&a, "endsolid box\n");
    const sbuf *files[2] = {&a, &b};
    for (int k = 0; k < 2; ++k) {
        pl_diag d;
        pl_mesh s = load(tu_write("box.stl", files[k]->p, files[k]->n), &d);
        ck_assert_int_eq(s.nverts, nsurf);
        ck_assert_int_eq(s.ntris, ntris);
        ck_assert_int_eq(tu_open_edges(s.tris, s.ntris), 0);
        /* box [-1,1]x[0,3]x[0.25,0.75]: volume 3 */
        ck_assert_double_eq_tol(tu_surface_volume(s.verts, s.tris, s.ntris), 3.0, 1e-6);
        pl_mesh_free(&s);
        pl_diag_free(&d);
    }
    free(on);
    free(tris);
    free(a.p);
    free(b.p);
    pl_mesh_free(&m);
    tu_cleanup();
}
END_TEST

int main(void)
{
    Suite *s = suite_create("loaders_formats");
    TCase *tc = tcase_create("formats");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, vtu_binary_variants_read_back_exactly);
    tcase_add_test(tc, vtu_written_by_vtk9_with_information_keys);
    tcase_add_test(tc, vtu_pieces_are_concatenated);
    tcase_add_test(tc, legacy_vtk_5_offsets_layout_ascii_and_binary);
    tcase_add_test(tc, polydata_polygons_and_strips_become_consistent_triangles);
    tcase_add_test(tc, gmsh_sparse_node_tags_are_mapped);
    tcase_add_test(tc, obj_corner_forms_negative_indices_and_polygons);
    tcase_add_test(tc, stl_ascii_and_binary_weld_to_the_box_surface);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
