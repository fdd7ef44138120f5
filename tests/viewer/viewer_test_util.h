/* viewer_test_util.h - what the viewer tests share: a falling-ball scene
 * seen by a fixed InteractiveCamera, loading with the viewer's prepare
 * hook, and the pixel check (the body's projected centroid shows the body,
 * not the background). */
#ifndef PLIANT_VIEWER_TEST_UTIL_H
#define PLIANT_VIEWER_TEST_UTIL_H

#include "app.h"

/* A ball of radius 0.1 m at the origin falling freely; the camera sees
 * y in about [-0.85, 0.45] m. */
extern const char *VT_FALLING_BALL;

/* Loads xml (a file when is_file) with vw_app_prepare into *sim. */
pl_sim *vt_load(const char *xml, int is_file, vw_app *app);
/* Whether pixel (x, y) of a w x h RGB picture differs from the background. */
int vt_not_background(const unsigned char *rgb, int w, int h, int x, int y);
/* Draws the app's frame with `draw` into the bound framebuffer, reads it
 * with `read` and checks that the centroid of body 0, projected with the
 * app's camera, is drawn (not background); returns the centroid's pixel. */
typedef void (*vt_read_fn)(void *user, unsigned char *rgb);
void vt_check_centroid(vw_app *a, vw_renderer *r, vt_read_fn read, void *user, double px[2]);

#endif
