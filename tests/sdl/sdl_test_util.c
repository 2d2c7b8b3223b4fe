/* sdl_test_util.c - see sdl_test_util.h. */
#include "sdl_test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <SDL_image.h>

static char g_base[1024] = "."; /* test-local; each test is its own process */
static char g_dir[1200];

void tu_set_base(const char *base)
{
    snprintf(g_base, sizeof g_base, "%s", base);
}

const char *tu_dir(const char *name)
{
    snprintf(g_dir, sizeof g_dir, "%s/%s", g_base, name);
    return g_dir;
}

void tu_frame_init(tu_frame *f, uint64_t number, double time)
{
    memset(f, 0, sizeof *f);
    f->frame.number = number;
    f->frame.time = time;
    f->frame.bodies = f->bodies;
}

rbs_frame_body *tu_add_sphere(tu_frame *f, const char *name, double x, double y,
                              double z, double radius, uint32_t color)
{
    rbs_frame_body *b = &f->bodies[f->frame.body_count];
    memset(b, 0, sizeof *b);
    b->type = RBS_BODY_SPHERE;
    b->slot = f->frame.body_count++;
    b->name = name;
    b->color = color;
    b->texture = RBS_TEXTURE_NONE;
    b->position[0] = x;
    b->position[1] = y;
    b->position[2] = z;
    b->orientation[0] = 1.0;
    b->radius = radius;
    return b;
}

rbs_frame_body *tu_add_plane(tu_frame *f, double px, double py, double pz,
                             double nx, double ny, double nz, uint32_t color)
{
    rbs_frame_body *b = &f->bodies[f->frame.body_count];
    memset(b, 0, sizeof *b);
    b->type = RBS_BODY_PLANE;
    b->slot = f->frame.body_count++;
    b->name = "ground";
    b->color = color;
    b->texture = RBS_TEXTURE_CHECKER;
    b->position[0] = px;
    b->position[1] = py;
    b->position[2] = pz;
    b->normal[0] = nx;
    b->normal[1] = ny;
    b->normal[2] = nz;
    b->orientation[0] = 1.0;
    return b;
}

rbs_status tu_create_full(const char *json, const char *path, const char *file,
                          int line, int column,
                          void (*control)(void *, const char *), void *ctx,
                          void **instance, char *err, size_t errlen)
{
    rbs_renderer_config c;
    memset(&c, 0, sizeof c);
    c.struct_size = sizeof c;
    c.type = "sdl";
    c.path = path;
    c.every = 1;
    c.json = json;
    c.file = file;
    c.line = line;
    c.column = column;
    c.control = control;
    c.control_context = ctx;
    err[0] = '\0';
    return rbsf_sdl_class()->create(NULL, &c, NULL, instance, err, errlen);
}

rbs_status tu_create(const char *json, const char *path, void **instance,
                     char *err, size_t errlen)
{
    return tu_create_full(json, path, NULL, 0, 0, NULL, NULL, instance, err, errlen);
}

SDL_Surface *tu_load(const char *path)
{
    SDL_Surface *raw = IMG_Load(path), *s;
    if (raw == NULL) return NULL;
    s = SDL_ConvertSurfaceFormat(raw, SDL_PIXELFORMAT_ARGB8888, 0);
    SDL_FreeSurface(raw);
    return s;
}

uint32_t tu_pixel(SDL_Surface *s, int x, int y)
{
    const uint32_t *row = (const uint32_t *)((const uint8_t *)s->pixels + (size_t)y * s->pitch);
    return row[x] & 0xffffffu;
}

double tu_hue(uint32_t rgb)
{
    double r = ((rgb >> 16) & 0xff) / 255.0, g = ((rgb >> 8) & 0xff) / 255.0,
           b = (rgb & 0xff) / 255.0;
    double mx = fmax(r, fmax(g, b)), mn = fmin(r, fmin(g, b)), d = mx - mn, h;
    if (d <= 0.0) return -1.0;
    if (mx == r) h = fmod((g - b) / d, 6.0);
    else if (mx == g) h = (b - r) / d + 2.0;
    else h = (r - g) / d + 4.0;
    h *= 60.0;
    return h < 0 ? h + 360.0 : h;
}

long tu_bbox(SDL_Surface *s, int x0, int y0, int w, int h,
             int (*match)(uint32_t rgb), int *xmin, int *ymin, int *xmax,
             int *ymax)
{
    long n = 0;
    int x, y;
    *xmin = *ymin = 1 << 30;
    *xmax = *ymax = -1;
    for (y = y0; y < y0 + h; y++)
        for (x = x0; x < x0 + w; x++)
            if (match(tu_pixel(s, x, y))) {
                n++;
                if (x < *xmin) *xmin = x;
                if (x > *xmax) *xmax = x;
                if (y < *ymin) *ymin = y;
                if (y > *ymax) *ymax = y;
            }
    return n;
}

int tu_project(const double eye[3], const double target[3], const double up[3],
               double fov, int W, int H, const double p[3], double *u,
               double *v, double *z)
{
    /* Camera axes: forward f, right s = f x up, true up u = s x f. */
    double f[3], s[3], uu[3], d[3], l, f_px;
    int i;
    for (i = 0; i < 3; i++) f[i] = target[i] - eye[i];
    l = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (i = 0; i < 3; i++) f[i] /= l;
    s[0] = f[1] * up[2] - f[2] * up[1];
    s[1] = f[2] * up[0] - f[0] * up[2];
    s[2] = f[0] * up[1] - f[1] * up[0];
    l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (i = 0; i < 3; i++) s[i] /= l;
    uu[0] = s[1] * f[2] - s[2] * f[1];
    uu[1] = s[2] * f[0] - s[0] * f[2];
    uu[2] = s[0] * f[1] - s[1] * f[0];
    for (i = 0; i < 3; i++) d[i] = p[i] - eye[i];
    *z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
    if (*z <= 0) return 0;
    f_px = (H / 2.0) / tan(fov * 3.14159265358979323846 / 360.0);
    *u = W / 2.0 + f_px * (d[0] * s[0] + d[1] * s[1] + d[2] * s[2]) / *z;
    *v = H / 2.0 - f_px * (d[0] * uu[0] + d[1] * uu[1] + d[2] * uu[2]) / *z;
    return 1;
}
