/* vtu_writer.c - one frame as a VTK XML unstructured grid (.vtu).
 *
 * Layout (VTK file formats, "UnstructuredGrid"): Piece with PointData,
 * Points (Float64 x 3) and Cells (connectivity Int32, offsets Int32 = end of
 * each cell in connectivity, types UInt8).  The "binary" flavour is inline
 * base64 of [UInt32 byte count][raw array], encoded as one stream and kept
 * on one line (VTK's base64 reader does not skip line breaks). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"
#include "export/export_internal.h"

enum { VTK_VERTEX = 1, VTK_LINE = 3, VTK_TRIANGLE = 5, VTK_TETRA = 10 };

/* ---- base64 to a stream -------------------------------------------------- */

typedef struct b64_out {
    FILE *f;
    unsigned char carry[3]; /* bytes waiting for a full triplet */
    int ncarry;
    char buf[4096];
    size_t nbuf;
    int failed;
} b64_out;

static const char b64_alphabet[] =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void b64_flush(b64_out *o)
{
    if (o->nbuf && fwrite(o->buf, 1, o->nbuf, o->f) != o->nbuf) o->failed = 1;
    o->nbuf = 0;
}

static void b64_quad(b64_out *o, const unsigned char t[3], int n)
{
    if (o->nbuf + 4 > sizeof o->buf) b64_flush(o);
    unsigned v = (unsigned)t[0] << 16 | (unsigned)(n > 1 ? t[1] : 0) << 8 | (n > 2 ? t[2] : 0);
    char *q = o->buf + o->nbuf;
    q[0] = b64_alphabet[(v >> 18) & 63];
    q[1] = b64_alphabet[(v >> 12) & 63];
    q[2] = n > 1 ? b64_alphabet[(v >> 6) & 63] : '=';
    q[3] = n > 2 ? b64_alphabet[v & 63] : '=';
    o->nbuf += 4;
}

static void b64_put(b64_out *o, const void *data, size_t n)
{
    const unsigned char *p = data;
    while (n > 0) {
        o->carry[o->ncarry++] = *p++;
        --n;
        if (o->ncarry == 3) {
            b64_quad(o, o->carry, 3);
            o->ncarry = 0;
        }
    }
}

static void b64_end(b64_out *o)
{
    if (o->ncarry) b64_quad(o, o->carry, o->ncarry);
    o->ncarry = 0;
    b64_flush(o);
}

/* ---- the arrays ---------------------------------------------------------- */

typedef enum { ARR_F64, ARR_I32, ARR_U8 } arr_type;

/* What a DataArray holds, produced element by element so that offsets and
 * types never need a temporary array. */
typedef struct cells_view {
    int nverts, ntets, ntris, nlines;
    const int *tets, *tris, *lines;
} cells_view;

static int no_cells(const cells_view *c)
{
    return !c->ntets && !c->ntris && !c->nlines;
}

static int cells_count(const cells_view *c)
{
    return no_cells(c) ? c->nverts : c->ntets + c->ntris + c->nlines;
}

static long conn_value(const cells_view *c, size_t i)
{
    if (no_cells(c)) return (long)i;
    size_t nt = (size_t)c->ntets * 4, nr = (size_t)c->ntris * 3;
    return i < nt ? c->tets[i] : i < nt + nr ? c->tris[i - nt] : c->lines[i - nt - nr];
}

static long offset_value(const cells_view *c, size_t i)
{
    if (no_cells(c)) return (long)i + 1;
    long nt = c->ntets, nr = c->ntris, k = (long)i;
    if (k < nt) return 4 * (k + 1);
    if (k < nt + nr) return 4 * nt + 3 * (k - nt + 1);
    return 4 * nt + 3 * nr + 2 * (k - nt - nr + 1);
}

static long type_value(const cells_view *c, size_t i)
{
    if (no_cells(c)) return VTK_VERTEX;
    long k = (long)i;
    return k < c->ntets ? VTK_TETRA : k < c->ntets + c->ntris ? VTK_TRIANGLE : VTK_LINE;
}

typedef long (*int_source)(const cells_view *c, size_t i);

