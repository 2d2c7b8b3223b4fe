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

#ifdef __cplusplus
}
#endif

#endif /* RBSF_SDL_RENDERER_H */
