/* cli_progress.c - how far a run is: a redrawn bar on a terminal, and in a
 * log (stderr not a terminal: batch jobs, CI) one line every few seconds, so
 * that a long run shows it is alive without filling the log. */
#include <pliant/pliant.h>

#include <stdio.h>
#include <unistd.h>

#include "cli.h"

void cli_progress_start(cli_progress *p, int total, int quiet, double every)
{
    p->total = total;
    p->tty = !quiet && isatty(fileno(stderr));
    p->every = quiet ? 0.0 : every;
    p->t0 = p->last = pl_now();
}

static void bar(const cli_progress *p, int done, double elapsed)
{
    double ms = done ? 1e3 * elapsed / done : 0.0;
    double eta = done ? elapsed / done * (p->total - done) : 0.0;
    int width = 30, fill = p->total ? width * done / p->total : width;
    fprintf(stderr, "\r[%.*s%*s] frame %d/%d  %.2f ms/frame  ETA %.0f s ", fill,
            "##############################", width - fill, "", done, p->total, ms, eta);
    fflush(stderr);
}

static void line(const cli_progress *p, int done, double t, double elapsed)
{
    double ms = done ? 1e3 * elapsed / done : 0.0;
    fprintf(stderr, "pliant: frame %d/%d, t = %.4g s, %.2f ms/frame, ETA %.0f s\n", done,
            p->total, t, ms, done ? elapsed / done * (p->total - done) : 0.0);
    fflush(stderr);
}

void cli_progress_update(cli_progress *p, int done, double t)
{
    if (p->tty) {
        if (done % 5 == 0) bar(p, done, pl_now() - p->t0);
        return;
    }
    if (p->every <= 0) return;
    double now = pl_now();
    if (now - p->last < p->every) return;
    p->last = now;
    line(p, done, t, now - p->t0);
}

void cli_progress_finish(cli_progress *p, int done, double t)
{
    if (!p->tty) return;
    bar(p, done, pl_now() - p->t0);
    fputc('\n', stderr);
}
