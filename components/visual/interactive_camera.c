/* interactive_camera.c - InteractiveCamera: where the viewer's camera
 * starts (SOFA's InteractiveCamera: position, lookAt, orientation,
 * fieldOfView).  Only a viewer reads it (pliant view, pliant render: by
 * type name, as runSofa finds the scene's camera); the simulation ignores
 * it.  Without one the viewer frames the whole scene. */
#include <math.h>

#include "visual/visual.h"

typedef struct interactive_camera {
    pl_component base;
    double position[3], look_at[3];
    pl_doubles orientation;
    double fov;
} interactive_camera;

static const pl_field FIELDS[] = {
    PL_FIELD(interactive_camera, position, "position", PL_F_VEC3, "0 0 1",
             "the eye [m]", 0),
    PL_FIELD(interactive_camera, look_at, "lookAt", PL_F_VEC3, "0 0 0",
             "the point looked at [m]; orbiting turns about it", 0),
    PL_FIELD(interactive_camera, orientation, "orientation", PL_F_DOUBLES, NULL,
             "SOFA's quaternion x y z w: the screen's up is its rotation of +y (empty: +y up, "
             "or +z when looking along y)",
             0),
    PL_FIELD(interactive_camera, fov, "fieldOfView", PL_F_DOUBLE, "45",
             "vertical field of view [deg]", 0),
};

static int ic_init(pl_component *c, pl_ctx *ctx)
{
    interactive_camera *ic = (interactive_camera *)c;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double d = ic->position[k] - ic->look_at[k];
        d2 += d * d;
        if (!isfinite(ic->position[k]) || !isfinite(ic->look_at[k]))
            return pl_component_error(c, ctx, PL_EINPUT, "position and lookAt must be finite");
    }
    if (!(d2 > 0.0))
        return pl_component_error(c, ctx, PL_EINPUT, "position and lookAt are the same point");
    if (!(ic->fov > 0.0 && ic->fov < 180.0))
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "fieldOfView must be between 0 and 180 degrees, got %g", ic->fov);
    if (ic->orientation.n != 0 && ic->orientation.n != 4)
        return pl_component_error(c, ctx, PL_EINPUT,
                                  "orientation: expected a quaternion x y z w (4 numbers), found %d",
                                  ic->orientation.n);
    if (ic->orientation.n == 4) {
        double n2 = 0.0;
        for (int k = 0; k < 4; ++k) n2 += ic->orientation.v[k] * ic->orientation.v[k];
        if (!(n2 > 1e-12) || !isfinite(n2))
            return pl_component_error(c, ctx, PL_EINPUT, "orientation: a zero quaternion");
    }
    return PL_OK;
}

const pl_type pl_interactive_camera_type = {
    .abi_version = PL_ABI_VERSION,
    .name = "InteractiveCamera",
    .help = "The viewer's starting camera (SOFA's InteractiveCamera: position, lookAt, "
            "orientation, fieldOfView); ignored by the simulation.",
    .size = sizeof(interactive_camera),
    .fields = FIELDS,
    .nfields = sizeof FIELDS / sizeof FIELDS[0],
    .ops = {.init = ic_init},
};
