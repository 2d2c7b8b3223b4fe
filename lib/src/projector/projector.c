/*
 * projector.c - the film projector: a simulation thread steps the world and
 * captures frames into the reel; a renderer thread takes them out and hands
 * each to the attached renderers; any thread may send commands.
 *
 * Design.
 *  - The world belongs to the simulation thread from start to the end of
 *    wait; renderers see only frames (copies in the reel).  So start claims
 *    it (a flag in the world, compare-and-exchange) and wait gives it back
 *    after joining both threads: a second projector's start on the same
 *    world fails instead of stepping it from a second thread.
 *  - One mutex (mu) guards the control state (paused, show_until, speed,
 *    quit), the counters and the first error.  One condition (cond, on the
 *    monotonic clock) is broadcast on every change of that state: the
 *    simulation thread waits on it while paused, the renderer thread while
 *    pacing, command callers while their renderer command is pending, and
 *    rbs_projector_finished while the run lasts.  Every wait is in a loop on
 *    its predicate.
 *  - Quit and errors close the reel: a writer waiting for a slot wakes with
 *    RBS_E_CLOSED, the reader drains the frames already published and ends.
 *    So outputs are complete up to the last frame published, and no thread
 *    can wait forever.
 *  - Renderer commands (camera lines) must run on the renderer thread: the
 *    caller posts the line, kicks the reel so the reader wakes, and waits for
 *    the answer.
 *  - While paused, live renderers get the held (last drawn) frame again
 *    about 30 times a second so a window stays responsive; recorders never
 *    get a frame twice.
 */
#include "reel_internal.h"
#include "core/world_internal.h" /* rbs__world_claim, rbs__world_release */

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ERROR_MAX 1024
#define COMMAND_MAX 256
#define REPLY_MAX 512
#define HOLD_PERIOD (1.0 / 30.0) /* s between repeats while paused */
#define LIVE_MIN_PERIOD 0.1      /* s: a live view gets a frame at least this
                                    often even when behind */

typedef struct renderer {
    const rbs_renderer_class *cls;
    void *instance;
    int created;
    int live;
    uint32_t every;
    char label[160]; /* "csv renderer 'out.csv'" for messages */
} renderer;

struct rbs_projector {
    rbs_world *world;
    const rbs_renderer_registry *registry;
    rbs_projector_def def;
    double dt;
    uint32_t max_bodies;
    uint64_t first_frame; /* the world's step count at start */
    rbs_reel *reel;
    renderer renderers[RBS_RENDERERS_MAX];
    uint32_t count;
    int live_count;
    int usable; /* create succeeded */

    pthread_t sim_thread, ren_thread;
    int started, joined;

    pthread_mutex_t mu;
    pthread_cond_t cond;
    /* --- guarded by mu --- */
    int paused;
    uint64_t show_until;  /* while paused, frames up to this number may be
                             made and drawn (pause: the frame on display;
                             "step N" adds N, saturating at the last) */
    uint64_t frame_taken; /* the frame on display: the last one the renderer
                             thread took to draw */
    double speed;
    int pace_reset;       /* resume/speed: re-anchor the real-time clock */
    int quit;
    int sim_done, ren_done;
    int completed;        /* the last frame was drawn */
    rbs_status result;    /* first error, or RBS_OK */
    char error[ERROR_MAX];
    uint64_t captured, drawn, frame_drawn, substeps, rollbacks, collisions, work_limited;
    uint64_t floor_hit_steps, sweep_limited;
    uint64_t rounded_base;  /* the world's rbs_world_rounded_steps at the start */
    uint64_t rounded_steps; /* ... since, as of the last frame captured */
    double max_overlap;     /* the deepest step-end overlap so far, m */
    uint64_t frame_made; /* number of the last frame captured */
    double time_drawn, energy_initial, energy_last;
    double t_start, t_end;
    /* one renderer command in flight */
    int cmd_busy, cmd_pending, cmd_done;
    char cmd_line[COMMAND_MAX];
    char cmd_reply[REPLY_MAX];
    rbs_status cmd_status;
    /* --- end of mu --- */

    pthread_mutex_t direct_mu; /* serialises direct renderer commands */

    /* Renderer thread only. */
    rbs_frame hold;
    rbs_frame_body *hold_bodies;
    /* The header of the last frame taken (its bodies NULL): a run stopped
     * there (quit, a signal) still gives it to a recorder whose every K
     * left it out, as its last frame (draw_tail, into tail_bodies: room
     * for max_bodies, only when some recorder's every > 1). */
    rbs_frame tail;
    rbs_frame_body *tail_bodies;
    int have_tail;
    int have_hold;
};

/* ---------------------------------------------------------------------- */
/* Helpers                                                                */
/* ---------------------------------------------------------------------- */

static void set_error_locked(rbs_projector *p, rbs_status st, const char *fmt,
                             va_list ap)
{
    if (p->result != RBS_OK)
        return; /* the first error is the one to report */
    p->result = st;
    rbs__vsnprintf_c(p->error, sizeof p->error, fmt, ap);
}

/* Record an error and stop the run: close the reel, wake everyone. */
static void fail(rbs_projector *p, rbs_status st, const char *fmt, ...)
{
    va_list ap;
    pthread_mutex_lock(&p->mu);
    va_start(ap, fmt);
    set_error_locked(p, st, fmt, ap);
    va_end(ap);
    p->quit = 1;
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->mu);
    rbs_reel_close(p->reel);
}

/* Whether a renderer's return is an rbs_status (a renderer's own code is
 * not: the projector's calls must return one -- rbsim.h; draw's was
 * mapped, check's, create's, finish's and command's passed out as 42 or 99:
 * a probe of session 40). */
static int is_status(rbs_status st)
{
    return strcmp(rbs_status_name(st), "UNKNOWN") != 0;
}

