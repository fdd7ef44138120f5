/* test_export_vtu.c - .vtu frames and .pvd series, read back with libxml2
 * (an independent XML parser) and an independent base64 decoder. */
#include <check.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/xpath.h>

#include "export/export.h"
#include "export_test_util.h"

/* ---- reading helpers ----------------------------------------------------- */

static xmlDocPtr parse(const char *path)
{
    return xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
}

/* Nodes matching expr (caller frees with xmlXPathFreeObject). */
static xmlXPathObjectPtr nodes(xmlDocPtr doc, const char *expr)
{
    xmlXPathContextPtr ctx = xmlXPathNewContext(doc);
    xmlXPathObjectPtr o = xmlXPathEvalExpression((const xmlChar *)expr, ctx);
    xmlXPathFreeContext(ctx);
    return o;
}

static int count_nodes(xmlDocPtr doc, const char *expr)
{
    xmlXPathObjectPtr o = nodes(doc, expr);
    int n = (o && o->nodesetval) ? o->nodesetval->nodeNr : -1;
    xmlXPathFreeObject(o);
    return n;
}

/* String value of the first node matching expr (attribute or element text), malloc'd. */
static char *value_of(xmlDocPtr doc, const char *expr)
{
    xmlXPathObjectPtr o = nodes(doc, expr);
    char *s = NULL;
    if (o && o->nodesetval && o->nodesetval->nodeNr > 0) {
        xmlChar *c = xmlNodeGetContent(o->nodesetval->nodeTab[0]);
        s = strdup((const char *)c);
        xmlFree(c);
    }
    xmlXPathFreeObject(o);
    return s;
}

static long attr_long(xmlDocPtr doc, const char *expr)
{
    char *s = value_of(doc, expr);
    long v = s ? strtol(s, NULL, 10) : -1;
    free(s);
    return v;
}

/* Whitespace-separated doubles of an ascii DataArray. */
static int ascii_doubles(xmlDocPtr doc, const char *expr, double *out, int max)
{
    char *s = value_of(doc, expr), *p = s, *end;
    int n = 0;
    if (!s) return -1;
    for (double v = strtod(p, &end); end != p && n < max; v = strtod(p, &end)) {
        out[n++] = v;
        p = end;
    }
    free(s);
    return n;
}

/* base64 decoder written from RFC 4648 (independent of the writer's encoder). */
static unsigned char *b64_decode(const char *s, size_t *n)
{
    size_t len = strlen(s);
    unsigned char *out = malloc(len / 4 * 3 + 3);
    unsigned acc = 0;
    int bits = 0;
    *n = 0;
    for (const char *p = s; *p; ++p) {
        int v;
        if (*p >= 'A' && *p <= 'Z') v = *p - 'A';
        else if (*p >= 'a' && *p <= 'z') v = *p - 'a' + 26;
        else if (*p >= '0' && *p <= '9') v = *p - '0' + 52;
        else if (*p == '+') v = 62;
        else if (*p == '/') v = 63;
        else continue; /* whitespace and '=' padding */
        acc = (acc << 6) | (unsigned)v;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out[(*n)++] = (unsigned char)(acc >> bits);
            acc &= (1u << bits) - 1;
        }
    }
    return out;
}

/* Decodes a binary DataArray; checks its UInt32 header equals the payload size. */
static unsigned char *binary_payload(xmlDocPtr doc, const char *expr, size_t *n)
{
    char *s = value_of(doc, expr);
    ck_assert_ptr_nonnull(s);
    size_t total;
    unsigned char *raw = b64_decode(s, &total);
    free(s);
    ck_assert_uint_ge(total, 4);
    uint32_t header;
    memcpy(&header, raw, 4);
    ck_assert_uint_eq(header, total - 4);
    *n = total - 4;
    memmove(raw, raw + 4, *n);
    return raw;
}

/* ---- a small mesh with awkward numbers ----------------------------------- */

