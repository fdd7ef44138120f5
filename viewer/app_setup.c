/* app_setup.c - what the viewer adds to a scene and reads from it once:
 * the mouse spring (vw_app_prepare) and the starting camera (the scene's
 * InteractiveCamera, else framed on the scene). */
#include "app.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vw_math.h"

static int find_first(pl_component *c, void *user)
{
    *(pl_component **)user = c;
    return 1;
}

int vw_app_prepare(pl_node *root, pl_registry *reg, pl_diag *diag, void *user)
{
    vw_app *a = user;
    a->pick_path[0] = '\0';
    pl_component *loop = NULL;
    pl_node_visit_role(root, PL_ROLE_ANIMATION_LOOP, find_first, &loop);
    /* only the local-global loop takes constraint rows */
    if (!loop || strcmp(loop->type->name, "LocalGlobalSolver") != 0) return 0;
    if (pl_node_count_role(loop->node, PL_ROLE_CONTACT_SOLVER) == 0) {
        pl_error e;
        if (pl_registry_load_plugin(reg, "ncp_contact", &e) != PL_OK) {
            pl_log_info("viewer: no mouse spring (%s)", e.msg);
            return 0;
        }
        if (!pl_node_add_component(loop->node, reg, "NonSmoothNewtonContactSolver",
                                   "viewerContact", diag))
            return 1;
    }
    pl_component *pick = pl_node_add_component(loop->node, reg, "PickSpring", "viewerPick", diag);
    if (!pick) return 1;
    pl_component_path(pick, a->pick_path, sizeof a->pick_path);
    return 0;
}

static pl_component *find_type(pl_node *n, const char *type)
{
    for (int k = 0; k < n->ncomponents; ++k)
        if (!strcmp(n->components[k]->type->name, type)) return n->components[k];
    for (int k = 0; k < n->nchildren; ++k) {
        pl_component *c = find_type(n->children[k], type);
        if (c) return c;
    }
    return NULL;
}

/* Up to max numbers of field `name` of c; returns how many. */
static int numbers(const pl_component *c, const char *name, double *v, int max)
{
    const pl_field *f = pl_component_field(c, name);
    char text[512];
    if (!f || pl_field_format(f, c, text, sizeof text) != PL_OK) return 0;
    int n = 0;
    char *s = text, *end;
    while (n < max) {
        double x = strtod(s, &end);
        if (end == s) break;
        v[n++] = x;
        s = end;
    }
    return n;
}

/* The camera of the scene's InteractiveCamera; 0 when it has none. */
static int scene_camera(vw_app *a)
{
    pl_component *c = find_type(pl_sim_model(a->sim)->root, "InteractiveCamera");
    double eye[3], at[3], q[4], fov;
    if (!c || numbers(c, "position", eye, 3) != 3 || numbers(c, "lookAt", at, 3) != 3 ||
        numbers(c, "fieldOfView", &fov, 1) != 1)
        return 0;
    double up[3] = {0.0, 1.0, 0.0}, *upp = NULL;
    if (numbers(c, "orientation", q, 4) == 4) {
        /* SOFA's quaternion (x, y, z, w) applied to +y */
        double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (int k = 0; k < 4; ++k) q[k] /= n;
        double x = q[0], y = q[1], z = q[2], w = q[3];
        up[0] = 2.0 * (x * y - w * z);
        up[1] = 1.0 - 2.0 * (x * x + z * z);
        up[2] = 2.0 * (y * z + w * x);
        upp = up;
    }
    vw_camera_look(&a->camera, eye, at, upp, fov);
    return 1;
}

void vw_app_frame_camera(vw_app *a)
{
    double g[3];
    pl_node_gravity(pl_sim_model(a->sim)->root, g);
    vw_camera_frame(&a->camera, a->scene.lo, a->scene.hi, g);
    double radius = a->camera.radius;
    if (scene_camera(a) && a->camera.radius < radius) a->camera.radius = radius;
    a->camera0 = a->camera;
}
