/* sweep_grid.c - the grid of a sweep: "--set PATH=a:b:n" (n values from a
 * to b, evenly spaced), "--set PATH=v1,v2,v3" (a list) or "--set PATH=v"
 * (one value); the runs are the product of the lists. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "sweep.h"

enum { MAX_RUNS = 1000000 };

static int push(sweep_axis *a, const char *text, size_t len)
{
    char **v = realloc(a->values, (size_t)(a->n + 1) * sizeof *v);
    if (!v) return -1;
    a->values = v;
    if (!(v[a->n] = malloc(len + 1))) return -1;
    memcpy(v[a->n], text, len);
    v[a->n++][len] = '\0';
    return 0;
}

/* "a:b:n": n values from a to b, the ends exact. */
static int range(sweep_axis *a, const char *spec)
{
    char *end;
    double lo = strtod(spec, &end), hi;
    long n;
    if (*end != ':' || !isfinite(lo)) return -1;
    hi = strtod(end + 1, &end);
    if (*end != ':' || !isfinite(hi)) return -1;
    n = strtol(end + 1, &end, 10);
    if (*end || n < 1 || n > MAX_RUNS) return -1;
    for (long k = 0; k < n; ++k) {
        double v = k == n - 1 ? hi : lo + (hi - lo) * (double)k / (double)(n - 1);
        char buf[64];
        int len = snprintf(buf, sizeof buf, "%.15g", n == 1 ? lo : v);
        if (push(a, buf, (size_t)len)) return -2;
    }
    return 0;
}

static int list(sweep_axis *a, const char *spec)
{
    for (const char *p = spec;;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == 0) return -1;
        if (push(a, p, len)) return -2;
        if (!comma) return 0;
        p = comma + 1;
    }
}

int sweep_add_axis(sweep *s, const char *arg)
{
    const char *eq = strchr(arg, '=');
    if (!eq || eq == arg || !eq[1])
        return cli_usage_error("sweep", "--set '%s': expected PATH=a:b:n, PATH=v1,v2 or PATH=v",
                               arg);
    for (int k = 0; k < s->naxes; ++k)
        if (strlen(s->axes[k].path) == (size_t)(eq - arg) &&
            !strncmp(s->axes[k].path, arg, (size_t)(eq - arg)))
            return cli_usage_error("sweep", "--set %.*s is given twice", (int)(eq - arg), arg);
    sweep_axis *axes = realloc(s->axes, (size_t)(s->naxes + 1) * sizeof *axes);
    if (!axes) return 1;
    s->axes = axes;
    sweep_axis *a = &axes[s->naxes++];
    memset(a, 0, sizeof *a);
    a->path = strndup(arg, (size_t)(eq - arg));
    a->spec = strdup(eq + 1);
    if (!a->path || !a->spec) return 1;
    int rc = strchr(a->spec, ':') ? range(a, a->spec) : list(a, a->spec);
    if (rc == -2) return 1;
    if (rc)
        return cli_usage_error("sweep", "--set %s=%s: expected a:b:n (n >= 1 values from a to "
                                        "b), v1,v2,... or one value",
                               a->path, a->spec);
    return 0;
}

int sweep_count(const sweep *s)
{
    long n = 1;
    for (int k = 0; k < s->naxes; ++k) {
        n *= s->axes[k].n;
        if (n > MAX_RUNS) return 0;
    }
    return (int)n;
}

const char *sweep_value(const sweep *s, int run, int a)
{
    /* mixed radix, the last axis fastest */
    for (int k = s->naxes - 1; k > a; --k) run /= s->axes[k].n;
    return s->axes[a].values[run % s->axes[a].n];
}

void sweep_free(sweep *s)
{
    for (int k = 0; k < s->naxes; ++k) {
        for (int v = 0; v < s->axes[k].n; ++v) free(s->axes[k].values[v]);
        free(s->axes[k].values);
        free(s->axes[k].path);
        free(s->axes[k].spec);
    }
    free(s->axes);
    free(s->records);
    s->axes = NULL;
    s->records = NULL;
}
