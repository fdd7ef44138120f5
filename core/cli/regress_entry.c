/* regress_entry.c - one line of a regression list, as its child process
 * runs it: load the scene (outputs into the rank's temporary folder), step
 * it recording every MechanicalObject's positions, then compare them with
 * the stored references or rewrite those.  The report, one "key value" per
 * line, goes back to the parent (cmd_regress.c), which prints the row. */
#include <pliant/pliant.h>

#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <pliant/export.h>
#include "regress.h"

typedef struct states {
    pl_component *items[64];
    int n;
    int with_mapped;          /* the entry's mapped 1: MappedPoints are recorded too */
    double *scratch;          /* a MappedPoints' positions, parsed */
    size_t scratch_cap;
} states;

static int is_mapped(const pl_component *c)
{
    return !strcmp(c->type->name, "MappedPoints") && c->type->ops.get;
}

/* The states SOFA's WriteState records, in its order (the scene's,
 * depth first): every MechanicalObject, and with mapped 1 every mapped one
 * (MappedPoints, which the SOFA loader keeps of a mapped node). */
static void add_states(pl_node *node, states *s)
{
    for (int k = 0; k < node->ncomponents; ++k) {
        pl_component *c = node->components[k];
        if (s->n < 64 && (pl_component_role(c, PL_ROLE_STATE) || (s->with_mapped && is_mapped(c))))
            s->items[s->n++] = c;
    }
    for (int k = 0; k < node->nchildren; ++k) add_states(node->children[k], s);
}

/* The positions of state k (n x 3); a MappedPoints' through its get op
 * (%.17g text, which reads back exactly). */
static int positions_of(states *st, int k, const pl_data *d, const double **x, int *n,
                        pl_error *err)
{
    const pl_component *c = st->items[k];
    const pl_state_ops *ops = pl_component_role(c, PL_ROLE_STATE);
    if (ops) {
        pl_buffer b = ops->positions(c, d);
        *x = pl_buffer_f64(&b);
        *n = (int)b.rows * 3;
        return PL_OK;
    }
    size_t size = 1 << 16;
    char *buf = NULL;
    int rc = PL_EINTERNAL;
    while (rc == PL_EINTERNAL && size < ((size_t)1 << 31)) {
        free(buf);
        buf = malloc(size *= 4);
        if (!buf) break;
        rc = c->type->ops.get(c, d, "position", buf, size);
    }
    int count = 0;
    for (char *p = buf, *end; rc == PL_OK && p && *p; p = end) {
        double v = strtod(p, &end);
        if (end == p) break;
        if ((size_t)count == st->scratch_cap) {
            size_t cap = st->scratch_cap ? 2 * st->scratch_cap : 3 * 1024;
            double *y = realloc(st->scratch, cap * sizeof *y);
            if (!y) {
                rc = PL_EINTERNAL;
                break;
            }
            st->scratch = y;
            st->scratch_cap = cap;
        }
        st->scratch[count++] = v;
    }
    free(buf);
    if (rc != PL_OK)
        return pl_error_set(err, PL_EINTERNAL, NULL, 0, c->name, "cannot read its positions");
    *x = st->scratch;
    *n = count;
    return PL_OK;
}

static const char *base_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static int record(pl_sim *sim, states *st, pl_state_records *rec, pl_error *err)
{
    for (int k = 0; k < st->n; ++k) {
        const double *x;
        int n;
        int rc = positions_of(st, k, pl_sim_data(sim), &x, &n, err);
        if (!rc) rc = pl_state_records_add(&rec[k], pl_sim_time(sim), x, n, NULL, 0, err);
        if (rc) return rc;
    }
    return PL_OK;
}

/* Estimates an entry's cost before running it: its steps, and the memory
 * its recorded states take, against the scene's work limits; an error
 * names the list's line. */
static int check_cost(pl_sim *sim, states *st, const pl_regression_entry *e,
                      const char *list, pl_error *err)
{
    pl_work_limits lim;
    pl_work_limits_of(pl_sim_model(sim), pl_sim_model(sim)->root, &lim);
    if (e->steps > lim.max_steps)
        return pl_error_set(err, PL_EINPUT, list, e->line, NULL,
                            "%d steps are above the cap of %lld (the scene may raise it with "
                            "<WorkLimits maxSteps=\"...\"/>)", e->steps, lim.max_steps);
    double values = 0;
    for (int k = 0; k < st->n; ++k) {
        const double *x;
        int n;
        if (positions_of(st, k, pl_sim_data(sim), &x, &n, err)) return err->code;
        values += n;
    }
    double mb = values * (e->last_only ? 2.0 : e->steps + 1.0) * sizeof(double) / 1048576.0;
    if (mb > lim.max_record_mb)
        return pl_error_set(err, PL_EINPUT, list, e->line, NULL,
                            "recording %d steps of %.0f values would take %.0f MB, above the cap "
                            "of %.0f MB (lastonly 1 records the last step only; the scene may "
                            "raise the cap with <WorkLimits maxRecordMB=\"...\"/>)",
                            e->steps, values, mb, lim.max_record_mb);
    return PL_OK;
}

