/* cli_common.c - what every command needs: argument errors in one style,
 * number parsing, scene names, temporary folders. */
#include <ftw.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

int cli_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "pliant %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\nTry 'pliant %s --help'.\n", cmd);
    va_end(ap);
    return 2;
}

int cli_bad_option(const char *cmd, char **argv, int optind_now, int optopt_now)
{
    /* getopt_long has already advanced past the offending word */
    const char *word = optind_now > 0 ? argv[optind_now - 1] : "?";
    if (optopt_now && word[0] == '-' && word[1] == optopt_now && !word[2])
        return cli_usage_error(cmd, "option '%s' needs a value", word);
    if (optopt_now && word[0] == '-' && word[1] != '-')
        return cli_usage_error(cmd, "unknown option '-%c'", optopt_now);
    return cli_usage_error(cmd, "unknown option, or one missing its value: '%s'", word);
}

int cli_parse_int(const char *cmd, const char *opt, const char *s, int min, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < min || v > 100000000)
        return cli_usage_error(cmd, "%s expects a whole number >= %d, got '%s'", opt, min, s);
    *out = (int)v;
    return 0;
}

int cli_parse_double(const char *cmd, const char *opt, const char *s, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v) || v < 0)
        return cli_usage_error(cmd, "%s expects a number >= 0, got '%s'", opt, s);
    *out = v;
    return 0;
}

void cli_scene_name(const char *path, char *buf, size_t size)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    size_t n = strlen(base);
    if (n > 4 && !strcmp(base + n - 4, ".xml")) n -= 4;
    snprintf(buf, size, "%.*s", (int)n, n ? base : "scene");
}

char *cli_tmpdir_create(const char *tag)
{
    const char *root = getenv("TMPDIR");
    if (!root || !*root) root = "/tmp";
    size_t n = strlen(root) + strlen(tag) + 32;
    char *path = malloc(n);
    if (!path) return NULL;
    snprintf(path, n, "%s/pliant_%s_XXXXXX", root, tag);
    if (!mkdtemp(path)) {
        free(path);
        return NULL;
    }
    return path;
}

int cli_make_dirs(const char *path)
{
    char buf[4096];
    size_t n = (size_t)snprintf(buf, sizeof buf, "%s", path);
    if (n >= sizeof buf) return -1;
    for (size_t i = 1; i <= n; ++i) {
        if (buf[i] != '/' && buf[i] != '\0') continue;
        char save = buf[i];
        buf[i] = '\0';
        struct stat st;
        if (mkdir(buf, 0777) != 0 && (stat(buf, &st) != 0 || !S_ISDIR(st.st_mode))) return -1;
        buf[i] = save;
    }
    return 0;
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    return remove(path);
}

int cli_remove_tree(const char *path)
{
    /* depth first, without following links out of the folder */
    return nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}
