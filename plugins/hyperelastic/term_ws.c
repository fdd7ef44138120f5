/* term_ws.c - freeing the local terms' per-data workspace (term_ws.h). */
#include "term_ws.h"

#include <stdlib.h>

#ifdef PLIANT_HAVE_CUDA
#include "fem_term.h"
#include "stencil_device.h"
#endif

double *hyper_term_work(const pl_component *c, pl_data *d, size_t n, pl_error *err)
{
    hyper_term_ws *w = pl_data_workspace(d, c);
    if (w && !w->work) w->work = malloc((n ? n : 1) * sizeof *w->work);
    if (!w || !w->work) {
        pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
        return NULL;
    }
    return w->work;
}

/* *rows, n doubles (zeros when new; remade when the model's size changed). */
static double *rows_of(const pl_component *c, double **rows, size_t *count, size_t n,
                       pl_error *err)
{
    if (*rows && *count != n) { /* the model was rebuilt with other sizes */
        free(*rows);
        *rows = NULL;
    }
    if (!*rows && (*rows = calloc(n ? n : 1, sizeof **rows))) *count = n;
    if (!*rows) pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
    return *rows;
}

double *hyper_term_warm(const pl_component *c, pl_data *d, size_t n, pl_error *err)
{
    hyper_term_ws *w = pl_data_workspace(d, c);
    if (!w) {
        pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
        return NULL;
    }
    return rows_of(c, &w->warm, &w->nwarm, n, err);
}

double *hyper_term_prev(const pl_component *c, pl_data *d, size_t n, pl_error *err)
{
    hyper_term_ws *w = pl_data_workspace(d, c);
    if (!w) {
        pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
        return NULL;
    }
    return rows_of(c, &w->prev, &w->nprev, n, err);
}

void hyper_term_workspace_free(const pl_component *c, void *ws)
{
    hyper_term_ws *w = ws;
    (void)c;
    free(w->work);
    free(w->warm);
    free(w->prev);
#ifdef PLIANT_HAVE_CUDA
    hyper_fem_device_free(&w->fem);
    hyper_stencil_device_free(&w->stencil);
#endif
}
