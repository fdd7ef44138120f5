/* cmd_regress.c - `pliant regress LIST [--update] [--sofa-steps] [--refs DIR]`: SOFA's
 * state regression.  Each line of LIST ("scene steps epsilon [mapped]
 * [lastonly]") runs a scene and compares every MechanicalObject's positions
 * with the stored reference files <refs>/<scene>.reference_<k>_<name>_mstate.txt.gz
 * using SOFA's measure (per compared step ||x - x_ref|| / nDoF, summed,
 * averaged over states, against epsilon).  --update rewrites the references.
 * Each entry runs in a child process (regress_entry.c), one after the other
 * or over the ranks of `mpirun` (cli_dispatch.h); a crash or time-out is the
 * entry's ERROR row, the others go on.  Rows print in list order.
 * Exit: 0 all passed, 1 some failed, 2 bad input or an entry that did not run. */
#include <pliant/pliant.h>

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "cli_dispatch.h"
#include "regress.h"

static void dir_of(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (slash)
        snprintf(out, size, "%.*s", (int)(slash - path), path);
    else
        snprintf(out, size, ".");
}

static const char USAGE[] =
    "usage: pliant regress LIST [OPTIONS]\n"
    "Runs every scene of LIST (lines \"scene steps epsilon [mapped] [lastonly]\", paths\n"
    "relative to LIST or absolute) and compares each MechanicalObject's positions with the stored\n"
    "references (SOFA's measure: per compared step ||x - x_ref|| / nDoF, against epsilon).\n"
    "Each scene runs in its own process; under mpirun the scenes are spread over the ranks.\n\n"
    "  -u, --update        rewrite the references instead of comparing\n"
    "  -s, --sofa-steps    SOFA's step counting: \"N steps\" records t = 0 ... (N-1) h\n"
    "                      (SOFA's WriteState records before each step; without it\n"
    "                      Pliant records t = 0 and after each step, up to N h)\n"
    "  -r, --refs DIR      reference folder (default: as LIST says, else LIST's folder/references)\n"
    "  -j, --threads N     OpenMP threads per scene\n"
    "  -t, --timeout S     stop a scene that runs longer than S seconds (default: no limit)\n"
    "  -q, --quiet         only warnings and errors from the scenes\n"
    "  -h, --help          this text\n"
    "Temporary outputs go to $TMPDIR (default /tmp) and are removed.\n"
    "exit codes: 0 all passed, 1 some failed, 2 bad input or a scene that did not run\n";

typedef struct regress_opts {
    const char *list_path, *refs;
    int update, sofa_steps, threads, quiet;
    double timeout;
} regress_opts;