/* Runs one entry and returns the sim (the caller frees it: the state
 * components' names are needed for the reference files), NULL on error. */
static pl_sim *run_entry(const char *scene, const pl_regression_entry *e, int sofa_steps,
                         const char *list, const char *out_dir, states *st, pl_state_records *rec,
                         pl_error *err)
{
    pl_diag diag;
    pl_diag_init(&diag);
    /* the references are CPU results: a GPU would differ by rounding */
    pl_sim_options opt = {.out_dir = out_dir, .device = "cpu"};
    pl_sim *sim = pl_sim_load_file(scene, &opt, &diag);
    if (!sim) {
        /* the row names the first error; all of them went to stderr */
        pl_diag_print(&diag, stderr);
        const pl_error *first = NULL;
        for (int k = 0; k < diag.count && !first; ++k)
            if (diag.items[k].code != PL_OK) first = &diag.items[k];
        char why[1400] = "";
        if (first) pl_error_format(first, why, sizeof why);
        pl_error_set(err, PL_EINPUT, scene, 0, NULL, "the scene does not load%s%s%s",
                     first ? ": " : "", why,
                     diag.nerrors > 1 ? " (and more errors on stderr)" : "");
        pl_diag_free(&diag);
        return NULL;
    }
    pl_diag_free(&diag);
    st->n = 0;
    st->with_mapped = e->mapped;
    add_states(pl_sim_model(sim)->root, st);
    for (int k = 0; k < st->n; ++k) pl_state_records_init(&rec[k]);
    int rc = check_cost(sim, st, e, list, err);
    if (rc == PL_OK) rc = record(sim, st, rec, err);
    /* Pliant: records t = 0 and after each step, t = h ... N h.  SOFA's
     * WriteState records before each step, t = 0 ... (N-1) h: its last step
     * is never recorded, so it is not run. */
    int run = sofa_steps ? e->steps - 1 : e->steps;
    for (int s = 0; rc == PL_OK && s < run; ++s) {
        rc = pl_sim_step(sim, 1, err);
        if (rc == PL_OK && (!e->last_only || s == run - 1)) rc = record(sim, st, rec, err);
    }
    if (rc != PL_OK) {
        pl_sim_free(sim);
        return NULL;
    }
    return sim;
}

static int reference_path(char *buf, size_t size, const char *refs, const char *scene, int k,
                          const char *name)
{
    char base[4096];
    snprintf(base, sizeof base, "%s/%s", refs, base_of(scene));
    return pl_regression_reference_path(buf, size, base, k, name) >= (int)size ? -1 : 0;
}

static int write_refs(const char *refs, const char *scene, const states *st,
                      const pl_state_records *rec, pl_error *err)
{
    for (int k = 0; k < st->n; ++k) {
        char path[2048];
        if (reference_path(path, sizeof path, refs, scene, k, st->items[k]->name))
            return pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "reference path too long");
        pl_state_writer *w = pl_state_writer_open(path, 0, err);
        if (!w) return err->code;
        for (int r = 0; r < rec[k].count; ++r)
            if (pl_state_writer_write(w, rec[k].items[r].time, rec[k].items[r].x,
                                      rec[k].items[r].nx, NULL, 0, err)) {
                pl_state_writer_close(w, NULL);
                return err->code;
            }
        if (pl_state_writer_close(w, err)) return err->code;
    }
    return PL_OK;
}

/* A reference of a state this run does not have (the next index, n): SOFA
 * records mapped MechanicalObjects too when the entry says mapped 1 (the
 * liver's sphere centres); Pliant keeps them as MappedPoints where the SOFA
 * loader could (docs/sofa.md).  With mapped 1 one left over is an error
 * naming the file; with mapped 0 SOFA would not compare it. */
static int extra_reference(const char *refs, const char *scene, int n, int mapped,
                           pl_error *err)
{
    char pattern[2048];
    snprintf(pattern, sizeof pattern, "%s/%s.reference_%d_*_mstate.txt.gz", refs,
             base_of(scene), n);
    glob_t g;
    int found = glob(pattern, 0, NULL, &g) == 0 && g.gl_pathc > 0;
    int rc = PL_OK;
    if (found && mapped)
        rc = pl_error_set(err, PL_EINPUT, g.gl_pathv[0], 0, NULL,
                          "a reference state (%d) that this run does not have: with 'mapped 1' "
                          "SOFA also records the states of mapped nodes; this scene keeps only "
                          "%d (a mapped node the SOFA loader dropped: its warnings say why); "
                          "give 'mapped 0' to compare the simulated states only",
                          n, n);
    globfree(&g);
    return rc;
}

