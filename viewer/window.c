/* window.c - the GLFW window of pliant view (window.h). */
#include <GLFW/glfw3.h>

#include "window.h"

#include <stdlib.h>
#include <string.h>

struct vw_window {
    GLFWwindow *w;
    vw_app *app;
    int mods;
    pl_error err;     /* the first error an event caused */
    int failed;
};

static int mods_of(int glfw_mods)
{
    return ((glfw_mods & GLFW_MOD_SHIFT) ? VW_MOD_SHIFT : 0) |
           ((glfw_mods & GLFW_MOD_CONTROL) ? VW_MOD_CTRL : 0);
}

static void send(vw_window *win, const vw_input *in)
{
    if (!win->app || win->failed) return;
    if (vw_app_input(win->app, in, &win->err) != PL_OK) win->failed = 1;
}

/* Keys that make no character (and any key with Ctrl held). */
static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    vw_window *win = glfwGetWindowUserPointer(w);
    win->mods = mods_of(mods);
    if (action == GLFW_RELEASE) return;
    int k = -1;
    switch (key) {
    case GLFW_KEY_ESCAPE: k = VW_KEY_ESCAPE; break;
    case GLFW_KEY_UP: k = PL_KEY_UP; break;
    case GLFW_KEY_DOWN: k = PL_KEY_DOWN; break;
    case GLFW_KEY_LEFT: k = PL_KEY_LEFT; break;
    case GLFW_KEY_RIGHT: k = PL_KEY_RIGHT; break;
    case GLFW_KEY_PAGE_UP: k = PL_KEY_PAGE_UP; break;
    case GLFW_KEY_PAGE_DOWN: k = PL_KEY_PAGE_DOWN; break;
    default:
        /* with Ctrl no character comes: letters and digits as themselves */
        if ((mods & GLFW_MOD_CONTROL) && key >= GLFW_KEY_A && key <= GLFW_KEY_Z)
            k = 'a' + (key - GLFW_KEY_A);
        else if ((mods & GLFW_MOD_CONTROL) && key >= GLFW_KEY_0 && key <= GLFW_KEY_9)
            k = '0' + (key - GLFW_KEY_0);
    }
    if (k < 0) return;
    vw_input in = {VW_IN_KEY, k, win->mods, 0, 0, 0.0, 0.0};
    send(win, &in);
}

static void on_char(GLFWwindow *w, unsigned int codepoint)
{
    vw_window *win = glfwGetWindowUserPointer(w);
    if (codepoint >= 127 || codepoint < 32) return;
    vw_input in = {VW_IN_KEY, (int)codepoint, win->mods & ~VW_MOD_CTRL, 0, 0, 0.0, 0.0};
    send(win, &in);
}

/* Cursor position in framebuffer pixels. */
static void cursor(GLFWwindow *w, double *x, double *y)
{
    int ww, wh, fw, fh;
    glfwGetCursorPos(w, x, y);
    glfwGetWindowSize(w, &ww, &wh);
    glfwGetFramebufferSize(w, &fw, &fh);
    if (ww > 0 && wh > 0) *x *= (double)fw / ww, *y *= (double)fh / wh;
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    vw_window *win = glfwGetWindowUserPointer(w);
    int b = button == GLFW_MOUSE_BUTTON_LEFT ? 0 : button == GLFW_MOUSE_BUTTON_RIGHT ? 1
          : button == GLFW_MOUSE_BUTTON_MIDDLE ? 2 : -1;
    if (b < 0) return;
    vw_input in = {VW_IN_BUTTON, 0, mods_of(mods), b, action == GLFW_PRESS, 0.0, 0.0};
    cursor(w, &in.x, &in.y);
    send(win, &in);
}

static void on_move(GLFWwindow *w, double x, double y)
{
    vw_window *win = glfwGetWindowUserPointer(w);
    vw_input in = {VW_IN_MOVE, 0, win->mods, 0, 0, x, y};
    cursor(w, &in.x, &in.y);
    send(win, &in);
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    vw_window *win = glfwGetWindowUserPointer(w);
    vw_input in = {VW_IN_SCROLL, 0, win->mods, 0, 0, 0.0, dy};
    send(win, &in);
}

static void on_resize(GLFWwindow *w, int width, int height)
{
    vw_window *win = glfwGetWindowUserPointer(w);
    vw_input in = {VW_IN_RESIZE, 0, 0, 0, 0, width, height};
    send(win, &in);
}

vw_window *vw_window_open(int w, int h, const char *title, pl_error *err)
{
    if (!glfwInit()) {
        const char *why = NULL;
        glfwGetError(&why);
        pl_error_set(err, PL_EINPUT, NULL, 0, "pliant view",
                     "no display to open a window on (%s); pliant render draws without one",
                     why ? why : "GLFW cannot start");
        return NULL;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    vw_window *win = calloc(1, sizeof *win);
    GLFWwindow *gw = win ? glfwCreateWindow(w, h, title, NULL, NULL) : NULL;
    if (!gw) {
        const char *why = NULL;
        glfwGetError(&why);
        pl_error_set(err, PL_EINPUT, NULL, 0, "pliant view",
                     "cannot open an OpenGL 3.3 window (%s)", why ? why : "out of memory");
        free(win);
        glfwTerminate();
        return NULL;
    }
    win->w = gw;
    glfwSetWindowUserPointer(gw, win);
    glfwMakeContextCurrent(gw);
    glfwSwapInterval(1);
    glfwSetKeyCallback(gw, on_key);
    glfwSetCharCallback(gw, on_char);
    glfwSetMouseButtonCallback(gw, on_button);
    glfwSetCursorPosCallback(gw, on_move);
    glfwSetScrollCallback(gw, on_scroll);
    glfwSetFramebufferSizeCallback(gw, on_resize);
    return win;
}

void vw_window_close(vw_window *win)
{
    if (!win) return;
    glfwDestroyWindow(win->w);
    free(win);
    glfwTerminate();
}

void vw_window_attach(vw_window *win, vw_app *app)
{
    win->app = app;
}

int vw_window_poll(vw_window *win, pl_error *err)
{
    glfwPollEvents();
    if (!win->failed) return PL_OK;
    *err = win->err;
    return err->code ? err->code : PL_EINTERNAL;
}

int vw_window_should_close(const vw_window *win)
{
    return glfwWindowShouldClose(win->w) || (win->app && win->app->quit);
}

void vw_window_size(const vw_window *win, int *w, int *h)
{
    glfwGetFramebufferSize(win->w, w, h);
}

void vw_window_swap(vw_window *win)
{
    glfwSwapBuffers(win->w);
}
