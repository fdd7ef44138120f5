/* export_test_util.h - temporary folders and files for the export tests. */
#ifndef PL_EXPORT_TEST_UTIL_H
#define PL_EXPORT_TEST_UTIL_H

#include <stddef.h>

/* A new empty folder under the build tree (malloc'd path). */
char *tu_tmpdir(void);
/* Removes a folder and everything in it. */
void tu_rmtree(const char *dir);
/* "dir/name" in a static rotating buffer (valid for the next few calls). */
const char *tu_path(const char *dir, const char *name);
/* Whole file as a NUL-terminated malloc'd string (size in *n), NULL if unreadable. */
char *tu_read_file(const char *path, size_t *n);
/* Writes text to path; 0 on success. */
int tu_write_file(const char *path, const char *text);
/* Whether path exists. */
int tu_exists(const char *path);
/* A test data file of tests/export/data. */
const char *tu_data(const char *name);

#endif
