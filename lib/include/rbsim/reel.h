/*
 * rbsim/reel.h - the projector: frames, the reel (a bounded ring of frames
 * between a simulation thread and a renderer thread), the renderer factory and
 * the projector that runs both threads.
 *
 * The reel and the projector's command functions are the thread-safe objects
 * of rbsim; everything else follows the world's rule (one thread at a time).
 * lib/ knows no concrete renderer: CSV, JSON and SDL live in frontends/ and
 * register through rbs_renderer_register().
 */
#ifndef RBSIM_REEL_H
#define RBSIM_REEL_H

#include "rbsim/rbsim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most renderers attached to one run (the seed's limit). */
#define RBS_RENDERERS_MAX 4

/** One body in a frame: its physical representation and velocities. */
typedef struct rbs_frame_body {
    int32_t type;              /**< rbs_body_type */
    uint32_t color;            /**< 0xRRGGBB */
    int32_t texture;           /**< rbs_texture */
    uint32_t slot;
    const char *name;          /**< owned by the world, stable for the run */
    double position[3];        /**< sphere centre or plane point, m */
    double orientation[4];     /**< [w x y z] */
    double velocity[3];        /**< m/s */
    double angular_velocity[3];/**< rad/s */
    double normal[3];          /**< planes */
    double radius;             /**< spheres, m */
} rbs_frame_body;

/** What a user needs to judge a frame's step (the --stats columns). */
typedef struct rbs_frame_stats {
    double kinetic, potential, total; /**< J */
    double momentum[3];               /**< kg m/s */
    double angular_momentum[3];       /**< kg m^2/s, about the origin */
    rbs_step_info step;               /**< the step that made this frame */
} rbs_frame_stats;

/** A frame of the filmstrip. */
typedef struct rbs_frame {
    uint64_t number;        /**< k: the frame at t = k dt; 0 is the start */
    double time;            /**< simulated time, s */
    double target_time;     /**< wall time it should stay on screen, s */
    int32_t last;           /**< nonzero on the run's last frame */
    int32_t paused;         /**< nonzero if the run is paused at this frame */
    uint32_t body_count;
    rbs_frame_body *bodies; /**< body_count entries, owned by the reel */
    rbs_frame_stats stats;
} rbs_frame;

/** Fill a frame (bodies array of at least the world's slot count) from a
 * world: the glue between the core and the reel. */
RBS_API rbs_status rbs_frame_capture(const rbs_world *world, rbs_frame *frame,
                                     uint32_t bodies_capacity);

/* ------------------------------------------------------------------------- */
/* Reel                                                                      */
/* ------------------------------------------------------------------------- */

typedef enum rbs_reel_policy {
    RBS_REEL_LOSSLESS = 0,    /**< the writer waits for the reader */
    RBS_REEL_LATEST_ONLY = 1, /**< the writer overwrites unread frames */
    RBS_REEL_POLICY_FORCE32 = 0x7fffffff
} rbs_reel_policy;

typedef struct rbs_reel rbs_reel;

/** Create a reel of `capacity` frames (>= 2), each with room for
 * `max_bodies` bodies; all memory is reserved here. */
RBS_API rbs_status rbs_reel_create(uint32_t capacity, uint32_t max_bodies,
                                   rbs_reel_policy policy, rbs_reel **out);
RBS_API void rbs_reel_destroy(rbs_reel *reel);
/** Writer: get the next free slot (blocks in lossless mode while the ring is
 * full).  RBS_E_CLOSED if the reel was closed. */
RBS_API rbs_status rbs_reel_begin_write(rbs_reel *reel, rbs_frame **slot);
/** Writer: publish the slot got by rbs_reel_begin_write. */
RBS_API rbs_status rbs_reel_end_write(rbs_reel *reel);
/** Reader: wait for the next frame.  RBS_E_CLOSED once closed and drained. */
RBS_API rbs_status rbs_reel_begin_read(rbs_reel *reel, const rbs_frame **frame);
/** Reader: give the frame back. */
RBS_API rbs_status rbs_reel_end_read(rbs_reel *reel);
/** Close: no more frames; wakes every waiter.  Idempotent. */
RBS_API void rbs_reel_close(rbs_reel *reel);
/** Frames dropped by the latest-only policy so far. */
RBS_API uint64_t rbs_reel_dropped(rbs_reel *reel);

/* ------------------------------------------------------------------------- */
/* Renderer factory                                                          */
/* ------------------------------------------------------------------------- */

/** Configuration handed to a renderer type's create(). */
typedef struct rbs_renderer_config {
    uint32_t struct_size;
    const char *type;      /**< registered name */
    const char *path;      /**< output path (file or folder) or NULL */
    uint32_t every;        /**< keep every K-th frame (and always the last) */
    const char *json;      /**< the scene entry as JSON text, or NULL */
    const char *file;      /**< scene file for messages, or NULL */
    int32_t line, column;
    /** Filled by the projector: lets a renderer send a command line
     * ("quit", "pause", "resume", ...) back to the run, e.g. from a window's
     * keys.  Thread-safe; may be NULL outside a projector. */
    void (*control)(void *control_context, const char *command);
    void *control_context;
} rbs_renderer_config;

/** A renderer type: a flat table of functions plus a context pointer.
 * create() makes an instance; draw() is called on the renderer thread for
 * each frame kept; finish() after the last frame (flush, close files);
 * destroy() always.  Each returns RBS_OK or an error and may write a message
 * into err (errlen bytes). */
typedef struct rbs_renderer_class {
    uint32_t struct_size;
    const char *name; /**< unique; copied pointer must outlive the registry */
    void *context;    /**< passed to create() */
    rbs_status (*create)(void *context, const rbs_renderer_config *config,
                         const rbs_world *world, void **instance, char *err,
                         size_t errlen);
    rbs_status (*draw)(void *instance, const rbs_frame *frame, char *err,
                       size_t errlen);
    rbs_status (*finish)(void *instance, char *err, size_t errlen);
    void (*destroy)(void *instance);
    /** Optional (NULL if none): a command line for this renderer from the
     * input thread (e.g. "orbit 10 0", "zoom 0.5", "reset" for cameras).
     * Called on the renderer thread between frames.  Returns RBS_OK if
     * handled, RBS_E_NOT_FOUND if the command is not this renderer's; may
     * write a reply into out. */
    rbs_status (*command)(void *instance, const char *line, char *out,
                          size_t outlen);
} rbs_renderer_class;

/** A table of renderer types (fixed capacity RBS_RENDERER_TYPES_MAX). */
#define RBS_RENDERER_TYPES_MAX 32
typedef struct rbs_renderer_registry rbs_renderer_registry;

RBS_API rbs_status rbs_renderer_registry_create(rbs_renderer_registry **out);
RBS_API void rbs_renderer_registry_destroy(rbs_renderer_registry *registry);
/** Register a type; RBS_E_INVALID if the name is taken, RBS_E_CAPACITY if
 * full.  The class is copied. */
RBS_API rbs_status rbs_renderer_register(rbs_renderer_registry *registry,
                                         const rbs_renderer_class *cls);
/** Find a type by name; RBS_E_NOT_FOUND if absent. */
RBS_API rbs_status rbs_renderer_find(const rbs_renderer_registry *registry,
                                     const char *name,
                                     const rbs_renderer_class **out);

#ifdef __cplusplus
}
#endif

#endif /* RBSIM_REEL_H */
