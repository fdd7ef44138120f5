/* test_loaders_hostile.c - files crafted to attack the mesh readers (issue
 * 13): size arithmetic that wraps, fields read before the size is checked,
 * error messages that would quote a file that is not a mesh.  Each case
 * is refused with PL_EINPUT and a message naming the file and the line;
 * without the fixes, the first one overflows the heap (AddressSanitizer
 * stops it, a plain build corrupts memory or gets the wrong message). */
#include "loader_test_util.h"

#include <stdint.h>
#include <zlib.h>

/* Base64 of n bytes, appended to out (which has room). */
static void b64(char *out, const unsigned char *p, size_t n)
{
    static const char A[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *o = out + strlen(out);
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)p[i] << 16 | (i + 1 < n ? (unsigned)p[i + 1] << 8 : 0) |
                     (i + 2 < n ? p[i + 2] : 0);
        *o++ = A[v >> 18 & 63];
        *o++ = A[v >> 12 & 63];
        *o++ = i + 1 < n ? A[v >> 6 & 63] : '=';
        *o++ = i + 2 < n ? A[v & 63] : '=';
    }
    *o = '\0';
}

static void put_u64(unsigned char *p, uint64_t v)
{
    for (int k = 0; k < 8; ++k) p[k] = (unsigned char)(v >> (8 * k));
}

/* Loads a file or buffer and returns the error that mentions `needle`,
 * checking the refusal (PL_EINPUT, empty mesh, the file named). */
static pl_error expect_refusal(const char *path, const void *buf, size_t n,
                               pl_mesh_format format, const char *needle)
{
    pl_mesh m;
    pl_diag d;
    pl_diag_init(&d);
    pl_mesh_load_options opt = {.format = format};
    int rc = buf ? pl_mesh_load_buffer(path, buf, n, &opt, &m, &d)
                 : pl_mesh_load(path, &opt, &m, &d);
    const pl_error *e = tu_find(&d, PL_EINPUT, needle);
    if (rc != PL_EINPUT || !e) pl_diag_print(&d, stderr);
    ck_assert_int_eq(rc, PL_EINPUT);
    ck_assert(m.nverts == 0 && m.ntets == 0 && m.ntris == 0 && !m.verts);
    ck_assert_msg(e != NULL, "no error mentioning '%s'", needle);
    ck_assert_str_eq(e->file, path);
    pl_error copy = *e;
    pl_diag_free(&d);
    return copy;
}

/* The reproducer: header_type="UInt64", two zlib blocks that each
 * claim 2^63 + 48 bytes.  (nb - 1) * bs + last wraps around to exactly the
 * 96 bytes of 4 points, and uncompress() would have been told that the
 * 97-byte buffer holds 2^63 + 48 bytes: the first block inflates to 64 kB
 * of file-chosen bytes. */