static int compare_refs(const char *refs, const char *scene, const states *st,
                        const pl_state_records *rec, double dt, double epsilon, int mapped,
                        pl_regression_result *res, pl_regression_detail *why, pl_error *err)
{
    pl_state_records ref[64];
    int rc = PL_OK;
    for (int k = 0; k < st->n; ++k) pl_state_records_init(&ref[k]);
    for (int k = 0; k < st->n && rc == PL_OK; ++k) {
        char path[2048];
        if (reference_path(path, sizeof path, refs, scene, k, st->items[k]->name))
            rc = pl_error_set(err, PL_EINPUT, NULL, 0, NULL, "reference path too long");
        else if (access(path, R_OK) != 0)
            rc = pl_error_set(err, PL_EINPUT, path, 0, NULL,
                              "no reference file (run with --update to create it)");
        else
            rc = pl_state_file_read(path, &ref[k], err);
    }
    if (rc == PL_OK) rc = extra_reference(refs, scene, st->n, mapped, err);
    if (rc == PL_OK)
        rc = pl_regression_compare_detail(ref, rec, st->n, 0.5 * dt, epsilon, res, why, err);
    for (int k = 0; k < st->n; ++k) pl_state_records_free(&ref[k]);
    return rc;
}

/* Why an entry failed, on one line: which state, which vertex, how far,
 * against which tolerance. */
static void write_why(FILE *out, const pl_regression_result *res, const pl_regression_detail *r,
                      const states *st, double eps)
{
    if (res->missing) {
        fprintf(out, "why state %d '%s': %d reference step%s not recorded by this run (the first "
                     "at T= %g; SOFA's step counting needs --sofa-steps)\n",
                r->missing_state, st->items[r->missing_state]->name, res->missing,
                res->missing == 1 ? "" : "s", r->missing_time);
    } else if (r->worst_state < 0) {
        fprintf(out, "why nothing compared (the reference states are empty)\n");
    } else {
        fprintf(out, "why state %d '%s': error/DoF %.3e > epsilon %.3g (mean over %d state%s "
                     "%.3e); its vertex %d is %.4g from the reference at T= %g\n",
                r->worst_state, st->items[r->worst_state]->name, r->worst_state_error, eps,
                st->n, st->n == 1 ? "" : "s", res->error_by_dof, r->worst_vertex,
                r->worst_distance, r->worst_time);
    }
}

/* The run of entry i in its child; writes the report, returns the exit code. */
int regress_entry_job(int i, void *user, FILE *out)
{
    const regress_ctx *x = user;
    const pl_regression_entry *e = &x->list->items[i];
    char scene[2048];
    if (e->scene[0] == '/') /* an absolute path stays as it is */
        snprintf(scene, sizeof scene, "%s", e->scene);
    else
        snprintf(scene, sizeof scene, "%s/%s", x->list_dir, e->scene);
    if (x->quiet) pl_log_set_level(PL_LOG_WARN);
    states st = {0};
    pl_state_records rec[64];
    pl_error err;
    pl_regression_result res = {0};
    pl_regression_detail why = {0};
    pl_sim *sim = run_entry(scene, e, x->sofa_steps, x->list_path, x->out_dir, &st, rec, &err);
    int rc = sim ? PL_OK : err.code;
    double dt = sim ? pl_node_dt(pl_sim_model(sim)->root) : 0.01;
    if (rc == PL_OK)
        rc = x->update ? write_refs(x->refs, e->scene, &st, rec, &err)
                       : compare_refs(x->refs, e->scene, &st, rec, dt, e->epsilon, e->mapped,
                                       &res, &why, &err);
    if (rc != PL_OK) {
        char msg[1600];
        pl_error_format(&err, msg, sizeof msg);
        for (char *p = msg; *p; ++p)
            if (*p == '\n') *p = ' ';
        fprintf(out, "result error\nmsg %s\n", msg);
    } else if (x->update) {
        fprintf(out, "result written\nstates %d\n", st.n);
    } else {
        fprintf(out, "result %s\nerror %.17g\nlast %.17g\n", res.passed ? "pass" : "FAIL",
                res.error_by_dof, why.last_relative);
        if (!res.passed) write_why(out, &res, &why, &st, e->epsilon);
    }
    for (int k = 0; k < st.n; ++k) pl_state_records_free(&rec[k]);
    free(st.scratch);
    pl_sim_free(sim);
    return rc == PL_OK ? 0 : rc;
}
