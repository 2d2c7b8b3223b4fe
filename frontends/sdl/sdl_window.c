/*
 * sdl_window.c - the live window of the SDL renderer, on a thread of its own.
 *
 * Design notes.
 *  - Why a thread: the renderer is a recorder (every kept frame must reach
 *    its PNG files), so the projector calls draw() only when a frame comes;
 *    while the run is paused none comes.  A window polled from draw() would
 *    then freeze, and the space key could never resume the run.  So this
 *    thread owns everything SDL video: it starts the video subsystem, opens
 *    the windows, waits for their events (at most 30 ms at a time), and
 *    shows what the renderer publishes.  No other thread calls SDL video.
 *  - Shared state, all under one mutex (mu): the cameras (the renderer's
 *    draw() and command() use them too, through rbsf__window_lock), the
 *    shown images, the held frame, the flags.  control() is called without
 *    mu held, so a projector that answers on another thread cannot deadlock
 *    with us.
 *  - When the camera moves (keys, mouse), this thread draws the held frame
 *    again into the shown images with its own depth buffer, so the picture
 *    follows the camera even while the run is paused.
 *  - Memory: everything is reserved by rbsf__window_create() except the held
 *    frame's bodies, which grow (allocate) only when a frame has more bodies
 *    than any before; and what SDL allocates for its windows and events.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <SDL.h>

#include "c_locale.h"
#include "sdl_internal.h"

/* Window controls: degrees per arrow key and per dragged pixel, zoom per
 * key and per wheel notch, event wait (ms). */
static const double kKeyDegrees = 5.0;
static const double kDragDegrees = 0.4;
static const double kKeyZoom = 1.25;
static const double kWheelZoom = 1.1;
static const double kPi = 3.14159265358979323846;
static const int kWaitMs = 30;

struct rbsf__window {
    rbsf__window_def def;
    SDL_Thread *thread; /* an SDL thread: SDL frees its per-thread data */
    int thread_started;
    pthread_mutex_t mu;
    pthread_cond_t cond;

    /* Guarded by mu. */
    int state;         /* 0 starting, 1 running, -1 failed, 2 ended */
    char error[400];
    int stop;
    uint32_t *shown[RBSF__VIEWS_MAX]; /* image_w x image_h each */
    uint64_t published, presented;
    int camera_moved;
    rbs_frame held;
    rbs_frame_body *held_bodies;
    uint32_t held_capacity;
    int have_held;
    int paused, frame_paused;

    /* The thread's own (no lock needed). */
    SDL_Window *windows[RBSF__VIEWS_MAX];
    SDL_Surface *surfaces[RBSF__VIEWS_MAX]; /* over shown[] */
    uint32_t window_count;
    double *depth;
    double *ray_x, *ray_y;
    int drag;          /* 0 none, 1 orbit, 2 pan */
    uint32_t drag_view;
    uint32_t selected; /* view of the keys in a tiled window */
    int video_on;
};

rbs_status rbsf__window_create(const rbsf__window_def *def, rbsf__window **out)
{
    rbsf__window *w;
    uint32_t i;
    *out = NULL;
    w = (rbsf__window *)calloc(1, sizeof *w);
    if (w == NULL) return RBS_E_MEMORY;
    w->def = *def;
    for (i = 0; i < def->image_count; i++) {
        w->shown[i] = (uint32_t *)calloc((size_t)def->image_w[i] * def->image_h[i],
                                         sizeof *w->shown[i]);
        if (w->shown[i] == NULL) goto nomem;
    }
    w->depth = (double *)malloc((size_t)def->width * def->height * sizeof *w->depth);
    w->ray_x = (double *)malloc(def->width * sizeof *w->ray_x);
    w->ray_y = (double *)malloc(def->height * sizeof *w->ray_y);
    if (w->depth == NULL || w->ray_x == NULL || w->ray_y == NULL) goto nomem;
    if (pthread_mutex_init(&w->mu, NULL) != 0) goto nomem;
    if (pthread_cond_init(&w->cond, NULL) != 0) {
        pthread_mutex_destroy(&w->mu);
        goto nomem;
    }
    *out = w;
    return RBS_OK;
nomem:
    for (i = 0; i < RBSF__VIEWS_MAX; i++) free(w->shown[i]);
    free(w->depth);
    free(w->ray_x);
    free(w->ray_y);
    free(w);
    return RBS_E_MEMORY;
}