static const int tets[] = {0, 1, 2, 3, 1, 2, 3, 4};
static const int tris[] = {0, 1, 4};
static double xyz[15], vel[15], press[5];

static void fill_mesh(void)
{
    const double special[] = {1.0 / 3.0, -0.0, 1e-300, DBL_MAX, M_PI, DBL_TRUE_MIN, -2.5e17,
                              0.1 + 0.2};
    for (int i = 0; i < 15; ++i) {
        xyz[i] = i < 8 ? special[i] : sin(i) * 1e3;
        vel[i] = -cos(3.0 * i) / 7.0;
    }
    for (int i = 0; i < 5; ++i) press[i] = exp(i) - 1.0 / (i + 3.0);
}

static const char *pressure_name = "pressure & <temp> \"p\"";

static void write_mesh(const char *path, int binary)
{
    fill_mesh();
    pl_vtu_array pd[2] = {{"velocity", 3, vel}, {pressure_name, 1, press}};
    pl_error err;
    ck_assert_int_eq(pl_vtu_write(path, 5, xyz, 2, tets, 1, tris, pd, 2, binary, &err), PL_OK);
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    ck_assert_msg(!tu_exists(tmp), "the temporary file must be renamed away");
}

static void check_header(xmlDocPtr doc, int ncells)
{
    ck_assert_ptr_nonnull(doc);
    char *type = value_of(doc, "/VTKFile/@type"), *hdr = value_of(doc, "/VTKFile/@header_type");
    ck_assert_str_eq(type, "UnstructuredGrid");
    ck_assert_str_eq(hdr, "UInt32");
    free(type);
    free(hdr);
    ck_assert_int_eq(attr_long(doc, "//Piece/@NumberOfPoints"), 5);
    ck_assert_int_eq(attr_long(doc, "//Piece/@NumberOfCells"), ncells);
    ck_assert_int_eq(attr_long(doc, "//Points/DataArray/@NumberOfComponents"), 3);
    ck_assert_int_eq(count_nodes(doc, "//PointData/DataArray"), 2);
    ck_assert_int_eq(attr_long(doc, "//PointData/DataArray[@Name='velocity']/@NumberOfComponents"),
                     3);
    /* the escaped name comes back intact through a real XML parser */
    char *name = value_of(doc, "//PointData/DataArray[2]/@Name");
    ck_assert_str_eq(name, pressure_name);
    free(name);
}

