/* mesh_io.h - private helpers shared by the mesh loaders (not installed).
 *
 * Every loader reads a whole file from memory through a pl_text cursor that
 * knows the file name and the current line, so that each error can say
 * "file:line: expected X, found Y".  Counts declared by a file are checked
 * against what the rest of the file can possibly hold before anything is
 * allocated (pl_io_check_count), so a corrupt header cannot make us allocate
 * gigabytes. */
#ifndef PLIANT_IO_MESH_IO_H
#define PLIANT_IO_MESH_IO_H

#include <stddef.h>
#include <stdint.h>

#include "pliant/error.h"
#include "pliant/mesh.h"

/* Files larger than this are refused: no mesh we simulate comes close. */
#define PL_IO_MAX_FILE ((size_t)1 << 30)

/* Cross-file helpers of this folder stay out of libpliant's exported ABI. */
#define PL_IO_HIDDEN __attribute__((visibility("hidden")))

/* A read cursor over a NUL-terminated buffer. */
typedef struct pl_text {
    const char *path;   /* file name for messages */
    const char *buf;    /* contents; buf[size] == '\0' */
    size_t size, pos;
    int line;           /* 1-based line of buf[pos] */
    pl_diag *diag;
} pl_text;

enum { PL_IO_ANY_LINE = 0, PL_IO_SAME_LINE = 1 };

PL_IO_HIDDEN void pl_io_text_init(pl_text *t, const char *path, const char *buf, size_t size,
                                  int first_line, pl_diag *diag);
/* Appends PL_EINPUT at t's current line (or at line) and returns PL_EINPUT. */
PL_IO_HIDDEN int pl_io_fail(pl_text *t, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
PL_IO_HIDDEN int pl_io_fail_at(pl_text *t, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Appends PL_EINTERNAL (allocation failure) and returns it. */
PL_IO_HIDDEN int pl_io_nomem(pl_text *t);

/* Skips whitespace, newlines included. */
PL_IO_HIDDEN void pl_io_skip_ws(pl_text *t);
/* Skips blanks, tabs and carriage returns (stays on the line). */
PL_IO_HIDDEN void pl_io_skip_blank(pl_text *t);
/* True when only blanks remain on the current line (or the file ended). */
PL_IO_HIDDEN int pl_io_at_eol(pl_text *t);
/* True when nothing but whitespace remains. */
PL_IO_HIDDEN int pl_io_at_eof(pl_text *t);
/* Moves past the next newline (or to the end). */
PL_IO_HIDDEN void pl_io_next_line(pl_text *t);
/* Copies the next whitespace-delimited token into tok; returns its length,
 * 0 when there is none (end of file, or end of line with PL_IO_SAME_LINE),
 * -1 when it does not fit in cap bytes (it is skipped all the same). */
PL_IO_HIDDEN int pl_io_token(pl_text *t, char *tok, size_t cap, int same_line);
/* Reads an integer / a finite double; on failure says that `what` was expected. */
PL_IO_HIDDEN int pl_io_read_int(pl_text *t, long long *v, const char *what, int same_line);
PL_IO_HIDDEN int pl_io_read_double(pl_text *t, double *v, const char *what, int same_line);
/* Reads an integer in [lo, hi]. */
PL_IO_HIDDEN int pl_io_read_int_range(pl_text *t, long long *v, long long lo, long long hi,
                                      const char *what, int same_line);
/* Parses a whole token as a number; 0 on success. */
PL_IO_HIDDEN int pl_io_parse_int(const char *tok, long long *v);
PL_IO_HIDDEN int pl_io_parse_double(const char *tok, double *v);

/* Refuses a declared count that the remaining `bytes` cannot hold when every
 * item needs at least min_bytes, or that exceeds the index range; the error
 * names `line` (0: the current line). */
PL_IO_HIDDEN int pl_io_check_count(pl_text *t, int line, long long count, size_t bytes,
                                   size_t min_bytes, const char *what);
/* Bytes left from the cursor. */
static inline size_t pl_io_left(const pl_text *t) { return t->size - t->pos; }

/* Big- and little-endian decoding of binary fields. */
PL_IO_HIDDEN uint32_t pl_io_u32(const unsigned char *p, int big_endian);
PL_IO_HIDDEN uint64_t pl_io_u64(const unsigned char *p, int big_endian);
PL_IO_HIDDEN double pl_io_f32(const unsigned char *p, int big_endian);
PL_IO_HIDDEN double pl_io_f64(const unsigned char *p, int big_endian);

/* Reads a whole file; *buf is NUL-terminated and owned by the caller. */
PL_IO_HIDDEN int pl_io_read_file(const char *path, char **buf, size_t *size, pl_diag *diag);

/* A mesh under construction: arrays grow geometrically. */
typedef struct pl_mesh_build {
    pl_mesh *m;
    int cap_verts, cap_tets, cap_tris;
} pl_mesh_build;

PL_IO_HIDDEN void pl_io_build_init(pl_mesh_build *b, pl_mesh *m);
PL_IO_HIDDEN int pl_io_add_vert(pl_mesh_build *b, double x, double y, double z);
PL_IO_HIDDEN int pl_io_add_tet(pl_mesh_build *b, int a, int c, int d, int e);
PL_IO_HIDDEN int pl_io_add_tri(pl_mesh_build *b, int a, int c, int d);
/* Reserves room for n more of each (PL_OK or PL_EINTERNAL). */
PL_IO_HIDDEN int pl_io_reserve(pl_mesh_build *b, long long nverts, long long ntets,
                               long long ntris);

/* Counts of skipped cell kinds, reported as one warning. */
#define PL_IO_MAX_KINDS 256
typedef struct pl_io_skipped {
    long long count[PL_IO_MAX_KINDS];
    long long other;   /* kinds outside 0..PL_IO_MAX_KINDS-1 */
} pl_io_skipped;

PL_IO_HIDDEN void pl_io_skip_cell(pl_io_skipped *s, long long kind);
/* Warns "skipped N <name> (<family> type K), ... cells" when anything was skipped. */
PL_IO_HIDDEN void pl_io_report_skipped(pl_text *t, const pl_io_skipped *s, const char *family,
                                       const char *(*name)(int kind), const pl_mesh *kept);

/* The format readers: fill out (initialised, empty) from t; PL_OK or an error. */
PL_IO_HIDDEN int pl_io_load_vtk_legacy(pl_text *t, pl_mesh *out);
PL_IO_HIDDEN int pl_io_load_vtu(pl_text *t, pl_mesh *out);
PL_IO_HIDDEN int pl_io_load_gmsh(pl_text *t, pl_mesh *out);
PL_IO_HIDDEN int pl_io_load_gmsh4(pl_text *t, pl_mesh *out);
PL_IO_HIDDEN int pl_io_load_obj(pl_text *t, pl_mesh *out);
PL_IO_HIDDEN int pl_io_load_stl_ascii(pl_text *t, pl_mesh *out);
PL_IO_HIDDEN int pl_io_load_stl_binary(pl_text *t, pl_mesh *out);

/* VTK cell names shared by the legacy and XML readers. */
PL_IO_HIDDEN const char *pl_io_vtk_cell_name(int type);

#endif
