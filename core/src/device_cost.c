/* device_cost.c - the cost model behind device="auto" (device_cost.h).
 *
 * A step costs, on either device, a sum of terms, each a size times a
 * constant (ms):
 *
 *   t = sum_j C[j] x_j
 *
 *   x_j        | size (K = local-global iterations per step)
 *   STEP       | 1: per-step host work (gather, scatter, copies, exporters)
 *   ITER       | K: per-iteration floor (launches, synchronisation, OpenMP)
 *   ARAP       | K * ARAP (and bending) elements / 1000 (local step)
 *   COROT      | K * corotational elements / 1000
 *   NH         | K * Neo-Hookean tetrahedra / 1000
 *   NHTRI      | K * Neo-Hookean triangles / 1000
 *   NHFLOOR    | K when there are Neo-Hookean tetrahedra (on the GPU the
 *              |   element whose prox Newton takes longest sets the local
 *              |   step's time: a floor per iteration)
 *   SOLVE      | K * nnz(S) / 1e6 (global step: S^T S b, 3 columns)
 *   CR         | K * crIterations when the scene has constraints (the
 *              |   constraint solver's per-iteration floor)
 *   ROWS       | K * crIterations * collision surface vertices / 1000 (the
 *              |   rows grow with the surface in contact)
 *   DETECT     | collision surface vertices / 1000 (detection, per step)
 *   ELEMS      | all elements / 1000, per step (the force residual, assembly)
 *
 * On the CPU the terms that run in parallel (ARAP, COROT, NH, SOLVE, ROWS,
 * ELEMS) scale as CAL_THREADS / threads: they were measured on CAL_THREADS
 * threads only, so that scaling is an assumption (it favours the GPU on
 * small machines, where the CPU is slower).  nnz(S) is not known before the
 * factorisation: it is estimated from the bodies' sizes (S_TET n^(4/3) for a
 * body of n vertices with tetrahedra, S_TRI n log2 n with triangles: the
 * fill of nested dissection in 3D and 2D).  When the iterations cannot run
 * on the device (device_path = 0: a term without a device step, a CPU
 * contact solver, forceTolerance with a term without a device gradient)
 * only the global solves go there, and the GPU step is PARTIAL times the
 * CPU step (the median ratio of those scenes, fitted when forceTolerance
 * and stickStart had no device path).  A forceTolerance scene's iteration
 * count is unknown ahead: the model takes min(iterations, FT_ITERATIONS).
 * Since forceTolerance and stickStart run in the device loop, stick_slip
 * and cable_finger are predicted by the full model; the constants were
 * refitted on 2026-11-26 at main 058ec34 (46 scenes, every choice right,
 * docs/benchmarks.md).  No scene of scenes/ lacks a device path now, so
 * PARTIAL is the earlier fit's (the fit keeps it when nothing measures it).
 *
 * The constants between the FITTED markers are written by
 * tests/bench/device_cost_fit.py (docs/benchmarks.md: command, machine,
 * date); everything else here is fixed. */
#include "device_cost.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

enum { STEP, ITER, ARAP, COROT, NH, NHTRI, NHFLOOR, SOLVE, CR, ROWS, DETECT, ELEMS, NTERMS };

/* BEGIN FITTED (tests/bench/device_cost_fit.py --write) */
/* STEP ITER ARAP COROT NH NHTRI NHFLOOR SOLVE CR ROWS DETECT ELEMS */
static const double CPU_MS[NTERMS] = {
    0, 0.2114, 0.03123, 0.01909, 0.006193, 0.05913,
    0.02643, 1.859, 0.005044, 0, 2.555, 0};
static const double GPU_MS[NTERMS] = {
    0, 0.03857, 0.001752, 0.005201, 0, 0.007703,
    0.01195, 0.02116, 0.00112, 0.002715, 0.1181, 0};
static const double S_TET = 6.58, S_TRI = 4.25, PARTIAL = 0.809;
static const int CAL_THREADS = 16, FT_ITERATIONS = 46;
/* END FITTED */

/* parallel on the CPU: divided by threads / CAL_THREADS */
static const int PARALLEL[NTERMS] = {[ARAP] = 1, [COROT] = 1, [NH] = 1, [NHTRI] = 1, [SOLVE] = 1,
                                     [ROWS] = 1, [ELEMS] = 1};

int pl_device_cost_iterations(int iterations_max, int force_tolerance)
{
    if (iterations_max < 1) return 1;
    return force_tolerance && iterations_max > FT_ITERATIONS ? FT_ITERATIONS : iterations_max;
}