/* Returns 0, 2 on a bad command line, -1 after --help. */
static int parse_args(int argc, char **argv, regress_opts *o)
{
    static const struct option opts[] = {
        {"update", no_argument, NULL, 'u'}, {"sofa-steps", no_argument, NULL, 's'},
        {"refs", required_argument, NULL, 'r'},
        {"threads", required_argument, NULL, 'j'}, {"timeout", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'}, {"help", no_argument, NULL, 'h'}, {0, 0, 0, 0}};
    memset(o, 0, sizeof *o);
    int c, rc = 0;
    opterr = 0;
    while (!rc && (c = getopt_long(argc, argv, "usr:j:t:qh", opts, NULL)) != -1) {
        switch (c) {
        case 'u': o->update = 1; break;
        case 's': o->sofa_steps = 1; break;
        case 'r': o->refs = optarg; break;
        case 'j': rc = cli_parse_int("regress", "--threads", optarg, 1, &o->threads); break;
        case 't': rc = cli_parse_double("regress", "--timeout", optarg, &o->timeout); break;
        case 'q': o->quiet = 1; break;
        case 'h': return fputs(USAGE, stdout), -1;
        default: rc = cli_bad_option("regress", argv, optind, optopt);
        }
    }
    if (rc) return rc;
    if (optind >= argc) return cli_usage_error("regress", "no regression LIST given");
    if (optind + 1 < argc) return cli_usage_error("regress", "more than one LIST given");
    o->list_path = argv[optind];
    return 0;
}

/* Rank 0's table: rows arrive in any order and print in list order. */
typedef struct table {
    const regress_ctx *x;
    double timeout;
    char **rows;
    int printed, failed, bad;
} table;

static char *format_row(table *t, const cli_job_result *r)
{
    const pl_regression_entry *e = &t->x->list->items[r->job];
    char result[32], val[1600], cell[3200];
    const char *res = cli_report_get(r->text, "result", result, sizeof result);
    if (res && (!strcmp(res, "pass") || !strcmp(res, "FAIL"))) {
        double err = atof(cli_report_get(r->text, "error", val, sizeof val) ? val : "nan");
        double last = atof(cli_report_get(r->text, "last", val, sizeof val) ? val : "nan");
        char why[1400];
        if (cli_report_get(r->text, "why", why, sizeof why))
            snprintf(cell, sizeof cell, "%12.3e %10.3e  %s: %s", err, last, res, why);
        else
            snprintf(cell, sizeof cell, "%12.3e %10.3e  %s", err, last, res);
        t->failed += !strcmp(res, "FAIL");
    } else if (res && !strcmp(res, "written")) {
        snprintf(cell, sizeof cell, "%12s %10s  reference written (%s states)", "-", "-",
                 cli_report_get(r->text, "states", val, sizeof val) ? val : "?");
    } else {
        /* the child reported an error (msg), or ended without a report */
        if (!cli_report_get(r->text, "msg", val, sizeof val)) {
            char how[160], where[160];
            cli_job_describe(r, t->timeout, how, sizeof how);
            cli_dispatch_where(r, where, sizeof where);
            snprintf(val, sizeof val, "the run %s", how);
            fprintf(stderr, "pliant regress: %s: the run %s (%s)\n", e->scene, how, where);
        }
        snprintf(cell, sizeof cell, "%12s %10s  ERROR: %s", "-", "-", val);
        t->bad++;
    }
    char line[4096];
    snprintf(line, sizeof line, "%-52s %6d %10.3g %s", e->scene, e->steps, e->epsilon, cell);
    return strdup(line);
}

static void row_done(const cli_job_result *r, void *user)
{
    table *t = user;
    t->rows[r->job] = format_row(t, r);
    while (t->printed < t->x->list->count && t->rows[t->printed]) {
        printf("%s\n", t->rows[t->printed++]);
        fflush(stdout);
    }
}

static void refs_dir(const regress_opts *o, const pl_regression_list *list, const char *list_dir,
                     char *refs, size_t size)
{
    if (o->refs)
        snprintf(refs, size, "%s", o->refs);
    else if (list->ref_dir && list->ref_dir[0] == '/')
        snprintf(refs, size, "%s", list->ref_dir);
    else if (list->ref_dir)
        snprintf(refs, size, "%s/%s", list_dir, list->ref_dir);
    else
        snprintf(refs, size, "%s/references", list_dir);
}

/* Every rank: runs the list (rank 0 prints the table); returns the exit code. */
static int run_list(const regress_opts *o, const pl_regression_list *list)
{
    char list_dir[1024], refs[2048];
    dir_of(o->list_path, list_dir, sizeof list_dir);
    refs_dir(o, list, list_dir, refs, sizeof refs);
    if (o->update) mkdir(refs, 0755);
    char *out_dir = cli_tmpdir_create("regress");
    if (!out_dir) {
        fprintf(stderr, "pliant regress: cannot create a temporary folder in $TMPDIR\n");
        return 1;
    }
    regress_ctx x = {.list = list, .list_path = o->list_path, .list_dir = list_dir, .refs = refs,
                     .out_dir = out_dir, .update = o->update, .sofa_steps = o->sofa_steps,
                     .quiet = o->quiet};
    table t = {&x, o->timeout, calloc((size_t)list->count + 1, sizeof(char *)), 0, 0, 0};
    int *todo = malloc(((size_t)list->count + 1) * sizeof *todo);
    int root = cli_dispatch_rank() == 0;
    for (int i = 0; todo && i < list->count; ++i) todo[i] = i;
    cli_dispatch d = {"regress", todo, todo && t.rows ? list->count : 0, regress_entry_job, &x,
                      o->timeout, row_done, &t};
    if (root)
        printf("%-52s %6s %10s %12s %10s  %s\n", "scene", "steps", "epsilon", "error/DoF",
               "last/diag", "result");
    cli_dispatch_run(&d);
    if (root)
        printf("%d scenes: %d passed, %d failed, %d errors\n", list->count,
               list->count - t.failed - t.bad, t.failed, t.bad);
    for (int i = 0; t.rows && i < list->count; ++i) free(t.rows[i]);
    free(t.rows);
    free(todo);
    cli_remove_tree(out_dir);
    free(out_dir);
    if (!root) return 0;
    return (!todo || !t.rows) ? 1 : t.bad ? 2 : t.failed ? 1 : 0;
}

int cli_regress(int argc, char **argv)
{
    regress_opts o;
    int rc = parse_args(argc, argv, &o);
    if (rc) return rc < 0 ? 0 : rc;
    if ((rc = cli_dispatch_init("regress", &argc, &argv)) != 0) return rc;
    cli_threads_set(o.threads ? o.threads : cli_dispatch_default_threads());
    pl_regression_list list = {0};
    pl_diag diag;
    pl_diag_init(&diag);
    if (pl_regression_list_load(o.list_path, &list, &diag) != PL_OK) {
        if (cli_dispatch_rank() == 0) pl_diag_print(&diag, stderr);
        pl_diag_free(&diag);
        pl_regression_list_free(&list);
        return cli_dispatch_finish(2);
    }
    pl_diag_free(&diag);
    rc = run_list(&o, &list);
    pl_regression_list_free(&list);
    return cli_dispatch_finish(rc);
}
