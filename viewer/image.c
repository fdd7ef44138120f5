/* image.c - PNG through libpng, MP4 through the ffmpeg program (image.h). */
#include "image.h"

#include <errno.h>
#include <png.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

int vw_png_write(const char *path, int w, int h, const unsigned char *rgb, pl_error *err)
{
    FILE *f = fopen(path, "wb");
    if (!f) return pl_error_set(err, PL_EINPUT, path, 0, NULL, "cannot write: %s", strerror(errno));
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_bytep *rows = malloc((size_t)h * sizeof *rows);
    if (!png || !info || !rows) {
        png_destroy_write_struct(&png, &info);
        free(rows);
        fclose(f);
        return pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "out of memory");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(rows);
        fclose(f);
        return pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "writing the PNG failed");
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 9);
    for (int y = 0; y < h; ++y) rows[y] = (png_bytep)(rgb + (size_t)y * w * 3);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(rows);
    if (fclose(f) != 0) return pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "writing failed");
    return PL_OK;
}

int vw_png_read(const char *path, int *w, int *h, unsigned char **rgb, pl_error *err)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return pl_error_set(err, PL_EINPUT, path, 0, NULL, "not a readable PNG: %s", img.message);
    img.format = PNG_FORMAT_RGB;
    *rgb = malloc(PNG_IMAGE_SIZE(img));
    if (!*rgb) {
        png_image_free(&img);
        return pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "out of memory");
    }
    if (!png_image_finish_read(&img, NULL, *rgb, 0, NULL)) {
        free(*rgb);
        *rgb = NULL;
        return pl_error_set(err, PL_EINPUT, path, 0, NULL, "a broken PNG: %s", img.message);
    }
    *w = (int)img.width;
    *h = (int)img.height;
    return PL_OK;
}

struct vw_video {
    FILE *pipe;
    pid_t pid;
    int w, h;
    char *path;
};

vw_video *vw_video_open(const char *path, int w, int h, int fps, pl_error *err)
{
    int fd[2];
    if (w % 2 || h % 2) {
        pl_error_set(err, PL_EINPUT, path, 0, NULL, "H.264 needs an even width and height, got %dx%d",
                     w, h);
        return NULL;
    }
    vw_video *v = calloc(1, sizeof *v);
    if (!v || !(v->path = strdup(path)) || pipe(fd) != 0) {
        if (v) free(v->path);
        free(v);
        pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "cannot start ffmpeg: out of resources");
        return NULL;
    }
    char size[32], rate[16];
    snprintf(size, sizeof size, "%dx%d", w, h);
    snprintf(rate, sizeof rate, "%d", fps);
    v->pid = fork();
    if (v->pid == 0) {
        dup2(fd[0], 0);
        close(fd[0]);
        close(fd[1]);
        execlp("ffmpeg", "ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", size, "-r", rate, "-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p",
               "-preset", "veryfast", "-movflags", "+faststart", path, (char *)NULL);
        _exit(127);
    }
    close(fd[0]);
    if (v->pid < 0 || !(v->pipe = fdopen(fd[1], "wb"))) {
        if (v->pid < 0) close(fd[1]);
        pl_error_set(err, PL_EINTERNAL, path, 0, NULL, "cannot start ffmpeg");
        vw_video_close(v, NULL);
        return NULL;
    }
    v->w = w, v->h = h;
    return v;
}

int vw_video_frame(vw_video *v, const unsigned char *rgb, pl_error *err)
{
    size_t n = (size_t)v->w * v->h * 3;
    if (fwrite(rgb, 1, n, v->pipe) != n)
        return pl_error_set(err, PL_EINPUT, v->path, 0, NULL,
                            "ffmpeg stopped taking frames (is it installed? apt-get install "
                            "ffmpeg)");
    return PL_OK;
}

int vw_video_close(vw_video *v, pl_error *err)
{
    if (!v) return PL_OK;
    int status = -1, rc = PL_OK;
    if (v->pipe) fclose(v->pipe);
    if (v->pid > 0) waitpid(v->pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        rc = err ? pl_error_set(err, PL_EINPUT, v->path, 0, NULL,
                                code == 127 ? "ffmpeg is not installed (apt-get install ffmpeg)"
                                            : "ffmpeg failed (exit status %d)",
                                code)
                 : PL_EINPUT;
    }
    free(v->path);
    free(v);
    return rc;
}
