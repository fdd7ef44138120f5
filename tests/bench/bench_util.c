/* bench_util.c - shared helpers of bench_scenes and bench_convergence. */
#include "bench_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pliant/pliant.h"

pl_sim *bench_load(const char *path, const char *xml, const char *const *overrides,
                   int noverrides, const char *out_dir)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = out_dir;
    opt.overrides = overrides;
    opt.noverrides = noverrides;
    pl_sim *sim = xml ? pl_sim_load_string(xml, path, &opt, &diag)
                      : pl_sim_load_file(path, &opt, &diag);
    if (!sim) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    return sim;
}

typedef struct describe_walk {
    bench_scene_info *info;
    int error;
} describe_walk;

static int count_state(pl_component *c, void *user)
{
    describe_walk *w = user;
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    if (ops->count) w->info->vertices += ops->count(c);
    return 0;
}

static int count_topology(pl_component *c, void *user)
{
    describe_walk *w = user;
    const pl_topology_ops *ops = pl_component_role(c, PL_ROLE_TOPOLOGY);
    const pl_mesh *m = ops->mesh ? ops->mesh(c) : NULL;
    /* a volume body's surface triangles (if any) are not elements of its material */
    if (m) w->info->elements += m->ntets > 0 ? m->ntets : m->ntris;
    return 0;
}

/* Appends the type name of every local term once ("ARAP", "Corotational+IsometricBending"). */
static int name_material(pl_component *c, void *user)
{
    describe_walk *w = user;
    char *dst = w->info->material;
    const char *name = c->type->name;
    size_t len = strlen(dst), nlen = strlen(name);
    /* already listed? (compare whole '+'-separated items) */
    for (const char *p = dst; *p;) {
        const char *end = strchr(p, '+');
        size_t ilen = end ? (size_t)(end - p) : strlen(p);
        if (ilen == nlen && strncmp(p, name, nlen) == 0) return 0;
        p += ilen + (end ? 1 : 0);
    }
    if (len + nlen + 2 > sizeof w->info->material) {
        w->error = 1;
        return 0;
    }
    if (len) dst[len++] = '+';
    memcpy(dst + len, name, nlen + 1);
    return 0;
}

int bench_describe(pl_sim *sim, bench_scene_info *info)
{
    memset(info, 0, sizeof *info);
    pl_model *model = pl_sim_model(sim);
    if (!model || !model->root) return PL_EINPUT;
    describe_walk w = {info, 0};
    pl_node_visit_role(model->root, PL_ROLE_STATE, count_state, &w);
    pl_node_visit_role(model->root, PL_ROLE_TOPOLOGY, count_topology, &w);
    pl_node_visit_role(model->root, PL_ROLE_LOCAL_TERM, name_material, &w);
    pl_component *loop = NULL;
    for (int k = 0; k < model->root->ncomponents && !loop; ++k)
        if (pl_component_role(model->root->components[k], PL_ROLE_ANIMATION_LOOP))
            loop = model->root->components[k];
    if (loop && strcmp(loop->type->name, "LocalGlobalSolver") == 0) {
        char path[300], value[64];
        pl_error err;
        snprintf(path, sizeof path, "%s.iterations", loop->name);
        if (pl_sim_get(sim, path, value, sizeof value, &err) == PL_OK) info->iterations = atoi(value);
    }
    return w.error ? PL_EINPUT : PL_OK;
}

double bench_stat(const pl_timers *t, const char *name)
{
    double v;
    return pl_stat_get(t, name, &v) == PL_OK ? v : NAN;
}

double bench_phase_median_ms(const pl_timers *t, const char *name)
{
    /* look the phase up by name: pl_timer_id would create a missing one */
    for (int id = 0; id < pl_timers_count(t); ++id)
        if (strcmp(pl_timers_name(t, id), name) == 0)
            return pl_timers_samples(t, id) > 0 ? pl_timers_median_ms(t, id) : NAN;
    return NAN;
}

char *bench_read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 4096 + 1 > cap) {
            cap = 2 * cap + 8192;
            char *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = nb;
        }
        size_t got = fread(buf + len, 1, 4096, f);
        len += got;
        if (got < 4096) break;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return NULL;
    }
    buf[len] = '\0';
    return buf;
}

int bench_split_list(char *list, char **items, int max)
{
    int n = 0;
    for (char *tok = strtok(list, ","); tok && n < max; tok = strtok(NULL, ","))
        if (*tok) items[n++] = tok;
    return n;
}

const char *bench_fmt(char *buf, size_t size, const char *fmt, double v)
{
    if (isnan(v))
        snprintf(buf, size, "n/a");
    else
        snprintf(buf, size, fmt, v);
    return buf;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
