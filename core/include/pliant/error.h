/* error.h - errors are values: a status code plus a message naming where.
 *
 * Every fallible function in Pliant returns an int status (PL_OK on
 * success) and fills a pl_error.  The scene loader collects many errors in
 * a pl_diag list so that a user sees all mistakes of a scene at once. */
#ifndef PLIANT_ERROR_H
#define PLIANT_ERROR_H

#include "api.h"
#include <stdarg.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes double as the CLI's exit codes. */
enum {
    PL_OK = 0,
    PL_EINTERNAL = 1, /* a bug, an allocation failure, a numerical breakdown */
    PL_EINPUT = 2     /* the user's input is wrong: scene, mesh, field value */
};

typedef struct pl_error {
    int code;          /* PL_OK, PL_EINPUT or PL_EINTERNAL */
    char file[256];    /* input file the error is about ("" if none) */
    int line;          /* 1-based line in that file (0 if unknown) */
    char where[192];   /* component path such as "root/bar/dofs" ("" if none) */
    char msg[1024];    /* what was expected and what was found */
} pl_error;

/* Clears an error to PL_OK. */
PL_API void pl_error_clear(pl_error *e);

/* Fills e (if not NULL) and returns code.  file/where may be NULL. */
PL_API int pl_error_set(pl_error *e, int code, const char *file, int line,
                        const char *where, const char *fmt, ...)
    __attribute__((format(printf, 6, 7)));
PL_API int pl_error_vset(pl_error *e, int code, const char *file, int line,
                         const char *where, const char *fmt, va_list ap);

/* Formats "file:line: where: msg" into buf; returns buf. */
PL_API const char *pl_error_format(const pl_error *e, char *buf, size_t size);

/* A list of errors and warnings, collected rather than stopping at the first. */
typedef struct pl_diag {
    pl_error *items;
    int count, cap;
    int nerrors;       /* items with code != PL_OK; warnings have code PL_OK */
} pl_diag;

PL_API void pl_diag_init(pl_diag *d);
PL_API void pl_diag_free(pl_diag *d);
/* Appends a copy of e (errors and warnings alike). */
PL_API void pl_diag_add(pl_diag *d, const pl_error *e);
/* Appends a new error; returns code. */
PL_API int pl_diag_error(pl_diag *d, int code, const char *file, int line,
                         const char *where, const char *fmt, ...)
    __attribute__((format(printf, 6, 7)));
/* Appends a warning (code PL_OK): shown to the user, does not stop a load. */
PL_API void pl_diag_warn(pl_diag *d, const char *file, int line, const char *where,
                         const char *fmt, ...) __attribute__((format(printf, 5, 6)));
/* Prints every item as "file:line: error|warning: where: msg" to a stream. */
PL_API void pl_diag_print(const pl_diag *d, void *stdio_file);
/* The first error's code, or PL_OK. */
PL_API int pl_diag_status(const pl_diag *d);

#ifdef __cplusplus
}
#endif
#endif
