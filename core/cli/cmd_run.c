/* cmd_run.c - `pliant run`: load a scene, step it, report. */
#include <pliant/pliant.h>

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char USAGE[] =
    "usage: pliant run SCENE.xml [OPTIONS]\n"
    "       pliant run SCRIPT.py [-n STEPS] [--set PATH=VALUE]  (a createScene script:\n"
    "       python3 -m pliant run, docs/python.md)\n"
    "Runs a scene headless and writes what its exporters write.\n\n"
    "  -n, --steps N          time steps to run (default 100)\n"
    "  -o, --out DIR          folder for the outputs (default out/<scene name>/)\n"
    "      --export-every K   write every K-th step (default: each exporter's own setting)\n"
    "      --timings FILE     per-phase timings as JSON\n"
    "  -s, --set PATH=VALUE   change a field before the run (e.g. bar/arap.youngModulus=1e6);\n"
    "                         repeatable\n"
    "      --device POLICY    cpu; auto: the GPU when the scene declares no device, one is\n"
    "                         usable and a cost model predicts the step faster there\n"
    "                         (the log says why); gpu-always: whenever one is usable\n"
    "                         (default PLIANT_DEVICE, else auto)\n"
    "  -j, --threads N        OpenMP threads (default OMP_NUM_THREADS, else the cores this\n"
    "                         process may use; never more than those)\n"
    "      --progress S       in a log (stderr not a terminal) a progress line every S\n"
    "                         seconds (default 5; 0 = none)\n"
    "      --allow-plugin-path  let the scene's <RequiredPlugin> name a file (runs its code:\n"
    "                         only for scenes you trust; default: plugin names only)\n"
    "  -q, --quiet            only warnings and errors\n"
    "  -h, --help             this text\n"
    "exit codes: 0 ok, 1 internal error, 2 bad input (scene, arguments)\n";

typedef struct run_args {
    const char *scene;
    int steps;
    const char *out;
    int export_every;
    const char *timings;
    const char **sets;
    int nsets;
    int quiet;
    int threads;
    double progress;
    const char *device;
    int allow_plugin_path;
} run_args;

enum { OPT_EXPORT_EVERY = 256, OPT_TIMINGS, OPT_DEVICE, OPT_PROGRESS, OPT_ALLOW_PLUGIN_PATH };

static const struct option OPTIONS[] = {
    {"steps", required_argument, NULL, 'n'},
    {"out", required_argument, NULL, 'o'},
    {"export-every", required_argument, NULL, OPT_EXPORT_EVERY},
    {"timings", required_argument, NULL, OPT_TIMINGS},
    {"set", required_argument, NULL, 's'},
    {"device", required_argument, NULL, OPT_DEVICE},
    {"threads", required_argument, NULL, 'j'},
    {"progress", required_argument, NULL, OPT_PROGRESS},
    {"allow-plugin-path", no_argument, NULL, OPT_ALLOW_PLUGIN_PATH},
    {"quiet", no_argument, NULL, 'q'},
    {"help", no_argument, NULL, 'h'},
    {0, 0, 0, 0}};

