/* vtu_data.c - one VTU <DataArray>: format="ascii" text, or format="binary"
 * base64 with a UInt32/UInt64 byte-count header, optionally made of
 * zlib-compressed blocks (compressor="vtkZLibDataCompressor").
 *
 * VTK writes the header and the data either as one base64 stream or as two
 * (each with its own '=' padding).  Decoding quad by quad and letting '='
 * end a segment handles both the same way.  Sizes announced by the header
 * are checked against the expected value count before anything is
 * allocated, so a hostile header cannot trigger a huge allocation or a zlib
 * bomb. */
#include "vtu_data.h"

#include "pliant/checked.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>

/* zlib's deflate cannot compress better than about 1032:1. */
#define ZLIB_MAX_RATIO 1032

typedef struct vtu_type {
    const char *name;
    int size, is_float, is_signed;
} vtu_type;

static const vtu_type types[] = {
    {"Int8", 1, 0, 1},   {"UInt8", 1, 0, 0},  {"Int16", 2, 0, 1},   {"UInt16", 2, 0, 0},
    {"Int32", 4, 0, 1},  {"UInt32", 4, 0, 0}, {"Int64", 8, 0, 1},   {"UInt64", 8, 0, 0},
    {"Float32", 4, 1, 1}, {"Float64", 8, 1, 1}, {NULL, 0, 0, 0}};

/* The array's name for messages ("Points" arrays often have none). */
static void array_label(xmlNode *node, char *buf, size_t cap)
{
    xmlChar *name = xmlGetProp(node, (const xmlChar *)"Name");
    snprintf(buf, cap, "%s%s%s", name ? "'" : "", name ? (const char *)name : "(unnamed)",
             name ? "'" : "");
    xmlFree(name);
}