START_TEST(vtu_ascii_round_trips_every_double_and_cell)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "mesh.vtu");
    write_mesh(path, 0);
    xmlDocPtr doc = parse(path);
    check_header(doc, 3);
    double v[32];
    ck_assert_int_eq(ascii_doubles(doc, "//Points/DataArray", v, 32), 15);
    ck_assert_mem_eq(v, xyz, sizeof xyz); /* %.17g is exact, -0.0 and subnormals included */
    ck_assert_int_eq(ascii_doubles(doc, "//PointData/DataArray[@Name='velocity']", v, 32), 15);
    ck_assert_mem_eq(v, vel, sizeof vel);
    ck_assert_int_eq(ascii_doubles(doc, "//PointData/DataArray[2]", v, 32), 5);
    ck_assert_mem_eq(v, press, sizeof press);
    const double conn[] = {0, 1, 2, 3, 1, 2, 3, 4, 0, 1, 4}, offs[] = {4, 8, 11},
                 types[] = {10, 10, 5};
    ck_assert_int_eq(ascii_doubles(doc, "//Cells/DataArray[@Name='connectivity']", v, 32), 11);
    ck_assert_mem_eq(v, conn, sizeof conn);
    ck_assert_int_eq(ascii_doubles(doc, "//Cells/DataArray[@Name='offsets']", v, 32), 3);
    ck_assert_mem_eq(v, offs, sizeof offs);
    ck_assert_int_eq(ascii_doubles(doc, "//Cells/DataArray[@Name='types']", v, 32), 3);
    ck_assert_mem_eq(v, types, sizeof types);
    xmlFreeDoc(doc);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(vtu_binary_base64_decodes_to_the_raw_arrays)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "mesh.vtu");
    write_mesh(path, 1);
    xmlDocPtr doc = parse(path);
    check_header(doc, 3);
    char *fmt = value_of(doc, "//Points/DataArray/@format");
    ck_assert_str_eq(fmt, "binary");
    free(fmt);
    size_t n;
    unsigned char *raw = binary_payload(doc, "//Points/DataArray", &n);
    ck_assert_uint_eq(n, sizeof xyz);
    ck_assert_mem_eq(raw, xyz, sizeof xyz);
    free(raw);
    raw = binary_payload(doc, "//PointData/DataArray[@Name='velocity']", &n);
    ck_assert_uint_eq(n, sizeof vel);
    ck_assert_mem_eq(raw, vel, sizeof vel);
    free(raw);
    raw = binary_payload(doc, "//PointData/DataArray[2]", &n);
    ck_assert_uint_eq(n, sizeof press);
    ck_assert_mem_eq(raw, press, sizeof press);
    free(raw);
    const int32_t conn[] = {0, 1, 2, 3, 1, 2, 3, 4, 0, 1, 4}, offs[] = {4, 8, 11};
    const uint8_t types[] = {10, 10, 5};
    raw = binary_payload(doc, "//Cells/DataArray[@Name='connectivity']", &n);
    ck_assert_uint_eq(n, sizeof conn);
    ck_assert_mem_eq(raw, conn, sizeof conn);
    free(raw);
    raw = binary_payload(doc, "//Cells/DataArray[@Name='offsets']", &n);
    ck_assert_uint_eq(n, sizeof offs);
    ck_assert_mem_eq(raw, offs, sizeof offs);
    free(raw);
    raw = binary_payload(doc, "//Cells/DataArray[@Name='types']", &n);
    ck_assert_uint_eq(n, sizeof types);
    ck_assert_mem_eq(raw, types, sizeof types);
    free(raw);
    char *tp = value_of(doc, "//Cells/DataArray[@Name='types']/@type");
    ck_assert_str_eq(tp, "UInt8");
    free(tp);
    xmlFreeDoc(doc);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Base64 of every length modulo 3 (padding "=", "==" and none). */
