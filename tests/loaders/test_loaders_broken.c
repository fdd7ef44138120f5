/* test_loaders_broken.c - every loader refuses broken input with PL_EINPUT,
 * the file name, the line where known and a message naming what was
 * expected; nothing crashes, nothing is silently defaulted, and absurd
 * declared counts are refused before any large allocation. */
#include "loader_test_util.h"

#include <sys/resource.h>
#include <time.h>

/* Loads `path` and checks the refusal: empty output mesh, an error whose
 * message contains `needle` (NULL: any), at `line` (> 0: exactly that line,
 * -1: some line, 0: unchecked). */
static void expect_error(const char *path_in, const char *needle, int line)
{
    char path[256];
    snprintf(path, sizeof path, "%s", path_in);
    pl_mesh m;
    pl_diag d;
    pl_diag_init(&d);
    memset(&m, 0x5a, sizeof m); /* garbage: the loader must reset it */
    int rc = pl_mesh_load(path, NULL, &m, &d);
    if (rc != PL_EINPUT || !tu_find(&d, PL_EINPUT, needle) || getenv("PL_TEST_VERBOSE"))
        pl_diag_print(&d, stderr);
    ck_assert_int_eq(rc, PL_EINPUT);
    ck_assert(m.nverts == 0 && m.ntets == 0 && m.ntris == 0);
    ck_assert(m.verts == NULL && m.tets == NULL && m.tris == NULL);
    const pl_error *e = tu_find(&d, PL_EINPUT, needle);
    ck_assert_msg(e != NULL, "no error mentioning '%s' for %s", needle ? needle : "", path);
    ck_assert_str_eq(e->file, path);
    if (line > 0) ck_assert_msg(e->line == line, "error at line %d, expected %d: %s", e->line,
                                line, e->msg);
    if (line < 0) ck_assert_msg(e->line > 0, "error without a line: %s", e->msg);
    pl_diag_free(&d);
}

/* Writes the first `percent` % of a real mesh into a temp file. */
static const char *truncated_copy(const char *file, int percent)
{
    char src[512];
    size_t n;
    snprintf(src, sizeof src, MESH_DIR "%s", file);
    char *buf = tu_slurp(src, &n);
    const char *p = tu_write(file, buf, n * (size_t)percent / 100);
    free(buf);
    return p;
}

#define VTK_HEAD "# vtk DataFile Version 2.0\ntest\nASCII\nDATASET UNSTRUCTURED_GRID\n"
#define VTK_TET_POINTS "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"

START_TEST(missing_empty_tiny_and_garbage_files_are_refused)
{
    expect_error(PL_SOURCE_DIR "/no/such/mesh.vtk", "cannot open", 0);
    expect_error(tu_write_str("empty.obj", ""), "empty file", 0);
    expect_error(tu_write_str("one.vtk", "#"), "unrecognised mesh format", 1);
    expect_error(tu_write("nul.stl", "\0", 1), "unrecognised mesh format", 1);
    unsigned char junk[4096];
    unsigned x = 12345;
    for (size_t i = 0; i < sizeof junk; ++i) junk[i] = (unsigned char)((x = x * 1103515245u + 12345u) >> 24);
    expect_error(tu_write("junk.msh", junk, sizeof junk), "unrecognised mesh format", 1);
    expect_error(PL_SOURCE_DIR "/scenes/meshes", "not a regular file", 0);
    /* a known magic followed by garbage fails inside the format reader */
    memcpy(junk, "$MeshFormat\n", 12);
    expect_error(tu_write("junk2.msh", junk, sizeof junk), NULL, -1);
    tu_cleanup();
}
END_TEST

START_TEST(legacy_vtk_truncated_files_are_refused)
{
    expect_error(truncated_copy("SOFA_volume.vtk", 60), NULL, -1);   /* ASCII, inside CELLS */
    expect_error(truncated_copy("SOFA_volume.vtk", 2), NULL, -1);    /* ASCII, inside POINTS */
    expect_error(truncated_copy("finger.vtk", 50), "truncated", -1);  /* BINARY double */
    expect_error(truncated_copy("liver.vtk", 30), "truncated", -1);   /* BINARY float */
    expect_error(truncated_copy("liver.vtk", 95), "truncated", -1);   /* inside POLYGONS */
    tu_cleanup();
}
END_TEST