static const char *type_name(arr_type t)
{
    return t == ARR_F64 ? "Float64" : t == ARR_I32 ? "Int32" : "UInt8";
}

static size_t type_size(arr_type t)
{
    return t == ARR_F64 ? 8 : t == ARR_I32 ? 4 : 1;
}

/* Opening tag of a DataArray; name may be NULL. */
static void array_open(FILE *f, arr_type t, const char *name, int ncomp, int binary)
{
    fprintf(f, "        <DataArray type=\"%s\"", type_name(t));
    if (name) {
        fputs(" Name=\"", f);
        pl_export_xml_attr(f, name);
        fputc('"', f);
    }
    if (ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", ncomp);
    fprintf(f, " format=\"%s\">\n", binary ? "binary" : "ascii");
}

/* count values from either doubles (dbl) or an integer source (src). */
static void array_body(FILE *f, arr_type t, const double *dbl, int_source src,
                       const cells_view *cv, size_t count, int per_line, int binary, int *failed)
{
    if (binary) {
        b64_out o = {.f = f};
        uint32_t header = (uint32_t)(count * type_size(t));
        fputs("          ", f);
        b64_put(&o, &header, sizeof header);
        if (dbl) {
            b64_put(&o, dbl, count * sizeof(double));
        } else {
            for (size_t i = 0; i < count; ++i) {
                long v = src(cv, i);
                if (t == ARR_I32) {
                    int32_t w = (int32_t)v;
                    b64_put(&o, &w, sizeof w);
                } else {
                    uint8_t w = (uint8_t)v;
                    b64_put(&o, &w, sizeof w);
                }
            }
        }
        b64_end(&o);
        if (o.failed) *failed = 1;
        fputc('\n', f);
    } else {
        for (size_t i = 0; i < count; ++i) {
            if (i % (size_t)per_line == 0) fputs("          ", f);
            if (dbl)
                fprintf(f, "%.17g", dbl[i]);
            else
                fprintf(f, "%ld", src(cv, i));
            fputc((i + 1) % (size_t)per_line == 0 || i + 1 == count ? '\n' : ' ', f);
        }
    }
    fputs("        </DataArray>\n", f);
}

/* ---- checks -------------------------------------------------------------- */

static int check_indices(const int *idx, int nelem, int per, int nverts, const char *what,
                         const char *path, pl_error *err)
{
    for (size_t i = 0; i < (size_t)nelem * (size_t)per; ++i)
        if (idx[i] < 0 || idx[i] >= nverts)
            return pl_error_set(err, PL_EINPUT, path, 0, NULL,
                                "%s %zu uses vertex %d; the mesh has %d vertices", what,
                                i / (size_t)per, idx[i], nverts);
    return PL_OK;
}

static int check_input(const char *path, int nverts, const double *xyz, const pl_vtu_cells *c,
                       const pl_vtu_array *pd, int npd, int binary, pl_error *err)
{
    if (!path || nverts < 0 || c->ntets < 0 || c->ntris < 0 || c->nlines < 0 || npd < 0 ||
        (nverts && !xyz) || (c->ntets && !c->tets) || (c->ntris && !c->tris) ||
        (c->nlines && !c->lines) || (npd && !pd))
        return pl_error_set(err, PL_EINPUT, path, 0, NULL, "invalid arguments to pl_vtu_write");
    /* connectivity and offsets are Int32, binary byte counts UInt32 */
    size_t nconn = (size_t)c->ntets * 4 + (size_t)c->ntris * 3 + (size_t)c->nlines * 2;
    size_t biggest = (size_t)nverts * 3 * sizeof(double);
    for (int k = 0; k < npd; ++k) {
        if (!pd[k].name || pd[k].ncomp < 1 || (nverts && !pd[k].values))
            return pl_error_set(err, PL_EINPUT, path, 0, NULL,
                                "point-data array %d needs a name, ncomp >= 1 and values", k);
        size_t b = (size_t)nverts * (size_t)pd[k].ncomp * sizeof(double);
        if (b > biggest) biggest = b;
    }
    if (nconn > INT32_MAX || (binary && (biggest > UINT32_MAX || nconn * 4 > UINT32_MAX)))
        return pl_error_set(err, PL_EINPUT, path, 0, NULL,
                            "mesh too large for a .vtu with 32-bit offsets");
    int rc = check_indices(c->tets, c->ntets, 4, nverts, "tetrahedron", path, err);
    if (rc == PL_OK) rc = check_indices(c->tris, c->ntris, 3, nverts, "triangle", path, err);
    if (rc == PL_OK) rc = check_indices(c->lines, c->nlines, 2, nverts, "line", path, err);
    return rc;
}

/* ---- the file ------------------------------------------------------------ */

static int host_is_little_endian(void)
{
    const uint16_t one = 1;
    return *(const unsigned char *)&one == 1;
}

static void write_body(FILE *f, int nverts, const double *xyz, const cells_view *cv,
                       const pl_vtu_array *pd, int npd, int binary, int *failed)
{
    int ncells = cells_count(cv);
    size_t nconn = no_cells(cv) ? (size_t)nverts
                                : (size_t)cv->ntets * 4 + (size_t)cv->ntris * 3 +
                                      (size_t)cv->nlines * 2;
    fprintf(f,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" "
            "header_type=\"UInt32\">\n"
            "  <UnstructuredGrid>\n"
            "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n",
            host_is_little_endian() ? "LittleEndian" : "BigEndian", nverts, ncells);
    fputs("      <PointData>\n", f);
    for (int k = 0; k < npd; ++k) {
        array_open(f, ARR_F64, pd[k].name, pd[k].ncomp, binary);
        array_body(f, ARR_F64, pd[k].values, NULL, cv, (size_t)nverts * (size_t)pd[k].ncomp,
                   pd[k].ncomp, binary, failed);
    }
    fputs("      </PointData>\n      <Points>\n", f);
    array_open(f, ARR_F64, "Points", 3, binary);
    array_body(f, ARR_F64, xyz, NULL, cv, (size_t)nverts * 3, 3, binary, failed);
    fputs("      </Points>\n      <Cells>\n", f);
    array_open(f, ARR_I32, "connectivity", 1, binary);
    array_body(f, ARR_I32, NULL, conn_value, cv, nconn,
               cv->ntets ? 4 : cv->ntris ? 3 : cv->nlines ? 2 : 12, binary, failed);
    array_open(f, ARR_I32, "offsets", 1, binary);
    array_body(f, ARR_I32, NULL, offset_value, cv, (size_t)ncells, 12, binary, failed);
    array_open(f, ARR_U8, "types", 1, binary);
    array_body(f, ARR_U8, NULL, type_value, cv, (size_t)ncells, 24, binary, failed);
    fputs("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n", f);
}

int pl_vtu_write(const char *path, int nverts, const double *xyz, int ntets, const int *tets,
                 int ntris, const int *tris, const pl_vtu_array *point_data, int npoint_data,
                 int binary, pl_error *err)
{
    pl_vtu_cells c = {ntets, tets, ntris, tris, 0, NULL};
    return pl_vtu_write_cells(path, nverts, xyz, &c, point_data, npoint_data, binary, err);
}

int pl_vtu_write_cells(const char *path, int nverts, const double *xyz, const pl_vtu_cells *c,
                       const pl_vtu_array *point_data, int npoint_data, int binary, pl_error *err)
{
    int rc = check_input(path, nverts, xyz, c, point_data, npoint_data, binary, err);
    if (rc != PL_OK) return rc;
    size_t n = strlen(path);
    char *tmp = malloc(n + 5);
    if (!tmp) return pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "out of memory");
    memcpy(tmp, path, n);
    memcpy(tmp + n, ".tmp", 5);
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot write '%s'", tmp);
        free(tmp);
        return PL_EINPUT;
    }
    cells_view cv = {nverts, c->ntets, c->ntris, c->nlines, c->tets, c->tris, c->lines};
    int failed = 0;
    write_body(f, nverts, xyz, &cv, point_data, npoint_data, binary, &failed);
    if (ferror(f)) failed = 1;
    if (fclose(f) != 0) failed = 1;
    if (failed || rename(tmp, path) != 0) {
        remove(tmp);
        free(tmp);
        return pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "writing the file failed");
    }
    free(tmp);
    return PL_OK;
}
