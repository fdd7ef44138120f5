/* image.h - pictures out: PNG files (libpng) and MP4 films (frames piped
 * to Debian's ffmpeg). */
#ifndef PLIANT_VW_IMAGE_H
#define PLIANT_VW_IMAGE_H

#include <stdio.h>

#include <pliant/error.h>

/* Writes w x h RGB pixels (top row first) as an 8-bit PNG.  PL_OK, or
 * PL_EINPUT (cannot write the file) / PL_EINTERNAL with err. */
int vw_png_write(const char *path, int w, int h, const unsigned char *rgb, pl_error *err);
/* Reads an 8-bit RGB or RGBA PNG into *rgb (malloc'ed, RGB, top row first). */
int vw_png_read(const char *path, int *w, int *h, unsigned char **rgb, pl_error *err);

typedef struct vw_video vw_video;
/* Starts ffmpeg encoding H.264 at `fps` frames per second into path (w and
 * h even).  NULL with err set when ffmpeg is missing or fails to start. */
vw_video *vw_video_open(const char *path, int w, int h, int fps, pl_error *err);
int vw_video_frame(vw_video *v, const unsigned char *rgb, pl_error *err);
/* Finishes the file; PL_OK when ffmpeg succeeded. */
int vw_video_close(vw_video *v, pl_error *err);

#endif