START_TEST(vtu_binary_padding_for_every_length)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "pts.vtu");
    double pts[3 * 4];
    for (int i = 0; i < 12; ++i) pts[i] = i * 0.25 - 1.0;
    for (int nv = 1; nv <= 4; ++nv) {
        double s[4];
        for (int i = 0; i < nv; ++i) s[i] = 1.0 / (i + 1);
        pl_vtu_array pd = {"s", 1, s};
        pl_error err;
        ck_assert_int_eq(pl_vtu_write(path, nv, pts, 0, NULL, 0, NULL, &pd, 1, 1, &err), PL_OK);
        xmlDocPtr doc = parse(path);
        ck_assert_ptr_nonnull(doc);
        size_t n;
        /* types: nv bytes + 4 header bytes covers all three paddings */
        unsigned char *raw = binary_payload(doc, "//Cells/DataArray[@Name='types']", &n);
        ck_assert_uint_eq(n, (size_t)nv);
        for (int i = 0; i < nv; ++i) ck_assert_uint_eq(raw[i], 1);
        free(raw);
        raw = binary_payload(doc, "//PointData/DataArray", &n);
        ck_assert_mem_eq(raw, s, (size_t)nv * sizeof(double));
        free(raw);
        xmlFreeDoc(doc);
    }
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(vtu_without_cells_writes_vertex_cells)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "pts.vtu");
    double pts[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    pl_error err;
    ck_assert_int_eq(pl_vtu_write(path, 4, pts, 0, NULL, 0, NULL, NULL, 0, 0, &err), PL_OK);
    xmlDocPtr doc = parse(path);
    ck_assert_ptr_nonnull(doc);
    ck_assert_int_eq(attr_long(doc, "//Piece/@NumberOfCells"), 4);
    double v[8];
    const double conn[] = {0, 1, 2, 3}, offs[] = {1, 2, 3, 4}, types[] = {1, 1, 1, 1};
    ck_assert_int_eq(ascii_doubles(doc, "//Cells/DataArray[@Name='connectivity']", v, 8), 4);
    ck_assert_mem_eq(v, conn, sizeof conn);
    ck_assert_int_eq(ascii_doubles(doc, "//Cells/DataArray[@Name='offsets']", v, 8), 4);
    ck_assert_mem_eq(v, offs, sizeof offs);
    ck_assert_int_eq(ascii_doubles(doc, "//Cells/DataArray[@Name='types']", v, 8), 4);
    ck_assert_mem_eq(v, types, sizeof types);
    ck_assert_int_eq(count_nodes(doc, "//PointData/DataArray"), 0);
    xmlFreeDoc(doc);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(vtu_rejects_bad_indices_and_leaves_no_file)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "bad.vtu");
    double pts[12] = {0};
    const int bad_tet[] = {0, 1, 2, 4}, bad_tri[] = {0, -1, 2};
    pl_error err;
    ck_assert_int_eq(pl_vtu_write(path, 4, pts, 1, bad_tet, 0, NULL, NULL, 0, 0, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "tetrahedron 0 uses vertex 4"));
    ck_assert_int_eq(pl_vtu_write(path, 4, pts, 0, NULL, 1, bad_tri, NULL, 0, 1, &err), PL_EINPUT);
    ck_assert_ptr_nonnull(strstr(err.msg, "vertex -1"));
    pl_vtu_array no_name = {NULL, 3, pts};
    ck_assert_int_eq(pl_vtu_write(path, 4, pts, 0, NULL, 0, NULL, &no_name, 1, 0, &err), PL_EINPUT);
    ck_assert(!tu_exists(path));
    ck_assert(!tu_exists(tu_path(dir, "bad.vtu.tmp")));
    /* a folder that does not exist is the user's input error */
    ck_assert_int_eq(pl_vtu_write(tu_path(dir, "no/such/x.vtu"), 4, pts, 0, NULL, 0, NULL, NULL,
                                  0, 0, &err),
                     PL_EINPUT);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(vtu_overwrite_replaces_the_whole_frame)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "m.vtu");
    write_mesh(path, 0);
    double pts[6] = {1, 2, 3, 4, 5, 6};
    pl_error err;
    ck_assert_int_eq(pl_vtu_write(path, 2, pts, 0, NULL, 0, NULL, NULL, 0, 0, &err), PL_OK);
    xmlDocPtr doc = parse(path);
    ck_assert_int_eq(attr_long(doc, "//Piece/@NumberOfPoints"), 2);
    double v[16];
    ck_assert_int_eq(ascii_doubles(doc, "//Points/DataArray", v, 16), 6);
    ck_assert_mem_eq(v, pts, sizeof pts);
    xmlFreeDoc(doc);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* ---- PVD ----------------------------------------------------------------- */

static void check_series(const char *path, int n, const double *times, const char *const *files)
{
    xmlDocPtr doc = parse(path);
    ck_assert_msg(doc != NULL, "the .pvd must be well-formed after every call");
    char *type = value_of(doc, "/VTKFile/@type");
    ck_assert_str_eq(type, "Collection");
    free(type);
    ck_assert_int_eq(count_nodes(doc, "/VTKFile/Collection/DataSet"), n);
    for (int i = 0; i < n; ++i) {
        char expr[128];
        snprintf(expr, sizeof expr, "/VTKFile/Collection/DataSet[%d]/@timestep", i + 1);
        char *t = value_of(doc, expr);
        double tv = strtod(t, NULL);
        ck_assert_mem_eq(&tv, &times[i], sizeof tv);
        free(t);
        snprintf(expr, sizeof expr, "/VTKFile/Collection/DataSet[%d]/@file", i + 1);
        char *f = value_of(doc, expr);
        ck_assert_str_eq(f, files[i]);
        free(f);
    }
    xmlFreeDoc(doc);
}

