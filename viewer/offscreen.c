/* offscreen.c - EGL without a display, and the framebuffers (offscreen.h). */
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include "offscreen.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render.h"

struct vw_offscreen {
    EGLDisplay dpy;
    EGLContext ctx;
    GLuint fbo_ms, rb_colour_ms, rb_depth_ms; /* drawn into */
    GLuint fbo, rb_colour;                    /* resolved, read from */
    int w, h;
    char platform[64];
};

/* A display on a GPU of the EGL device platform (a device that is not
 * Mesa's software one), or EGL_NO_DISPLAY. */
static EGLDisplay gpu_display(char *name, size_t size)
{
    PFNEGLQUERYDEVICESEXTPROC query = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    PFNEGLQUERYDEVICESTRINGEXTPROC qstr =
        (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
    PFNEGLGETPLATFORMDISPLAYEXTPROC get =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    EGLDeviceEXT devs[16];
    EGLint n = 0;
    if (!query || !get || !query(16, devs, &n)) return EGL_NO_DISPLAY;
    for (EGLint k = 0; k < n; ++k) {
        const char *ext = qstr ? qstr(devs[k], EGL_EXTENSIONS) : NULL;
        if (ext && strstr(ext, "EGL_MESA_device_software")) continue;
        EGLDisplay d = get(EGL_PLATFORM_DEVICE_EXT, devs[k], NULL);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL)) {
            snprintf(name, size, "EGL device %d", (int)k);
            return d;
        }
    }
    return EGL_NO_DISPLAY;
}

static EGLDisplay software_display(char *name, size_t size)
{
    PFNEGLGETPLATFORMDISPLAYEXTPROC get =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    EGLDisplay d = get ? get(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL)
                       : EGL_NO_DISPLAY;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL)) {
        snprintf(name, size, "Mesa surfaceless");
        return d;
    }
    return EGL_NO_DISPLAY;
}

static int make_context(vw_offscreen *o, pl_error *err)
{
    if (!eglBindAPI(EGL_OPENGL_API))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "EGL", "this EGL has no desktop OpenGL");
    const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig cfg = NULL;
    EGLint ncfg = 0;
    eglChooseConfig(o->dpy, cfg_attr, &cfg, 1, &ncfg);
    const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    o->ctx = eglCreateContext(o->dpy, ncfg ? cfg : (EGLConfig)0, EGL_NO_CONTEXT, ctx_attr);
    if (o->ctx == EGL_NO_CONTEXT)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "EGL",
                            "no OpenGL 3.3 core context on %s (EGL error 0x%x)", o->platform,
                            (unsigned)eglGetError());
    if (!eglMakeCurrent(o->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, o->ctx))
        return pl_error_set(err, PL_EINPUT, NULL, 0, "EGL",
                            "cannot use a context without a surface on %s", o->platform);
    return PL_OK;
}

static int make_framebuffers(vw_offscreen *o, pl_error *err)
{
    GLint samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &samples);
    if (samples > 4) samples = 4;
    glGenFramebuffers(1, &o->fbo_ms);
    glGenRenderbuffers(1, &o->rb_colour_ms);
    glGenRenderbuffers(1, &o->rb_depth_ms);
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo_ms);
    glBindRenderbuffer(GL_RENDERBUFFER, o->rb_colour_ms);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, o->w, o->h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, o->rb_colour_ms);
    glBindRenderbuffer(GL_RENDERBUFFER, o->rb_depth_ms);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, o->w, o->h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, o->rb_depth_ms);
    int ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glGenFramebuffers(1, &o->fbo);
    glGenRenderbuffers(1, &o->rb_colour);
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    glBindRenderbuffer(GL_RENDERBUFFER, o->rb_colour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, o->w, o->h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, o->rb_colour);
    ok = ok && glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    if (!ok)
        return pl_error_set(err, PL_EINPUT, NULL, 0, "OpenGL",
                            "cannot make a %dx%d framebuffer (%s)", o->w, o->h,
                            vw_renderer_gl_name());
    return PL_OK;
}

vw_offscreen *vw_offscreen_create(int w, int h, pl_error *err)
{
    vw_offscreen *o = calloc(1, sizeof *o);
    if (!o) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        return NULL;
    }
    o->w = w, o->h = h;
    o->dpy = gpu_display(o->platform, sizeof o->platform);
    if (o->dpy == EGL_NO_DISPLAY) o->dpy = software_display(o->platform, sizeof o->platform);
    int rc = o->dpy == EGL_NO_DISPLAY
                 ? pl_error_set(err, PL_EINPUT, NULL, 0, "EGL",
                                "no EGL display: neither a GPU nor Mesa's surfaceless platform "
                                "(apt-get install libegl-mesa0 libgl1-mesa-dri)")
                 : make_context(o, err);
    if (!rc) rc = make_framebuffers(o, err);
    if (rc) {
        vw_offscreen_free(o);
        return NULL;
    }
    return o;
}

void vw_offscreen_free(vw_offscreen *o)
{
    if (!o) return;
    if (o->ctx != EGL_NO_CONTEXT && o->ctx) {
        GLuint fb[2] = {o->fbo_ms, o->fbo}, rb[3] = {o->rb_colour_ms, o->rb_depth_ms, o->rb_colour};
        glDeleteFramebuffers(2, fb);
        glDeleteRenderbuffers(3, rb);
        eglMakeCurrent(o->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(o->dpy, o->ctx);
    }
    if (o->dpy != EGL_NO_DISPLAY && o->dpy) eglTerminate(o->dpy);
    free(o);
}

void vw_offscreen_bind(vw_offscreen *o)
{
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo_ms);
}

void vw_offscreen_read(vw_offscreen *o, unsigned char *rgb)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, o->fbo_ms);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, o->fbo);
    glBlitFramebuffer(0, 0, o->w, o->h, 0, 0, o->w, o->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    vw_read_pixels(o->w, o->h, rgb);
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo_ms);
}

const char *vw_offscreen_platform(const vw_offscreen *o)
{
    return o->platform;
}