void rbsf__window_lock(rbsf__window *w) { pthread_mutex_lock(&w->mu); }
void rbsf__window_moved(rbsf__window *w) { w->camera_moved = 1; }
void rbsf__window_unlock(rbsf__window *w) { pthread_mutex_unlock(&w->mu); }

int rbsf__window_running(const rbsf__window *w)
{
    int running;
    pthread_mutex_lock((pthread_mutex_t *)&w->mu);
    running = w->state == 1;
    pthread_mutex_unlock((pthread_mutex_t *)&w->mu);
    return running;
}

static void send(rbsf__window *w, const char *command)
{
    if (w->def.control != NULL) w->def.control(w->def.control_context, command);
}

/* ------------------------------------------------------------------------- */
/* The thread                                                                */
/* ------------------------------------------------------------------------- */

static void close_windows(rbsf__window *w)
{
    uint32_t i;
    for (i = 0; i < RBSF__VIEWS_MAX; i++) {
        if (w->surfaces[i] != NULL) SDL_FreeSurface(w->surfaces[i]);
        if (w->windows[i] != NULL) SDL_DestroyWindow(w->windows[i]);
        w->surfaces[i] = NULL;
        w->windows[i] = NULL;
    }
    w->window_count = 0;
    if (w->video_on) SDL_QuitSubSystem(SDL_INIT_VIDEO);
    w->video_on = 0;
}

/* Whether the list SDL_VIDEODRIVER holds (names separated by commas, any
 * case, as SDL reads it) names drv. */
static int driver_named(const char *list, const char *drv)
{
    size_t n = strlen(drv);
    while (list != NULL && *list != '\0') {
        const char *end = strchr(list, ',');
        size_t len = end != NULL ? (size_t)(end - list) : strlen(list);
        if (len == n && strncasecmp(list, drv, n) == 0) return 1;
        list = end != NULL ? end + 1 : NULL;
    }
    return 0;
}

/* Start video and open the windows; 0 or -1 with w->error set. */
static int open_windows(rbsf__window *w)
{
    uint32_t i;
    /* SDL has one event queue per process, read by the thread that started
     * video: a second window thread would take the first one's events. */
    if (SDL_WasInit(SDL_INIT_VIDEO) != 0) {
        snprintf(w->error, sizeof w->error,
                 "window: SDL video is already in use in this process (one "
                 "window per run)");
        return -1;
    }
    if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
        snprintf(w->error, sizeof w->error, "window: cannot start SDL video: %s",
                 SDL_GetError());
        return -1;
    }
    w->video_on = 1;
    {
        /* With no display to reach, SDL falls back to a driver that shows
         * nothing ("offscreen", "dummy"): DISPLAY=:99 with no server opened
         * an invisible window, and "window": true ran as if shown.  Such a
         * driver is taken only when SDL_VIDEODRIVER names it (the tests
         * drive the window through "offscreen" so). */
        const char *drv = SDL_GetCurrentVideoDriver(), *asked = getenv("SDL_VIDEODRIVER");
        if (drv == NULL || ((strcmp(drv, "offscreen") == 0 || strcmp(drv, "dummy") == 0) &&
                            !driver_named(asked, drv))) {
            const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
            snprintf(w->error, sizeof w->error,
                     "window: no display answered (DISPLAY '%s', WAYLAND_DISPLAY '%s'): SDL "
                     "video fell back to its '%s' driver, which shows nothing",
                     x != NULL ? x : "", wl != NULL ? wl : "", drv != NULL ? drv : "(none)");
            return -1;
        }
    }
    for (i = 0; i < w->def.image_count; i++) {
        char title[64];
        int iw = (int)w->def.image_w[i], ih = (int)w->def.image_h[i];
        if (w->def.image_count > 1) snprintf(title, sizeof title, "rbsim - view %u", i);
        else snprintf(title, sizeof title, "rbsim");
        w->surfaces[i] = SDL_CreateRGBSurfaceWithFormatFrom(w->shown[i], iw, ih, 32, iw * 4,
                                                            SDL_PIXELFORMAT_ARGB8888);
        w->windows[i] = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED,
                                         SDL_WINDOWPOS_UNDEFINED, iw, ih, 0);
        if (w->surfaces[i] == NULL || w->windows[i] == NULL) {
            snprintf(w->error, sizeof w->error, "window: cannot open: %s", SDL_GetError());
            return -1;
        }
        /* Copy, do not blend: the pictures are opaque. */
        SDL_SetSurfaceBlendMode(w->surfaces[i], SDL_BLENDMODE_NONE);
        w->window_count = i + 1;
    }
    return 0;
}