/* Error text for a create-time failure (no threads yet). */
static void set_error(rbs_projector *p, rbs_status st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    set_error_locked(p, st, fmt, ap);
    va_end(ap);
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

/* Copy the first word of s into word (size n); return the rest, spaces
 * skipped. */
static const char *split_word(const char *s, char *word, size_t n)
{
    size_t i = 0;
    while (is_space(*s))
        s++;
    while (*s && !is_space(*s)) {
        if (i + 1 < n)
            word[i++] = *s;
        s++;
    }
    word[i] = '\0';
    while (is_space(*s))
        s++;
    return s;
}

static void reply_to(char *reply, size_t n, const char *fmt, ...)
{
    va_list ap;
    if (reply == NULL || n == 0)
        return;
    va_start(ap, fmt);
    rbs__vsnprintf_c(reply, n, fmt, ap);
    va_end(ap);
}

/* ---------------------------------------------------------------------- */
/* Definition                                                             */
/* ---------------------------------------------------------------------- */

void rbs_projector_def_init_sized(rbs_projector_def *def, size_t def_size)
{
    rbs_projector_def d;
    if (def == NULL || def_size < sizeof(uint32_t))
        return;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)(def_size < sizeof d ? def_size : sizeof d);
    d.steps = 0;
    d.reel_capacity = 64;
    d.policy = RBS_REEL_LOSSLESS;
    d.realtime = 0;
    d.speed = 1.0;
    d.start_paused = 0;
    d.pause_on_collision = 0;
    d.endless = 0;
    d.after_step = NULL;
    d.after_step_context = NULL;
    d.skip_first_frame = 0;
    d.continued = 0;
    memcpy(def, &d, d.struct_size);
}

/* ---------------------------------------------------------------------- */
/* Creation                                                               */
/* ---------------------------------------------------------------------- */

static void control_hook(void *context, const char *command)
{
    rbs_projector_command((rbs_projector *)context, command, NULL, 0);
}

/* The i-th config of the caller's array, whose element size is the
 * struct_size the caller's header gave (older callers: shorter, the rest
 * zero; newer: longer, the rest ignored).  -1 if struct_size is not set. */
static int config_at(const rbs_renderer_config *configs, uint32_t i,
                     rbs_renderer_config *out)
{
    size_t stride = configs[0].struct_size;
    const unsigned char *base = (const unsigned char *)configs;
    memset(out, 0, sizeof *out);
    if (stride < offsetof(rbs_renderer_config, control))
        return -1;
    memcpy(out, base + (size_t)i * stride,
           stride < sizeof *out ? stride : sizeof *out);
    if (out->struct_size != stride)
        return -1;
    out->struct_size = (uint32_t)sizeof *out;
    return 0;
}

static void label_renderer(renderer *r, const rbs_renderer_config *c)
{
    char where[96] = "";
    if (c->file != NULL && c->line > 0)
        snprintf(where, sizeof where, "%s:%d:%d: ", c->file, (int)c->line,
                 (int)c->column);
    if (c->path != NULL)
        snprintf(r->label, sizeof r->label, "%s%s renderer '%s'", where,
                 c->type, c->path);
    else
        snprintf(r->label, sizeof r->label, "%s%s renderer", where, c->type);
}

rbs_status rbs_projector_create(rbs_world *world,
                                const rbs_renderer_registry *registry,
                                const rbs_renderer_config *configs,
                                uint32_t count, const rbs_projector_def *def,
                                rbs_projector **out)
{
    rbs_projector *p;
    rbs_world_def wd;
    rbs_reel_policy policy;
    pthread_condattr_t attr;
    rbs_renderer_config cfg[RBS_RENDERERS_MAX];
    char err[ERROR_MAX - 200];
    rbs_status st;
    uint32_t i;

    if (out == NULL)
        return RBS_E_INVALID;
    *out = NULL;
    if (world == NULL || def == NULL || count > RBS_RENDERERS_MAX ||
        (count > 0 && (configs == NULL || registry == NULL)) ||
        def->struct_size < offsetof(rbs_projector_def, pause_on_collision))
        return RBS_E_INVALID;
    rbs_world_def_init(&wd);
    if (rbs_world_get_def(world, &wd) != RBS_OK)
        return RBS_E_INVALID;

    p = calloc(1, sizeof *p);
    if (p == NULL)
        return RBS_E_MEMORY;
    rbs_projector_def_init(&p->def);
    memcpy(&p->def, def,
           def->struct_size < sizeof p->def ? def->struct_size : sizeof p->def);
    p->def.struct_size = (uint32_t)sizeof p->def;
    p->world = world;
    p->registry = registry;
    p->dt = wd.dt;
    p->max_bodies = wd.max_bodies;
    p->speed = p->def.speed;
    p->paused = 0;
    p->result = RBS_OK;

    if (pthread_mutex_init(&p->mu, NULL) != 0) {
        free(p);
        return RBS_E_MEMORY;
    }
    if (pthread_mutex_init(&p->direct_mu, NULL) != 0) {
        pthread_mutex_destroy(&p->mu);
        free(p);
        return RBS_E_MEMORY;
    }
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    if (pthread_cond_init(&p->cond, &attr) != 0) {
        pthread_condattr_destroy(&attr);
        pthread_mutex_destroy(&p->direct_mu);
        pthread_mutex_destroy(&p->mu);
        free(p);
        return RBS_E_MEMORY;
    }
    pthread_condattr_destroy(&attr);
    *out = p;

    /* Check the definition. */
    if (p->def.reel_capacity < 2) {
        set_error(p, RBS_E_INVALID, "reel capacity must be >= 2, got %lu",
                  (unsigned long)p->def.reel_capacity);
        return RBS_E_INVALID;
    }
    if (!(p->def.speed > 0) || !isfinite(p->def.speed)) {
        char nb[32];
        set_error(p, RBS_E_INVALID, "speed must be > 0 and finite, got %s",
                  rbs__shortest(nb, p->def.speed));
        return RBS_E_INVALID;
    }
    if (p->def.policy != RBS_REEL_LOSSLESS &&
        p->def.policy != RBS_REEL_LATEST_ONLY) {
        set_error(p, RBS_E_INVALID, "unknown reel policy %d",
                  (int)p->def.policy);
        return RBS_E_INVALID;
    }

    /* Find every renderer type, then check every configuration, before
     * creating any: a rejected run writes nothing. */
    for (i = 0; i < count; i++) {
        const rbs_renderer_config *c = &cfg[i];
        renderer *r = &p->renderers[i];
        if (config_at(configs, i, &cfg[i]) != 0) {
            set_error(p, RBS_E_INVALID,
                      "renderer %lu: struct_size is not set (use "
                      "sizeof(rbs_renderer_config))",
                      (unsigned long)i);
            return RBS_E_INVALID;
        }
        if (c->type == NULL) {
            set_error(p, RBS_E_INVALID, "renderer %lu: no type",
                      (unsigned long)i);
            return RBS_E_INVALID;
        }
        label_renderer(r, c);
        if (rbs_renderer_find(registry, c->type, &r->cls) != RBS_OK) {
            set_error(p, RBS_E_NOT_FOUND, "%s: unknown renderer type '%s'",
                      r->label, c->type);
            return RBS_E_NOT_FOUND;
        }
        if (c->every > RBS_EVERY_MAX) {
            set_error(p, RBS_E_INVALID,
                      "%s: every must be from 1 to %lu (0 means 1), got %lu",
                      r->label, (unsigned long)RBS_EVERY_MAX,
                      (unsigned long)c->every);
            return RBS_E_INVALID;
        }
        r->every = c->every == 0 ? 1 : c->every;
        r->live = (r->cls->flags & RBS_RENDERER_LIVE) != 0;
    }
    p->count = count;
    for (i = 0; i < count; i++) {
        renderer *r = &p->renderers[i];
        if (r->cls->check == NULL)
            continue;
        err[0] = '\0';
        st = r->cls->check(r->cls->context, &cfg[i], world, err, sizeof err);
        if (st != RBS_OK && !is_status(st)) {
            set_error(p, RBS_E_RENDERER, "%s: check returned %d, not an rbs_status%s%s", r->label,
                      (int)st, err[0] ? ": " : "", err);
            return RBS_E_RENDERER;
        }
        if (st != RBS_OK) {
            set_error(p, st, "%s: %s", r->label,
                      err[0] ? err : rbs_status_string(st));
            return st;
        }
    }

    /* Create the renderers; each gets the control hook. */
    for (i = 0; i < count; i++) {
        renderer *r = &p->renderers[i];
        rbs_renderer_config c = cfg[i];
        c.control = control_hook;
        c.control_context = p;
        err[0] = '\0';
        st = r->cls->create(r->cls->context, &c, world, &r->instance, err,
                            sizeof err);
        if (st != RBS_OK && !is_status(st)) {
            set_error(p, RBS_E_RENDERER, "%s: create returned %d, not an rbs_status%s%s", r->label,
                      (int)st, err[0] ? ": " : "", err);
            return RBS_E_RENDERER;
        }
        if (st != RBS_OK) {
            set_error(p, st, "%s: %s", r->label,
                      err[0] ? err : rbs_status_string(st));
            return st;
        }
        r->created = 1;
        if (r->live)
            p->live_count++;
    }

    /* The reel: latest-only only when nobody records. */
    policy = p->def.policy;
    if (p->live_count != (int)count || count == 0)
        policy = RBS_REEL_LOSSLESS;
    st = rbs_reel_create(p->def.reel_capacity, p->max_bodies, policy, &p->reel);
    if (st != RBS_OK) {
        /* (the size and the way out: "out of memory or buffer too small"
         * alone left a user of the largest reel_capacity guessing) */
        double bytes = (double)p->def.reel_capacity *
                       ((double)sizeof(rbs_frame) +
                        (double)p->max_bodies * (double)sizeof(rbs_frame_body));
        set_error(p, st, "cannot make a reel of %lu frames of %lu bodies (%.3g MB): %s%s",
                  (unsigned long)p->def.reel_capacity,
                  (unsigned long)p->max_bodies, bytes / 1e6,
                  st == RBS_E_MEMORY ? "out of memory" : rbs_status_string(st),
                  st == RBS_E_MEMORY || st == RBS_E_CAPACITY
                      ? "; a reel of fewer frames (reel_capacity) needs less"
                      : "");
        return st;
    }
    if (p->live_count > 0) {
        p->hold_bodies = calloc(p->max_bodies, sizeof *p->hold_bodies);
        if (p->hold_bodies == NULL) {
            set_error(p, RBS_E_MEMORY, "out of memory");
            return RBS_E_MEMORY;
        }
    }
    {
        uint32_t k;
        for (k = 0; k < p->count; k++)
            if (!p->renderers[k].live && p->renderers[k].every > 1)
                break;
        if (k < p->count) {
            p->tail_bodies = calloc(p->max_bodies, sizeof *p->tail_bodies);
            if (p->tail_bodies == NULL) {
                set_error(p, RBS_E_MEMORY, "out of memory");
                return RBS_E_MEMORY;
            }
        }
    }
    p->usable = 1;
    return RBS_OK;
}