START_TEST(vtu_block_sizes_that_wrap_around_are_refused)
{
    enum { INFLATED = 64 * 1024 };
    unsigned char *plain = malloc(INFLATED), *z = malloc(compressBound(INFLATED));
    ck_assert(plain && z);
    memset(plain, 0x41, INFLATED);
    uLongf zn = compressBound(INFLATED);
    ck_assert_int_eq(compress2(z, &zn, plain, INFLATED, 9), Z_OK);
    unsigned char head[5 * 8];
    const uint64_t huge = ((uint64_t)1 << 63) + 48;
    put_u64(head, 2);
    put_u64(head + 8, huge);
    put_u64(head + 16, huge);
    put_u64(head + 24, zn);
    put_u64(head + 32, zn);
    size_t cap = 4096 + 2 * (sizeof head + 2 * zn);
    char *doc = malloc(cap);
    ck_assert_ptr_nonnull(doc);
    snprintf(doc, cap,
             "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\" "
             "compressor=\"vtkZLibDataCompressor\"><UnstructuredGrid>\n"
             "<Piece NumberOfPoints=\"4\" NumberOfCells=\"0\">\n<Points>\n"
             "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">");
    b64(doc, head, sizeof head);
    b64(doc, z, zn);
    b64(doc, z, zn);
    strcat(doc, "</DataArray></Points></Piece></UnstructuredGrid></VTKFile>\n");
    pl_error e = expect_refusal(tu_write_str("wrap.vtu", doc), NULL, 0, PL_MESH_AUTO,
                                "corrupt compressed header");
    ck_assert_int_eq(e.line, 4);
    ck_assert_msg(strstr(e.msg, "overflow"), "%s", e.msg);
    /* the same wrap in a 32-bit header cannot happen; a sum of block sizes
     * that wraps is refused too */
    put_u64(head, 2);
    put_u64(head + 8, 48);
    put_u64(head + 16, 48);
    put_u64(head + 24, ~(uint64_t)0);
    put_u64(head + 32, 2);
    snprintf(doc, cap,
             "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\" "
             "compressor=\"vtkZLibDataCompressor\"><UnstructuredGrid>\n"
             "<Piece NumberOfPoints=\"4\" NumberOfCells=\"0\">\n<Points>\n"
             "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">");
    b64(doc, head, sizeof head);
    b64(doc, z, 8);
    strcat(doc, "</DataArray></Points></Piece></UnstructuredGrid></VTKFile>\n");
    e = expect_refusal(tu_write_str("sum.vtu", doc), NULL, 0, PL_MESH_AUTO,
                       "announce more than the");
    ck_assert_int_eq(e.line, 4);
    free(doc);
    free(plain);
    free(z);
    tu_cleanup();
}
END_TEST

/* A binary STL's triangle count sits at bytes 80..83: a file shorter than
 * that is refused before they are read (the format sniffer alone needs 84
 * bytes, so the buffer entry point with the format named reaches it). */
START_TEST(stl_binary_count_is_read_only_after_the_size_check)
{
    unsigned char *short_stl = malloc(80); /* exact size: ASan sees a read past it */
    ck_assert_ptr_nonnull(short_stl);
    memset(short_stl, 0, 80);
    expect_refusal("short.stl", short_stl, 80, PL_MESH_STL_BINARY,
                   "expected at least the 84-byte header");
    free(short_stl);
    /* a count whose 50-byte records overflow nothing but do not match the size */
    unsigned char hdr[84] = {0};
    hdr[80] = hdr[81] = hdr[82] = hdr[83] = 0xff;
    expect_refusal("count.stl", hdr, sizeof hdr, PL_MESH_STL_BINARY,
                   "declares 4294967295 triangles");
}
END_TEST

/* Naming a file that is not a mesh must not reveal its content. */
START_TEST(errors_about_non_mesh_files_do_not_quote_them)
{
    const char *secret = "root:x:0:0:SECRET-TOKEN-1234:/root:/bin/bash\n";
    const char *path = tu_write_str("passwd", secret);
    pl_error e = expect_refusal(path, NULL, 0, PL_MESH_AUTO, "unrecognised mesh format");
    ck_assert_msg(!strstr(e.msg, "root:x") && !strstr(e.msg, "SECRET"), "%s", e.msg);
    ck_assert_msg(strstr(e.msg, "the file holds text"), "%s", e.msg);
    unsigned char bin[100];
    for (size_t i = 0; i < sizeof bin; ++i) bin[i] = (unsigned char)(i * 7);
    e = expect_refusal(tu_write("blob", bin, sizeof bin), NULL, 0, PL_MESH_AUTO,
                       "the file holds binary data");
    tu_cleanup();
}
END_TEST

/* A DTD spelled in UTF-16 (no "<!DOCTYPE" bytes in the file) is refused
 * like one in UTF-8: the parser decides, not a byte search. */
START_TEST(vtu_dtd_in_utf16_is_refused)
{
    const char *xml =
        "<?xml version=\"1.0\" encoding=\"UTF-16\"?>\n"
        "<!DOCTYPE r [<!ENTITY e \"0 0 0 1 0 0 0 1 0 0 0 1\">]>\n"
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"4\" "
        "NumberOfCells=\"0\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"ascii\">&e;</DataArray></Points></Piece></UnstructuredGrid></VTKFile>\n";
    for (int big = 0; big < 2; ++big) {
        size_t n = strlen(xml);
        unsigned char *u = malloc(2 * n + 2);
        ck_assert_ptr_nonnull(u);
        u[0] = big ? 0xfe : 0xff;
        u[1] = big ? 0xff : 0xfe;
        for (size_t i = 0; i < n; ++i) {
            u[2 + 2 * i + !big] = 0;
            u[2 + 2 * i + big] = (unsigned char)xml[i];
        }
        pl_error e = expect_refusal(big ? "be.vtu" : "le.vtu", u, 2 * n + 2, PL_MESH_VTU, "DTD");
        ck_assert_int_eq(e.line, 2);
        free(u);
    }
}
END_TEST

/* The buffer entry point reads what the file entry point reads. */
START_TEST(buffer_and_file_entry_points_agree)
{
    const char *obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    pl_mesh a, b;
    pl_diag d;
    pl_diag_init(&d);
    ck_assert_int_eq(pl_mesh_load(tu_write_str("t.obj", obj), NULL, &a, &d), PL_OK);
    pl_mesh_load_options opt = {.format = PL_MESH_OBJ};
    ck_assert_int_eq(pl_mesh_load_buffer("t.obj", obj, strlen(obj), &opt, &b, &d), PL_OK);
    ck_assert_int_eq(a.nverts, 4);
    ck_assert_int_eq(a.ntris, 4);
    ck_assert_int_eq(b.nverts, a.nverts);
    ck_assert_int_eq(b.ntris, a.ntris);
    ck_assert_mem_eq(a.verts, b.verts, 12 * sizeof(double));
    ck_assert_mem_eq(a.tris, b.tris, 12 * sizeof(int));
    /* the closed tetrahedron surface encloses 1/6 */
    ck_assert_double_eq_tol(fabs(tu_surface_volume(b.verts, b.tris, b.ntris)), 1.0 / 6, 1e-15);
    pl_mesh_free(&a);
    pl_mesh_free(&b);
    /* a named format is not second-guessed: OBJ text read as legacy VTK fails */
    opt.format = PL_MESH_VTK_LEGACY;
    ck_assert_int_eq(pl_mesh_load_buffer("t.obj", obj, strlen(obj), &opt, &b, &d), PL_EINPUT);
    pl_diag_free(&d);
    tu_cleanup();
}
END_TEST

int main(void)
{
    Suite *s = suite_create("loaders_hostile");
    TCase *tc = tcase_create("hostile");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, vtu_block_sizes_that_wrap_around_are_refused);
    tcase_add_test(tc, stl_binary_count_is_read_only_after_the_size_check);
    tcase_add_test(tc, errors_about_non_mesh_files_do_not_quote_them);
    tcase_add_test(tc, vtu_dtd_in_utf16_is_refused);
    tcase_add_test(tc, buffer_and_file_entry_points_agree);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