START_TEST(legacy_vtk_wrong_counts_and_indices_are_refused)
{
    const char *types_mismatch = VTK_HEAD VTK_TET_POINTS "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10 10\n";
    expect_error(tu_write_str("a.vtk", types_mismatch), "CELL_TYPES declares 2 cells but CELLS "
                 "declared 1", 12);
    const char *out_of_range = VTK_HEAD VTK_TET_POINTS "CELLS 1 5\n4 0 1 2 7\nCELL_TYPES 1\n10\n";
    expect_error(tu_write_str("b.vtk", out_of_range), "uses point 7: expected an index in 0..3", 10);
    const char *short_tet = VTK_HEAD VTK_TET_POINTS "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n";
    expect_error(tu_write_str("c.vtk", short_tet), "with 3 points: expected 4", 10);
    const char *size_wrong = VTK_HEAD VTK_TET_POINTS "CELLS 1 6\n4 0 1 2 3\nCELL_TYPES 1\n10\n";
    expect_error(tu_write_str("d.vtk", size_wrong), "found 'CELL_TYPES'", 12);
    const char *nan = VTK_HEAD "POINTS 4 double\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n";
    expect_error(tu_write_str("e.vtk", nan), "not finite", 7);
    const char *word = VTK_HEAD "POINTS 4 double\n0 0 0\n1 0 0\n0 one 0\n0 0 1\n";
    expect_error(tu_write_str("f.vtk", word), "expected a point coordinate (a number), found "
                 "'one'", 8);
    const char *negative = VTK_HEAD VTK_TET_POINTS "CELLS 1 5\n4 0 1 -2 3\nCELL_TYPES 1\n10\n";
    expect_error(tu_write_str("g.vtk", negative), "out of range", 11);
    const char *no_types = VTK_HEAD VTK_TET_POINTS "CELLS 1 5\n4 0 1 2 3\n";
    expect_error(tu_write_str("h.vtk", no_types), "CELLS without CELL_TYPES", 0);
    tu_cleanup();
}
END_TEST

START_TEST(legacy_vtk_unsupported_variants_say_what_is_expected)
{
    expect_error(tu_write_str("sp.vtk", "# vtk DataFile Version 2.0\nx\nASCII\nDATASET "
                                        "STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n"),
                 "expected UNSTRUCTURED_GRID or POLYDATA", 4);
    expect_error(tu_write_str("int.vtk", VTK_HEAD "POINTS 4 int\n0 0 0\n"),
                 "expected float or double", 5);
    expect_error(tu_write_str("enc.vtk", "# vtk DataFile Version 2.0\nx\nHEX\n"),
                 "expected ASCII or BINARY", 3);
    expect_error(tu_write_str("kw.vtk", VTK_HEAD VTK_TET_POINTS "SPLINES 3\n"),
                 "unexpected 'SPLINES'", 10);
    /* binary NaN coordinate */
    unsigned char bin[256];
    const char *head = "# vtk DataFile Version 2.0\nx\nBINARY\nDATASET POLYDATA\nPOINTS 1 float\n";
    size_t n = strlen(head);
    memcpy(bin, head, n);
    const unsigned char qnan_be[4] = {0x7f, 0xc0, 0, 0};
    memset(bin + n, 0, 12);
    memcpy(bin + n + 4, qnan_be, 4);
    expect_error(tu_write("nanbin.vtk", bin, n + 12), "non-finite", 5);
    tu_cleanup();
}
END_TEST

static const char *vtu_doc(const char *name, const char *piece_attrs, const char *points,
                           const char *conn, const char *offsets, const char *types)
{
    static char buf[4096];
    snprintf(buf, sizeof buf,
             "<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
             "<UnstructuredGrid>\n<Piece %s>\n"
             "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n"
             "%s\n</DataArray>\n</Points>\n<Cells>\n"
             "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n%s\n</DataArray>\n"
             "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n%s\n</DataArray>\n"
             "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n%s\n</DataArray>\n"
             "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n",
             piece_attrs, points, conn, offsets, types);
    return tu_write_str(name, buf);
}

#define TET_PTS "0 0 0 1 0 0 0 1 0 0 0 1"
#define NP4 "NumberOfPoints=\"4\" NumberOfCells=\"1\""

