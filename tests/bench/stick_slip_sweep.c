/* stick_slip_sweep.c - finds the stick/slide threshold of the stick-slip
 * scene by bisection on mu, for each complementarity preconditioner, and
 * reports it against mu* = tan(theta) (10 degrees in scenes/stick_slip.xml:
 * 0.17632698, the paper's Fig. "Stick-Sliding test").  A run "slides" when
 * the box moves more than --moved metres (default 1e-3) along the slope in
 * --steps steps.
 *
 *   stick_slip_sweep [--scene scenes/stick_slip.xml] [--steps 100] [--tol 1e-4]
 *                    [--moved 1e-3] [--lo 0.05] [--hi 0.35] [--markdown]
 *                    [--angle DEG [--size "W H D"] [--grid "NX NY NZ"] [--young E]]
 *                    [--preconditioners delassus,mass] [--set component.field=value ...]
 *                    [--verbose]
 *
 * --angle builds the scene instead of reading --scene: the stick_slip.xml
 * settings (10 local-global and 24 CR iterations, h = 0.01 s, Neo-Hookean,
 * rho 1000 kg/m^3, nu 0.3, contactDistance 0.5 mm) with a W x H x D box
 * (default 0.1 0.1 0.1 m; W along the slope, H its height) of NX x NY x NZ
 * vertices (default 6 6 6) and Young's modulus E (default 1e8 Pa) resting at
 * the kept gap on a plane inclined DEG degrees; the bracket then defaults to
 * tan(DEG) -/+ 0.05.
 * --set passes overrides to every run (up to 8), e.g. with a scene that has
 * a CudaDevice in its root: --set solver.device=cuda --set global.device=cuda
 * (tests/bench/run_gpu.sh does that on the GPU machine).
 */
#include <math.h>
#include <pliant/pliant.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_tmp.h"

enum { MAX_SETS = 8 };

typedef struct sweep {
    const char *scene;
    int steps;
    double tol, moved, lo, hi;
    int markdown;
    const char *sets[MAX_SETS];
    int nsets;
    double angle;            /* degrees */
    int generate;            /* build the scene from angle, size, grid, young */
    double size[3], young;
    int grid[3];
    char *xml;               /* the generated scene */
    int verbose;             /* every run to stderr */
} sweep;

/* The stick_slip.xml scene on a slope of sw->angle degrees. */
static char *scene_text(const sweep *sw)
{
    const double a = sw->angle * M_PI / 180.0, gap = 0.0005;
    char *xml = malloc(4096);
    if (!xml) return NULL;
    snprintf(xml, 4096,
             "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
             "  <RequiredPlugin name=\"hyperelastic\"/>\n"
             "  <RequiredPlugin name=\"sparse_inverse\"/>\n"
             "  <RequiredPlugin name=\"ncp_contact\"/>\n"
             "  <RequiredPlugin name=\"collision\"/>\n"
             "  <LocalGlobalSolver name=\"solver\" iterations=\"10\"/>\n"
             "  <SparseInverseSolver name=\"global\"/>\n"
             "  <NonSmoothNewtonContactSolver name=\"contact\" stickStart=\"1\" ncp=\"fischer-burmeister\" "
             "crIterations=\"24\" preconditioner=\"delassus\"/>\n"
             "  <PlaneObstacle name=\"slope\" normal=\"0 1 0\" rotation=\"0 0 %.17g\" mu=\"0.18\" "
             "alarmDistance=\"0.002\" contactDistance=\"%g\"/>\n"
             "  <Node name=\"box\">\n"
             "    <RegularGridTetrahedra name=\"grid\" min=\"%.17g 0 %.17g\" max=\"%.17g %.17g %.17g\" "
             "n=\"%d %d %d\" rotation=\"0 0 %.17g\" translation=\"%.17g %.17g 0\"/>\n"
             "    <MechanicalObject name=\"dofs\" src=\"@grid\"/>\n"
             "    <DiagonalMass massDensity=\"1000\"/>\n"
             "    <NeoHookean name=\"material\" youngModulus=\"%g\" poissonRatio=\"0.3\"/>\n"
             "    <SurfaceCollisionModel name=\"surface\"/>\n"
             "    <VTKExporter name=\"vtk\" filename=\"stick_slip\" every=\"10\"/>\n"
             "  </Node>\n"
             "</Node>\n",
             sw->angle, gap, -0.5 * sw->size[0], -0.5 * sw->size[2], 0.5 * sw->size[0], sw->size[1],
             0.5 * sw->size[2], sw->grid[0], sw->grid[1], sw->grid[2], sw->angle, -gap * sin(a),
             gap * cos(a), sw->young);
    return xml;
}

/* Displacement of the box along the slope after the run [m], or NAN. */
static double run(const sweep *sw, const char *precond, double mu)
{
    char set_mu[64], set_pc[64];
    snprintf(set_mu, sizeof set_mu, "slope.mu=%.10g", mu);
    snprintf(set_pc, sizeof set_pc, "contact.preconditioner=%s", precond);
    const char *sets[3 + MAX_SETS] = {set_mu, set_pc, "vtk.every=100000000"};
    for (int k = 0; k < sw->nsets; ++k) sets[3 + k] = sw->sets[k];
    pl_sim_options opt = {.out_dir = test_tmp_dir(), .overrides = sets, .noverrides = 3 + sw->nsets};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = sw->xml ? pl_sim_load_string(sw->xml, "stick_slip_generated.xml", &opt, &diag)
                        : pl_sim_load_file(sw->scene, &opt, &diag);
    if (!s) {
        pl_diag_print(&diag, stderr);
        pl_diag_free(&diag);
        return NAN;
    }
    pl_diag_free(&diag);
    pl_component *c = pl_sim_component(s, "box/dofs");
    const pl_state_ops *ops = c ? pl_component_role(c, PL_ROLE_STATE) : NULL;
    if (!ops) {
        fprintf(stderr, "stick_slip_sweep: the scene has no box/dofs\n");
        pl_sim_free(s);
        return NAN;
    }
    pl_buffer b = ops->positions(c, pl_sim_data(s));
    size_t n = b.rows;
    double *x0 = malloc(n * 3 * sizeof *x0);
    memcpy(x0, b.data, n * 3 * sizeof *x0);
    pl_error err;
    double d = NAN;
    if (pl_sim_step(s, sw->steps, &err) == PL_OK) {
        const double a = sw->angle * M_PI / 180.0, dir[3] = {-cos(a), -sin(a), 0.0};
        const double *x = ops->positions(c, pl_sim_data(s)).data;
        d = 0;
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) d += dir[k] * (x[3 * i + k] - x0[3 * i + k]) / (double)n;
    }
    free(x0);
    pl_sim_free(s);
    return d;
}

