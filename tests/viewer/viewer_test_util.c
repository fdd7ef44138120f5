/* viewer_test_util.c - see viewer_test_util.h. */
#include "viewer_test_util.h"

#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_tmp.h"

const char *VT_FALLING_BALL =
    "<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
    "<RequiredPlugin name=\"hyperelastic\"/><RequiredPlugin name=\"sparse_inverse\"/>\n"
    "<LocalGlobalSolver name=\"solver\" iterations=\"5\"/><SparseInverseSolver/>\n"
    "<InteractiveCamera position=\"0 -0.2 2\" lookAt=\"0 -0.2 0\" fieldOfView=\"36\"/>\n"
    "<Node name=\"ball\">\n"
    "<SphereMesh name=\"mesh\" center=\"0 0 0\" radius=\"0.1\" volume=\"1\" vertices=\"200\"/>\n"
    "<MechanicalObject name=\"dofs\" src=\"@mesh\"/><UniformMass totalMass=\"1\"/>\n"
    "<NeoHookean name=\"material\" youngModulus=\"1e5\" poissonRatio=\"0.3\"/>\n"
    "</Node></Node>\n";

pl_sim *vt_load(const char *xml, int is_file, vw_app *app)
{
    memset(app, 0, sizeof *app);
    pl_sim_options opt = {.out_dir = test_tmp_dir(), .device = "cpu"};
    pl_diag diag;
    pl_diag_init(&diag);
    pl_sim *s = is_file ? pl_sim_load_file_prepared(xml, &opt, vw_app_prepare, app, &diag)
                        : pl_sim_load_string_prepared(xml, "viewer_test.xml", &opt,
                                                      vw_app_prepare, app, &diag);
    if (!s) pl_diag_print(&diag, stderr);
    pl_diag_free(&diag);
    ck_assert_ptr_nonnull(s);
    return s;
}

int vt_not_background(const unsigned char *rgb, int w, int h, int x, int y)
{
    ck_assert(x >= 0 && x < w && y >= 0 && y < h);
    const unsigned char *p = rgb + 3 * ((size_t)y * w + x);
    int d = 0;
    for (int k = 0; k < 3; ++k) d += abs(p[k] - (int)(VW_BACKGROUND[k] * 255.0f + 0.5f));
    return d > 40;
}

void vt_check_centroid(vw_app *a, vw_renderer *r, vt_read_fn read, void *user, double px[2])
{
    pl_error err;
    ck_assert_int_eq(vw_app_render(a, r, &err), PL_OK);
    unsigned char *rgb = malloc((size_t)a->w * a->h * 3);
    ck_assert_ptr_nonnull(rgb);
    read(user, rgb);
    double c[3], depth;
    vw_scene_centroid(&a->scene, 0, c);
    ck_assert(vw_camera_project(&a->camera, a->w, a->h, c, &px[0], &px[1], &depth));
    ck_assert_msg(vt_not_background(rgb, a->w, a->h, (int)px[0], (int)px[1]),
                  "the body's centroid (%g %g %g) projects to pixel (%g, %g), which shows the "
                  "background", c[0], c[1], c[2], px[0], px[1]);
    /* a corner far from the ball is background */
    ck_assert(!vt_not_background(rgb, a->w, a->h, 2, a->h - 3));
    free(rgb);
}
