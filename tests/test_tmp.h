/* test_tmp.h - temporary files and folders for the tests: under $TMPDIR
 * (default /tmp), as every Unix tool puts them, and removed by the test that
 * made them (test_tmp_dir's folder at the process's exit, so that each Check
 * child removes its own). */
#ifndef PLIANT_TEST_TMP_H
#define PLIANT_TEST_TMP_H

#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* "$TMPDIR/pliant_<tag>_XXXXXX" into buf (the template of mkstemp/mkdtemp). */
static inline void test_tmp_template(char *buf, size_t size, const char *tag)
{
    const char *root = getenv("TMPDIR");
    snprintf(buf, size, "%s/pliant_%s_XXXXXX", root && *root ? root : "/tmp", tag);
}

/* A new empty file; its path in buf; returns an open descriptor or -1. */
static inline int test_tmp_file(char *buf, size_t size, const char *tag)
{
    test_tmp_template(buf, size, tag);
    return mkstemp(buf);
}

static inline int test_tmp_rm_one(const char *p, const struct stat *st, int flag, struct FTW *f)
{
    (void)st, (void)flag, (void)f;
    return remove(p);
}

/* Removes a folder with everything in it. */
static inline void test_tmp_rmtree(const char *dir)
{
    if (dir && *dir) nftw(dir, test_tmp_rm_one, 16, FTW_DEPTH | FTW_PHYS);
}

/* A new folder (malloc'ed path, NULL on failure); the caller removes it. */
static inline char *test_tmp_mkdtemp(const char *tag)
{
    char buf[1024];
    test_tmp_template(buf, sizeof buf, tag);
    return mkdtemp(buf) ? strdup(buf) : NULL;
}

static char test_tmp_process_dir[1024];
static int test_tmp_registered;

/* Removes test_tmp_dir's folder now (the next call makes a new one). */
static inline void test_tmp_dir_remove(void)
{
    test_tmp_rmtree(test_tmp_process_dir);
    test_tmp_process_dir[0] = '\0';
}

/* One folder per process, made on first use and removed when it exits. */
static inline const char *test_tmp_dir(void)
{
    if (!test_tmp_process_dir[0]) {
        test_tmp_template(test_tmp_process_dir, sizeof test_tmp_process_dir, "test");
        if (!mkdtemp(test_tmp_process_dir)) {
            test_tmp_process_dir[0] = '\0';
            return NULL;
        }
        if (!test_tmp_registered++) atexit(test_tmp_dir_remove);
    }
    return test_tmp_process_dir;
}

#endif