/* Returns 0, 2 on a bad command line, or -1 when --help was printed. */
static int parse_args(int argc, char **argv, run_args *a)
{
    memset(a, 0, sizeof *a);
    a->steps = 100;
    a->progress = 5.0;
    a->sets = calloc((size_t)argc + 1, sizeof *a->sets);
    if (!a->sets) return 1;
    opterr = 0;
    int c, rc = 0;
    while (!rc && (c = getopt_long(argc, argv, "n:o:s:j:qh", OPTIONS, NULL)) != -1) {
        switch (c) {
        case 'n': rc = cli_parse_int("run", "--steps", optarg, 0, &a->steps); break;
        case 'o': a->out = optarg; break;
        case OPT_EXPORT_EVERY:
            rc = cli_parse_int("run", "--export-every", optarg, 1, &a->export_every);
            break;
        case OPT_TIMINGS: a->timings = optarg; break;
        case 's': a->sets[a->nsets++] = optarg; break;
        case OPT_DEVICE:
            a->device = optarg;
            if (strcmp(optarg, "cpu") && strcmp(optarg, "auto") && strcmp(optarg, "gpu-always"))
                rc = cli_usage_error("run", "--device expects cpu, auto or gpu-always, got '%s'", optarg);
            break;
        case 'j': rc = cli_parse_int("run", "--threads", optarg, 1, &a->threads); break;
        case OPT_PROGRESS: rc = cli_parse_double("run", "--progress", optarg, &a->progress); break;
        case OPT_ALLOW_PLUGIN_PATH: a->allow_plugin_path = 1; break;
        case 'q': a->quiet = 1; break;
        case 'h': fputs(USAGE, stdout); return -1;
        default: rc = cli_bad_option("run", argv, optind, optopt);
        }
    }
    if (rc) return rc;
    if (optind >= argc) return cli_usage_error("run", "no scene given (pliant run SCENE.xml)");
    if (optind + 1 < argc)
        return cli_usage_error("run", "more than one scene given ('%s', '%s')", argv[optind],
                               argv[optind + 1]);
    a->scene = argv[optind];
    return 0;
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

static pl_sim *load(const run_args *a, const char *out_dir, int *status)
{
    pl_sim_options opt = {.out_dir = out_dir, .export_every = a->export_every,
                          .overrides = a->sets, .noverrides = a->nsets, .device = a->device,
                          .allow_plugin_path = a->allow_plugin_path};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *sim = pl_sim_load_file(a->scene, &opt, &diag);
    if (!a->quiet || !sim) pl_diag_print(&diag, stderr);
    if (!sim)
        fprintf(stderr, "pliant: %s: %d error%s; the scene was not run\n", a->scene,
                diag.nerrors, diag.nerrors == 1 ? "" : "s");
    *status = pl_diag_status(&diag) == PL_EINTERNAL ? 1 : 2;
    pl_diag_free(&diag);
    return sim;
}

/* Steps the scene; returns the status and the steps done. */
static int step_all(pl_sim *sim, const run_args *a, int *done, double *run_s)
{
    pl_error err;
    pl_error_clear(&err);
    cli_progress prog;
    cli_progress_start(&prog, a->steps, a->quiet, a->progress);
    int rc = PL_OK;
    for (*done = 0; *done < a->steps; ++*done) {
        cli_progress_update(&prog, *done, pl_sim_time(sim));
        if ((rc = pl_sim_step(sim, 1, &err)) != PL_OK) break;
    }
    *run_s = pl_now() - prog.t0;
    cli_progress_finish(&prog, *done, pl_sim_time(sim));
    if (rc == PL_OK && pl_sim_finish(sim, &err) != PL_OK) rc = err.code;
    if (rc != PL_OK) {
        char msg[1600];
        fprintf(stderr, "pliant: step %d failed: %s\n", *done + 1,
                pl_error_format(&err, msg, sizeof msg));
    }
    return rc;
}

/* "; device=auto chose the CPU (predicted 2.1 vs 5.5 ms/step on the GPU)"
 * when the loader's cost model chose (sim_device.c). */
static void print_device_choice(const pl_timers *t)
{
    double gpu, cpu_ms, gpu_ms;
    if (pl_stat_get(t, "device auto: GPU chosen", &gpu) != 0 ||
        pl_stat_get(t, "predicted CPU [ms/step]", &cpu_ms) != 0 ||
        pl_stat_get(t, "predicted GPU [ms/step]", &gpu_ms) != 0)
        return;
    printf("; device=auto chose the %s (predicted %.3g vs %.3g ms/step on the %s)",
           gpu ? "GPU" : "CPU", gpu ? gpu_ms : cpu_ms, gpu ? cpu_ms : gpu_ms, gpu ? "CPU" : "GPU");
}

int cli_run(int argc, char **argv)
{
    if (cli_is_python_script(argc, argv)) return cli_run_python(argc, argv);
    run_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) {
        free(a.sets);
        return rc < 0 ? 0 : rc;
    }
    if (a.quiet) pl_log_set_level(PL_LOG_WARN);
    int threads = cli_threads_set(a.threads);
    char out_dir[1024], name[256];
    cli_scene_name(a.scene, name, sizeof name);
    snprintf(out_dir, sizeof out_dir, "%s", a.out ? a.out : "out/");
    if (!a.out) strncat(out_dir, name, sizeof out_dir - strlen(out_dir) - 1);
    double t0 = pl_now();
    pl_sim *sim = load(&a, out_dir, &rc);
    free(a.sets);
    if (!sim) return rc;
    double load_s = pl_now() - t0, run_s;
    int done;
    rc = step_all(sim, &a, &done, &run_s);
    if (a.timings && write_timings(sim, a.timings) != 0 && rc == PL_OK) rc = PL_EINTERNAL;
    const char *outs[16];
    int nout = pl_sim_outputs(sim, outs, 16);
    printf("%s: %d steps, t = %.4g s, load %.3f s, %.3f ms/step, %d thread%s", a.scene, done,
           pl_sim_time(sim), load_s, done ? 1e3 * run_s / done : 0.0, threads,
           threads == 1 ? "" : "s");
    print_device_choice(pl_sim_timers(sim));
    const double *residual;
    int nres = pl_series_get(pl_sim_timers(sim), "force residual", &residual);
    double res_max = 0.0;
    for (int k = 0; k < nres; ++k) res_max = residual[k] > res_max ? residual[k] : res_max;
    if (nres > 0)
        printf("; force residual %.3g N at the last step (max %.3g N)", residual[nres - 1], res_max);
    for (int k = 0; k < nout; ++k) printf("%s%s", k ? ", " : "; output: ", outs[k]);
    if (a.timings) printf("; timings: %s", a.timings);
    printf("\n");
    pl_sim_free(sim);
    return rc == PL_OK ? 0 : (rc == PL_EINPUT ? 2 : 1);
}
