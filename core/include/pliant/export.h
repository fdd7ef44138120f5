/* export.h - output files and regression references, usable without a
 * scene (the built-in exporters and `pliant regress` use them):
 *   VTU      one frame of a mesh as a VTK XML unstructured grid (.vtu)
 *   PVD      a time series of frames for ParaView (.pvd)
 *   state    SOFA WriteState text files ("T= t" then "  X= ..." records)
 *   regression  SOFA's regression list format and its error measure
 *
 * Numbers are written and read in the C numeric locale (Pliant never calls
 * setlocale; a program that does must keep LC_NUMERIC at "C"). */
#ifndef PLIANT_EXPORT_H
#define PLIANT_EXPORT_H

#include "api.h"
#include <stddef.h>
#include "error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- VTU: one frame ------------------------------------------------------ */

/* A per-point array: nverts x ncomp doubles, row-major. */
typedef struct pl_vtu_array {
    const char *name;       /* shown in ParaView, e.g. "velocity" */
    int ncomp;              /* components per point (>= 1) */
    const double *values;
} pl_vtu_array;

/* Writes a .vtu (VTKFile UnstructuredGrid, version 1.0, header_type UInt32,
 * host byte order) with points xyz (nverts x 3), tetrahedra (VTK type 10)
 * then triangles (type 5), 0-based indices, and the given point data.  When
 * there are neither tetrahedra nor triangles every point becomes a vertex
 * cell (type 1) so that viewers show the points.  binary != 0 writes inline
 * base64 (UInt32 byte count then the raw array, encoded as one stream, no
 * compression); 0 writes ascii with %.17g (exact).  The file is written as
 * "<path>.tmp" and renamed, so a reader never sees half a frame.
 * PL_EINPUT for an index out of range or bad counts; PL_EINTERNAL on I/O. */
PL_API int pl_vtu_write(const char *path, int nverts, const double *xyz, int ntets, const int *tets,
                        int ntris, const int *tris, const pl_vtu_array *point_data, int npoint_data,
                        int binary, pl_error *err);

#if PL_ABI_TARGET_MINOR >= 2
/* Cells of a frame: tetrahedra, triangles, then line segments (VTK type 3). */
typedef struct pl_vtu_cells {
    int ntets;
    const int *tets;   /* ntets x 4 */
    int ntris;
    const int *tris;   /* ntris x 3 */
    int nlines;
    const int *lines;  /* nlines x 2 */
} pl_vtu_cells;

/* pl_vtu_write with line segments too (cable paths); points only (vertex
 * cells) when there is no cell.  Since ABI 5.2. */
PL_API int pl_vtu_write_cells(const char *path, int nverts, const double *xyz,
                              const pl_vtu_cells *c, const pl_vtu_array *point_data,
                              int npoint_data, int binary, pl_error *err);
#endif

/* ---- PVD: a time series -------------------------------------------------- */

typedef struct pl_pvd pl_pvd;

/* Opens a .pvd collection.  append != 0 continues a series this module wrote
 * before (its entries are kept; a missing file starts a new one); append == 0
 * truncates.  The file is complete and valid after every call (the footer is
 * rewritten after each entry), so ParaView can open it while a run goes on.
 * NULL on failure (err filled). */
PL_API pl_pvd *pl_pvd_open(const char *path, int append, pl_error *err);
/* Adds <DataSet timestep="time" part="0" file="file"/>; file is written as
 * given (relative to the .pvd's folder), XML-escaped. */
PL_API int pl_pvd_append(pl_pvd *s, double time, const char *file, pl_error *err);
#if PL_ABI_TARGET_MINOR >= 2
/* Same for part `part` of a multi-part series: ParaView shows the parts of
 * one time step together (a body, its obstacles, its cable, its contacts).
 * Since ABI 5.2. */
PL_API int pl_pvd_append_part(pl_pvd *s, double time, int part, const char *file,
                              pl_error *err);
#endif
/* Entries written through this handle (after an append-open: including the old ones). */
PL_API int pl_pvd_count(const pl_pvd *s);
/* Flushes, closes and frees s (NULL is a no-op). */
PL_API int pl_pvd_close(pl_pvd *s, pl_error *err);

/* ---- SOFA WriteState files ----------------------------------------------- */

/* One record: the time and the values that followed it.  nx / nv count
 * doubles (3 per vertex for a Vec3 state); 0 when the line was absent. */
typedef struct pl_state_record {
    double time;
    double *x;
    int nx;
    double *v;
    int nv;
} pl_state_record;

typedef struct pl_state_records {
    pl_state_record *items;
    int count, cap;
} pl_state_records;

PL_API void pl_state_records_init(pl_state_records *r);
PL_API void pl_state_records_free(pl_state_records *r);
/* Appends a deep copy of (time, x, v); x or v may be NULL with count 0. */
PL_API int pl_state_records_add(pl_state_records *r, double time, const double *x, int nx,
                                const double *v, int nv, pl_error *err);

/* Reads every record of a WriteState file, plain or gzip (detected from the
 * content).  Lines "T= t", "  X= ...", "  V= ..."; other "KEY= ..." lines
 * (X0=, F=) are skipped.  Records are appended to out (init it first).
 * PL_EINPUT with file:line for a malformed line. */
