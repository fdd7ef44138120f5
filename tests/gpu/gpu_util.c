/* gpu_util.c - device buffers and result lines (gpu_util.h). */
#include "gpu_util.h"

#include <cuda_runtime_api.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int failures;

static int ok(cudaError_t e, const char *what)
{
    if (e == cudaSuccess) return 1;
    fprintf(stderr, "CUDA error (%s): %s\n", what, cudaGetErrorString(e));
    failures++;
    return 0;
}

void gpu_require(const char *prog)
{
    int n = 0;
    cudaError_t e = cudaGetDeviceCount(&n);
    if (e == cudaSuccess && n > 0) return;
    printf("%s: skipped: no GPU (%s)\n", prog,
           e != cudaSuccess ? cudaGetErrorString(e) : "no CUDA device found");
    fflush(stdout);
    exit(GPU_SKIP);
}

void *gpu_put(const double *h, size_t m, pl_precision prec)
{
    size_t es = prec == PL_F32 ? sizeof(float) : sizeof(double), bytes = (m ? m : 1) * es;
    void *d = NULL, *tmp = NULL;
    if (!ok(cudaMalloc(&d, bytes), "cudaMalloc")) return NULL;
    if (!h) return ok(cudaMemset(d, 0, bytes), "cudaMemset") ? d : NULL;
    const void *src = h;
    if (prec == PL_F32) {
        float *f = malloc(bytes);
        if (!f) return NULL;
        for (size_t i = 0; i < m; ++i) f[i] = (float)h[i];
        src = tmp = f;
    }
    int good = ok(cudaMemcpy(d, src, m * es, cudaMemcpyHostToDevice), "copy to device");
    free(tmp);
    if (!good) {
        cudaFree(d);
        return NULL;
    }
    return d;
}

int gpu_get(double *h, const void *d, size_t m, pl_precision prec)
{
    if (prec != PL_F32)
        return ok(cudaMemcpy(h, d, m * sizeof(double), cudaMemcpyDeviceToHost), "copy to host") ? 0 : -1;
    float *f = malloc((m ? m : 1) * sizeof *f);
    if (!f) return -1;
    int good = ok(cudaMemcpy(f, d, m * sizeof(float), cudaMemcpyDeviceToHost), "copy to host");
    for (size_t i = 0; good && i < m; ++i) h[i] = f[i];
    free(f);
    return good ? 0 : -1;
}

void gpu_free(void *d)
{
    if (d) cudaFree(d);
}

int gpu_sync(const char *what)
{
    return ok(cudaDeviceSynchronize(), what) && ok(cudaGetLastError(), what) ? 0 : -1;
}

void gpu_check_line(FILE *md, const char *what, double value, double tol)
{
    int pass = value <= tol; /* NaN fails */
    if (!pass) failures++;
    printf("%-64s %10.3e  <= %.0e  %s\n", what, value, tol, pass ? "PASS" : "FAIL");
    if (md) fprintf(md, "| %s | %.2e | %.0e | %s |\n", what, value, tol, pass ? "pass" : "FAIL");
}

void gpu_note_line(FILE *md, const char *what, double value)
{
    printf("%-64s %10.3e\n", what, value);
    if (md) fprintf(md, "| %s | %.3g | | |\n", what, value);
}

int gpu_failures(void)
{
    return failures;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double gpu_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

char *gpu_scene_with_device(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    const char *add = "<RequiredPlugin name=\"cuda\"/><CudaDevice name=\"gpu\" graph=\"1\"/>";
    char *s = malloc((size_t)n + strlen(add) + 1), *out = malloc((size_t)n + strlen(add) + 1);
    size_t got = s ? fread(s, 1, (size_t)n, f) : 0;
    fclose(f);
    if (!s || !out || got != (size_t)n) return free(s), free(out), NULL;
    s[n] = '\0';
    /* the root node: the first <Node that is not inside a comment */
    char *node = s;
    for (;;) {
        char *cm = strstr(node, "<!--"), *nd = strstr(node, "<Node");
        if (!nd || !cm || nd < cm) {
            node = nd;
            break;
        }
        char *end = strstr(cm, "-->");
        if (!end) return free(s), free(out), NULL;
        node = end + 3;
    }
    char *gt = node ? strchr(node, '>') : NULL;
    if (!gt) return free(s), free(out), NULL;
    size_t head = (size_t)(gt + 1 - s);
    memcpy(out, s, head);
    strcpy(out + head, add);
    strcat(out, gt + 1);
    free(s);
    return out;
}

pl_sim *gpu_load_scene(char *xml, const char *path, const char *const *ov, int nov,
                       const char *out_dir)
{
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim_options opt = {0};
    opt.out_dir = out_dir;
    opt.export_every = 1000000;
    opt.overrides = ov;
    opt.noverrides = nov;
    pl_sim *sim = xml ? pl_sim_load_string(xml, path, &opt, &diag) : NULL;
    if (!sim) pl_diag_print(&diag, stdout);
    pl_diag_free(&diag);
    free(xml);
    return sim;
}
