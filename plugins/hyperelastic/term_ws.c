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

double *hyper_term_warm(const pl_component *c, pl_data *d, size_t n, pl_error *err)
{
    hyper_term_ws *w = pl_data_workspace(d, c);
    if (w && w->warm && w->nwarm != n) { /* the model was rebuilt with other sizes */
        free(w->warm);
        w->warm = NULL;
    }
    if (w && !w->warm && (w->warm = calloc(n ? n : 1, sizeof *w->warm))) w->nwarm = n;
    if (!w || !w->warm) {
        pl_component_fail(c, err, PL_EINTERNAL, "out of memory (workspace)");
        return NULL;
    }
    return w->warm;
}

void hyper_term_workspace_free(const pl_component *c, void *ws)
{
    hyper_term_ws *w = ws;
    (void)c;
    free(w->work);
    free(w->warm);
#ifdef PLIANT_HAVE_CUDA
    hyper_fem_device_free(&w->fem);
    hyper_stencil_device_free(&w->stencil);
#endif
}
