/* sweep_run.c - one run of a sweep, in its child process: the scene with
 * the run's --set values, outputs and messages in OUT/run_NNNN/, the
 * recorded fields read after the last step.  The report goes to the parent
 * and, when the run completed, to OUT/run_NNNN/result.txt (written under
 * another name and renamed, so that it exists only when complete). */
#include <pliant/pliant.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "sweep.h"

enum { VALUE_MAX = 1 << 20 };

void sweep_run_dir(const sweep *s, int run, char *buf, size_t size)
{
    snprintf(buf, size, "%s/run_%04d", s->out, run);
}

static const char **overrides(const sweep *s, int run)
{
    const char **sets = calloc((size_t)s->naxes + 1, sizeof *sets);
    for (int a = 0; sets && a < s->naxes; ++a) {
        const char *v = sweep_value(s, run, a);
        char *kv = malloc(strlen(s->axes[a].path) + strlen(v) + 2);
        if (!kv) return sets; /* the NULL entry stops the list: the load then fails */
        sprintf(kv, "%s=%s", s->axes[a].path, v);
        sets[a] = kv;
    }
    return sets;
}

static pl_sim *load(const sweep *s, int run, const char *out_dir)
{
    const char **sets = overrides(s, run);
    pl_sim_options opt = {.out_dir = out_dir, .overrides = sets,
                          .noverrides = sets ? s->naxes : 0, .device = s->device};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *sim = pl_sim_load_file(s->scene, &opt, &diag);
    pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    for (int a = 0; sets && a < s->naxes; ++a) free((char *)sets[a]);
    free(sets);
    return sim;
}

/* One line of a report: newlines inside a value would end it early. */
static void put(FILE *f, const char *key, const char *value)
{
    fprintf(f, "%s ", key);
    for (const char *p = value; *p; ++p) fputc(*p == '\n' || *p == '\r' ? ' ' : *p, f);
    fputc('\n', f);
}

/* Steps the run and reads its records into rec[] (malloc'ed); returns the
 * status with err filled on failure. */
static int step_and_record(pl_sim *sim, const sweep *s, int *done, double *ms, char **rec,
                           pl_error *err)
{
    int rc = PL_OK;
    double t0 = pl_now();
    for (*done = 0; *done < s->steps && rc == PL_OK; ++*done) rc = pl_sim_step(sim, 1, err);
    if (rc != PL_OK) --*done;
    *ms = *done ? 1e3 * (pl_now() - t0) / *done : 0.0;
    if (rc == PL_OK) rc = pl_sim_finish(sim, err);
    for (int k = 0; rc == PL_OK && k < s->nrecords; ++k) {
        if (!(rec[k] = malloc(VALUE_MAX))) return pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL,
                                                               "out of memory");
        rc = pl_sim_get(sim, s->records[k], rec[k], VALUE_MAX, err);
    }
    return rc;
}

static void report(FILE *f, const sweep *s, int run, int rc, int done, double ms, char **rec,
                   const pl_error *err)
{
    char buf[1600];
    fprintf(f, "status %s\nsteps %d\nms %.6f\n", rc == PL_OK ? "ok" : "error", done, ms);
    for (int a = 0; a < s->naxes; ++a) {
        snprintf(buf, sizeof buf, "set %d", a);
        put(f, buf, sweep_value(s, run, a));
    }
    for (int k = 0; rc == PL_OK && k < s->nrecords; ++k) {
        snprintf(buf, sizeof buf, "rec %d", k);
        put(f, buf, rec[k]);
    }
    if (rc != PL_OK) put(f, "msg", pl_error_format(err, buf, sizeof buf));
}

/* result.txt: the report plus where it ran, renamed into place at the end. */
static void write_result(const sweep *s, const char *dir, int run, int done, double ms,
                         char **rec)
{
    char tmp[1200], path[1200], host[64] = "?";
    snprintf(tmp, sizeof tmp, "%s/result.txt.part", dir);
    snprintf(path, sizeof path, "%s/result.txt", dir);
    FILE *f = fopen(tmp, "w");
    if (!f) return;
    report(f, s, run, PL_OK, done, ms, rec, NULL);
    gethostname(host, sizeof host - 1);
    const char *gpu = getenv("CUDA_VISIBLE_DEVICES");
    fprintf(f, "rank %d\nhost %s\ngpu %s\n", s->rank, host, gpu ? gpu : "-");
    if (fclose(f) == 0) rename(tmp, path);
}

int sweep_run_job(int run, void *user, FILE *out)
{
    const sweep *s = user;
    char dir[1100], log[1200];
    sweep_run_dir(s, run, dir, sizeof dir);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(out, "status error\nsteps 0\nms 0\nmsg cannot create %s: %s\n", dir,
                strerror(errno));
        return 2;
    }
    snprintf(log, sizeof log, "%s/log.txt", dir);
    if (!freopen(log, "w", stderr)) fprintf(out, "msg cannot write %s\n", log);
    pl_log_set_level(s->quiet ? PL_LOG_WARN : PL_LOG_INFO);
    pl_error err;
    pl_error_clear(&err);
    char *rec[64] = {0};
    int done = 0, rc;
    double ms = 0;
    pl_sim *sim = load(s, run, dir);
    if (!sim)
        rc = pl_error_set(&err, PL_EINPUT, s->scene, 0, NULL,
                          "the scene does not load with these values (see the run's log.txt)");
    else
        rc = step_and_record(sim, s, &done, &ms, rec, &err);
    if (rc != PL_OK) fprintf(stderr, "pliant sweep: %s\n", pl_error_format(&err, log, sizeof log));
    report(out, s, run, rc, done, ms, rec, &err);
    if (rc == PL_OK) write_result(s, dir, run, done, ms, rec);
    for (int k = 0; k < s->nrecords; ++k) free(rec[k]);
    pl_sim_free(sim);
    return rc;
}

int sweep_check_job(int run, void *user, FILE *out)
{
    const sweep *s = user;
    (void)out;
    pl_log_set_level(PL_LOG_WARN);
    char *tmp = cli_tmpdir_create("sweep_check");
    pl_sim *sim = tmp ? load(s, run, tmp) : NULL;
    int rc = sim ? 0 : 2;
    char *buf = malloc(VALUE_MAX);
    for (int k = 0; sim && buf && k < s->nrecords; ++k) {
        pl_error err;
        if (pl_sim_get(sim, s->records[k], buf, VALUE_MAX, &err) != PL_OK) {
            fprintf(stderr, "--record: error: %s: %s\n", s->records[k], err.msg);
            rc = 2;
        }
    }
    free(buf);
    pl_sim_free(sim);
    if (tmp) cli_remove_tree(tmp);
    free(tmp);
    return rc;
}