START_TEST(vtu_entity_bomb_is_refused_quickly)
{
    char doc[2048] = "<?xml version=\"1.0\"?>\n<!DOCTYPE lolz [\n<!ENTITY lol \"lol\">\n";
    for (int k = 1; k <= 9; ++k) {
        char line[160];
        snprintf(line, sizeof line, "<!ENTITY lol%d \"", k);
        for (int j = 0; j < 10; ++j)
            snprintf(line + strlen(line), sizeof line - strlen(line), "&lol%s;",
                     k == 1 ? "" : (char[]){(char)('0' + k - 1), 0});
        strcat(line, "\">\n");
        strcat(doc, line);
    }
    strcat(doc, "]>\n<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece "
                "NumberOfPoints=\"1\" NumberOfCells=\"0\"><Points><DataArray type=\"Float32\" "
                "NumberOfComponents=\"3\" format=\"ascii\">&lol9;</DataArray></Points></Piece>"
                "</UnstructuredGrid></VTKFile>\n");
    clock_t t0 = clock();
    expect_error(tu_write_str("bomb.vtu", doc), "refused", 2);
    /* the same bomb under a .vtk name is sniffed as XML and refused too */
    expect_error(tu_write_str("bomb.vtk", doc), "refused", 2);
    ck_assert(clock() - t0 < CLOCKS_PER_SEC / 2);
    tu_cleanup();
}
END_TEST

START_TEST(vtu_wrong_value_counts_are_refused)
{
    expect_error(vtu_doc("few.vtu", NP4, TET_PTS, "0 1 2", "4", "10"),
                 "DataArray 'connectivity' ends after 3 values: expected 4", 11);
    expect_error(vtu_doc("fewpts.vtu", NP4, "0.0 0.0 0.0 1.0 0.0 0.0 0.0 1.0 0.0", "0 1 2 3", "4", "10"),
                 "ends after 9 values: expected 12", 6);
    expect_error(vtu_doc("many.vtu", NP4, TET_PTS, "0 1 2 3 3", "4", "10"),
                 "more than the expected 4 values", 11);
    expect_error(vtu_doc("range.vtu", NP4, TET_PTS, "0 1 2 9", "4", "10"),
                 "cell 0 uses point 9: expected an index in 0..3", 11);
    expect_error(vtu_doc("offs.vtu", "NumberOfPoints=\"4\" NumberOfCells=\"2\"", TET_PTS,
                         "0 1 2 3", "4 2", "10 10"),
                 "expected increasing offsets", 14);
    expect_error(vtu_doc("nan.vtu", NP4, "0 0 0 1 0 0 0 1 0 0 0 inf", "0 1 2 3", "4", "10"),
                 "not finite", 7);
    expect_error(vtu_doc("absurd2.vtu", "NumberOfPoints=\"4000000000\" NumberOfCells=\"1\"",
                         TET_PTS, "0 1 2 3", "4", "10"),
                 "NumberOfPoints=\"4000000000\": expected an integer", 4);
    tu_cleanup();
}
END_TEST