/* ---------------------------------------------------------------------- */
/* Simulation thread                                                      */
/* ---------------------------------------------------------------------- */

/* Capture the world into the next slot and publish it.  Returns 0 to go on,
 * -1 to stop (closed or failed). */
static int publish(rbs_projector *p, const rbs_step_info *info, int last)
{
    rbs_frame *slot;
    rbs_status st;
    int paused;
    double speed;

    st = rbs_reel_begin_write(p->reel, &slot);
    if (st != RBS_OK)
        return -1; /* closed: quit or an error */
    st = rbs_frame_capture(p->world, slot, p->max_bodies);
    if (st != RBS_OK) {
        /* Say which part of the capture failed. */
        const char *why = rbs_world_last_error(p->world);
        rbs_energy e;
        rbs_vec3 lin, ang;
        const char *what =
            rbs_world_energy(p->world, &e) != RBS_OK           ? "energy: "
            : rbs_world_momentum(p->world, &lin, &ang) != RBS_OK ? "momentum: "
                                                                 : "";
        char tb[40], body[200];
        if (what[0] == 'm') {
            /* which body's momentum overflowed, and what */
            rbs__momentum_failure(p->world, body, sizeof body);
            why = body;
        }
        fail(p, st, "frame capture at t = %s s failed: %s%s%s%s",
             rbs__shortest(tb, rbs_world_time(p->world)), what, rbs_status_string(st),
             why && why[0] ? ": " : "", why ? why : "");
        rbs_reel_end_write(p->reel);
        return -1;
    }
    slot->stats.step = *info;
    slot->last = last;

    pthread_mutex_lock(&p->mu);
    if (p->def.pause_on_collision && info->colliding > 0 && !last) {
        p->paused = 1;
        p->show_until = slot->number; /* show up to this frame, then hold */
    }
    paused = p->paused && slot->number >= p->show_until && !last;
    speed = p->speed;
    if (p->captured == 0 && !p->def.skip_first_frame)
        p->energy_initial = slot->stats.total;
    p->energy_last = slot->stats.total;
    p->captured++;
    p->frame_made = slot->number;
    p->substeps += info->substeps;
    p->rollbacks += info->rollbacks;
    p->collisions += info->colliding;
    p->work_limited += info->work_limit != 0;
    p->floor_hit_steps += info->floor_hits != 0;
    p->sweep_limited += info->sweep_limit != 0;
    p->rounded_steps = rbs_world_rounded_steps(p->world) - p->rounded_base;
    if (info->max_overlap > p->max_overlap)
        p->max_overlap = info->max_overlap;
    pthread_mutex_unlock(&p->mu);

    slot->paused = paused;
    slot->target_time = p->dt / speed;
    return rbs_reel_end_write(p->reel) == RBS_OK ? 0 : -1;
}

