/* render.c - the OpenGL drawing of the viewer (render.h).  One small
 * shader pair for everything 3D (per-vertex colour, two-sided headlight
 * shading for surfaces, flat for lines and points) and one for the
 * overlay's text; geometry is streamed into one vertex buffer per draw
 * call, as it changes every frame anyway. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "font.h"
#include "vw_math.h"

const float VW_BACKGROUND[3] = {0.16f, 0.17f, 0.20f};
static const float BODY_COLOUR[3] = {0.86f, 0.56f, 0.36f};
static const float OBSTACLE_COLOUR[3] = {0.60f, 0.63f, 0.68f};
static const float PLANE_COLOUR[3] = {0.42f, 0.44f, 0.48f};
static const float CABLE_COLOUR[3] = {1.00f, 0.82f, 0.10f};
static const float CONTACT_COLOUR[3] = {1.00f, 0.25f, 0.25f};
static const float EDGE_COLOUR[3] = {0.10f, 0.10f, 0.12f};
static const float PICK_COLOUR[3] = {0.20f, 1.00f, 0.40f};

/* A vertex: position, normal, colour. */
typedef struct vertex {
    float p[3], n[3], c[3];
} vertex;

struct vw_renderer {
    GLuint prog, vao, vbo, ebo;
    GLint u_mvp, u_view, u_lit, u_psize;
    GLuint text_prog, text_vao, text_vbo, font_tex;
    GLint u_screen, u_tcolour;
    vertex *v;
    unsigned *idx;
    size_t capv, capi;
};

static const char *VS =
    "#version 330 core\n"
    "layout(location = 0) in vec3 pos;\n"
    "layout(location = 1) in vec3 nrm;\n"
    "layout(location = 2) in vec3 col;\n"
    "uniform mat4 mvp, view;\n"
    "uniform float psize;\n"
    "out vec3 vn, vc;\n"
    "void main() {\n"
    "  gl_Position = mvp * vec4(pos, 1.0);\n"
    "  gl_PointSize = psize;\n"
    "  vn = mat3(view) * nrm;\n"
    "  vc = col;\n"
    "}\n";
static const char *FS =
    "#version 330 core\n"
    "in vec3 vn, vc;\n"
    "uniform float lit;\n"
    "out vec4 frag;\n"
    "void main() {\n"
    "  float d = lit > 0.5 ? abs(normalize(vn).z) : 1.0;\n"
    "  frag = vec4(vc * (lit > 0.5 ? 0.30 + 0.70 * d : 1.0), 1.0);\n"
    "}\n";
static const char *TEXT_VS =
    "#version 330 core\n"
    "layout(location = 0) in vec2 pos;\n"
    "layout(location = 1) in vec2 uv;\n"
    "uniform vec2 screen;\n"
    "out vec2 tuv;\n"
    "void main() {\n"
    "  gl_Position = vec4(2.0 * pos.x / screen.x - 1.0, 1.0 - 2.0 * pos.y / screen.y, 0.0, 1.0);\n"
    "  tuv = uv;\n"
    "}\n";
static const char *TEXT_FS =
    "#version 330 core\n"
    "in vec2 tuv;\n"
    "uniform sampler2D font;\n"
    "uniform vec4 colour;\n"
    "out vec4 frag;\n"
    "void main() {\n"
    "  float a = tuv.x < 0.0 ? 1.0 : texture(font, tuv).r;\n"
    "  frag = vec4(colour.rgb, colour.a * a);\n"
    "}\n";

