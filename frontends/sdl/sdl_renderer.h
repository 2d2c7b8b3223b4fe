/*
 * sdl_renderer.h - the SDL2 front end of rbsim: a renderer type ("sdl") that
 * draws frames with software ray casting into SDL surfaces, writes them as
 * PNG files through SDL2_image, and shows them in a window when a display is
 * there.  See frontends/sdl/README.md for the scene keys and the pictures.
 *
 * Register it with rbs_renderer_register(registry, rbsf_sdl_class()).
 */
#ifndef RBSF_SDL_RENDERER_H
#define RBSF_SDL_RENDERER_H

#include "rbsim/reel.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The "sdl" renderer type: a constant table with static storage (never
 * NULL; its context is NULL).  Thread safety of the functions in it: create()
 * and destroy() may be called on any thread; draw(), finish() and command()
 * must be called on one thread at a time per instance (the projector's
 * renderer thread).  The instance owns SDL windows only when it opened them;
 * it never initialises SDL video when no display is there. */
const rbs_renderer_class *rbsf_sdl_class(void);

/** What the "sdl" renderer's check needs of the library to place its
 * cameras at the world's start (the renderer calls no library function
 * itself): rbs_world_state and rbs_frame_capture. */
typedef struct rbsf_sdl_world_api {
    rbs_status (*state)(const rbs_world *world, rbs_state_view *out);
    rbs_status (*capture)(const rbs_world *world, rbs_frame *frame,
                          uint32_t bodies_capacity);
    /* Optional (appended; NULL or zero: none): a PNG file's open() and its
     * write()s, which block on a FIFO no one reads or a pipe whose reader
     * stopped, are each done between enter(stopper) and leave(stopper,
     * slot), so that another thread can end them with a signal whose
     * handler does nothing (no SA_RESTART): the call fails with EINTR.
     * Then, if stopped(stopper) is nonzero, the file is given up (draw or
     * finish returns RBS_E_CLOSED, naming the file); before that, EINTR is
     * retried.  rbsim passes its signal thread's rbsf_stopper
     * (frontends/dump/dump.h), as for the csv, json and stats outputs. */
    void *stopper;
    int (*enter)(void *stopper);
    void (*leave)(void *stopper, int slot);
    int (*stopped)(void *stopper);
} rbsf_sdl_world_api;

/** rbsf_sdl_class() with api as its context (borrowed: it must outlive the
 * registry the class is registered in).  Its check then also refuses, before
 * the run, a camera placed from the spheres' bounding box that has no usable
 * view at the world's start ("view 0: position: not finite or beyond 1e100 m
 * at frame 0 (the default camera, ...)"); without it that stops the run at
 * its first frame. */
rbs_renderer_class rbsf_sdl_class_with(rbsf_sdl_world_api *api);

#ifdef __cplusplus
}
#endif

#endif /* RBSF_SDL_RENDERER_H */