static void *sim_main(void *arg)
{
    rbs_projector *p = arg;
    rbs_step_info info;
    uint64_t k;
    const uint64_t steps = p->def.steps;
    const int endless = p->def.endless != 0;

    /* Frame 0 (the initial state) was published by rbs_projector_start. */
    for (k = 1; endless || k <= steps; k++) {
        rbs_status st;
        /* Wait while paused, unless "step N" allows this frame. */
        pthread_mutex_lock(&p->mu);
        while (!p->quit && p->paused && p->first_frame + k > p->show_until)
            pthread_cond_wait(&p->cond, &p->mu);
        if (p->quit) {
            pthread_mutex_unlock(&p->mu);
            break;
        }
        pthread_mutex_unlock(&p->mu);

        memset(&info, 0, sizeof info);
        st = rbs_world_step(p->world, &info);
        if (st != RBS_OK) {
            const char *why = rbs_world_last_error(p->world);
            char tb[40];
            fail(p, st, "step %llu (t = %s s) failed: %s%s%s",
                 (unsigned long long)rbs_world_step_count(p->world) + 1,
                 rbs__shortest(tb, rbs_world_time(p->world)),
                 rbs_status_string(st), why && why[0] ? ": " : "",
                 why ? why : "");
            break;
        }
        if (publish(p, &info, !endless && k == steps) != 0)
            break;
        /* The caller's hook (e.g. a checkpoint), the frame now in the reel. */
        if (p->def.after_step != NULL) {
            char err[ERROR_MAX - 200];
            uint64_t frame = rbs_world_step_count(p->world);
            err[0] = '\0';
            st = p->def.after_step(p->def.after_step_context, p->world, frame,
                                   err, sizeof err);
            if (st != RBS_OK) {
                fail(p, st, "after frame %llu: %s", (unsigned long long)frame,
                     err[0] ? err : rbs_status_string(st));
                break;
            }
        }
    }

    /* No more frames: the reader drains what was published, then ends. */
    rbs_reel_close(p->reel);
    pthread_mutex_lock(&p->mu);
    p->sim_done = 1;
    if (p->sim_done && p->ren_done)
        p->t_end = rbs__now();
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

/* ---------------------------------------------------------------------- */
/* Renderer thread                                                        */
/* ---------------------------------------------------------------------- */

/* Offer a command line to every renderer (on the renderer thread, or with
 * the renderers otherwise idle). */
static rbs_status forward_command(rbs_projector *p, const char *line,
                                  char *out, size_t outlen)
{
    rbs_status result = RBS_E_NOT_FOUND;
    uint32_t i;
    if (out && outlen)
        out[0] = '\0';
    for (i = 0; i < p->count; i++) {
        renderer *r = &p->renderers[i];
        char buf[REPLY_MAX];
        rbs_status st;
        if (!r->created || r->cls->command == NULL)
            continue;
        buf[0] = '\0';
        st = r->cls->command(r->instance, line, buf, sizeof buf);
        if (st == RBS_E_NOT_FOUND)
            continue;
        if (st != RBS_OK && !is_status(st)) {
            snprintf(buf, sizeof buf, "%s: command returned %d, not an rbs_status", r->label, (int)st);
            st = RBS_E_RENDERER;
        }
        if (result == RBS_E_NOT_FOUND || (result == RBS_OK && st != RBS_OK)) {
            result = st;
            if (out && outlen)
                snprintf(out, outlen, "%s", buf);
        }
    }
    return result;
}

/* Run a posted renderer command, if any.  Renderer thread. */
static void serve_command(rbs_projector *p)
{
    char line[COMMAND_MAX], out[REPLY_MAX];
    rbs_status st;
    pthread_mutex_lock(&p->mu);
    if (!p->cmd_pending) {
        pthread_mutex_unlock(&p->mu);
        return;
    }
    memcpy(line, p->cmd_line, sizeof line);
    pthread_mutex_unlock(&p->mu);

    st = forward_command(p, line, out, sizeof out);

    pthread_mutex_lock(&p->mu);
    p->cmd_status = st;
    memcpy(p->cmd_reply, out, sizeof out);
    p->cmd_pending = 0;
    p->cmd_done = 1;
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->mu);
}

/* Whether recorder r leaves frame f out (its every K: rbs_frame_written,
 * reel.h; the last frame is kept unless the run is continued from it). */
static int every_skips(const rbs_projector *p, const renderer *r, const rbs_frame *f)
{
    return !r->live && !rbs_frame_written(f->number, r->every, p->first_frame,
                                          p->def.skip_first_frame, f->last,
                                          p->def.continued);
}

/* Draw one frame on the renderers that keep it.  Returns 0 or -1 (failed). */
/* Renderer r draws f.  0, or -1 after fail(). */
static int draw_one(rbs_projector *p, renderer *r, const rbs_frame *f)
{
    char err[ERROR_MAX - 200];
    rbs_status st;
    err[0] = '\0';
    st = r->cls->draw(r->instance, f, err, sizeof err);
    if (st != RBS_OK && !is_status(st)) {
        /* not an rbs_status (a renderer's own code): the run's result
         * must be one */
        fail(p, RBS_E_RENDERER, "%s: frame %llu: draw returned %d, not an rbs_status%s%s",
             r->label, (unsigned long long)f->number, (int)st, err[0] ? ": " : "", err);
        return -1;
    }
    if (st != RBS_OK) {
        fail(p, st == RBS_E_INVALID ? RBS_E_RENDERER : st,
             "%s: frame %llu: %s", r->label,
             (unsigned long long)f->number,
             err[0] ? err : rbs_status_string(st));
        return -1;
    }
    return 0;
}

static int draw_frame(rbs_projector *p, const rbs_frame *f, int live_ok, int repeat)
{
    uint32_t i;
    for (i = 0; i < p->count; i++) {
        renderer *r = &p->renderers[i];
        if (repeat && !r->live)
            continue; /* recorders never get a frame twice */
        if (r->live && !live_ok)
            continue;
        if (!repeat && every_skips(p, r, f))
            continue;
        if (draw_one(p, r, f) != 0)
            return -1;
    }
    return 0;
}

/* The run stopped on a frame that some recorder's every K left out: that
 * recorder gets it now, as the run's last (the README's promise: an
 * interrupted run's last frame is kept).  Its bodies come from the world,
 * which the simulation thread, done, left at that frame (the header kept
 * when the frame was taken gives its step's counts); no frame is copied
 * while the run goes on.  0, or -1 after fail(). */
