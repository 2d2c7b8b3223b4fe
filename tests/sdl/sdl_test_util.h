/*
 * sdl_test_util.h - helpers for the SDL renderer tests: frames built by hand
 * (no physics), a renderer driven through its class, PNG files read back
 * with IMG_Load, and the pinhole formulas written out independently of the
 * renderer.
 */
#ifndef RBSF_SDL_TEST_UTIL_H
#define RBSF_SDL_TEST_UTIL_H

#include <stddef.h>
#include <stdint.h>

#include <SDL.h>

#include "sdl_renderer.h"

#define TU_MAX_BODIES 16

/** A frame with room for TU_MAX_BODIES bodies. */
typedef struct tu_frame {
    rbs_frame frame;
    rbs_frame_body bodies[TU_MAX_BODIES];
} tu_frame;

/** Empty frame number k at time t. */
void tu_frame_init(tu_frame *f, uint64_t number, double time);
/** Add a sphere (identity orientation, no texture); returns its body. */
rbs_frame_body *tu_add_sphere(tu_frame *f, const char *name, double x, double y,
                              double z, double radius, uint32_t color);
/** Add a plane through p with normal n (checker texture). */
rbs_frame_body *tu_add_plane(tu_frame *f, double px, double py, double pz,
                             double nx, double ny, double nz, uint32_t color);

/** The output folder for a test: argv[1] (given by meson) / name. */
const char *tu_dir(const char *name);
void tu_set_base(const char *base);

/** Create an "sdl" renderer with this JSON entry and path (either may be
 * NULL); returns the status and fills err. */
rbs_status tu_create(const char *json, const char *path, void **instance,
                     char *err, size_t errlen);
/** Same with a file/line/column for messages and a control callback. */
rbs_status tu_create_full(const char *json, const char *path, const char *file,
                          int line, int column,
                          void (*control)(void *, const char *), void *ctx,
                          void **instance, char *err, size_t errlen);

/** Load a PNG as an ARGB8888 surface (NULL if it cannot be read). */
SDL_Surface *tu_load(const char *path);
/** Pixel (x, y) as 0xRRGGBB. */
uint32_t tu_pixel(SDL_Surface *s, int x, int y);
/** Hue of a 0xRRGGBB colour in degrees [0, 360); -1 for greys. */
double tu_hue(uint32_t rgb);

/** Bounding box of the pixels for which match(rgb) is true, in the
 * rectangle [x0, x0+w) x [y0, y0+h); returns the count (0: none). */
long tu_bbox(SDL_Surface *s, int x0, int y0, int w, int h,
             int (*match)(uint32_t rgb), int *xmin, int *ymin, int *xmax,
             int *ymax);

/** Pinhole projection of world point p for a camera at eye looking at
 * target with up, vertical fov (degrees) into a W x H image: writes u, v
 * (pixels, v down) and depth z; returns 0 if the point is behind. */
int tu_project(const double eye[3], const double target[3], const double up[3],
               double fov, int W, int H, const double p[3], double *u,
               double *v, double *z);

#endif
