/* script.c - scripted viewer input (script.h). */
#include "script.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    const char *name;
    int key;
} NAMES[] = {{"space", ' '},       {"escape", VW_KEY_ESCAPE}, {"up", PL_KEY_UP},
             {"down", PL_KEY_DOWN}, {"left", PL_KEY_LEFT},     {"right", PL_KEY_RIGHT},
             {"pageup", PL_KEY_PAGE_UP}, {"pagedown", PL_KEY_PAGE_DOWN}};

/* A key token with an optional ctrl+ prefix; -1 if unknown. */
static int parse_key(const char *t, int *mods)
{
    *mods = 0;
    if (!strncmp(t, "ctrl+", 5) && t[5]) *mods = VW_MOD_CTRL, t += 5;
    if (strlen(t) == 1) return (unsigned char)t[0];
    for (size_t k = 0; k < sizeof NAMES / sizeof NAMES[0]; ++k)
        if (!strcmp(t, NAMES[k].name)) return NAMES[k].key;
    return -1;
}

/* Checks one command; returns 0 when well formed. */
static int check(const char *line)
{
    char cmd[32], a[256];
    double x[5];
    int mods;
    if (sscanf(line, "%31s", cmd) != 1) return -1;
    if (!strcmp(cmd, "step")) return sscanf(line, "%*s %lf", x) == 1 && x[0] >= 0 ? 0 : -1;
    if (!strcmp(cmd, "key")) return sscanf(line, "%*s %255s", a) == 1 && parse_key(a, &mods) >= 0 ? 0 : -1;
    if (!strcmp(cmd, "drag"))
        return sscanf(line, "%*s %lf %lf %lf %lf %lf", x, x + 1, x + 2, x + 3, x + 4) == 5 ? 0 : -1;
    if (!strcmp(cmd, "orbit")) return sscanf(line, "%*s %lf %lf", x, x + 1) == 2 ? 0 : -1;
    if (!strcmp(cmd, "screenshot") || !strcmp(cmd, "print"))
        return sscanf(line, "%*s %255s", a) == 1 ? 0 : -1;
    return strcmp(cmd, "quit");
}

static int add_line(vw_script *s, const char *text, int no)
{
    char **l = realloc(s->lines, (size_t)(s->n + 1) * sizeof *l);
    if (!l) return -1;
    s->lines = l;
    int *nl = realloc(s->line_no, (size_t)(s->n + 1) * sizeof *nl);
    if (!nl) return -1;
    s->line_no = nl;
    if (!(s->lines[s->n] = strdup(text))) return -1;
    s->line_no[s->n++] = no;
    return 0;
}

int vw_script_load(vw_script *s, const char *path, pl_error *err)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "r");
    if (!f) return pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot read: %s", strerror(errno));
    if (!(s->file = strdup(path))) return fclose(f), PL_EINTERNAL;
    char buf[512];
    int no = 0, rc = PL_OK;
    while (!rc && fgets(buf, sizeof buf, f)) {
        ++no;
        buf[strcspn(buf, "\r\n")] = '\0';
        const char *t = buf + strspn(buf, " \t");
        if (!*t || *t == '#') continue;
        if (check(t))
            rc = pl_error_set(err, PL_EINPUT, path, no, NULL,
                              "'%s': expected step N, key K, drag X0 Y0 X1 Y1 N, orbit DX DY, "
                              "screenshot FILE, print PATH or quit",
                              t);
        else if (add_line(s, t, no))
            rc = pl_error_set(err, PL_EINTERNAL, path, no, NULL, "out of memory");
    }
    fclose(f);
    return rc;
}

void vw_script_free(vw_script *s)
{
    for (int k = 0; k < s->n; ++k) free(s->lines[k]);
    free(s->lines);
    free(s->line_no);
    free(s->file);
    memset(s, 0, sizeof *s);
}

static int input(vw_app *a, vw_input_kind kind, int button, int pressed, int mods, double x,
                 double y, pl_error *err)
{
    vw_input in = {kind, 0, mods, button, pressed, x, y};
    return vw_app_input(a, &in, err);
}

static int drag(vw_app *a, const double *v, pl_error *err)
{
    int rc = input(a, VW_IN_MOVE, 0, 0, 0, v[0], v[1], err);
    if (!rc) rc = input(a, VW_IN_BUTTON, 0, 1, VW_MOD_SHIFT, v[0], v[1], err);
    if (!rc) rc = input(a, VW_IN_MOVE, 0, 0, VW_MOD_SHIFT, v[2], v[3], err);
    if (!rc) rc = vw_app_step(a, (int)v[4], err);
    if (!rc) rc = input(a, VW_IN_BUTTON, 0, 0, VW_MOD_SHIFT, v[2], v[3], err);
    return rc;
}

static int run(vw_script *s, const char *line, vw_app *a, vw_script_shot shot, void *user,
               int *done, pl_error *err)
{
    char cmd[32], arg[256], out[4096];
    double v[5];
    int mods, rc = PL_OK;
    sscanf(line, "%31s", cmd);
    if (!strcmp(cmd, "step")) {
        sscanf(line, "%*s %lf", v);
        rc = vw_app_step(a, (int)v[0], err);
    } else if (!strcmp(cmd, "key")) {
        sscanf(line, "%*s %255s", arg);
        vw_input in = {VW_IN_KEY, parse_key(arg, &mods), 0, 0, 0, 0.0, 0.0};
        in.mods = mods;
        rc = vw_app_input(a, &in, err);
    } else if (!strcmp(cmd, "drag")) {
        sscanf(line, "%*s %lf %lf %lf %lf %lf", v, v + 1, v + 2, v + 3, v + 4);
        rc = drag(a, v, err);
    } else if (!strcmp(cmd, "orbit")) {
        sscanf(line, "%*s %lf %lf", v, v + 1);
        rc = input(a, VW_IN_BUTTON, 0, 1, 0, a->mx, a->my, err);
        if (!rc) rc = input(a, VW_IN_MOVE, 0, 0, 0, a->mx + v[0], a->my + v[1], err);
        if (!rc) rc = input(a, VW_IN_BUTTON, 0, 0, 0, a->mx, a->my, err);
    } else if (!strcmp(cmd, "screenshot")) {
        sscanf(line, "%*s %255s", arg);
        rc = shot(user, arg, err);
    } else if (!strcmp(cmd, "print")) {
        sscanf(line, "%*s %255s", arg);
        rc = pl_sim_get(a->sim, arg, out, sizeof out, err);
        if (!rc) printf("%s = %s\n", arg, out), fflush(stdout);
    } else {
        *done = 1;
    }
    (void)s;
    return rc;
}

int vw_script_next(vw_script *s, vw_app *a, vw_script_shot shot, void *user, int *done,
                   pl_error *err)
{
    *done = s->next >= s->n;
    if (*done) return PL_OK;
    int k = s->next++;
    int rc = run(s, s->lines[k], a, shot, user, done, err);
    if (rc && !err->file[0]) {
        snprintf(err->file, sizeof err->file, "%s", s->file);
        err->line = s->line_no[k];
    }
    if (s->next >= s->n) *done = 1;
    return rc;
}
