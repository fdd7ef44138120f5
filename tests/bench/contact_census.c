/* contact_census.c - what a contact scene's contacts are (issue 16 item 6:
 * why our counts differ from the paper's Table 3).  Runs a scene on the CPU
 * and, after every step, reads the contacts recorded by the
 * CollisionPipeline (pl_data slot "contacts", coll_contact_record) and by
 * the analytic obstacles (PlaneObstacle ..., pl_obstacle_contact), and
 * sorts them by
 *   - kind: a body vertex against an obstacle's face ("v-obst"), an
 *     obstacle's vertex against a body's face ("obstv-f"), vertex-face
 *     between bodies ("v-f body"), edge-edge with an obstacle or between
 *     bodies, and analytic obstacles ("shape": the floor);
 *   - the gap at detection (start of the step): through (< 0), within
 *     contactDistance, below alarm / 2, below alarm, and at or beyond alarm
 *     (rows of the look-ahead: pairs apart at the start that the predicted
 *     motion brings into contact);
 *   - whether the row carries force at the end of the step (lambda_n > 0).
 * It also counts rows per feature: body vertices with several
 * vertex-face rows, obstacle vertices with several rows (a knife's apex),
 * and the rows per obstacle edge.  Prints Markdown tables for the step with
 * the most contacts and for the last step, and one line per --every steps.
 *
 *   contact_census [--steps N] [--every K] [--dump STEP FILE] [--set PATH=VALUE ...]
 *                  SCENE.xml
 *
 * --dump writes every pipeline row of that step (vertices, weights, normal,
 * gap, lambda_n) to FILE.
 *
 * Run with PLIANT_DEVICE=cpu (the records are the same; the tool only
 * reads them). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "../test_tmp.h"
#include "obstacle.h"
#include "pipeline.h"
#include "pliant/pliant.h"

enum { K_VOBST, K_OBSTVF, K_VFBODY, K_EEOBST, K_EEBODY, K_SHAPE, NKIND };
static const char *const KIND[NKIND] = {"v-obst (body vertex, obstacle face)",
                                        "obstv-f (obstacle vertex, body face)",
                                        "v-f body-body",
                                        "e-e body-obstacle",
                                        "e-e body-body",
                                        "shape (analytic obstacle)"};
enum { G_THROUGH, G_CONTACT, G_HALF, G_ALARM, G_AHEAD, NGAP };
static const char *const GAP[NGAP] = {"< 0", "[0, cd)", "[cd, alarm/2)", "[alarm/2, alarm)",
                                      ">= alarm (look-ahead)"};

typedef struct census {
    int step;
    int n[NKIND][NGAP];      /* rows */
    int act[NKIND][NGAP];    /* of them that carry force (lambda_n > ACTIVE x the median
                                of the positive lambda_n of the step) */
    double force[NKIND][NGAP]; /* sum of lambda_n [N] */
    double fsum, median;     /* median: the mean lambda_n [N] */
    int most;                /* rows carrying 99 % of sum lambda_n */
    int vmulti[4];           /* body vertices with 1, 2, 3, 4+ vertex-face rows (obstacles) */
    int omulti[4];           /* obstacle vertices with 1, 2-3, 4-9, 10+ rows */
    int omax;                /* most rows on one obstacle vertex */
    int ee_per_oedge_max;    /* most edge-edge rows on one obstacle edge */
    int ee_oedges;           /* obstacle edges with edge-edge rows */
    int total, active, solver;
} census;

typedef struct scan {
    FILE *dump;              /* --dump: every row of that step */
    census *c;
    pl_data *d;
    double alarm, cd;
    int *vcount, nvcount;    /* per (model, vertex): scratch */
} scan;

static int is_obstacle_model(const pl_component *m)
{
    return !strcmp(m->type->name, "MeshObstacle");
}

static int gap_class(double gap, double cd, double alarm)
{
    if (gap < 0.0) return G_THROUGH;
    if (gap < cd) return G_CONTACT;
    if (gap < 0.5 * alarm) return G_HALF;
    if (gap < alarm) return G_ALARM;
    return G_AHEAD;
}