START_TEST(pvd_is_valid_after_every_append_and_resumes)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "bar.pvd");
    const double times[] = {0.0, 0.1 + 0.2, 1.0 / 3.0, 7.5};
    const char *const files[] = {"bar_0000.vtu", "a&b <c>_0001.vtu", "bar_0002.vtu", "bar_0003.vtu"};
    pl_error err;
    pl_pvd *s = pl_pvd_open(path, 0, &err);
    ck_assert_ptr_nonnull(s);
    check_series(path, 0, times, files);
    for (int i = 0; i < 3; ++i) {
        ck_assert_int_eq(pl_pvd_append(s, times[i], files[i], &err), PL_OK);
        check_series(path, i + 1, times, files);
    }
    ck_assert_int_eq(pl_pvd_close(s, &err), PL_OK);
    check_series(path, 3, times, files);
    /* append-open keeps the three entries and adds after them */
    s = pl_pvd_open(path, 1, &err);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(pl_pvd_count(s), 3);
    ck_assert_int_eq(pl_pvd_append(s, times[3], files[3], &err), PL_OK);
    ck_assert_int_eq(pl_pvd_count(s), 4);
    ck_assert_int_eq(pl_pvd_close(s, &err), PL_OK);
    check_series(path, 4, times, files);
    /* a plain open starts over */
    s = pl_pvd_open(path, 0, &err);
    ck_assert_int_eq(pl_pvd_count(s), 0);
    ck_assert_int_eq(pl_pvd_close(s, &err), PL_OK);
    check_series(path, 0, times, files);
    /* append-open of a missing file starts a new series */
    s = pl_pvd_open(tu_path(dir, "new.pvd"), 1, &err);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(pl_pvd_close(s, &err), PL_OK);
    check_series(tu_path(dir, "new.pvd"), 0, times, files);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(pvd_refuses_to_append_to_a_foreign_file)
{
    char *dir = tu_tmpdir();
    const char *path = tu_path(dir, "other.pvd");
    ck_assert_int_eq(tu_write_file(path, "<VTKFile type=\"Collection\"><Collection/></VTKFile>\n"), 0);
    pl_error err;
    ck_assert_ptr_null(pl_pvd_open(path, 1, &err));
    ck_assert_int_eq(err.code, PL_EINPUT);
    size_t n;
    char *text = tu_read_file(path, &n);
    ck_assert_str_eq(text, "<VTKFile type=\"Collection\"><Collection/></VTKFile>\n"); /* untouched */
    free(text);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("export_vtu");
    TCase *tc = tcase_create("vtu");
    tcase_add_test(tc, vtu_ascii_round_trips_every_double_and_cell);
    tcase_add_test(tc, vtu_binary_base64_decodes_to_the_raw_arrays);
    tcase_add_test(tc, vtu_binary_padding_for_every_length);
    tcase_add_test(tc, vtu_without_cells_writes_vertex_cells);
    tcase_add_test(tc, vtu_rejects_bad_indices_and_leaves_no_file);
    tcase_add_test(tc, vtu_overwrite_replaces_the_whole_frame);
    suite_add_tcase(s, tc);
    TCase *tp = tcase_create("pvd");
    tcase_add_test(tp, pvd_is_valid_after_every_append_and_resumes);
    tcase_add_test(tp, pvd_refuses_to_append_to_a_foreign_file);
    suite_add_tcase(s, tp);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    xmlCleanupParser();
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