static int draw_tail(rbs_projector *p)
{
    rbs_frame f;
    uint32_t i;
    if (p->tail.last || p->def.continued)
        return 0; /* (the run ended: every recorder had it; or its next part
                   * goes on from here) */
    f = p->tail;
    f.bodies = p->tail_bodies;
    if (rbs_frame_capture(p->world, &f, p->max_bodies) != RBS_OK || f.number != p->tail.number)
        return 0; /* (not the frame taken: nothing to add) */
    f.stats.step = p->tail.stats.step;
    for (i = 0; i < p->count; i++) {
        renderer *r = &p->renderers[i];
        if (!every_skips(p, r, &p->tail))
            continue;
        f.last = 1;
        if (draw_one(p, r, &f) != 0)
            return -1;
    }
    return 0;
}

static void copy_to_hold(rbs_projector *p, const rbs_frame *f)
{
    p->hold = *f;
    p->hold.bodies = p->hold_bodies;
    memcpy(p->hold_bodies, f->bodies, f->body_count * sizeof *f->bodies);
    p->have_hold = 1;
}

/* Real time: wait until the frame is due.  Returns nonzero if the frame is
 * late by more than its own duration (live views may skip it). */
static int pace(rbs_projector *p, const rbs_frame *f, double *base_wall,
                double *base_sim, int *anchored)
{
    double due, now, speed;
    struct timespec ts;

    pthread_mutex_lock(&p->mu);
    if (p->pace_reset) {
        p->pace_reset = 0;
        *anchored = 0;
    }
    speed = p->speed;
    pthread_mutex_unlock(&p->mu);

    now = rbs__now();
    if (!*anchored) {
        *base_wall = now;
        *base_sim = f->time;
        *anchored = 1;
    }
    due = *base_wall + (f->time - *base_sim) / speed;
    if (now > due + f->target_time)
        return 1;
    /* Sleep until due, awake for quit, speed changes and commands. */
    pthread_mutex_lock(&p->mu);
    while (!p->quit && !p->pace_reset && rbs__now() < due) {
        if (p->cmd_pending) {
            pthread_mutex_unlock(&p->mu);
            serve_command(p);
            pthread_mutex_lock(&p->mu);
            continue;
        }
        ts = rbs__deadline_after(due - rbs__now());
        pthread_cond_timedwait(&p->cond, &p->mu, &ts);
    }
    pthread_mutex_unlock(&p->mu);
    return 0;
}