/* Counts of keys (sorted ints): how many distinct, and the histogram. */
static int cmp_ll(const void *x, const void *y)
{
    long long a = *(const long long *)x, b = *(const long long *)y;
    return (a > b) - (a < b);
}

static void runs(long long *k, int n, void (*fn)(census *, int), census *c)
{
    qsort(k, (size_t)n, sizeof *k, cmp_ll);
    for (int i = 0; i < n;) {
        int j = i;
        while (j < n && k[j] == k[i]) j++;
        fn(c, j - i);
        i = j;
    }
}

static void vmulti_add(census *c, int r) { c->vmulti[r >= 4 ? 3 : r - 1]++; }
static void omulti_add(census *c, int r)
{
    c->omulti[r >= 10 ? 3 : r >= 4 ? 2 : r >= 2 ? 1 : 0]++;
    if (r > c->omax) c->omax = r;
}
static void oedge_add(census *c, int r)
{
    c->ee_oedges++;
    if (r > c->ee_per_oedge_max) c->ee_per_oedge_max = r;
}

/* A row "carries force" above this fraction of the step's mean lambda_n
 * (the Fischer-Burmeister solve leaves multipliers of 1e-19 N on rows that
 * stay open) */
#define ACTIVE 1e-3

typedef struct row {
    int kind, g;
    double lambda;
} row;

static row *rows_of;
static int nrows, caprows;

static void add(census *c, int kind, double gap, double lambda, double cd, double alarm)
{
    (void)c;
    if (nrows == caprows) {
        caprows = caprows ? 2 * caprows : 1024;
        rows_of = realloc(rows_of, (size_t)caprows * sizeof *rows_of);
        if (!rows_of) abort();
    }
    rows_of[nrows++] = (row){kind, gap_class(gap, cd, alarm), lambda};
}