START_TEST(vtu_malformed_or_unsupported_files_are_refused)
{
    expect_error(truncated_copy("raptorTetra_8418.vtu", 50), "malformed XML", -1);
    expect_error(tu_write_str("poly.vtu", "<VTKFile type=\"PolyData\"><PolyData/></VTKFile>"),
                 "expected type=\"UnstructuredGrid\"", 1);
    expect_error(tu_write_str("lz4.vtu", "<VTKFile type=\"UnstructuredGrid\" "
                                         "compressor=\"vtkLZ4DataCompressor\"/>"),
                 "vtkLZ4DataCompressor\" is not supported", 1);
    expect_error(tu_write_str("hdr.vtu", "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt16\"/>"),
                 "expected UInt32 or UInt64", 1);
    expect_error(tu_write_str("nogrid.vtu", "<VTKFile type=\"UnstructuredGrid\">\n</VTKFile>"),
                 "lacks <UnstructuredGrid>", 1);
    const char *appended =
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\n<Piece NumberOfPoints=\"1\" "
        "NumberOfCells=\"0\">\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"appended\" offset=\"0\"/></Points></Piece></UnstructuredGrid></VTKFile>";
    expect_error(tu_write_str("app.vtu", appended), "appended data is not supported", 3);
    const char *b64bad =
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\n<Piece NumberOfPoints=\"1\" "
        "NumberOfCells=\"0\">\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"binary\">DAAAA*AAAAAAAAAAAAAAAA</DataArray></Points></Piece></UnstructuredGrid></VTKFile>";
    expect_error(tu_write_str("b64.vtu", b64bad), "invalid base64", 3);
    /* header says 12 bytes; only 8 follow (base64 of 0c000000 + 8 zero bytes) */
    const char *shortbin =
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\n<Piece NumberOfPoints=\"1\" "
        "NumberOfCells=\"0\">\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"binary\">DAAAAAAAAAAAAAAA</DataArray></Points></Piece></UnstructuredGrid></VTKFile>";
    expect_error(tu_write_str("short.vtu", shortbin), "is truncated", 3);
    /* a consistent binary array of 2 floats where 3 are needed */
    const char *fewbin =
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\n<Piece NumberOfPoints=\"1\" "
        "NumberOfCells=\"0\">\n<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"binary\">CAAAAAAAAAAAAAAA</DataArray></Points></Piece></UnstructuredGrid></VTKFile>";
    expect_error(tu_write_str("fewbin.vtu", fewbin), "holds 2 values of Float32, expected 3", 3);
    /* zlib header: 1 block of 12 bytes, compressed size 8, then 8 bytes of junk */
    const char *badzlib =
        "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZLibDataCompressor\"><UnstructuredGrid>\n"
        "<Piece NumberOfPoints=\"1\" NumberOfCells=\"0\">\n<Points><DataArray type=\"Float32\" "
        "NumberOfComponents=\"3\" format=\"binary\">AQAAAAwAAAAMAAAACAAAAP////////////8=</DataArray>"
        "</Points></Piece></UnstructuredGrid></VTKFile>";
    expect_error(tu_write_str("zlib.vtu", badzlib), "zlib block 0 is corrupt", 3);
    tu_cleanup();
}
END_TEST

#define MSH2_HEAD "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
#define MSH2_NODES "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"

START_TEST(gmsh_broken_files_are_refused)
{
    expect_error(truncated_copy("liver.msh", 50), "end of file", -1);
    expect_error(truncated_copy("msh4_cube.msh", 70), NULL, -1);
    expect_error(truncated_copy("cube_low_res.msh", 50), NULL, -1);
    expect_error(tu_write_str("huge.msh", MSH2_HEAD "$Nodes\n4000000000\n1 0 0 0\n"), "too large", 5);
    expect_error(tu_write_str("big.msh", MSH2_HEAD "$Nodes\n400000000\n1 0 0 0\n"),
                 "room for at most", 5);
    expect_error(tu_write_str("bin.msh", "$MeshFormat\n2.2 1 8\n$EndMeshFormat\n"),
                 "binary Gmsh files", 2);
    expect_error(tu_write_str("v3.msh", "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n"),
                 "expected 2.x or 4.1", 2);
    const char *missing = MSH2_HEAD MSH2_NODES "$Elements\n1\n1 4 2 0 1 1 2 3 5\n$EndElements\n";
    expect_error(tu_write_str("miss.msh", missing), "uses node 5, which is not in the node list", 13);
    const char *three = MSH2_HEAD MSH2_NODES "$Elements\n1\n1 4 2 0 1 1 2 3\n$EndElements\n";
    expect_error(tu_write_str("three.msh", three), "with 3 nodes: expected 4", 13);
    const char *dup = MSH2_HEAD "$Nodes\n2\n7 0 0 0\n7 1 0 0\n$EndNodes\n";
    expect_error(tu_write_str("dup.msh", dup), "node tag 7 appears twice", 5);
    const char *nan = MSH2_HEAD "$Nodes\n1\n1 0 NaN 0\n$EndNodes\n";
    expect_error(tu_write_str("nan.msh", nan), "not finite", 6);
    const char *noend = MSH2_HEAD "$Nodes\n1\n1 0 0 0\n$Elements\n";
    expect_error(tu_write_str("noend.msh", noend), "expected $EndNodes, found '$Elements'", 7);
    const char *extra = MSH2_HEAD "$Nodes\n1\n1 0 0 0 5\n$EndNodes\n";
    expect_error(tu_write_str("extra.msh", extra), "expected the end of the line", 6);
    const char *noelem = MSH2_HEAD MSH2_NODES;
    expect_error(tu_write_str("noelem.msh", noelem), "no element section", 0);
    const char *v1 = "$NOD\n1\n1 0 0 0\n$ENDNOD\n$ELM\n1\n1 15 0 0 2 1\n$ENDELM\n";
    expect_error(tu_write_str("v1.msh", v1), "declares 2 nodes but lists 1", 7);
    const char *v4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 5\n0 1 0 4\n1\n2\n3\n"
                     "4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";
    expect_error(tu_write_str("v4.msh", v4), "$Nodes announced 5 nodes but its blocks hold 4", 5);
    const char *v4b = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n0 1 0 3\n1\n2\n";
    expect_error(tu_write_str("v4b.msh", v4b), "node block declares 3 nodes", 6);
    tu_cleanup();
}
END_TEST