static void *ren_main(void *arg)
{
    rbs_projector *p = arg;
    int anchored = 0;
    double base_wall = 0, base_sim = 0, last_live = -1e300;
    uint32_t i;
    int drained = 0;

    for (;;) {
        const rbs_frame *f;
        struct timespec ts;
        rbs_status st;
        int paused, quit, late = 0;

        serve_command(p);
        pthread_mutex_lock(&p->mu);
        paused = p->paused;
        pthread_mutex_unlock(&p->mu);

        /* Wait for a frame; while paused with live views, repeat the held
         * frame now and then. */
        if (paused && p->live_count > 0 && p->have_hold) {
            ts = rbs__deadline_after(HOLD_PERIOD);
            st = rbs__reel_read_until(p->reel, &ts, &f);
        } else {
            st = rbs__reel_read_until(p->reel, NULL, &f);
        }
        if (st == RBS_E_NOT_FOUND) {
            /* Timed out or kicked (a command is waiting). */
            if (paused && p->live_count > 0 && p->have_hold) {
                p->hold.paused = 1;
                if (draw_frame(p, &p->hold, 1, 1) != 0)
                    break;
            }
            anchored = 0; /* re-anchor the clock after a pause */
            continue;
        }
        if (st != RBS_OK) {
            drained = 1;
            break; /* closed and drained */
        }

        pthread_mutex_lock(&p->mu);
        quit = p->quit;
        pthread_mutex_unlock(&p->mu);
        if (p->def.realtime && !quit)
            late = pace(p, f, &base_wall, &base_sim, &anchored);

        /* Paused: hold this frame back (the display stays on the frame
         * taken last) until resumed, stepped up to it, or quit; live views
         * get the held frame again meanwhile.  A latest-only reel may have
         * dropped the frames up to show_until: then the next one is shown. */
        {
            int waited = 0, failed = 0;
            pthread_mutex_lock(&p->mu);
            while (!p->quit && p->paused && f->number > p->show_until &&
                   p->frame_taken >= p->show_until) {
                waited = 1;
                if (p->cmd_pending) {
                    pthread_mutex_unlock(&p->mu);
                    serve_command(p);
                    pthread_mutex_lock(&p->mu);
                    continue;
                }
                if (p->live_count > 0 && p->have_hold) {
                    ts = rbs__deadline_after(HOLD_PERIOD);
                    if (pthread_cond_timedwait(&p->cond, &p->mu, &ts) ==
                        ETIMEDOUT) {
                        pthread_mutex_unlock(&p->mu);
                        p->hold.paused = 1;
                        failed = draw_frame(p, &p->hold, 1, 1) != 0;
                        pthread_mutex_lock(&p->mu);
                        if (failed)
                            break;
                    }
                } else {
                    pthread_cond_wait(&p->cond, &p->mu);
                }
            }
            p->frame_taken = f->number;
            if (waited)
                p->pace_reset = 0; /* anchored at this frame, below */
            pthread_mutex_unlock(&p->mu);
            if (failed) {
                rbs_reel_end_read(p->reel);
                break;
            }
            if (waited && p->def.realtime) {
                base_wall = rbs__now();
                base_sim = f->time;
                anchored = 1;
                late = 0;
            }
        }
        {
            /* Live views skip late frames, but not all of them. */
            double now = rbs__now();
            int live_ok = !late || f->last || now - last_live >= LIVE_MIN_PERIOD;
            if (live_ok && p->live_count > 0)
                last_live = now;
            if (draw_frame(p, f, live_ok, 0) != 0) {
                rbs_reel_end_read(p->reel);
                break;
            }
        }
        if (p->live_count > 0)
            copy_to_hold(p, f);
        if (p->tail_bodies != NULL) {
            /* (the header only: draw_tail takes the bodies from the world) */
            p->tail = *f;
            p->tail.bodies = NULL;
            p->have_tail = 1;
        }

        pthread_mutex_lock(&p->mu);
        p->drawn++;
        p->frame_drawn = f->number;
        p->time_drawn = f->time;
        if (f->last)
            p->completed = 1;
        pthread_mutex_unlock(&p->mu);
        rbs_reel_end_read(p->reel);
    }

    if (drained && p->have_tail)
        (void)draw_tail(p);

    /* Finish every renderer (flush, close), even after a failure, so each
     * output is complete up to its last frame. */
    for (i = 0; i < p->count; i++) {
        renderer *r = &p->renderers[i];
        char err[ERROR_MAX - 200];
        rbs_status st;
        if (!r->created || r->cls->finish == NULL)
            continue;
        err[0] = '\0';
        st = r->cls->finish(r->instance, err, sizeof err);
        if (st != RBS_OK && !is_status(st))
            fail(p, RBS_E_RENDERER, "%s: finish returned %d, not an rbs_status%s%s", r->label, (int)st,
                 err[0] ? ": " : "", err);
        else if (st != RBS_OK)
            fail(p, st == RBS_E_INVALID ? RBS_E_RENDERER : st, "%s: %s",
                 r->label, err[0] ? err : rbs_status_string(st));
    }

    rbs_reel_close(p->reel); /* a failed renderer stops the simulation */
    pthread_mutex_lock(&p->mu);
    p->ren_done = 1;
    /* A pending renderer command gets no answer now. */
    if (p->cmd_pending) {
        p->cmd_pending = 0;
        p->cmd_done = 1;
        p->cmd_status = RBS_E_CLOSED;
        snprintf(p->cmd_reply, sizeof p->cmd_reply, "the run is over");
    }
    if (p->sim_done && p->ren_done)
        p->t_end = rbs__now();
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

/* ---------------------------------------------------------------------- */
/* Control                                                                */
/* ---------------------------------------------------------------------- */

rbs_status rbs_projector_start(rbs_projector *p)
{
    int ok;
    if (p == NULL)
        return RBS_E_INVALID;
    /* Commands may come from other threads already (a signal's "quit"). */
    pthread_mutex_lock(&p->mu);
    ok = p->usable && !p->started;
    if (ok && rbs__world_claim(p->world) != 0) {
        /* (not the run's error: this projector may start once that run is
         * over, and then its result must be its own) */
        snprintf(p->error, sizeof p->error,
                 "the world is in use by another projector's run (from its "
                 "rbs_projector_start until its rbs_projector_wait returns): "
                 "one run of a world at a time");
        pthread_mutex_unlock(&p->mu);
        return RBS_E_INVALID;
    }
    if (ok) {
        if (p->result == RBS_OK)
            p->error[0] = '\0'; /* (a refused start's message) */
        p->first_frame = rbs_world_step_count(p->world);
        p->frame_taken = p->show_until = p->first_frame;
        /* (what status says until a frame is drawn: the world's own frame,
         * not 0 -- a resumed run's starts at its checkpoint's) */
        p->frame_drawn = p->first_frame;
        p->frame_made = p->first_frame;
        p->time_drawn = rbs_world_time(p->world);
        p->rounded_base = rbs_world_rounded_steps(p->world);
        if (p->def.start_paused)
            p->paused = 1;
        p->t_start = rbs__now();
        p->started = 1;
    }
    pthread_mutex_unlock(&p->mu);
    if (!ok)
        return RBS_E_INVALID;

    /* Frame 0, the initial state, on the caller's thread (the world is
     * still the caller's): when start returns it is in the reel, so a run
     * started paused is paused after frame 0.  A world that has stepped
     * already (a checkpoint) starts at its step count; with
     * skip_first_frame that frame is not published at all. */
    p->first_frame = rbs_world_step_count(p->world);
    if (p->def.skip_first_frame) {
        rbs_energy e;
        pthread_mutex_lock(&p->mu);
        if (rbs_world_energy(p->world, &e) == RBS_OK)
            p->energy_initial = p->energy_last = e.total;
        pthread_mutex_unlock(&p->mu);
    } else {
        rbs_step_info none;
        memset(&none, 0, sizeof none);
        if (publish(p, &none, !p->def.endless && p->def.steps == 0) != 0) {
            rbs_status st;
            pthread_mutex_lock(&p->mu);
            p->sim_done = p->ren_done = 1; /* no threads: over already */
            p->t_end = rbs__now();
            st = p->result;
            pthread_mutex_unlock(&p->mu);
            p->joined = 1;
            rbs__world_release(p->world);
            return st != RBS_OK ? st : RBS_E_CLOSED;
        }
    }

    pthread_mutex_lock(&p->mu); /* the renderer thread id, before anyone reads it */
    ok = pthread_create(&p->ren_thread, NULL, ren_main, p) == 0;
    if (!ok) {
        p->started = 0;
        p->sim_done = p->ren_done = 0;
        set_error(p, RBS_E_MEMORY, "cannot start the renderer thread");
    }
    pthread_mutex_unlock(&p->mu);
    if (!ok) {
        rbs__world_release(p->world);
        return RBS_E_MEMORY;
    }
    if (pthread_create(&p->sim_thread, NULL, sim_main, p) != 0) {
        /* Stop the renderer thread we started, then report: the run is
         * over (done, with this error). */
        fail(p, RBS_E_MEMORY, "cannot start the simulation thread");
        pthread_join(p->ren_thread, NULL);
        pthread_mutex_lock(&p->mu);
        p->sim_done = 1;
        pthread_mutex_unlock(&p->mu);
        p->joined = 1;
        rbs__world_release(p->world);
        return RBS_E_MEMORY;
    }
    return RBS_OK;
}

static void status_locked(rbs_projector *p, rbs_run_info *info)
{
    memset(info, 0, sizeof *info);
    info->state = !p->started ? RBS_RUN_READY
                  : (p->sim_done && p->ren_done) ? RBS_RUN_DONE
                                                 : RBS_RUN_RUNNING;
    info->result = p->result;
    if (info->state == RBS_RUN_DONE && p->result == RBS_OK && !p->completed)
        info->result = RBS_E_CLOSED;
    info->paused = p->paused;
    info->quit = p->quit;
    info->realtime = p->def.realtime;
    info->speed = p->speed;
    info->steps = p->def.steps;
    info->endless = p->def.endless;
    info->captured = p->captured;
    info->frame = p->frame_drawn;
    info->time = p->time_drawn;
    info->drawn = p->drawn;
    info->substeps = p->substeps;
    info->rollbacks = p->rollbacks;
    info->collisions = p->collisions;
    info->work_limited = p->work_limited;
    info->floor_hit_steps = p->floor_hit_steps;
    info->sweep_limited = p->sweep_limited;
    info->rounded_steps = p->rounded_steps;
    info->max_overlap = p->max_overlap;
    info->energy_initial = p->energy_initial;
    info->energy_last = p->energy_last;
    if (p->started)
        info->wall_time = (info->state == RBS_RUN_DONE ? p->t_end : rbs__now()) -
                          p->t_start;
}

rbs_status rbs_projector_status_sized(rbs_projector *p, rbs_run_info *out,
                                      size_t out_size)
{
    rbs_run_info info;
    if (p == NULL || out == NULL || out_size == 0)
        return RBS_E_INVALID;
    pthread_mutex_lock(&p->mu);
    status_locked(p, &info);
    pthread_mutex_unlock(&p->mu);
    info.dropped = p->reel ? rbs_reel_dropped(p->reel) : 0;
    memcpy(out, &info, out_size < sizeof info ? out_size : sizeof info);
    return RBS_OK;
}

/* Parse a whole unsigned decimal number. */
static int parse_count(const char *s, uint64_t *out)
{
    char *end;
    unsigned long long v;
    if (*s < '0' || *s > '9')
        return -1;
    errno = 0;
    v = strtoull(s, &end, 10);
    while (is_space(*end))
        end++;
    if (errno != 0 || *end != '\0')
        return -1;
    *out = (uint64_t)v;
    return 0;
}

static rbs_status renderer_command(rbs_projector *p, const char *line,
                                   char *reply, size_t reply_size)
{
    rbs_status st;
    int on_renderer_thread, running;

    pthread_mutex_lock(&p->mu);
    running = p->started && !p->ren_done;
    on_renderer_thread = running && pthread_equal(pthread_self(), p->ren_thread);
    pthread_mutex_unlock(&p->mu);

    if (!running || on_renderer_thread) {
        /* No renderer thread to disturb (or we are it): call directly. */
        char out[REPLY_MAX];
        pthread_mutex_lock(&p->direct_mu);
        st = forward_command(p, line, out, sizeof out);
        pthread_mutex_unlock(&p->direct_mu);
        if (st == RBS_E_NOT_FOUND)
            reply_to(reply, reply_size, "unknown command '%s'", line);
        else
            reply_to(reply, reply_size, "%s", out);
        return st;
    }

    /* Post the line to the renderer thread and wait for its answer. */
    pthread_mutex_lock(&p->mu);
    while (p->cmd_busy && !p->ren_done)
        pthread_cond_wait(&p->cond, &p->mu);
    if (p->ren_done) {
        pthread_mutex_unlock(&p->mu);
        reply_to(reply, reply_size, "the run is over");
        return RBS_E_CLOSED;
    }
    p->cmd_busy = 1;
    p->cmd_pending = 1;
    p->cmd_done = 0;
    snprintf(p->cmd_line, sizeof p->cmd_line, "%s", line);
    pthread_cond_broadcast(&p->cond); /* out of a pacing sleep */
    pthread_mutex_unlock(&p->mu);
    rbs__reel_kick(p->reel); /* out of a wait for frames */

    pthread_mutex_lock(&p->mu);
    while (!p->cmd_done)
        pthread_cond_wait(&p->cond, &p->mu);
    st = p->cmd_status;
    if (st == RBS_E_NOT_FOUND)
        reply_to(reply, reply_size, "unknown command '%s'", line);
    else
        reply_to(reply, reply_size, "%s", p->cmd_reply);
    p->cmd_busy = 0;
    p->cmd_done = 0;
    pthread_cond_broadcast(&p->cond);
    pthread_mutex_unlock(&p->mu);
    return st;
}

rbs_status rbs_projector_command(rbs_projector *p, const char *line,
                                 char *reply, size_t reply_size)
{
    char word[32];
    const char *rest;
    rbs_run_info info;
    uint64_t held = 0;

    if (reply && reply_size)
        reply[0] = '\0';
    if (p == NULL || line == NULL)
        return RBS_E_INVALID;
    if (strlen(line) >= COMMAND_MAX) {
        reply_to(reply, reply_size, "command too long (at most %d bytes)",
                 COMMAND_MAX - 1);
        return RBS_E_INVALID;
    }
    rest = split_word(line, word, sizeof word);
    if (word[0] == '\0') {
        reply_to(reply, reply_size, "empty command");
        return RBS_E_INVALID;
    }

    if (strcmp(word, "pause") == 0 || strcmp(word, "resume") == 0 ||
        strcmp(word, "quit") == 0) {
        int pause = word[0] == 'p', quit = word[0] == 'q';
        if (*rest) {
            reply_to(reply, reply_size, "%s takes no argument", word);
            return RBS_E_INVALID;
        }
        pthread_mutex_lock(&p->mu);
        if (!quit && p->started && p->sim_done && p->ren_done) {
            /* (after the end there is nothing to hold or go on with: it
             * said "paused at frame K") */
            held = p->frame_drawn;
            pthread_mutex_unlock(&p->mu);
            reply_to(reply, reply_size, "the run is over (at frame %llu): nothing to %s",
                     (unsigned long long)held, word);
            return RBS_E_CLOSED;
        }
        if (!quit && p->paused == pause &&
            (!pause || p->show_until <= p->frame_taken)) {
            /* Nothing to change: say so, rather than "resumed at frame K"
             * for a run that was never paused, or "paused" twice (a probe
             * of session 47).  A pause during a step still holds it. */
            held = p->frame_taken;
            pthread_mutex_unlock(&p->mu);
            reply_to(reply, reply_size, "%s at frame %llu",
                     pause ? "already paused" : "not paused: running",
                     (unsigned long long)held);
            return RBS_OK;
        }
        if (quit) {
            p->quit = 1;
        } else {
            /* Pause holds the display at once: the frame on display is the
             * last one drawn (the simulation may be ahead, its frames wait
             * in the reel). */
            p->paused = pause;
            p->show_until = p->frame_taken;
            p->pace_reset = 1;
        }
        held = p->frame_taken;
        status_locked(p, &info);
        pthread_cond_broadcast(&p->cond);
        pthread_mutex_unlock(&p->mu);
        if (quit) {
            /* Stop after the frame being made: the simulation thread sees
             * quit before its next step, publishes the frame it is making
             * (the reader keeps draining, so it never waits for long) and
             * closes the reel.  So the world always ends at the last frame
             * published, and an after_step hook saw every frame.  Published
             * frames are still drawn. */
            reply_to(reply, reply_size, "quitting after the frame being made");
        } else {
            if (p->reel)
                rbs__reel_kick(p->reel);
            reply_to(reply, reply_size, "%s at frame %llu",
                     pause ? "paused" : "resumed", (unsigned long long)held);
        }
        return RBS_OK;
    }
    if (strcmp(word, "step") == 0) {
        uint64_t n = 1;
        if (*rest && (parse_count(rest, &n) != 0 || n == 0)) {
            reply_to(reply, reply_size,
                     "step: expected a whole number of frames >= 1, got '%s'",
                     rest);
            return RBS_E_INVALID;
        }
        {
            /* From where the display holds (or will hold after earlier
             * steps), saturating at the run's last frame (UINT64_MAX when
             * endless). */
            uint64_t base, end, to, last;
            pthread_mutex_lock(&p->mu);
            base = p->paused ? p->show_until : p->frame_taken;
            last = p->def.endless || p->first_frame > UINT64_MAX - p->def.steps
                       ? UINT64_MAX
                       : p->first_frame + p->def.steps;
            end = base >= last ? base : last;
            to = n > end - base ? end : base + n;
            p->paused = 1;
            p->show_until = to;
            pthread_cond_broadcast(&p->cond);
            pthread_mutex_unlock(&p->mu);
            if (to - base < n)
                reply_to(reply, reply_size,
                         "stepping %llu frame%s (asked %llu; the run ends at "
                         "frame %llu), then paused at frame %llu",
                         (unsigned long long)(to - base),
                         to - base == 1 ? "" : "s", (unsigned long long)n,
                         (unsigned long long)last, (unsigned long long)to);
            else
                reply_to(reply, reply_size,
                         "stepping %llu frame%s, then paused at frame %llu",
                         (unsigned long long)n, n == 1 ? "" : "s",
                         (unsigned long long)to);
        }
        return RBS_OK;
    }
    if (strcmp(word, "speed") == 0) {
        char *end;
        double x;
        errno = 0;
        x = rbs__strtod_c(rest, &end);
        while (is_space(*end))
            end++;
        /* (decimal only: strtod also reads "0x10" and "inf") */
        if (*rest == '\0' || *end != '\0' || errno != 0 || !isfinite(x) ||
            !(x > 0) || x > 1e6 || strpbrk(rest, "xXpP") != NULL) {
            reply_to(reply, reply_size,
                     "speed: expected a factor > 0 and <= 1e6, got '%s'", rest);
            return RBS_E_INVALID;
        }
        pthread_mutex_lock(&p->mu);
        p->speed = x;
        p->pace_reset = 1;
        pthread_cond_broadcast(&p->cond);
        pthread_mutex_unlock(&p->mu);
        reply_to(reply, reply_size, "speed %g%s", x,
                 p->def.realtime ? "" : " (used in real-time runs)");
        return RBS_OK;
    }
    if (strcmp(word, "status") == 0) {
        /* the frame shown, and how far the simulation has gone when it is
         * ahead (the counters are the simulation's, to its last frame) */
        char ahead[96] = "", capped[64] = "", of[40];
        uint64_t made;
        if (*rest) {
            /* (an argument was ignored: "status 3" answered as "status") */
            reply_to(reply, reply_size, "status takes no argument");
            return RBS_E_INVALID;
        }
        pthread_mutex_lock(&p->mu);
        status_locked(p, &info);
        made = p->frame_made;
        pthread_mutex_unlock(&p->mu);
        if (info.captured > 0 && made > info.frame)
            snprintf(ahead, sizeof ahead, " (counts to frame %llu, made ahead of the frame shown)",
                     (unsigned long long)made);
        if (info.work_limited > 0)
            snprintf(capped, sizeof capped, ", %llu steps at the work cap",
                     (unsigned long long)info.work_limited);
        /* the last frame's number; an endless run has none (it read "frame
         * 11584 of 0": its steps are ignored) */
        if (info.endless)
            snprintf(of, sizeof of, " (endless run)");
        else
            snprintf(of, sizeof of, " of %llu",
                     (unsigned long long)(p->first_frame + info.steps));
        reply_to(reply, reply_size,
                 "frame %llu%s, t = %.6g s, %s%s, speed %g, "
                 "%llu collisions, %llu sub-steps, %llu rollbacks%s%s",
                 (unsigned long long)info.frame, of, info.time,
                 info.state == RBS_RUN_READY   ? "not started"
                 : info.state == RBS_RUN_DONE  ? "done"
                 : info.paused                 ? "paused"
                                               : "running",
                 info.quit && info.state != RBS_RUN_DONE ? " (quitting)" : "",
                 info.speed, (unsigned long long)info.collisions,
                 (unsigned long long)info.substeps,
                 (unsigned long long)info.rollbacks, capped, ahead);
        return RBS_OK;
    }
    return renderer_command(p, line, reply, reply_size);
}

int32_t rbs_projector_finished(rbs_projector *p, double timeout)
{
    struct timespec ts;
    int done;
    if (p == NULL)
        return 1;
    ts = rbs__deadline_after(timeout > 0 ? timeout : 0);
    pthread_mutex_lock(&p->mu);
    if (!p->started) {
        pthread_mutex_unlock(&p->mu);
        return 0;
    }
    while (!(p->sim_done && p->ren_done) && timeout > 0 &&
           pthread_cond_timedwait(&p->cond, &p->mu, &ts) != ETIMEDOUT) {
    }
    done = p->sim_done && p->ren_done;
    pthread_mutex_unlock(&p->mu);
    return done;
}

rbs_status rbs_projector_wait(rbs_projector *p)
{
    rbs_run_info info;
    if (p == NULL || !p->started)
        return RBS_E_INVALID;
    if (!p->joined) {
        pthread_join(p->sim_thread, NULL);
        pthread_join(p->ren_thread, NULL);
        p->joined = 1;
        rbs__world_release(p->world); /* the caller's again */
    }
    rbs_projector_status(p, &info);
    return info.result;
}

rbs_status rbs_projector_run(rbs_projector *p)
{
    rbs_status st = rbs_projector_start(p);
    if (st != RBS_OK)
        return st;
    return rbs_projector_wait(p);
}

const char *rbs_projector_last_error(const rbs_projector *p)
{
    if (p == NULL)
        return "no projector";
    return p->error;
}

void rbs_projector_destroy(rbs_projector *p)
{
    uint32_t i;
    if (p == NULL)
        return;
    if (p->started && !p->joined) {
        rbs_projector_command(p, "quit", NULL, 0);
        rbs_projector_wait(p);
    }
    for (i = 0; i < p->count; i++)
        if (p->renderers[i].created && p->renderers[i].cls->destroy)
            p->renderers[i].cls->destroy(p->renderers[i].instance);
    rbs_reel_destroy(p->reel);
    free(p->hold_bodies);
    free(p->tail_bodies);
    pthread_cond_destroy(&p->cond);
    pthread_mutex_destroy(&p->direct_mu);
    pthread_mutex_destroy(&p->mu);
    free(p);
}