PL_API int pl_state_file_read(const char *path, pl_state_records *out, pl_error *err);

typedef struct pl_state_writer pl_state_writer;

/* Opens a WriteState file for writing, gzip-compressed when path ends in
 * ".gz" (as SOFA does).  append != 0 adds to an existing file.  NULL on failure. */
PL_API pl_state_writer *pl_state_writer_open(const char *path, int append, pl_error *err);
/* Writes "T= time\n", then "  X= x0 x1 ...\n" (nx values) when x != NULL and
 * then "  V= ...\n" (nv values) when v != NULL (a NULL array's count is
 * ignored), every number with %.17g so that reading it back gives the same
 * doubles bit for bit. */
PL_API int pl_state_writer_write(pl_state_writer *w, double time, const double *x, int nx,
                                 const double *v, int nv, pl_error *err);
/* Flushes, closes and frees w (NULL is a no-op). */
PL_API int pl_state_writer_close(pl_state_writer *w, pl_error *err);

/* ---- Regression lists and SOFA's error measure --------------------------- */

/* One line "scene steps epsilon [mapped] [lastonly]". */
typedef struct pl_regression_entry {
    char *scene;       /* scene path as written (relative to the list file) */
    int steps;         /* time steps to run (> 0) */
    double epsilon;    /* tolerance on the error by DoF (>= 0) */
    int mapped;        /* 1: also compare states under a mapping (default 0) */
    int last_only;     /* 1: the reference stores only the first and last step (default 0) */
    int line;          /* 1-based line in the list */
} pl_regression_entry;

typedef struct pl_regression_list {
    char *ref_dir;     /* SOFA's header line: the references folder, or NULL */
    pl_regression_entry *items;
    int count, cap;
} pl_regression_list;

/* Parses a regression list: '#' starts a comment (a whole line, or the rest
 * of a line after the fields), blank lines are skipped.  As in SOFA's
 * *.regression-tests files, a first non-comment line holding a single word
 * is the references folder.  Every malformed line is reported in diag with
 * `name` and its line number (all of them, not just the first); returns
 * PL_EINPUT if there was any.  out must be zeroed or freed before. */
PL_API int pl_regression_list_parse(const char *text, const char *name, pl_regression_list *out,
                                    pl_diag *diag);
/* Same, from a file. */
PL_API int pl_regression_list_load(const char *path, pl_regression_list *out, pl_diag *diag);
PL_API void pl_regression_list_free(pl_regression_list *l);

/* "<base>.reference_<k>_<name>_mstate.txt.gz" (SOFA's file of state k);
 * returns the length needed, as snprintf. */
PL_API int pl_regression_reference_path(char *buf, size_t size, const char *base, int k,
                                        const char *state_name);

/* ||x - x_ref||_2 / n over n doubles: one compared step of one state. */
PL_API double pl_regression_step_error(const double *x, const double *x_ref, int n);

typedef struct pl_regression_result {
    double error_by_dof;  /* mean over states of sum over compared steps of ||x - x_ref||_2 / nDoF */
    double total_error;   /* mean over states of sum over compared steps of ||x - x_ref||_2 */
    int compared;         /* (state, step) pairs compared */
    int missing;          /* reference steps with no current record within time_tol */
    int passed;           /* compared > 0, missing == 0, finite and error_by_dof <= epsilon */
} pl_regression_result;

/* SOFA's Regression measure.  ref[i] and cur[i] are the records of state i
 * (i < nstates).  Every reference record is matched to the current record
 * of the nearest time; they are compared when |t - t_ref| < time_tol (SOFA
 * uses dt / 2, as reference times are printed with 6 digits).  nDoF is the
 * number of doubles of the state (3 per vertex), as in SOFA.  States with no
 * values are skipped.  PL_EINPUT when a compared pair differs in size or an
 * argument is invalid. */
PL_API int pl_regression_compare(const pl_state_records *ref, const pl_state_records *cur,
                                 int nstates, double time_tol, double epsilon,
                                 pl_regression_result *res, pl_error *err);

#if PL_ABI_TARGET_MINOR >= 4 /* since 5.4 */
/* Why an entry fails, and how far a SOFA scene is from SOFA. */
typedef struct pl_regression_detail {
    /* the state with the largest error by DoF, and in it the largest vertex
     * distance over the compared steps */
    int worst_state;          /* -1: nothing compared */
    double worst_state_error; /* its sum over compared steps of ||x - x_ref||_2 / nDoF */
    int worst_vertex;
    double worst_distance;
    double worst_time;        /* the reference time where it is */
    int missing_state;        /* a state with a missing reference step (-1: none) */
    double missing_time;      /* the first such reference time */
    /* at the last reference time, the largest vertex distance divided by the
     * diagonal of the bounding box of the first reference record (the rest
     * shape), the largest over the states; NaN if nothing was compared */
    double last_relative;
    double last_time;
} pl_regression_detail;

/* pl_regression_compare, and what went wrong where into *why (may be NULL). */
PL_API int pl_regression_compare_detail(const pl_state_records *ref,
                                        const pl_state_records *cur, int nstates,
                                        double time_tol, double epsilon,
                                        pl_regression_result *res, pl_regression_detail *why,
                                        pl_error *err);
#endif

#ifdef __cplusplus
}
#endif
#endif
