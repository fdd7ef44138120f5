/* script.h - scripted input for the viewer (pliant view --script FILE and
 * the tests): each line is a command fed through the same input events as a
 * person's keys and mouse, one command per displayed frame.
 *
 *     step N              N time steps
 *     key K               press key K: a character, space, escape, up, down,
 *                         left, right, pageup, pagedown; ctrl+K for Ctrl held
 *     drag X0 Y0 X1 Y1 N  Shift + left press at pixel (X0, Y0), move to
 *                         (X1, Y1), N time steps while held, release
 *     orbit DX DY         a left drag by (DX, DY) pixels
 *     screenshot FILE     the picture of the frame as PNG
 *     print PATH          the value of PATH (pl_sim_get) on standard output
 *     quit
 * Blank lines and lines starting with # are skipped. */
#ifndef PLIANT_VW_SCRIPT_H
#define PLIANT_VW_SCRIPT_H

#include <stdio.h>

#include "app.h"

typedef struct vw_script {
    char **lines;
    int *line_no;
    int n, next;
    char *file;
} vw_script;

/* Reads and checks every line; errors name file and line (PL_EINPUT). */
int vw_script_load(vw_script *s, const char *path, pl_error *err);
void vw_script_free(vw_script *s);
/* Runs the next command; *done when the script has ended (or said quit).
 * `shot` saves the current picture: called for screenshot, after a draw. */
typedef int (*vw_script_shot)(void *user, const char *file, pl_error *err);
int vw_script_next(vw_script *s, vw_app *a, vw_script_shot shot, void *user, int *done,
                   pl_error *err);

#endif
