/* cmd_run.c - `pliant run`: load a scene, step it, report. */
#include <pliant/pliant.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

typedef struct run_args {
    const char *scene;
    int steps;
    const char *out;
    int export_every;
    const char *timings;
    const char **sets;
    int nsets;
    int quiet;
    const char *device;
} run_args;

static int parse_int_arg(const char *s, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < 0 || v > 100000000) return -1;
    *out = (int)v;
    return 0;
}

static int parse_args(int argc, char **argv, run_args *a)
{
    memset(a, 0, sizeof *a);
    a->steps = 100;
    a->sets = calloc((size_t)argc + 1, sizeof *a->sets);
    if (!a->sets) return 1;
    for (int k = 0; k < argc; ++k) {
        const char *s = argv[k];
        int more = k + 1 < argc;
        if ((!strcmp(s, "-n") || !strcmp(s, "--steps")) && more) {
            if (parse_int_arg(argv[++k], &a->steps)) {
                fprintf(stderr, "pliant run: -n expects a number of steps, got '%s'\n", argv[k]);
                return 2;
            }
        } else if (!strcmp(s, "--out") && more) {
            a->out = argv[++k];
        } else if (!strcmp(s, "--export-every") && more) {
            if (parse_int_arg(argv[++k], &a->export_every) || a->export_every == 0) {
                fprintf(stderr, "pliant run: --export-every expects a positive number\n");
                return 2;
            }
        } else if (!strcmp(s, "--timings") && more) {
            a->timings = argv[++k];
        } else if (!strcmp(s, "--set") && more) {
            a->sets[a->nsets++] = argv[++k];
        } else if (!strcmp(s, "--device") && more) {
            a->device = argv[++k];
            if (strcmp(a->device, "cpu") && strcmp(a->device, "auto")) {
                fprintf(stderr, "pliant run: --device expects cpu or auto, got '%s'\n", a->device);
                return 2;
            }
        } else if (!strcmp(s, "--quiet") || !strcmp(s, "-q")) {
            a->quiet = 1;
        } else if (s[0] == '-') {
            fprintf(stderr, "pliant run: unknown or incomplete option '%s'\n", s);
            return 2;
        } else if (!a->scene) {
            a->scene = s;
        } else {
            fprintf(stderr, "pliant run: more than one scene given ('%s', '%s')\n", a->scene, s);
            return 2;
        }
    }
    if (!a->scene) {
        fprintf(stderr, "pliant run: no scene given (pliant run SCENE.xml)\n");
        return 2;
    }
    return 0;
}

static void progress(int done, int total, double elapsed)
{
    double ms = done ? 1e3 * elapsed / done : 0.0;
    double eta = done ? elapsed / done * (total - done) : 0.0;
    int width = 30, fill = total ? width * done / total : width;
    fprintf(stderr, "\r[%.*s%*s] frame %d/%d  %.2f ms/frame  ETA %.0f s ", fill,
            "##############################", width - fill, "", done, total, ms, eta);
    fflush(stderr);
}

static int write_timings(pl_sim *sim, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "pliant run: cannot write %s\n", path);
        return 2;
    }
    int rc = pl_timers_write_json(pl_sim_timers(sim), f);
    if (fclose(f) != 0) rc = 1;
    return rc ? 1 : 0;
}

int cli_run(int argc, char **argv)
{
    run_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) {
        free(a.sets);
        return rc;
    }
    if (a.quiet) pl_log_set_level(PL_LOG_WARN);
    pl_sim_options opt = {.out_dir = a.out, .export_every = a.export_every, .overrides = a.sets,
                          .noverrides = a.nsets, .device = a.device};
    pl_diag diag;
    pl_diag_init(&diag);
    double t0 = pl_now();
    pl_sim *sim = pl_sim_load_file(a.scene, &opt, &diag);
    if (!a.quiet || !sim) pl_diag_print(&diag, stderr);
    free(a.sets);
    if (!sim) {
        int status = pl_diag_status(&diag);
        fprintf(stderr, "pliant: %s: %d error%s; the scene was not run\n", a.scene, diag.nerrors,
                diag.nerrors == 1 ? "" : "s");
        pl_diag_free(&diag);
        return status == PL_EINTERNAL ? 1 : 2;
    }
    pl_diag_free(&diag);
    double load_s = pl_now() - t0;
    int tty = isatty(fileno(stderr)) && !a.quiet;
    pl_error err;
    pl_error_clear(&err);
    t0 = pl_now();
    int done = 0;
    for (; done < a.steps; ++done) {
        if (tty && (done % 5 == 0)) progress(done, a.steps, pl_now() - t0);
        if ((rc = pl_sim_step(sim, 1, &err)) != PL_OK) break;
    }
    double run_s = pl_now() - t0;
    if (tty) {
        progress(done, a.steps, run_s);
        fputc('\n', stderr);
    }
    if (rc == PL_OK && pl_sim_finish(sim, &err) != PL_OK) rc = err.code;
    if (rc != PL_OK) {
        char msg[1600];
        fprintf(stderr, "pliant: step %d failed: %s\n", done + 1,
                pl_error_format(&err, msg, sizeof msg));
    }
    if (a.timings && write_timings(sim, a.timings) != 0 && rc == PL_OK) rc = PL_EINTERNAL;
    const char *outs[16];
    int nout = pl_sim_outputs(sim, outs, 16);
    printf("%s: %d steps, t = %.4g s, load %.3f s, %.3f ms/step", a.scene, done,
           pl_sim_time(sim), load_s, done ? 1e3 * run_s / done : 0.0);
    for (int k = 0; k < nout; ++k) printf("%s%s", k ? ", " : "; output: ", outs[k]);
    if (a.timings) printf("; timings: %s", a.timings);
    printf("\n");
    pl_sim_free(sim);
    return rc == PL_OK ? 0 : (rc == PL_EINPUT ? 2 : 1);
}
