/* cmd_sweep.c - `pliant sweep SCENE --set PATH=a:b:n ... -n STEPS`: one run
 * per point of the grid of --set values, each in its own process (one after
 * the other, or over the ranks of `mpirun`), and a table of chosen outputs
 * per run.  A sweep cut short is resumed by running the same command: runs
 * that completed (run_NNNN/result.txt) are not run again.  Layout: sweep.h. */
#include <pliant/pliant.h>

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_dispatch.h"
#include "sweep.h"

static const char USAGE[] =
    "usage: pliant sweep SCENE.xml --set PATH=SPEC [--set ...] [OPTIONS]\n"
    "Runs the scene once per point of the grid of --set values (the product of the lists)\n"
    "and tabulates each run's recorded outputs, ms/step and status in OUT/sweep.csv and\n"
    "OUT/sweep.md; run k's outputs and log go to OUT/run_k/.  Under mpirun the runs are\n"
    "spread over the ranks.  Running the same command again skips the runs that completed.\n\n"
    "  -s, --set PATH=SPEC   SPEC: a:b:n (n values from a to b), v1,v2,... or v; repeatable\n"
    "  -n, --steps N         time steps per run (default 100)\n"
    "  -r, --record PATH     a field to tabulate after the last step (e.g.\n"
    "                        finger/cable.cableLength); repeatable\n"
    "  -o, --out OUT         folder of the sweep (default out/<scene name>_sweep)\n"
    "  -j, --threads N       OpenMP threads per run (default: the cores, shared among the\n"
    "                        ranks on a node)\n"
    "  -t, --timeout S       stop a run that takes longer than S seconds (default: no limit)\n"
    "      --device cpu|auto|gpu-always as for pliant run\n"
    "  -q, --quiet           no line per finished run\n"
    "  -h, --help            this text\n"
    "exit codes: 0 every run ok, 1 some run failed, crashed or timed out, 2 bad input\n";

typedef struct sweep_opts {
    int threads;
    double timeout;
} sweep_opts;

enum { OPT_DEVICE = 256 };

static int parse_option(int c, sweep *s, sweep_opts *o, char **argv)
{
    switch (c) {
    case 's': return sweep_add_axis(s, optarg);
    case 'n': return cli_parse_int("sweep", "--steps", optarg, 1, &s->steps);
    case 'r': s->records[s->nrecords++] = optarg; return 0;
    case 'o': snprintf(s->out, sizeof s->out, "%s", optarg); return 0;
    case 'j': return cli_parse_int("sweep", "--threads", optarg, 1, &o->threads);
    case 't': return cli_parse_double("sweep", "--timeout", optarg, &o->timeout);
    case 'q': s->quiet = 1; return 0;
    case OPT_DEVICE:
        s->device = optarg;
        if (strcmp(optarg, "cpu") && strcmp(optarg, "auto") && strcmp(optarg, "gpu-always"))
            return cli_usage_error("sweep", "--device expects cpu, auto or gpu-always, got '%s'", optarg);
        return 0;
    case 'h': fputs(USAGE, stdout); return -1;
    default: return cli_bad_option("sweep", argv, optind, optopt);
    }
}

/* Returns 0, 2 on a bad command line, -1 after --help. */
static int parse_args(int argc, char **argv, sweep *s, sweep_opts *o)
{
    static const struct option opts[] = {
        {"set", required_argument, NULL, 's'},      {"steps", required_argument, NULL, 'n'},
        {"record", required_argument, NULL, 'r'},   {"out", required_argument, NULL, 'o'},
        {"threads", required_argument, NULL, 'j'},  {"timeout", required_argument, NULL, 't'},
        {"device", required_argument, NULL, OPT_DEVICE}, {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},           {0, 0, 0, 0}};
    s->steps = 100;
    s->records = calloc((size_t)argc + 1, sizeof *s->records);
    if (!s->records) return 1;
    opterr = 0;
    int c, rc = 0;
    while (!rc && (c = getopt_long(argc, argv, "s:n:r:o:j:t:qh", opts, NULL)) != -1)
        rc = parse_option(c, s, o, argv);
    if (rc) return rc;
    if (optind >= argc) return cli_usage_error("sweep", "no scene given");
    if (optind + 1 < argc) return cli_usage_error("sweep", "more than one scene given");
    s->scene = argv[optind];
    if (s->nrecords > 64) return cli_usage_error("sweep", "at most 64 --record");
    if (!s->out[0]) {
        char name[256];
        cli_scene_name(s->scene, name, sizeof name);
        snprintf(s->out, sizeof s->out, "out/%s_sweep", name);
    }
    if (!(s->nruns = sweep_count(s)))
        return cli_usage_error("sweep", "the grid has more than 1000000 runs");
    return 0;
}

/* Rank 0's view of the runs. */
typedef struct runs {
    sweep *s;
    double timeout;
    char **reports, **status;
    int *todo, ntodo, skipped, finished, failed;
} runs;