static int b64_value(int c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

/* Decodes base64 text (whitespace ignored, '=' ends a segment) into out,
 * which has room for 3/4 of len; returns the byte count or -1. */
static long long b64_decode(const char *s, size_t len, unsigned char *out)
{
    long long n = 0;
    int quad[4], q = 0, pad = 0;
    for (size_t i = 0; i < len; ++i) {
        int c = (unsigned char)s[i];
        if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
        int v = c == '=' ? 0 : b64_value(c);
        if (v < 0 || (pad && c != '=')) return -1;
        if (c == '=') {
            if (q < 2) return -1;
            pad++;
        }
        quad[q++] = v;
        if (q < 4) continue;
        unsigned u = (unsigned)quad[0] << 18 | (unsigned)quad[1] << 12 | (unsigned)quad[2] << 6 |
                     (unsigned)quad[3];
        out[n++] = (unsigned char)(u >> 16);
        if (pad < 2) out[n++] = (unsigned char)(u >> 8);
        if (pad < 1) out[n++] = (unsigned char)u;
        q = pad = 0;
    }
    return q == 0 ? n : -1;
}

/* Converts raw value i of type ty to double or long long. */
static void convert(const unsigned char *p, const vtu_type *ty, int big, int as_int, void *out,
                    long long i)
{
    const unsigned char *q = p + (size_t)i * (size_t)ty->size;
    long long iv = 0;
    double dv;
    if (ty->is_float) {
        dv = ty->size == 4 ? pl_io_f32(q, big) : pl_io_f64(q, big);
        ((double *)out)[i] = dv; /* float arrays are only read as doubles */
        return;
    }
    uint64_t u = ty->size == 1   ? q[0]
                 : ty->size == 2 ? (uint64_t)(big ? (q[0] << 8 | q[1]) : (q[1] << 8 | q[0]))
                 : ty->size == 4 ? pl_io_u32(q, big)
                                 : pl_io_u64(q, big);
    if (ty->is_signed) { /* sign-extend from size bytes */
        int bits = 8 * ty->size;
        if (bits < 64 && (u >> (bits - 1)) & 1) u |= ~(uint64_t)0 << bits;
        iv = (long long)u;
    } else
        iv = u > (uint64_t)LLONG_MAX ? LLONG_MAX : (long long)u;
    if (as_int) ((long long *)out)[i] = iv;
    else ((double *)out)[i] = (double)iv;
}

/* Allocates room for n doubles or long longs (same size). */
static int alloc_values(pl_text *t, long long n, void **out)
{
    size_t bytes;
    *out = n < 0 || pl_array_bytes((uint64_t)n, sizeof(double), 1, &bytes) ? NULL : malloc(bytes);
    return *out ? PL_OK : pl_io_nomem(t);
}

/* Parses n whitespace-separated numbers; exactly n must be present. */
static int read_ascii(pl_text *t, const char *text, int line, const char *label, long long n,
                      int as_int, void **outp)
{
    pl_text a;
    pl_io_text_init(&a, t->path, text, strlen(text), line, t->diag);
    if ((unsigned long long)n > (a.size + 1) / 2)
        return pl_io_fail_at(t, line, "DataArray %s declares %lld values but its %zu characters "
                             "can hold at most %zu", label, n, a.size, (a.size + 1) / 2);
    if (alloc_values(t, n, outp)) return PL_EINTERNAL;
    void *out = *outp;
    for (long long i = 0; i < n; ++i) {
        if (pl_io_at_eof(&a))
            return pl_io_fail_at(t, line, "DataArray %s ends after %lld values: expected %lld",
                                 label, i, n);
        int rc = as_int ? pl_io_read_int(&a, (long long *)out + i, "an integer", PL_IO_ANY_LINE)
                        : pl_io_read_double(&a, (double *)out + i, "a number", PL_IO_ANY_LINE);
        if (rc) return rc;
    }
    if (!pl_io_at_eof(&a))
        return pl_io_fail_at(t, line, "DataArray %s holds more than the expected %lld values",
                             label, n);
    return PL_OK;
}

/* Reads header word k (0: block count, 1: block size, 2: last block size,
 * 3 + b: compressed size of block b). */
static uint64_t header_word(const vtu_format *f, const unsigned char *d, uint64_t k)
{
    int hs = f->header64 ? 8 : 4;
    const unsigned char *p = d + k * (uint64_t)hs;
    return f->header64 ? pl_io_u64(p, f->big_endian) : pl_io_u32(p, f->big_endian);
}

/* Checks a compressed array's header against the `need` bytes expected and
 * the `len` bytes decoded; sets *nb, the block count.  Every sum and product
 * of header values is checked (pliant/checked.h): with 64-bit headers,
 * (nb - 1) * bs + last could otherwise wrap around to exactly `need` while
 * each block claims 2^63 bytes, and uncompress() would write past the
 * buffer. */
static int check_blocks(pl_text *t, int line, const char *label, const vtu_format *f,
                        const unsigned char *d, long long len, long long need, uint64_t *nbp)
{
    int hs = f->header64 ? 8 : 4;
    if (len < 3 * hs)
        return pl_io_fail_at(t, line, "DataArray %s: compressed header is truncated", label);
    uint64_t nb = header_word(f, d, 0), bs = header_word(f, d, 1), last = header_word(f, d, 2);
    if (nb > (uint64_t)(len / hs) - 3 || (nb > 0 && bs == 0) || last > bs)
        return pl_io_fail_at(t, line, "DataArray %s: corrupt compressed header", label);
    uint64_t total = 0, sum = 0, bound;
    if (nb && pl_muladd_u64(nb - 1, bs, last ? last : bs, &total))
        return pl_io_fail_at(t, line, "DataArray %s: corrupt compressed header (%llu blocks of "
                             "%llu bytes overflow)", label, (unsigned long long)nb,
                             (unsigned long long)bs);
    if (total != (uint64_t)need)
        return pl_io_fail_at(t, line, "DataArray %s: compressed blocks hold %llu bytes, expected "
                             "%lld", label, (unsigned long long)total, need);
    uint64_t left = (uint64_t)len - (3 + nb) * (uint64_t)hs; /* nb <= len / hs - 3 */
    for (uint64_t b = 0; b < nb; ++b)
        if (pl_add_u64(sum, header_word(f, d, 3 + b), &sum) || sum > left)
            return pl_io_fail_at(t, line, "DataArray %s: the compressed blocks announce more "
                                 "than the %llu bytes present", label, (unsigned long long)left);
    if (pl_muladd_u64(ZLIB_MAX_RATIO, sum, 64, &bound) || (uint64_t)need > bound)
        return pl_io_fail_at(t, line, "DataArray %s: the compressed blocks (%llu bytes) cannot "
                             "hold %lld bytes", label, (unsigned long long)sum, need);
    *nbp = nb;
    return PL_OK;
}

/* Inflates the blocks of a compressed array into *out (need bytes, which
 * this allocates once the header has been checked). */
static int inflate_blocks(pl_text *t, int line, const char *label, const vtu_format *f,
                          const unsigned char *d, long long len, unsigned char **out,
                          long long need)
{
    uint64_t nb = 0;
    if (check_blocks(t, line, label, f, d, len, need, &nb)) return PL_EINPUT;
    int hs = f->header64 ? 8 : 4;
    uint64_t bs = header_word(f, d, 1), last = header_word(f, d, 2);
    unsigned char *raw = malloc((size_t)need + 1);
    if (!raw) return pl_io_nomem(t);
    *out = raw;
    const unsigned char *c = d + (3 + nb) * (uint64_t)hs;
    for (uint64_t b = 0; b < nb; ++b) {
        uint64_t cs = header_word(f, d, 3 + b); /* their sum fits in what is left */
        uLongf want = (uLongf)(b + 1 < nb || !last ? bs : last), got = want;
        if (uncompress(raw, &got, c, (uLong)cs) != Z_OK || got != want)
            return pl_io_fail_at(t, line, "DataArray %s: zlib block %llu is corrupt", label,
                                 (unsigned long long)b);
        raw += want;
        c += cs;
    }
    return PL_OK;
}

/* Decodes a format="binary" array into n values. */
static int read_binary(pl_text *t, const vtu_format *f, const char *text, int line,
                       const char *label, const vtu_type *ty, long long n, int as_int,
                       void **out)
{
    size_t len = strlen(text);
    int hs = f->header64 ? 8 : 4;
    /* refuse sizes the text cannot possibly hold before allocating them */
    long long need, cap = (long long)(len / 4 * 3 + 3), most = LLONG_MAX;
    if (pl_mul_i64(cap, f->zlib ? ZLIB_MAX_RATIO : 1, &most) || pl_mul_i64(n, ty->size, &need) ||
        need > most)
        return pl_io_fail_at(t, line, "DataArray %s declares %lld values but holds at most %lld "
                             "bytes of data", label, n, most);
    unsigned char *d = malloc((size_t)cap + 1), *raw = NULL;
    int rc = PL_OK;
    if (!d) rc = pl_io_nomem(t);
    long long dl = rc ? 0 : b64_decode(text, len, d);
    if (rc == PL_OK && dl < 0)
        rc = pl_io_fail_at(t, line, "DataArray %s: invalid base64 data", label);
    const unsigned char *src = d + hs;
    if (rc == PL_OK && f->zlib) {
        rc = inflate_blocks(t, line, label, f, d, dl, &raw, need);
        src = raw;
    } else if (rc == PL_OK) {
        unsigned long long nbytes = dl < hs ? 0
                                    : f->header64 ? pl_io_u64(d, f->big_endian)
                                                  : pl_io_u32(d, f->big_endian);
        if (dl < hs || nbytes > (unsigned long long)(dl - hs))
            rc = pl_io_fail_at(t, line, "DataArray %s is truncated: its header announces %llu "
                               "bytes, %lld are present", label, nbytes, dl < hs ? 0 : dl - hs);
        else if (nbytes != (unsigned long long)need)
            rc = pl_io_fail_at(t, line, "DataArray %s holds %llu values of %s, expected %lld",
                               label, nbytes / (unsigned)ty->size, ty->name, n);
    }
    if (rc == PL_OK) rc = alloc_values(t, n, out); /* only once the data is known to be there */
    for (long long i = 0; rc == PL_OK && i < n; ++i)
        convert(src, ty, f->big_endian, as_int, *out, i);
    free(d);
    free(raw);
    return rc;
}

/* The array's own text: VTK 9 nests <InformationKey> elements (with
 * numbers of their own) inside DataArrays, so only direct text children
 * count.  Returns a malloc'ed string or NULL when out of memory. */
static char *own_text(xmlNode *node)
{
    size_t n = 0;
    for (xmlNode *c = node->children; c; c = c->next)
        if ((c->type == XML_TEXT_NODE || c->type == XML_CDATA_SECTION_NODE) && c->content)
            n += strlen((const char *)c->content);
    char *s = malloc(n + 1), *p = s;
    if (!s) return NULL;
    for (xmlNode *c = node->children; c; c = c->next)
        if ((c->type == XML_TEXT_NODE || c->type == XML_CDATA_SECTION_NODE) && c->content) {
            size_t k = strlen((const char *)c->content);
            memcpy(p, c->content, k);
            p += k;
        }
    *p = '\0';
    return s;
}

int pl_io_vtu_array(pl_text *t, const vtu_format *f, xmlNode *node, long long n, int as_int,
                    void **out)
{
    char label[96];
    *out = NULL;
    int line = (int)xmlGetLineNo(node);
    array_label(node, label, sizeof label);
    xmlChar *type = xmlGetProp(node, (const xmlChar *)"type");
    xmlChar *format = xmlGetProp(node, (const xmlChar *)"format");
    const vtu_type *ty = NULL;
    for (int k = 0; type && types[k].name; ++k)
        if (strcmp((const char *)type, types[k].name) == 0) ty = &types[k];
    int rc = PL_OK;
    if (!ty)
        rc = pl_io_fail_at(t, line, "DataArray %s has type '%s': expected Int8..Int64, "
                           "UInt8..UInt64, Float32 or Float64", label,
                           type ? (const char *)type : "(missing)");
    else if (as_int && ty->is_float)
        rc = pl_io_fail_at(t, line, "DataArray %s has type %s: expected an integer type", label,
                           ty->name);
    char *text = rc ? NULL : own_text(node);
    if (rc == PL_OK && !text) rc = pl_io_nomem(t);
    const char *fmt = format ? (const char *)format : "(missing)";
    if (rc == PL_OK && strcasecmp(fmt, "ascii") == 0)
        rc = read_ascii(t, text, line, label, n, as_int, out);
    else if (rc == PL_OK && strcasecmp(fmt, "binary") == 0)
        rc = read_binary(t, f, text, line, label, ty, n, as_int, out);
    else if (rc == PL_OK)
        rc = pl_io_fail_at(t, line, "DataArray %s has format '%s': expected ascii or binary "
                           "(appended data is not supported; re-save the file with inline data)",
                           label, fmt);
    for (long long i = 0; rc == PL_OK && !as_int && i < n; ++i)
        if (!isfinite(((double *)*out)[i]))
            rc = pl_io_fail_at(t, line, "DataArray %s value %lld is not finite", label, i);
    free(text);
    if (rc) {
        free(*out);
        *out = NULL;
    }
    xmlFree(type);
    xmlFree(format);
    return rc;
}