#define OBJ_QUAD "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"

START_TEST(obj_broken_files_are_refused)
{
    expect_error(tu_write_str("range.obj", OBJ_QUAD "f 1 2 9\n"), "face uses vertex 9 but the "
                 "file defines only 4 vertices", 5);
    expect_error(tu_write_str("zero.obj", OBJ_QUAD "f 0 1 2\n"), "indices start at 1", 5);
    expect_error(tu_write_str("rel.obj", OBJ_QUAD "f -1 -2 -5\n"), "relative index -5", 5);
    expect_error(tu_write_str("two.obj", OBJ_QUAD "f 1 2\n"), "face with 2 corners: expected at "
                 "least 3", 5);
    expect_error(tu_write_str("short.obj", "v 0 0\n"), "line ended early: expected the vertex z", 1);
    expect_error(tu_write_str("nan.obj", "v 0 0 0\nv 1 -nan 0\n"), "not finite", 2);
    expect_error(tu_write_str("word.obj", OBJ_QUAD "f 1 2 x/1\n"), "face corner 'x/1'", 5);
    expect_error(tu_write_str("points.obj", OBJ_QUAD), "no tetrahedra or triangles", 0);
    tu_cleanup();
}
END_TEST

#define STL_FACET "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n" \
                  "endloop\nendfacet\n"

START_TEST(stl_broken_files_are_refused)
{
    expect_error(tu_write_str("noend.stl", "solid x\n" STL_FACET), "expected 'endsolid'", 0);
    expect_error(tu_write_str("two.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                         "vertex 1 0 0\nendloop\nendfacet\nendsolid\n"),
                 "expected 'vertex' (a facet has three vertices), found 'endloop'", 6);
    expect_error(tu_write_str("nan.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                         "vertex 1 0 inf\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n"),
                 "not finite", 5);
    expect_error(tu_write_str("junk.stl", "solid x\n" STL_FACET "garbage\nendsolid\n"),
                 "expected 'facet' or 'endsolid', found 'garbage'", 9);
    /* size no longer 84 + 50n: the message gives both numbers */
    expect_error(truncated_copy("finger.stl", 50),
                 "declares 306 triangles, which need 15384 bytes; the file has 7692", 1);
    /* a binary STL whose only triangle holds a NaN */
    unsigned char bin[134] = {0};
    bin[80] = 1;
    const unsigned char qnan_le[4] = {0, 0, 0xc0, 0x7f};
    memcpy(bin + 84 + 12 + 4, qnan_le, 4);
    expect_error(tu_write("nan_bin.stl", bin, sizeof bin), "triangle 0 has a non-finite", 0);
    tu_cleanup();
}
END_TEST

/* Caps the address space at its current size + 256 MB (not under
 * AddressSanitizer, which reserves terabytes of shadow memory): a loader
 * that tried to allocate gigabytes for a declared count would then get
 * NULL and report PL_EINTERNAL instead of the expected PL_EINPUT. */
#ifndef __SANITIZE_ADDRESS__
static struct rlimit saved_limit;
#endif

static void limit_memory(void)
{
#ifndef __SANITIZE_ADDRESS__
    long pages = 0, page = sysconf(_SC_PAGESIZE);
    FILE *f = fopen("/proc/self/statm", "r");
    ck_assert_ptr_nonnull(f);
    ck_assert_int_eq(fscanf(f, "%ld", &pages), 1);
    fclose(f);
    ck_assert_int_eq(getrlimit(RLIMIT_AS, &saved_limit), 0);
    struct rlimit r = saved_limit;
    r.rlim_cur = (rlim_t)pages * (rlim_t)page + ((rlim_t)256 << 20);
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &r), 0);
#endif
}