static void announce(runs *t, const cli_job_result *r, const char *status)
{
    char dir[1100], where[160];
    sweep_run_dir(t->s, r->job, dir, sizeof dir);
    if (!strcmp(status, "ok")) {
        if (!t->s->quiet)
            fprintf(stderr, "pliant sweep: run_%04d ok [%d/%d]\n", r->job, t->finished,
                    t->ntodo);
        return;
    }
    cli_dispatch_where(r, where, sizeof where);
    fprintf(stderr, "pliant sweep: run_%04d %s on %s: %s", r->job, status, where, t->s->scene);
    for (int a = 0; a < t->s->naxes; ++a)
        fprintf(stderr, " --set %s=%s", t->s->axes[a].path, sweep_value(t->s, r->job, a));
    fprintf(stderr, " (log: %s/log.txt) [%d/%d]\n", dir, t->finished, t->ntodo);
}

static void run_done(const cli_job_result *r, void *user)
{
    runs *t = user;
    char buf[160], how[160];
    const char *st = cli_report_get(r->text, "status", buf, sizeof buf);
    t->reports[r->job] = st ? strdup(r->text) : NULL;
    if (r->end == CLI_JOB_EXITED && r->code == 0 && st && !strcmp(st, "ok")) {
        snprintf(how, sizeof how, "ok");
    } else if (r->end == CLI_JOB_EXITED) {
        snprintf(how, sizeof how, "failed (exit %d)", r->code);
    } else if (r->end == CLI_JOB_SIGNALLED) {
        const char *abbrev = sigabbrev_np(r->code);
        snprintf(how, sizeof how, "crashed (SIG%s)", abbrev ? abbrev : "?");
    } else {
        cli_job_describe(r, t->timeout, how, sizeof how);
    }
    t->status[r->job] = strdup(how);
    t->finished++;
    t->failed += strcmp(how, "ok") != 0;
    announce(t, r, how);
}

/* Checks the scene, --set and --record paths once, in a child, before the
 * grid runs: a misspelled path is one message, not a failed run per point. */
static int check_paths(sweep *s, int run)
{
    cli_job j;
    cli_job_result r;
    cli_job_start(&j, run, sweep_check_job, s, 0, NULL);
    while (!cli_job_poll(&j, 1000, &r)) {}
    int ok = r.end == CLI_JOB_EXITED && r.code == 0;
    cli_job_result_free(&r);
    if (!ok) fprintf(stderr, "pliant sweep: %s: the sweep was not run\n", s->scene);
    return ok ? 0 : 2;
}

/* Rank 0: the folder, the request, the runs completed before, the check.
 * Returns 0 or the exit code (then nothing runs). */
static int prepare(runs *t)
{
    sweep *s = t->s;
    if (cli_make_dirs(s->out) != 0) {
        fprintf(stderr, "pliant sweep: cannot create the folder %s\n", s->out);
        return 2;
    }
    int rc = sweep_spec_check(s);
    if (rc) return rc;
    for (int r = 0; r < s->nruns; ++r) {
        if ((t->reports[r] = sweep_completed(s, r))) {
            t->status[r] = strdup("ok");
            t->skipped++;
        } else {
            t->todo[t->ntodo++] = r;
        }
    }
    if (t->skipped)
        fprintf(stderr, "pliant sweep: %d of %d runs completed before; running the other %d\n",
                t->skipped, s->nruns, t->ntodo);
    return t->ntodo ? check_paths(s, t->todo[0]) : 0;
}

static int finish(runs *t)
{
    sweep *s = t->s;
    int rc = sweep_write_tables(s, t->reports, t->status);
    printf("%d runs: %d ok, %d failed", s->nruns, s->nruns - t->failed, t->failed);
    if (t->skipped) printf(" (%d completed before)", t->skipped);
    printf("; tables: %s/sweep.csv, %s/sweep.md\n", s->out, s->out);
    return rc ? 1 : t->failed ? 1 : 0;
}

/* Every rank: rank 0 prepares, hands out the runs and writes the tables;
 * the others run what they are given. */
static int run_sweep(sweep *s, const sweep_opts *o)
{
    int root = cli_dispatch_rank() == 0, rc = 0;
    size_t n = (size_t)s->nruns;
    runs t = {s, o->timeout, calloc(n, sizeof(char *)), calloc(n, sizeof(char *)),
              malloc(n * sizeof(int)), 0, 0, 0, 0};
    if (!t.reports || !t.status || !t.todo) rc = 1;
    if (root && !rc) rc = prepare(&t);
    cli_dispatch d = {"sweep", t.todo, rc ? 0 : t.ntodo, sweep_run_job, s, o->timeout,
                      run_done, &t};
    cli_dispatch_run(&d);
    if (root && !rc) rc = finish(&t);
    for (size_t r = 0; r < n; ++r) {
        if (t.reports) free(t.reports[r]);
        if (t.status) free(t.status[r]);
    }
    free(t.reports);
    free(t.status);
    free(t.todo);
    return root ? rc : 0;
}

int cli_sweep(int argc, char **argv)
{
    sweep s;
    sweep_opts o = {0, 0};
    memset(&s, 0, sizeof s);
    int rc = parse_args(argc, argv, &s, &o);
    if (rc == 0) rc = cli_dispatch_init("sweep", &argc, &argv);
    if (rc) {
        sweep_free(&s);
        return rc < 0 ? 0 : rc;
    }
    cli_threads_set(o.threads ? o.threads : cli_dispatch_default_threads());
    s.rank = cli_dispatch_rank();
    rc = run_sweep(&s, &o);
    sweep_free(&s);
    return cli_dispatch_finish(rc);
}