static GLuint compile(GLenum kind, const char *src, pl_error *err)
{
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        pl_error_set(err, PL_EINTERNAL, NULL, 0, "OpenGL", "a shader does not compile: %s", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

static GLuint program(const char *vs, const char *fs, pl_error *err)
{
    GLuint v = compile(GL_VERTEX_SHADER, vs, err), f = v ? compile(GL_FRAGMENT_SHADER, fs, err) : 0;
    if (!f) {
        if (v) glDeleteShader(v);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, "OpenGL", "the shaders do not link");
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

static void setup_mesh_vao(vw_renderer *r)
{
    glGenVertexArrays(1, &r->vao);
    glGenBuffers(1, &r->vbo);
    glGenBuffers(1, &r->ebo);
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ebo);
    for (int a = 0; a < 3; ++a) {
        glEnableVertexAttribArray((GLuint)a);
        glVertexAttribPointer((GLuint)a, 3, GL_FLOAT, GL_FALSE, sizeof(vertex),
                              (const void *)(sizeof(float) * 3 * (size_t)a));
    }
    glBindVertexArray(0);
}

static void setup_text(vw_renderer *r)
{
    glGenVertexArrays(1, &r->text_vao);
    glGenBuffers(1, &r->text_vbo);
    glBindVertexArray(r->text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->text_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), (const void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float),
                          (const void *)(2 * sizeof(float)));
    glBindVertexArray(0);
    static unsigned char atlas[VW_FONT_COUNT * VW_FONT_CELL_W * VW_FONT_CELL_H];
    vw_font_atlas(atlas);
    glGenTextures(1, &r->font_tex);
    glBindTexture(GL_TEXTURE_2D, r->font_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, VW_FONT_COUNT * VW_FONT_CELL_W, VW_FONT_CELL_H, 0, GL_RED,
                 GL_UNSIGNED_BYTE, atlas);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

const char *vw_renderer_gl_name(void)
{
    static char name[256];
    const char *r = (const char *)glGetString(GL_RENDERER);
    const char *v = (const char *)glGetString(GL_VERSION);
    snprintf(name, sizeof name, "%s, OpenGL %s", r ? r : "?", v ? v : "?");
    return name;
}

vw_renderer *vw_renderer_create(pl_error *err)
{
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 33) {
        pl_error_set(err, PL_EINPUT, NULL, 0, "OpenGL",
                     "OpenGL 3.3 is needed, this context has %d.%d (%s)", major, minor,
                     vw_renderer_gl_name());
        return NULL;
    }
    vw_renderer *r = calloc(1, sizeof *r);
    if (!r) {
        pl_error_set(err, PL_EINTERNAL, NULL, 0, NULL, "out of memory");
        return NULL;
    }
    r->prog = program(VS, FS, err);
    r->text_prog = r->prog ? program(TEXT_VS, TEXT_FS, err) : 0;
    if (!r->text_prog) {
        vw_renderer_free(r);
        return NULL;
    }
    r->u_mvp = glGetUniformLocation(r->prog, "mvp");
    r->u_view = glGetUniformLocation(r->prog, "view");
    r->u_lit = glGetUniformLocation(r->prog, "lit");
    r->u_psize = glGetUniformLocation(r->prog, "psize");
    r->u_screen = glGetUniformLocation(r->text_prog, "screen");
    r->u_tcolour = glGetUniformLocation(r->text_prog, "colour");
    setup_mesh_vao(r);
    setup_text(r);
    return r;
}

void vw_renderer_free(vw_renderer *r)
{
    if (!r) return;
    if (r->prog) glDeleteProgram(r->prog);
    if (r->text_prog) glDeleteProgram(r->text_prog);
    if (r->vao) glDeleteVertexArrays(1, &r->vao);
    if (r->text_vao) glDeleteVertexArrays(1, &r->text_vao);
    GLuint bufs[3] = {r->vbo, r->ebo, r->text_vbo};
    glDeleteBuffers(3, bufs);
    if (r->font_tex) glDeleteTextures(1, &r->font_tex);
    free(r->v);
    free(r->idx);
    free(r);
}

/* ---- batches ------------------------------------------------------------- */

static int reserve(vw_renderer *r, size_t nv, size_t ni)
{
    if (nv > r->capv) {
        vertex *v = realloc(r->v, nv * sizeof *v);
        if (!v) return -1;
        r->v = v, r->capv = nv;
    }
    if (ni > r->capi) {
        unsigned *i = realloc(r->idx, ni * sizeof *i);
        if (!i) return -1;
        r->idx = i, r->capi = ni;
    }
    return 0;
}

static void put(vertex *v, const double *p, const float n[3], const float c[3])
{
    for (int k = 0; k < 3; ++k) {
        v->p[k] = (float)p[k];
        v->n[k] = n ? n[k] : 0.0f;
        v->c[k] = c[k];
    }
}

/* Streams nv vertices and ni indices and draws them as `mode`. */
static void flush(vw_renderer *r, GLenum mode, size_t nv, size_t ni, int lit, float psize)
{
    if (!nv || (!ni && mode != GL_POINTS)) return;
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * sizeof(vertex)), r->v, GL_STREAM_DRAW);
    glUniform1f(r->u_lit, lit ? 1.0f : 0.0f);
    glUniform1f(r->u_psize, psize);
    if (ni) {
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * sizeof(unsigned)), r->idx,
                     GL_STREAM_DRAW);
        glDrawElements(mode, (GLsizei)ni, GL_UNSIGNED_INT, 0);
    } else {
        glDrawArrays(mode, 0, (GLsizei)nv);
    }
}

