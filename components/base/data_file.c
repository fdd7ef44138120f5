/* data_file.c - where a file named in a scene is found (pl_util_data_file,
 * util.h): meshes, state files, cable paths. */
#include "pliant/util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int pl_util_data_file(const char *scene_file, const char *name, char *out, size_t size,
                      char *tried, size_t tried_size)
{
    size_t n = 0;
    tried[0] = '\0';
    if (name[0] == '/') {
        snprintf(out, size, "%s", name);
        if (access(out, R_OK) == 0) return 0;
        snprintf(tried, tried_size, "%s", name);
        return -1;
    }
    const char *slash = scene_file ? strrchr(scene_file, '/') : NULL;
    if (slash)
        snprintf(out, size, "%.*s/%s", (int)(slash - scene_file), scene_file, name);
    else
        snprintf(out, size, "%s", name);
    if (access(out, R_OK) == 0) return 0;
    n += (size_t)snprintf(tried + n, tried_size - n, "%s", out);
    snprintf(out, size, "%s", name);
    if (access(out, R_OK) == 0) return 0;
    if (n < tried_size) n += (size_t)snprintf(tried + n, tried_size - n, ", ./%s", name);
    const char *env = getenv("PLIANT_DATA_PATH");
    if (env && *env) {
        char *copy = strdup(env), *save = NULL;
        for (char *d = copy ? strtok_r(copy, ":", &save) : NULL; d; d = strtok_r(NULL, ":", &save)) {
            snprintf(out, size, "%s/%s", d, name);
            if (access(out, R_OK) == 0) {
                free(copy);
                return 0;
            }
            if (n < tried_size) n += (size_t)snprintf(tried + n, tried_size - n, ", %s", out);
        }
        free(copy);
    }
    return -1;
}
