/* regress.h - `pliant regress`: what the command (cmd_regress.c) hands to
 * the child that runs one entry of the list (regress_entry.c). */
#ifndef PLIANT_CLI_REGRESS_H
#define PLIANT_CLI_REGRESS_H

#include <stdio.h>

#include <pliant/export.h>

typedef struct regress_ctx {
    const pl_regression_list *list;
    const char *list_path;    /* the list itself, for errors that name its lines */
    const char *list_dir;     /* scenes are relative to the list's folder */
    const char *refs;         /* reference folder */
    const char *out_dir;      /* this rank's temporary folder for the scenes' outputs */
    int update;               /* rewrite the references instead of comparing */
    int sofa_steps;           /* SOFA's counting: N steps record t = 0 .. (N-1) h */
    int quiet;
} regress_ctx;

/* cli_job_fn: runs entry i; its report lines are "result pass|FAIL|written|
 * error", then "error E" and "last R" (pass/FAIL; "why TEXT" on FAIL),
 * "states N" (written) or "msg TEXT". */
int regress_entry_job(int i, void *ctx, FILE *out);

#endif
