/* camera.h - the viewer's orbiting camera: a point looked at, a distance,
 * the direction from that point to the eye and the screen's up; a
 * perspective projection.  Both pliant view and pliant render use it, so a
 * picture is the same in both, and the tests project points with it. */
#ifndef PLIANT_VW_CAMERA_H
#define PLIANT_VW_CAMERA_H

typedef struct vw_camera {
    double target[3];   /* the point looked at and orbited about [m] */
    double dist;        /* eye to target [m] */
    double back[3];     /* unit: from the target to the eye */
    double up[3];       /* unit, orthogonal to back: the screen's up */
    double world_up[3]; /* unit: the axis orbiting turns about (against gravity) */
    double fov;         /* vertical field of view [deg] */
    double radius;      /* of the scene [m]: sets the clipping planes */
} vw_camera;

/* Frames a box (lo, hi) seen from a three-quarter view above it, world_up
 * against gravity g (any non-zero vector; zero: +y). */
void vw_camera_frame(vw_camera *c, const double lo[3], const double hi[3], const double g[3]);
/* SOFA's InteractiveCamera: eye, point looked at, up (NULL: world_up, or
 * another axis when looking along it), field of view [deg]. */
void vw_camera_look(vw_camera *c, const double eye[3], const double at[3], const double up[3],
                    double fov);
void vw_camera_eye(const vw_camera *c, double eye[3]);

/* Mouse gestures, in pixels of a viewport of height h: orbit about the
 * target, pan the target across the screen, zoom by a factor (> 1: closer). */
void vw_camera_orbit(vw_camera *c, double dx, double dy);
void vw_camera_pan(vw_camera *c, double dx, double dy, int h);
void vw_camera_zoom(vw_camera *c, double factor);

/* Column-major view and projection matrices for a w x h viewport. */
void vw_camera_matrices(const vw_camera *c, int w, int h, double view[16], double proj[16]);
/* Pixel (origin at the top left, y down) of the world point p; returns 0
 * when p is behind the eye. *depth: the distance along the view axis. */
int vw_camera_project(const vw_camera *c, int w, int h, const double p[3], double *px, double *py,
                      double *depth);
/* The ray through pixel (px, py): origin (the eye) and unit direction. */
void vw_camera_ray(const vw_camera *c, int w, int h, double px, double py, double origin[3],
                   double dir[3]);
/* The world point at pixel (px, py) on the plane through p facing the eye
 * (the plane a dragged vertex moves in). */
void vw_camera_unproject_at(const vw_camera *c, int w, int h, double px, double py,
                            const double p[3], double out[3]);

#endif