static int cmp_d(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* Sorts the step's rows into c (then forgets them). */
static void finish(census *c)
{
    double *pos = malloc(sizeof(double) * (size_t)(nrows ? nrows : 1));
    int np = 0;
    for (int i = 0; i < nrows; ++i)
        if (rows_of[i].lambda > 0.0) pos[np++] = rows_of[i].lambda;
    qsort(pos, (size_t)np, sizeof *pos, cmp_d);
    double sum = 0.0, acc = 0.0;
    for (int i = 0; i < np; ++i) sum += pos[i];
    c->median = nrows ? sum / nrows : 0.0;
    c->most = 0; /* fewest rows (largest first) that carry 99 % of the sum */
    for (int i = np - 1; i >= 0 && acc < 0.99 * sum; --i) acc += pos[i], c->most++;
    free(pos);
    for (int i = 0; i < nrows; ++i) {
        const row *r = &rows_of[i];
        c->n[r->kind][r->g]++;
        c->total++;
        c->force[r->kind][r->g] += r->lambda;
        c->fsum += r->lambda;
        if (r->lambda > ACTIVE * c->median) {
            c->act[r->kind][r->g]++;
            c->active++;
        }
    }
    nrows = 0;
}

static void scan_pipeline(scan *s, const collision_pipeline *p)
{
    const coll_contact_record *r = pl_data_slot(s->d, p->slot);
    int n = (int)(pl_data_slot_bytes(s->d, p->slot) / sizeof *r);
    long long *vk = malloc(sizeof(long long) * (size_t)(n ? n : 1));
    long long *ok = malloc(sizeof(long long) * (size_t)(n ? n : 1));
    long long *ek = malloc(sizeof(long long) * (size_t)(n ? n : 1));
    int nv = 0, no = 0, ne = 0;
    for (int k = 0; k < n; ++k) {
        const pl_proximity *x = &r[k].prox;
        int oa = is_obstacle_model(p->models[x->model_a]);
        int ob = is_obstacle_model(p->models[x->model_b]);
        int kind;
        if (x->kind == PL_PROX_EDGE_EDGE) {
            kind = (oa || ob) ? K_EEOBST : K_EEBODY;
            if (oa || ob) { /* the obstacle's edge: its two vertices */
                const int *e = oa ? x->a : x->b;
                int lo = e[0] < e[1] ? e[0] : e[1], hi = e[0] < e[1] ? e[1] : e[0];
                ek[ne++] = ((long long)(oa ? x->model_a : x->model_b) << 48) |
                           ((long long)lo << 24) | hi;
            }
        } else {
            kind = oa ? K_OBSTVF : ob ? K_VOBST : K_VFBODY;
            long long key = ((long long)x->model_a << 32) | (unsigned)x->a[0];
            if (oa) ok[no++] = key;
            else if (ob) vk[nv++] = key;
        }
        add(s->c, kind, x->gap, r[k].lambda[0], s->cd, s->alarm);
        if (s->dump)
            fprintf(s->dump,
                    "%d %d %d %d %d %d %d %d %.4f %.4f %.4f %.4f %.4f %.4f %.4f %.4f %.6e %.4e\n",
                    kind, x->model_a, x->model_b, x->a[0], x->a[1], x->b[0], x->b[1],
                    x->b[2], x->wa[0], x->wa[1], x->wb[0], x->wb[1], x->wb[2], x->normal[0],
                    x->normal[1], x->normal[2], x->gap, r[k].lambda[0]);
    }
    runs(vk, nv, vmulti_add, s->c);
    runs(ok, no, omulti_add, s->c);
    runs(ek, ne, oedge_add, s->c);
    free(vk);
    free(ok);
    free(ek);
}

static void scan_obstacle(scan *s, const coll_obstacle *o)
{
    const pl_obstacle_contact *r = pl_data_slot(s->d, o->slot);
    int n = (int)(pl_data_slot_bytes(s->d, o->slot) / sizeof *r);
    for (int k = 0; k < n; ++k)
        add(s->c, K_SHAPE, r[k].gap, r[k].lambda[0], o->contact_distance, o->alarm_distance);
}

static int visit(pl_component *c, void *user)
{
    scan *s = user;
    const char *t = c->type->name;
    size_t len = strlen(t);
    if (!strcmp(t, "CollisionPipeline")) {
        const collision_pipeline *p = (const collision_pipeline *)c;
        s->alarm = p->alarm;
        s->cd = p->contact;
        scan_pipeline(s, p);
    } else if (len > 8 && !strcmp(t + len - 8, "Obstacle")) {
        scan_obstacle(s, (const coll_obstacle *)c);
    }
    return 0;
}

static void print_census(const char *title, const census *c)
{
    printf("\n%s (step %d): %d contacts, %d carry force (lambda_n > %g x the mean "
           "lambda_n, %.3g N), %d carry 99 %% of sum lambda_n; the solver's normal rows, most "
           "over the run: %d\n\n",
           title, c->step, c->total, c->active, ACTIVE, c->median, c->most, c->solver);
    printf("| kind |");
    for (int g = 0; g < NGAP; ++g) printf(" gap %s |", GAP[g]);
    printf(" all | carry force | share of sum lambda_n |\n|---|");
    for (int g = 0; g <= NGAP; ++g) printf("--:|");
    printf("--:|--:|\n");
    for (int k = 0; k < NKIND; ++k) {
        int all = 0, act = 0;
        double f = 0.0;
        for (int g = 0; g < NGAP; ++g) all += c->n[k][g], act += c->act[k][g], f += c->force[k][g];
        if (!all) continue;
        printf("| %s |", KIND[k]);
        for (int g = 0; g < NGAP; ++g) printf(" %d (%d) |", c->n[k][g], c->act[k][g]);
        printf(" %d | %d | %.1f %% |\n", all, act,
               c->fsum > 0.0 ? 100.0 * f / c->fsum : 0.0);
    }
    printf("| share of sum lambda_n |");
    for (int g = 0; g < NGAP; ++g) {
        double f = 0.0;
        for (int k = 0; k < NKIND; ++k) f += c->force[k][g];
        printf(" %.1f %% |", c->fsum > 0.0 ? 100.0 * f / c->fsum : 0.0);
    }
    printf(" | | |\n\n(in brackets: the rows that carry force at the end of the step)\n");
    printf("body vertices with 1 / 2 / 3 / 4+ vertex-face rows against obstacles: %d / %d / %d / "
           "%d\n",
           c->vmulti[0], c->vmulti[1], c->vmulti[2], c->vmulti[3]);
    printf("obstacle vertices with 1 / 2-3 / 4-9 / 10+ rows against body faces: %d / %d / %d / "
           "%d (most %d)\n",
           c->omulti[0], c->omulti[1], c->omulti[2], c->omulti[3], c->omax);
    printf("obstacle edges with edge-edge rows: %d (most rows on one: %d)\n", c->ee_oedges,
           c->ee_per_oedge_max);
}

int main(int argc, char **argv)
{
    int steps = 200, every = 10, dump_step = -1;
    const char *dump_path = NULL;
    const char *sets[8], *scene = NULL;
    int nsets = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--steps") && i + 1 < argc) steps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--every") && i + 1 < argc) every = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--dump") && i + 2 < argc)
            dump_step = atoi(argv[++i]), dump_path = argv[++i];
        else if (!strcmp(argv[i], "--set") && i + 1 < argc && nsets < 8) sets[nsets++] = argv[++i];
        else if (argv[i][0] != '-' && !scene) scene = argv[i];
        else {
            fprintf(stderr, "usage: contact_census [--steps N] [--every K] [--dump STEP FILE] "
                            "[--set PATH=VALUE ...] SCENE.xml\n");
            return 2;
        }
    }
    if (!scene || steps < 1 || every < 1) {
        fprintf(stderr, "contact_census: a scene and positive --steps / --every are needed\n");
        return 2;
    }
    /* exporters write under $TMPDIR (the scenes' VTK series are not wanted here) */
    char out[1024];
    test_tmp_template(out, sizeof out, "contact_census");
    if (!mkdtemp(out)) {
        perror(out);
        return 2;
    }
    pl_sim *sim = bench_load(scene, NULL, sets, nsets, out);
    if (!sim) return 2;
    census best, cur;
    memset(&best, 0, sizeof best);
    printf("step contacts active v-obst obstv-f vf-body ee-obst ee-body shape ahead\n");
    for (int st = 1; st <= steps; ++st) {
        pl_error err;
        if (pl_sim_step(sim, 1, &err) != PL_OK) {
            char b[1600];
            fprintf(stderr, "%s: %s\n", scene, pl_error_format(&err, b, sizeof b));
            pl_sim_free(sim);
            test_tmp_rmtree(out);
            return 1;
        }
        memset(&cur, 0, sizeof cur);
        cur.step = st;
        scan s = {.c = &cur, .d = pl_sim_data(sim)};
        if (st == dump_step && !(s.dump = fopen(dump_path, "w"))) {
            fprintf(stderr, "contact_census: cannot write %s\n", dump_path);
            pl_sim_free(sim);
            test_tmp_rmtree(out);
            return 2;
        }
        if (s.dump)
            fprintf(s.dump, "# kind model_a model_b a0 a1 b0 b1 b2 wa0 wa1 wb0 wb1 wb2 nx ny nz "
                            "gap lambda_n (pipeline rows; kinds as in the table, 0-based)\n");
        pl_node_visit_role(pl_sim_model(sim)->root, PL_ROLE_CONSTRAINT, visit, &s);
        if (s.dump) fclose(s.dump);
        finish(&cur);
        if (cur.total > best.total) best = cur;
        if (st % every == 0 || st == steps) {
            int byk[NKIND] = {0}, ahead = 0;
            for (int k = 0; k < NKIND; ++k)
                for (int g = 0; g < NGAP; ++g) byk[k] += cur.n[k][g];
            for (int k = 0; k < NKIND; ++k) ahead += cur.n[k][G_AHEAD];
            printf("%4d %8d %6d %6d %7d %7d %7d %7d %5d %5d\n", st, cur.total, cur.active,
                   byk[K_VOBST], byk[K_OBSTVF], byk[K_VFBODY], byk[K_EEOBST], byk[K_EEBODY],
                   byk[K_SHAPE], ahead);
            fflush(stdout);
        }
    }
    best.solver = (int)bench_stat(pl_sim_timers(sim), "contacts max");
    cur.solver = best.solver;
    printf("\n%s, %d steps\n", scene, steps);
    print_census("Step with the most contacts", &best);
    print_census("Last step", &cur);
    pl_sim_free(sim);
    test_tmp_rmtree(out);
    free(rows_of);
    return 0;
}