/* Area-weighted vertex normals of triangles over x (n vertices). */
static void vertex_normals(const double *x, int n, const int *tris, int ntris, float *nrm)
{
    memset(nrm, 0, (size_t)n * 3 * sizeof *nrm);
    for (int t = 0; t < ntris; ++t) {
        const int *tr = &tris[3 * t];
        double e1[3], e2[3], fn[3];
        vw_sub(&x[3 * tr[1]], &x[3 * tr[0]], e1);
        vw_sub(&x[3 * tr[2]], &x[3 * tr[0]], e2);
        vw_cross(e1, e2, fn);
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) nrm[3 * tr[j] + k] += (float)fn[k];
    }
    for (int i = 0; i < n; ++i) {
        float *v = &nrm[3 * i], l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (l > 0.0f) v[0] /= l, v[1] /= l, v[2] /= l;
    }
}

/* A surface of triangles, coloured per vertex (colour NULL: by value/vmax). */
static void draw_surface(vw_renderer *r, const double *x, int n, const int *tris, int ntris,
                         const double *value, double vmax, const float colour[3], int wireframe)
{
    float *nrm = malloc((size_t)(n ? n : 1) * 3 * sizeof *nrm);
    if (!nrm || reserve(r, (size_t)n, (size_t)ntris * 3)) {
        free(nrm);
        return;
    }
    vertex_normals(x, n, tris, ntris, nrm);
    for (int i = 0; i < n; ++i) {
        float c[3];
        if (colour)
            memcpy(c, colour, sizeof c);
        else
            vw_colormap(vmax > 0.0 ? value[i] / vmax : 0.0, c);
        put(&r->v[i], &x[3 * i], &nrm[3 * i], c);
    }
    free(nrm);
    for (int k = 0; k < 3 * ntris; ++k) r->idx[k] = (unsigned)tris[k];
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    flush(r, GL_TRIANGLES, (size_t)n, (size_t)ntris * 3, 1, 1.0f);
    glDisable(GL_POLYGON_OFFSET_FILL);
    if (wireframe) {
        for (int i = 0; i < n; ++i) memcpy(r->v[i].c, EDGE_COLOUR, sizeof EDGE_COLOUR);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        flush(r, GL_TRIANGLES, (size_t)n, (size_t)ntris * 3, 0, 1.0f);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
}

static void draw_points(vw_renderer *r, const double *x, int n, const float colour[3], float size)
{
    if (reserve(r, (size_t)n, 0)) return;
    for (int i = 0; i < n; ++i) put(&r->v[i], &x[3 * i], NULL, colour);
    flush(r, GL_POINTS, (size_t)n, 0, 0, size);
}

static void draw_lines(vw_renderer *r, const double *x, int n, const int *lines, int nlines,
                       const float colour[3])
{
    if (reserve(r, (size_t)n, (size_t)nlines * 2)) return;
    for (int i = 0; i < n; ++i) put(&r->v[i], &x[3 * i], NULL, colour);
    for (int k = 0; k < 2 * nlines; ++k) r->idx[k] = (unsigned)lines[k];
    flush(r, GL_LINES, (size_t)n, (size_t)nlines * 2, 0, 1.0f);
}

/* Contact points and their forces as segments scaled so that the largest
 * is `len` long. */
static void draw_contacts(vw_renderer *r, const pl_draw_part *p, double fmax, double len)
{
    draw_points(r, p->x, p->nverts, CONTACT_COLOUR, 5.0f);
    if (!(fmax > 0.0) || reserve(r, (size_t)p->nverts * 2, (size_t)p->nverts * 2)) return;
    for (int i = 0; i < p->nverts; ++i) {
        double tip[3];
        for (int k = 0; k < 3; ++k) tip[k] = p->x[3 * i + k] + p->vec[3 * i + k] * len / fmax;
        put(&r->v[2 * i], &p->x[3 * i], NULL, CONTACT_COLOUR);
        put(&r->v[2 * i + 1], tip, NULL, CONTACT_COLOUR);
        r->idx[2 * i] = (unsigned)(2 * i);
        r->idx[2 * i + 1] = (unsigned)(2 * i + 1);
    }
    flush(r, GL_LINES, (size_t)p->nverts * 2, (size_t)p->nverts * 2, 0, 1.0f);
}

static void set_line_width(float w)
{
    GLfloat range[2] = {1.0f, 1.0f};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    glLineWidth(w < range[1] ? w : range[1]);
}

static void draw_parts(vw_renderer *r, const vw_scene *s, const vw_draw_options *o, double radius)
{
    double fmax = 0.0;
    for (int k = 0; k < s->drawing.nparts; ++k) {
        const pl_draw_part *p = &s->drawing.parts[k];
        if (p->kind == PL_DRAW_CONTACTS)
            for (int i = 0; i < p->nverts; ++i) {
                double f = vw_norm(&p->vec[3 * i]);
                if (f > fmax) fmax = f;
            }
    }
    for (int k = 0; k < s->drawing.nparts; ++k) {
        const pl_draw_part *p = &s->drawing.parts[k];
        if (p->kind == PL_DRAW_OBSTACLE)
            draw_surface(r, p->x, p->nverts, p->tris, p->ntris, NULL, 0.0,
                         p->unbounded ? PLANE_COLOUR : OBSTACLE_COLOUR, o->wireframe);
        if (p->kind == PL_DRAW_CABLE) {
            set_line_width(3.0f);
            draw_lines(r, p->x, p->nverts, p->lines, p->nlines, CABLE_COLOUR);
            set_line_width(1.0f);
            draw_points(r, p->x, p->nverts, CABLE_COLOUR, 4.0f);
        }
        if (p->kind == PL_DRAW_CONTACTS && o->contacts) draw_contacts(r, p, fmax, 0.25 * radius);
    }
}

void vw_renderer_draw(vw_renderer *r, const vw_scene *s, const vw_camera *c,
                      const vw_draw_options *o, int w, int h)
{
    glViewport(0, 0, w, h);
    glClearColor(VW_BACKGROUND[0], VW_BACKGROUND[1], VW_BACKGROUND[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    double view[16], proj[16], mvp[16];
    float fv[16], fm[16];
    vw_camera_matrices(c, w, h, view, proj);
    vw_mat4_mul(proj, view, mvp);
    for (int k = 0; k < 16; ++k) fv[k] = (float)view[k], fm[k] = (float)mvp[k];
    glUseProgram(r->prog);
    glUniformMatrix4fv(r->u_mvp, 1, GL_FALSE, fm);
    glUniformMatrix4fv(r->u_view, 1, GL_FALSE, fv);
    for (int k = 0; k < s->nbodies; ++k) {
        const vw_body *b = &s->bodies[k];
        int by_field = o->field != VW_FIELD_NONE;
        if (b->ntris)
            draw_surface(r, b->x, b->n, b->tris, b->ntris, b->value, s->field_max,
                         by_field ? NULL : BODY_COLOUR, o->wireframe);
        else
            draw_points(r, b->x, b->n, BODY_COLOUR, 3.0f);
    }
    draw_parts(r, s, o, c->radius);
    if (o->pick) {
        double seg[6];
        memcpy(seg, o->pick_from, sizeof o->pick_from);
        memcpy(seg + 3, o->pick_to, sizeof o->pick_to);
        int line[2] = {0, 1};
        set_line_width(2.0f);
        draw_lines(r, seg, 2, line, 1, PICK_COLOUR);
        set_line_width(1.0f);
        draw_points(r, seg + 3, 1, PICK_COLOUR, 7.0f);
    }
    glBindVertexArray(0);
}

/* ---- text ---------------------------------------------------------------- */

/* Appends a quad (two triangles) of screen rectangle and atlas rectangle
 * (u0 < 0: a solid quad) to q. */
static float *quad(float *q, float x0, float y0, float x1, float y1, float u0, float v0, float u1,
                   float v1)
{
    const float c[6][4] = {{x0, y0, u0, v0}, {x1, y0, u1, v0}, {x1, y1, u1, v1},
                           {x0, y0, u0, v0}, {x1, y1, u1, v1}, {x0, y1, u0, v1}};
    memcpy(q, c, sizeof c);
    return q + 24;
}

void vw_renderer_text(vw_renderer *r, int w, int h, const char *const *lines, int n, int corner,
                      int scale)
{
    size_t chars = 0, longest = 0;
    for (int k = 0; k < n; ++k) {
        size_t l = strlen(lines[k]);
        chars += l;
        if (l > longest) longest = l;
    }
    if (!n || scale < 1) return;
    float *q = malloc((chars + 1) * 24 * sizeof *q), *e = q;
    if (!q) return;
    float cw = (float)(VW_FONT_CELL_W * scale), ch = (float)(VW_FONT_CELL_H * scale);
    float pad = 4.0f * scale, x0 = pad, y0 = corner ? h - pad - n * ch : pad;
    float aw = (float)(VW_FONT_COUNT * VW_FONT_CELL_W);
    for (int k = 0; k < n; ++k)
        for (size_t i = 0; lines[k][i]; ++i) {
            int g = (unsigned char)lines[k][i] - VW_FONT_FIRST;
            if (g <= 0 || g >= VW_FONT_COUNT) continue; /* spaces and unknowns */
            float x = x0 + (float)i * cw, y = y0 + (float)k * ch;
            e = quad(e, x, y, x + cw, y + ch, g * VW_FONT_CELL_W / aw, 0.0f,
                     (g + 1) * VW_FONT_CELL_W / aw, 1.0f);
        }
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glViewport(0, 0, w, h);
    glUseProgram(r->text_prog);
    glUniform2f(r->u_screen, (float)w, (float)h);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, r->font_tex);
    glBindVertexArray(r->text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->text_vbo);
    /* the box behind the text */
    float box[24];
    quad(box, x0 - pad * 0.5f, y0 - pad * 0.5f, x0 + longest * cw + pad * 0.5f,
         y0 + n * ch + pad * 0.5f, -1.0f, 0.0f, -1.0f, 0.0f);
    glUniform4f(r->u_tcolour, 0.0f, 0.0f, 0.0f, 0.45f);
    glBufferData(GL_ARRAY_BUFFER, sizeof box, box, GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glUniform4f(r->u_tcolour, 0.95f, 0.95f, 0.95f, 1.0f);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)(e - q) * sizeof *q), q, GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)((e - q) / 4));
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    free(q);
}

void vw_read_pixels(int w, int h, unsigned char *rgb)
{
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    unsigned char *tmp = malloc((size_t)w * h * 3);
    if (!tmp) return;
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, tmp);
    for (int y = 0; y < h; ++y)
        memcpy(rgb + (size_t)y * w * 3, tmp + (size_t)(h - 1 - y) * w * 3, (size_t)w * 3);
    free(tmp);
}