static void terms(const pl_device_sizes *z, double nnz_s, double x[NTERMS])
{
    double k = z->iterations > 0 ? z->iterations : 1, all = 0;
    for (int l = 0; l < PL_COST_NLAWS; ++l) all += z->tets[l] + z->tris[l];
    double cr = z->constraints > 0 ? (z->cr_iterations > 0 ? z->cr_iterations : 1) : 0;
    x[STEP] = 1;
    x[ITER] = k;
    x[ARAP] = k * (z->tets[PL_COST_ARAP] + z->tris[PL_COST_ARAP]) / 1e3;
    x[COROT] = k * (z->tets[PL_COST_COROT] + z->tris[PL_COST_COROT]) / 1e3;
    x[NH] = k * z->tets[PL_COST_NH] / 1e3;
    x[NHTRI] = k * z->tris[PL_COST_NH] / 1e3;
    x[NHFLOOR] = z->tets[PL_COST_NH] > 0 ? k : 0;
    x[SOLVE] = k * nnz_s / 1e6;
    x[CR] = k * cr;
    x[ROWS] = k * cr * z->surface_vertices / 1e3;
    x[DETECT] = z->surface_vertices / 1e3;
    x[ELEMS] = all / 1e3;
}

pl_device_estimate pl_device_cost_predict(const pl_device_sizes *z, int threads)
{
    pl_device_estimate e = {0, 0, 0, 0};
    double x[NTERMS];
    e.nnz_s = S_TET * z->s_tet + S_TRI * z->s_tri;
    terms(z, e.nnz_s, x);
    double scale = (double)CAL_THREADS / (threads > 0 ? threads : 1);
    for (int j = 0; j < NTERMS; ++j) {
        e.cpu_ms += CPU_MS[j] * x[j] * (PARALLEL[j] ? scale : 1.0);
        e.gpu_ms += GPU_MS[j] * x[j];
    }
    if (!z->sparse_inverse) e.gpu_ms = e.cpu_ms; /* nothing would run on the device */
    else if (!z->device_path) e.gpu_ms = PARTIAL * e.cpu_ms;
    e.gpu = e.gpu_ms < e.cpu_ms;
    return e;
}

/* "3.2k" for 3200 */
static const char *count(double v, char *buf, size_t size)
{
    if (v >= 1e6) snprintf(buf, size, "%.3gM", v / 1e6);
    else if (v >= 1e3) snprintf(buf, size, "%.3gk", v / 1e3);
    else snprintf(buf, size, "%.0f", v);
    return buf;
}

int pl_device_cost_choose(const pl_device_sizes *z, int threads, int gpu_present,
                          pl_device_estimate *e, char *buf, size_t size)
{
    *e = pl_device_cost_predict(z, threads);
    if (!gpu_present) e->gpu = 0;
    static const char *const LAW[PL_COST_NLAWS] = {"ARAP", "corotational", "Neo-Hookean"};
    char a[32], what[256] = "";
    size_t len = 0;
    for (int l = 0; l < PL_COST_NLAWS; ++l)
        for (int kind = 0; kind < 2; ++kind) {
            int n = kind ? z->tris[l] : z->tets[l];
            if (n > 0 && len < sizeof what)
                len += (size_t)snprintf(what + len, sizeof what - len, "%s%s %s %s",
                                        len ? ", " : "", count(n, a, sizeof a),
                                        kind ? "triangles" : "tetrahedra", LAW[l]);
        }
    if (len < sizeof what)
        len += (size_t)snprintf(what + len, sizeof what - len, "%s%s vertices, %d iterations%s",
                                len ? ", " : "", count(z->vertices, a, sizeof a), z->iterations,
                                z->force_tolerance ? " (assumed: forceTolerance)" : "");
    if (z->constraints > 0 && len < sizeof what)
        len += (size_t)snprintf(what + len, sizeof what - len,
                                ", %d constraint component(s), %s collision surface vertices",
                                z->constraints, count(z->surface_vertices, a, sizeof a));
    if (!z->sparse_inverse && len < sizeof what)
        snprintf(what + len, sizeof what - len, "; the global solver has no device path");
    else if (!z->device_path && len < sizeof what)
        snprintf(what + len, sizeof what - len,
                 "; only the global solves would run on the GPU");
    snprintf(buf, size,
             "%s chosen%s: predicted %.3g ms/step on %d thread%s vs %.3g ms on the GPU (%s)",
             e->gpu ? "GPU" : "CPU", gpu_present ? "" : " (no GPU answers)", e->cpu_ms, threads,
             threads == 1 ? "" : "s", e->gpu_ms, what);
    return e->gpu;
}