static uint32_t window_index(const rbsf__window *w, Uint32 id)
{
    uint32_t i;
    for (i = 0; i < w->window_count; i++)
        if (SDL_GetWindowID(w->windows[i]) == id) return i;
    return 0;
}

/* The view under pixel (x, y) of window i. */
static uint32_t view_at(const rbsf__window *w, uint32_t i, int x, int y)
{
    uint32_t v;
    if (w->def.image_count > 1) return i;
    for (v = 0; v < w->def.views; v++)
        if (x >= (int)w->def.view_x[v] && x < (int)(w->def.view_x[v] + w->def.width) &&
            y >= (int)w->def.view_y[v] && y < (int)(w->def.view_y[v] + w->def.height))
            return v;
    return w->selected;
}

/* A camera reply in the title of the view's window (there is no console). */
static void title(rbsf__window *w, uint32_t view, rbs_status st, const char *reply)
{
    char text[320];
    uint32_t i = w->def.image_count > 1 ? view : 0;
    if (i >= w->window_count) return;
    if (st == RBS_OK) snprintf(text, sizeof text, "rbsim - view %u", view);
    else snprintf(text, sizeof text, "rbsim - view %u - %s", view, reply);
    SDL_SetWindowTitle(w->windows[i], text);
}

/* Move camera v: kind 0 orbit (a, b), 1 pan (a, b), 2 zoom (a), 3 reset. */
static void move(rbsf__window *w, uint32_t v, int kind, double a, double b)
{
    char reply[256] = "";
    rbs_status st;
    rbsf__camera *c;
    if (v >= w->def.views) return;
    pthread_mutex_lock(&w->mu);
    c = &w->def.cameras[v];
    if (kind == 0) {
        st = rbsf__camera_orbit(c, a, b, reply, sizeof reply);
    } else if (kind == 1) {
        /* a, b in pixels: metres per pixel at the target's distance. */
        double dx = c->position.x - c->target.x, dy = c->position.y - c->target.y,
               dz = c->position.z - c->target.z;
        double m = sqrt(dx * dx + dy * dy + dz * dz) * 2.0 *
                   tan(0.5 * c->fov * kPi / 180.0) / (double)w->def.height;
        st = rbsf__camera_pan(c, -m * a, m * b, reply, sizeof reply);
    } else if (kind == 2) {
        st = rbsf__camera_zoom(c, a, reply, sizeof reply);
    } else {
        st = rbsf__camera_reset(c, reply, sizeof reply);
    }
    if (st == RBS_OK) w->camera_moved = 1;
    pthread_mutex_unlock(&w->mu);
    title(w, v, st, reply);
}