static void bisect(const sweep *sw, const char *precond)
{
    double lo = sw->lo, hi = sw->hi; /* lo slides, hi sticks */
    int runs = 0;
    double dlo = run(sw, precond, lo), dhi = run(sw, precond, hi);
    runs += 2;
    if (!(dlo > sw->moved) || !(fabs(dhi) <= sw->moved)) {
        printf("%-10s  bracket failed: mu=%.4f moved %.3g m, mu=%.4f moved %.3g m\n", precond, lo,
               dlo, hi, dhi);
        return;
    }
    while (hi - lo > sw->tol) {
        double mid = 0.5 * (lo + hi), d = run(sw, precond, mid);
        runs++;
        if (sw->verbose) fprintf(stderr, "%s: mu = %.6f moved %.4g m\n", precond, mid, d);
        if (d > sw->moved)
            lo = mid;
        else
            hi = mid;
    }
    double thr = 0.5 * (lo + hi), mu_star = tan(sw->angle * M_PI / 180.0);
    if (sw->markdown)
        printf("| %s | %.5f | %.5f | %+.5f | %d |\n", precond, thr, mu_star, thr - mu_star, runs);
    else
        printf("%-10s  threshold %.5f  (mu* %.5f, error %+.5f, %d runs)\n", precond, thr, mu_star,
               thr - mu_star, runs);
}

static int parse3(const char *v, double *x)
{
    return sscanf(v, "%lf %lf %lf", &x[0], &x[1], &x[2]) == 3 && x[0] > 0 && x[1] > 0 && x[2] > 0;
}

int main(int argc, char **argv)
{
    sweep sw = {"scenes/stick_slip.xml", 100, 1e-4, 1e-3, NAN, NAN, 0, {NULL}, 0, 10.0, 0,
                {0.1, 0.1, 0.1}, 1e8, {6, 6, 6}, NULL, 0};
    const char *preconds = "delassus,mass";
    for (int k = 1; k < argc; ++k) {
        const char *a = argv[k], *v = k + 1 < argc ? argv[k + 1] : NULL;
        double g[3];
        if (!strcmp(a, "--markdown")) sw.markdown = 1;
        else if (!strcmp(a, "--verbose")) sw.verbose = 1;
        else if (!v) { fprintf(stderr, "stick_slip_sweep: %s needs a value\n", a); return 2; }
        else if (!strcmp(a, "--scene")) sw.scene = v, k++;
        else if (!strcmp(a, "--steps")) sw.steps = atoi(v), k++;
        else if (!strcmp(a, "--tol")) sw.tol = atof(v), k++;
        else if (!strcmp(a, "--moved")) sw.moved = atof(v), k++;
        else if (!strcmp(a, "--lo")) sw.lo = atof(v), k++;
        else if (!strcmp(a, "--hi")) sw.hi = atof(v), k++;
        else if (!strcmp(a, "--angle")) sw.angle = atof(v), sw.generate = 1, k++;
        else if (!strcmp(a, "--young")) sw.young = atof(v), k++;
        else if (!strcmp(a, "--preconditioners")) preconds = v, k++;
        else if (!strcmp(a, "--size") && parse3(v, sw.size)) k++;
        else if (!strcmp(a, "--grid") && parse3(v, g) && g[0] >= 2 && g[1] >= 2 && g[2] >= 2)
            sw.grid[0] = (int)g[0], sw.grid[1] = (int)g[1], sw.grid[2] = (int)g[2], k++;
        else if (!strcmp(a, "--set") && sw.nsets < MAX_SETS) sw.sets[sw.nsets++] = v, k++;
        else { fprintf(stderr, "stick_slip_sweep: bad option or value: %s %s\n", a, v); return 2; }
    }
    if (sw.generate && !(sw.angle > 0 && sw.angle < 60 && sw.young > 0)) {
        fprintf(stderr, "stick_slip_sweep: --angle must be in (0, 60) degrees, --young > 0\n");
        return 2;
    }
    double mu_star = tan(sw.angle * M_PI / 180.0);
    if (isnan(sw.lo)) sw.lo = sw.generate ? mu_star - 0.05 : 0.05;
    if (isnan(sw.hi)) sw.hi = sw.generate ? mu_star + 0.05 : 0.35;
    if (sw.generate && !(sw.xml = scene_text(&sw))) return 1;
    pl_log_set_level(PL_LOG_WARN);
    if (sw.markdown)
        printf("| preconditioner | threshold | mu* | error | runs |\n| --- | --- | --- | --- | --- |\n");
    if (strstr(preconds, "delassus")) bisect(&sw, "delassus");
    if (strstr(preconds, "mass")) bisect(&sw, "mass");
    free(sw.xml);
    return 0;
}