static void unlimit_memory(void)
{
#ifndef __SANITIZE_ADDRESS__
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &saved_limit), 0);
#endif
}

START_TEST(absurd_counts_are_refused_within_a_small_memory_budget)
{
    limit_memory();
    clock_t t0 = clock();
    expect_error(tu_write_str("huge.vtk", VTK_HEAD "POINTS 4000000000 float\n0 0 0\n"),
                 "POINTS count 4000000000", 5);
    expect_error(tu_write_str("big.vtk", VTK_HEAD "POINTS 100000000 float\n0 0 0\n"),
                 "room for at most", 5);
    expect_error(tu_write_str("cells.vtk", VTK_HEAD VTK_TET_POINTS "CELLS 1 300000000\n5 0\n"),
                 "room for at most", -1);
    /* binary: 100 million doubles announced, 24 bytes present */
    const char bin[] = "# vtk DataFile Version 2.0\nx\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
                       "POINTS 100000000 double\n0123456789abcdef01234567";
    expect_error(tu_write("hugebin.vtk", bin, sizeof bin - 1), "room for at most", -1);
    /* VTU: ascii points, offsets that announce 2e9 connectivity values, a
     * zlib header announcing a 1.2 GB block held in 8 compressed bytes */
    expect_error(vtu_doc("absurd.vtu", "NumberOfPoints=\"100000000\" NumberOfCells=\"1\"",
                         TET_PTS, "0 1 2 3", "4", "10"),
                 "can hold at most", 6);
    expect_error(vtu_doc("absurd_off.vtu", "NumberOfPoints=\"4\" NumberOfCells=\"2\"", TET_PTS,
                         "0 1 2 3", "4 2000000000", "10 10"),
                 "DataArray 'connectivity' declares 2000000000 values", 11);
    const char *bomb =
        "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZLibDataCompressor\"><UnstructuredGrid>\n"
        "<Piece NumberOfPoints=\"100000000\" NumberOfCells=\"0\">\n<Points><DataArray type=\"Float32\" "
        "NumberOfComponents=\"3\" format=\"binary\">AQAAAACMhkcAjIZHCAAAAP////////////8=</DataArray>"
        "</Points></Piece></UnstructuredGrid></VTKFile>";
    expect_error(tu_write_str("zbomb.vtu", bomb), "declares 300000000 values but holds at most", 3);
    /* Gmsh v2 and v4 node and element counts */
    expect_error(tu_write_str("big4.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n"
                                          "1 300000000 1 300000000\n0 1 0 1\n1\n0 0 0\n"),
                 "room for at most", 5);
    const char *elems = MSH2_HEAD MSH2_NODES "$Elements\n300000000\n1 4 2 0 1 1 2 3 4\n";
    expect_error(tu_write_str("bigel.msh", elems), "room for at most", 12);
    ck_assert(clock() - t0 < CLOCKS_PER_SEC); /* refused up front, nothing parsed */
    unlimit_memory();
    tu_cleanup();
}
END_TEST

int main(void)
{
    Suite *s = suite_create("loaders_broken");
    TCase *tc = tcase_create("broken");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, missing_empty_tiny_and_garbage_files_are_refused);
    tcase_add_test(tc, legacy_vtk_truncated_files_are_refused);
    tcase_add_test(tc, absurd_counts_are_refused_within_a_small_memory_budget);
    tcase_add_test(tc, legacy_vtk_wrong_counts_and_indices_are_refused);
    tcase_add_test(tc, legacy_vtk_unsupported_variants_say_what_is_expected);
    tcase_add_test(tc, vtu_entity_bomb_is_refused_quickly);
    tcase_add_test(tc, vtu_wrong_value_counts_are_refused);
    tcase_add_test(tc, vtu_malformed_or_unsupported_files_are_refused);
    tcase_add_test(tc, gmsh_broken_files_are_refused);
    tcase_add_test(tc, obj_broken_files_are_refused);
    tcase_add_test(tc, stl_broken_files_are_refused);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