static void handle(rbsf__window *w, const SDL_Event *e)
{
    uint32_t v;
    switch (e->type) {
    case SDL_QUIT:
        send(w, "quit");
        break;
    case SDL_WINDOWEVENT:
        if (e->window.event == SDL_WINDOWEVENT_CLOSE) send(w, "quit");
        if (e->window.event == SDL_WINDOWEVENT_EXPOSED) {
            pthread_mutex_lock(&w->mu);
            w->presented = w->published - 1; /* show again */
            pthread_mutex_unlock(&w->mu);
        }
        break;
    case SDL_KEYDOWN: {
        SDL_Keycode k = e->key.keysym.sym;
        uint32_t i = window_index(w, e->key.windowID);
        int paused;
        v = w->def.image_count > 1 ? i : w->selected;
        switch (k) {
        case SDLK_SPACE:
            pthread_mutex_lock(&w->mu);
            paused = w->paused;
            w->paused = !paused;
            pthread_mutex_unlock(&w->mu);
            send(w, paused ? "resume" : "pause");
            break;
        case SDLK_q:
        case SDLK_ESCAPE:
            send(w, "quit");
            break;
        case SDLK_LEFT: move(w, v, 0, -kKeyDegrees, 0); break;
        case SDLK_RIGHT: move(w, v, 0, kKeyDegrees, 0); break;
        case SDLK_UP: move(w, v, 0, 0, kKeyDegrees); break;
        case SDLK_DOWN: move(w, v, 0, 0, -kKeyDegrees); break;
        case SDLK_PLUS:
        case SDLK_EQUALS:
        case SDLK_KP_PLUS: move(w, v, 2, kKeyZoom, 0); break;
        case SDLK_MINUS:
        case SDLK_KP_MINUS: move(w, v, 2, 1.0 / kKeyZoom, 0); break;
        case SDLK_r: move(w, v, 3, 0, 0); break;
        case SDLK_1:
        case SDLK_2:
        case SDLK_3:
        case SDLK_4:
            if ((uint32_t)(k - SDLK_1) < w->def.views) w->selected = (uint32_t)(k - SDLK_1);
            break;
        default:
            break;
        }
        break;
    }
    case SDL_MOUSEBUTTONDOWN:
        w->drag = e->button.button == SDL_BUTTON_LEFT ? 1 : 2;
        w->drag_view = view_at(w, window_index(w, e->button.windowID), e->button.x,
                               e->button.y);
        break;
    case SDL_MOUSEBUTTONUP:
        w->drag = 0;
        break;
    case SDL_MOUSEMOTION:
        if (w->drag == 1)
            move(w, w->drag_view, 0, -kDragDegrees * e->motion.xrel,
                 kDragDegrees * e->motion.yrel);
        else if (w->drag == 2)
            move(w, w->drag_view, 1, e->motion.xrel, e->motion.yrel);
        break;
    case SDL_MOUSEWHEEL:
        v = view_at(w, window_index(w, e->wheel.windowID), 0, 0);
        move(w, v, 2, pow(kWheelZoom, (double)e->wheel.y), 0);
        break;
    default:
        break;
    }
}

/* Draw the held frame again with the current cameras (mu held). */
static void redraw(rbsf__window *w)
{
    uint32_t v;
    for (v = 0; v < w->def.views; v++) {
        rbsf__view view;
        rbsf__canvas cv;
        char err[256];
        uint32_t i = w->def.view_image[v];
        size_t pitch = w->def.image_w[i];
        if (rbsf__camera_view(&w->def.cameras[v], &w->held, w->def.width, w->def.height,
                              &view, err, sizeof err) != RBS_OK)
            continue; /* keep the last picture; draw() reports the error */
        cv.pixels = w->shown[i] + (size_t)w->def.view_y[v] * pitch + w->def.view_x[v];
        cv.pitch = pitch;
        cv.depth = w->depth;
        cv.ray_x = w->ray_x;
        cv.ray_y = w->ray_y;
        rbsf__raster_frame(&cv, &view, &w->held);
        rbsf__legend(cv.pixels, pitch, (int)w->def.width, (int)w->def.height, &w->held, v,
                     w->def.views);
    }
}

static void present(rbsf__window *w)
{
    uint32_t i;
    for (i = 0; i < w->window_count; i++) {
        SDL_Surface *ws = SDL_GetWindowSurface(w->windows[i]);
        if (ws == NULL) continue;
        SDL_BlitSurface(w->surfaces[i], NULL, ws, NULL);
        SDL_UpdateWindowSurface(w->windows[i]);
    }
}

static int SDLCALL window_main(void *arg)
{
    rbsf__window *w = (rbsf__window *)arg;
    rbsf__locale l;
    int ok;
    /* the legend and the camera replies in the titles, in the "C" locale
     * (a new thread has the process's) */
    rbsf__c_locale_push(&l);
    ok = open_windows(w) == 0;
    pthread_mutex_lock(&w->mu);
    w->state = ok ? 1 : -1;
    pthread_cond_broadcast(&w->cond);
    pthread_mutex_unlock(&w->mu);
    if (!ok) {
        close_windows(w);
        rbsf__c_locale_pop(&l);
        return 0;
    }
    for (;;) {
        SDL_Event e;
        int stop;
        /* Wait for input (or the time to look for a new picture). */
        if (SDL_WaitEventTimeout(&e, kWaitMs)) {
            handle(w, &e);
            while (SDL_PollEvent(&e)) handle(w, &e);
        }
        pthread_mutex_lock(&w->mu);
        stop = w->stop;
        if (!stop) {
            int show = 0;
            if (w->camera_moved && w->have_held) {
                redraw(w);
                show = 1;
            }
            w->camera_moved = 0;
            if (w->presented != w->published) {
                w->presented = w->published;
                show = 1;
            }
            if (show) present(w);
        }
        pthread_mutex_unlock(&w->mu);
        if (stop) break;
    }
    close_windows(w);
    pthread_mutex_lock(&w->mu);
    w->state = 2;
    pthread_mutex_unlock(&w->mu);
    rbsf__c_locale_pop(&l);
    return 0;
}

rbs_status rbsf__window_start(rbsf__window *w, char *err, size_t errlen)
{
    int state;
    w->thread = SDL_CreateThread(window_main, "rbsim-window", w);
    if (w->thread == NULL) {
        snprintf(w->error, sizeof w->error, "window: cannot start its thread: %s",
                 SDL_GetError());
        state = -1;
    } else {
        w->thread_started = 1;
        pthread_mutex_lock(&w->mu);
        while (w->state == 0) pthread_cond_wait(&w->cond, &w->mu);
        state = w->state;
        pthread_mutex_unlock(&w->mu);
    }
    if (state == 1) return RBS_OK;
    if (w->thread_started) {
        SDL_WaitThread(w->thread, NULL);
        w->thread_started = 0;
    }
    if (w->def.required) {
        if (err != NULL && errlen > 0) snprintf(err, errlen, "%s", w->error);
        return RBS_E_RENDERER;
    }
    fprintf(stderr, "rbsim: sdl renderer '%s': %s; writing PNG files only\n",
            w->def.label, w->error);
    return RBS_OK;
}

rbs_status rbsf__window_publish(rbsf__window *w, const uint32_t *const *pixels,
                                const size_t *pitch, const rbs_frame *frame)
{
    uint32_t i, y;
    rbs_status st = RBS_OK;
    pthread_mutex_lock(&w->mu);
    for (i = 0; i < w->def.image_count; i++)
        for (y = 0; y < w->def.image_h[i]; y++)
            memcpy(w->shown[i] + (size_t)y * w->def.image_w[i], pixels[i] + (size_t)y * pitch[i],
                   w->def.image_w[i] * sizeof *pixels[i]);
    w->published++;
    /* The pause state as the frames say, when they change their mind; the
     * space key flips it in between. */
    if ((frame->paused != 0) != w->frame_paused) {
        w->frame_paused = frame->paused != 0;
        w->paused = w->frame_paused;
    }
    /* Keep the frame for drawing it again when the camera moves. */
    if (frame->body_count > w->held_capacity) {
        rbs_frame_body *b = (rbs_frame_body *)realloc(
            w->held_bodies, (size_t)frame->body_count * sizeof *b);
        if (b == NULL) {
            st = RBS_E_MEMORY;
            w->have_held = 0;
        } else {
            w->held_bodies = b;
            w->held_capacity = frame->body_count;
        }
    }
    if (st == RBS_OK) {
        w->held = *frame;
        w->held.bodies = w->held_bodies;
        if (frame->body_count > 0)
            memcpy(w->held_bodies, frame->bodies, frame->body_count * sizeof *frame->bodies);
        w->have_held = 1;
    }
    pthread_mutex_unlock(&w->mu);
    return st;
}

void rbsf__window_destroy(rbsf__window *w)
{
    uint32_t i;
    if (w == NULL) return;
    if (w->thread_started) {
        pthread_mutex_lock(&w->mu);
        w->stop = 1;
        pthread_mutex_unlock(&w->mu);
        SDL_WaitThread(w->thread, NULL);
    }
    pthread_cond_destroy(&w->cond);
    pthread_mutex_destroy(&w->mu);
    for (i = 0; i < RBSF__VIEWS_MAX; i++) free(w->shown[i]);
    free(w->held_bodies);
    free(w->depth);
    free(w->ray_x);
    free(w->ray_y);
    free(w);
}
