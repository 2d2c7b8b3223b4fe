/*
 * rbsim/reel.h - the projector: frames, the reel (a bounded ring of frames
 * between a simulation thread and a renderer thread), the renderer factory and
 * the projector that runs both threads.
 *
 * The reel and the projector's command functions are the thread-safe objects
 * of rbsim; everything else follows the world's rule (one thread at a time).
 * While a projector runs (from rbs_projector_start until rbs_projector_wait
 * returns) its world belongs to the simulation thread: no other thread may
 * touch it, not even to read.  Renderers see copies (frames), never the
 * world.  Declarations avoid function-like macros and varargs, so cffi can
 * read them (the *_init and _status macros have _sized functions beside).
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

/** Largest "every" (keep every K-th frame) a renderer entry, --every and
 * the scene's "every" accept: 2^31 - 1, so it fits any renderer's int. */
#define RBS_EVERY_MAX 2147483647

/** One body in a frame: its physical representation and velocities. */
typedef struct rbs_frame_body {
    int32_t type;              /**< rbs_body_type */
    uint32_t color;            /**< 0xRRGGBB */
    int32_t texture;           /**< rbs_texture */
    uint32_t slot;             /**< the body's slot index in the world */
    const char *name;          /**< owned by the world ("" if unnamed), valid
                                    while the world lives and its bodies are
                                    not removed */
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
    double target_time;     /**< wall time it should stay on screen, s
                                 (dt / speed when it was made) */
    int32_t last;           /**< nonzero on the run's last frame (a run
                                 stopped by quit or an error has none, but
                                 for its last frame given at the end to a
                                 recorder whose every K had left it out) */
    int32_t paused;         /**< nonzero if the run was paused when this
                                 frame was made, and on repeats of the held
                                 frame shown to live views while paused */
    uint32_t body_count;    /**< occupied slots, in slot order */
    rbs_frame_body *bodies; /**< body_count entries, owned by the reel */
    rbs_frame_stats stats;
} rbs_frame;

/** Fill a frame from a world through the public world API: the glue
 * between the core and the reel.  frame->bodies must hold bodies_capacity
 * entries; every occupied slot is copied, in slot order (RBS_E_CAPACITY if
 * they do not fit).  Sets number (the step count), time, body_count and the
 * energies and momenta of stats; stats.step is zeroed for the caller to fill;
 * target_time, last and paused are left alone.  Allocates nothing.  Reads
 * the world: not concurrently with anything that changes it. */
RBS_API rbs_status rbs_frame_capture(const rbs_world *world, rbs_frame *frame,
                                     uint32_t bodies_capacity);

/** Whether a recorder that keeps every K-th frame
 * (rbs_renderer_config.every) writes frame `frame` (a step count) of a run
 * that starts at frame `start` (the world's step count at start): the
 * projector's rule, given here so that a front end can tell which files a
 * run will write before it starts.  A frame is written if its number is a
 * multiple of every (0 means 1, so every frame), or it is the starting
 * frame, or it is the run's last (is_last nonzero) and the run is not
 * continued (rbs_projector_def.continued: a part saved at its end for the
 * next part to go on from keeps its last frame only if it is a multiple of
 * every).  With skip_first nonzero (rbs_projector_def.skip_first_frame: a
 * run resumed from a checkpoint) the starting frame is not drawn at all;
 * a frame before start is not written either.  Returns 1 or 0.  A pure
 * function of its arguments: thread-safe. */
RBS_API int32_t rbs_frame_written(uint64_t frame, uint32_t every, uint64_t start,
                                  int32_t skip_first, int32_t is_last,
                                  int32_t continued);

/* ------------------------------------------------------------------------- */
/* Reel                                                                      */
/* ------------------------------------------------------------------------- */

/** What the writer does when the ring is full. */
typedef enum rbs_reel_policy {
    RBS_REEL_LOSSLESS = 0,    /**< the writer waits for the reader */
    RBS_REEL_LATEST_ONLY = 1, /**< the writer takes back the oldest unread
                                   frame (never the one being read); the
                                   reader sees increasing frames, some
                                   skipped */
    RBS_REEL_POLICY_FORCE32 = 0x7fffffff
} rbs_reel_policy;

/** A bounded ring of frames between one writer thread and one reader
 * thread.  Every call below is thread-safe; each side holds at most one slot
 * at a time (RBS_E_INVALID otherwise).  Opaque. */
typedef struct rbs_reel rbs_reel;

/** Create a reel of `capacity` frames (>= 2), each with room for
 * `max_bodies` (>= 1) bodies; all memory is reserved here, none later.
 * RBS_E_INVALID for bad arguments, RBS_E_CAPACITY if capacity x
 * max_bodies is beyond what one allocation can hold, RBS_E_MEMORY if out of
 * memory. */
RBS_API rbs_status rbs_reel_create(uint32_t capacity, uint32_t max_bodies,
                                   rbs_reel_policy policy, rbs_reel **out);
/** Free a reel (no thread may be using it).  NULL ok. */
RBS_API void rbs_reel_destroy(rbs_reel *reel);
/** Writer: get the next free slot, cleared (blocks in lossless mode while
 * the ring is full).  RBS_E_CLOSED if the reel was closed, also while
 * waiting. */
RBS_API rbs_status rbs_reel_begin_write(rbs_reel *reel, rbs_frame **slot);
/** Writer: publish the slot got by rbs_reel_begin_write.  RBS_E_CLOSED (the
 * frame is discarded) if the reel was closed meanwhile. */
RBS_API rbs_status rbs_reel_end_write(rbs_reel *reel);
/** Reader: wait for the next frame (the oldest published).  Frames
 * published before a close are still delivered; RBS_E_CLOSED once closed and
 * drained. */
RBS_API rbs_status rbs_reel_begin_read(rbs_reel *reel, const rbs_frame **frame);
/** Reader: give the frame back (it must not be used afterwards). */
RBS_API rbs_status rbs_reel_end_read(rbs_reel *reel);
/** Close: no more frames; wakes every waiter.  Idempotent. */
RBS_API void rbs_reel_close(rbs_reel *reel);
/** Frames dropped by the latest-only policy so far. */
RBS_API uint64_t rbs_reel_dropped(rbs_reel *reel);

/* ------------------------------------------------------------------------- */
/* Worker pool                                                               */
/* ------------------------------------------------------------------------- */

/** Threads of the library's own to lend a world's steps (rbs_workers,
 * rbsim.h): the core starts none, the pool does.  Between tasks a thread
 * spins for a few tens of microseconds (a step follows another closely),
 * then sleeps.  Opaque; one world's steps at a time (start and finish are
 * not for two worlds stepping at once). */
typedef struct rbs_pool rbs_pool;

/** A pool of `threads` (1 .. RBS_WORKERS_MAX - 1) threads besides the
 * caller's.  RBS_E_INVALID for a count out of range, RBS_E_MEMORY when a
 * thread or its memory cannot be had (nothing is left behind). */
RBS_API rbs_status rbs_pool_create(uint32_t threads, rbs_pool **out);
/** The workers to lend a world (rbs_world_set_workers): count = the pool's
 * threads + 1, the stepping thread included.  Initialise *out with
 * rbs_workers_init first. */
RBS_API rbs_status rbs_pool_workers(rbs_pool *pool, rbs_workers *out);
/** Stop and join the threads and free the pool.  No world may still use it
 * (rbs_world_set_workers(world, NULL) first).  NULL ok. */
RBS_API void rbs_pool_destroy(rbs_pool *pool);

/* ------------------------------------------------------------------------- */
/* Renderer factory                                                          */
/* ------------------------------------------------------------------------- */

/** Configuration handed to a renderer type's check() and create().  The
 * strings are borrowed for the call only: copy what you keep. */
typedef struct rbs_renderer_config {
    uint32_t struct_size;  /**< sizeof(rbs_renderer_config) */
    const char *type;      /**< registered name */
    const char *path;      /**< output path (file or folder) or NULL */
    uint32_t every;        /**< keep frames whose number is a multiple of
                                K, the starting frame and the last; the
                                projector does the keeping; 0 means 1;
                                at most RBS_EVERY_MAX */
    const char *json;      /**< the scene entry as JSON text, or NULL */
    const char *file;      /**< scene file for messages, or NULL */
    int32_t line, column;  /**< place of the entry in file, 1-based, or 0 */
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
 * into err (errlen bytes).  create() and destroy() run on the thread that
 * creates/destroys the projector; draw(), finish() and command() on its
 * renderer thread, never two at once.  The frame given to draw() is valid
 * only during the call.  A renderer must not call into the world. */
typedef struct rbs_renderer_class {
    uint32_t struct_size;  /**< sizeof(rbs_renderer_class) */
    const char *name; /**< unique; copied pointer must outlive the registry */
    void *context;    /**< passed to create() */
    rbs_status (*create)(void *context, const rbs_renderer_config *config,
                         const rbs_world *world, void **instance, char *err,
                         size_t errlen);
    /** RBS_OK, or an rbs_status with a message in err (a code that is no
     * rbs_status ends the run as RBS_E_RENDERER, naming it). */
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
    /** rbs_renderer_flags, OR-ed; 0 (default) is a recorder that needs
     * every frame, in order. */
    uint32_t flags;
    /** Optional (NULL if none): validate a configuration without side
     * effects (no file opened, nothing written).  The projector calls it for
     * every renderer before it creates any, so a rejected run writes
     * nothing. */
    rbs_status (*check)(void *context, const rbs_renderer_config *config,
                        const rbs_world *world, char *err, size_t errlen);
} rbs_renderer_class;

/** Flags of a renderer class. */
typedef enum rbs_renderer_flags {
    /** A live view: may miss frames (the latest-only reel; skipped when
     * behind in real time) and, while the run is paused, gets the held
     * frame again about 30 times a second with frame->paused set, so it can
     * keep its window alive.  Recorders (flag clear) never see a frame
     * twice. */
    RBS_RENDERER_LIVE = 1,
    RBS_RENDERER_FLAGS_FORCE32 = 0x7fffffff
} rbs_renderer_flags;

/** A table of renderer types (fixed capacity RBS_RENDERER_TYPES_MAX). */
#define RBS_RENDERER_TYPES_MAX 32
typedef struct rbs_renderer_registry rbs_renderer_registry;

/** Make an empty registry (the caller owns it; no globals).  Not
 * thread-safe: register before runs start. */
RBS_API rbs_status rbs_renderer_registry_create(rbs_renderer_registry **out);
/** Free a registry (after every projector using it).  NULL ok. */
RBS_API void rbs_renderer_registry_destroy(rbs_renderer_registry *registry);
/** Register a type; RBS_E_INVALID if the name is taken or the class lacks
 * a name, create() or draw(); RBS_E_CAPACITY if full.  The class is copied
 * (its strings and context are borrowed). */
RBS_API rbs_status rbs_renderer_register(rbs_renderer_registry *registry,
                                         const rbs_renderer_class *cls);
/** Find a type by name; RBS_E_NOT_FOUND (and *out NULL) if absent.  The
 * pointer is valid while the registry lives. */
RBS_API rbs_status rbs_renderer_find(const rbs_renderer_registry *registry,
                                     const char *name,
                                     const rbs_renderer_class **out);

/* ------------------------------------------------------------------------- */
/* Projector: the simulation thread, the renderer thread and the controls    */
/* ------------------------------------------------------------------------- */

/** How a run is projected.  Initialise with rbs_projector_def_init(&def). */
typedef struct rbs_projector_def {
    uint32_t struct_size;     /**< set by the init macro; do not touch */
    uint64_t steps;           /**< steps to take: frames k = 0..steps at
                                   t = k dt (frame 0 is the initial state;
                                   0 gives frame 0 only).  Default 0 */
    uint32_t reel_capacity;   /**< frames in the reel, >= 2; default 64 */
    rbs_reel_policy policy;   /**< default lossless.  Latest-only is used
                                   only if every renderer is
                                   RBS_RENDERER_LIVE; otherwise lossless */
    int32_t realtime;         /**< nonzero: show frame k at k dt / speed of
                                   wall time (the renderer thread sleeps
                                   until a frame is due; when more than a
                                   frame behind, live views skip frames,
                                   recorders never do); 0 (default): as
                                   fast as possible */
    double speed;             /**< real-time factor, > 0; default 1 */
    int32_t start_paused;     /**< nonzero: pause after frame 0; default 0 */
    int32_t pause_on_collision; /**< nonzero: pause after a frame whose step
                                   resolved an impact; default 0 */
    int32_t endless;          /**< nonzero: ignore steps, run until "quit";
                                   default 0 */
    /** Optional (default NULL): called on the simulation thread after each
     * step, once that step's frame is in the reel (not for the starting
     * frame), with the world at that frame (frame = its step count), e.g.
     * to save checkpoints (rbs_world_save).  It must not change the world
     * (a const pointer) nor call the projector except by
     * rbs_projector_command.  A status other than RBS_OK stops the run with
     * that status and the message written into err (errlen bytes) as
     * rbs_projector_last_error(); outputs stay complete up to this frame. */
    rbs_status (*after_step)(void *context, const rbs_world *world,
                             uint64_t frame, char *err, size_t errlen);
    void *after_step_context; /**< passed to after_step; default NULL */
    /** Nonzero: the starting state's frame (number = the world's step count
     * at start) is not given to the renderers, e.g. a run resumed from a
     * checkpoint whose frame an earlier run wrote; the first frame drawn is
     * then the next one.  Default 0 (it is drawn). */
    int32_t skip_first_frame;
    /** Nonzero: the run is one part of a longer one, continued from its end
     * (a checkpoint saved at its last frame; the next part sets
     * skip_first_frame), so a recorder with every K > 1 keeps the last frame
     * -- also an interrupted run's -- only if its number is a multiple of
     * K, as the whole run would: the parts joined are the whole run's
     * frames.  Default 0: the last frame is always kept. */
    int32_t continued;
} rbs_projector_def;

/** Fill a projector definition with defaults.  Prefer the macro. */
RBS_API void rbs_projector_def_init_sized(rbs_projector_def *def,
                                          size_t def_size);
#define rbs_projector_def_init(def) \
    rbs_projector_def_init_sized((def), sizeof *(def))

/** Where a run is. */
typedef enum rbs_run_state {
    RBS_RUN_READY = 0,   /**< created, not started */
    RBS_RUN_RUNNING = 1, /**< threads running (possibly paused) */
    RBS_RUN_DONE = 2,    /**< both threads finished; see result */
    RBS_RUN_STATE_FORCE32 = 0x7fffffff
} rbs_run_state;

/** A snapshot of a run, from rbs_projector_status(). */
typedef struct rbs_run_info {
    rbs_run_state state;
    rbs_status result;        /**< RBS_OK so far, or the run's status when
                                   done (as rbs_projector_wait returns) */
    int32_t paused;           /**< nonzero while paused */
    int32_t quit;             /**< nonzero once quit was asked */
    int32_t realtime;         /**< nonzero if paced to the wall clock */
    double speed;             /**< real-time factor */
    uint64_t steps;           /**< steps asked */
    int32_t endless;          /**< nonzero: until quit */
    uint64_t captured;        /**< frames captured by the simulation so far */
    uint64_t frame;           /**< number of the last frame drawn */
    double time;              /**< simulated time of the last frame drawn, s */
    uint64_t drawn;           /**< frames taken from the reel so far */
    uint64_t dropped;         /**< frames dropped by a latest-only reel */
    uint64_t substeps;        /**< sub-steps accepted, all steps so far */
    uint64_t rollbacks;       /**< sub-steps undone, all steps so far */
    uint64_t collisions;      /**< impacts resolved, all steps so far */
    double energy_initial;    /**< total energy at frame 0, J */
    double energy_last;       /**< total energy at the last frame captured, J */
    double wall_time;         /**< seconds since start (until done) */
    uint64_t work_limited;    /**< steps that hit their work cap
                                   (rbs_step_info.work_limit), all steps so
                                   far: their impacts may be missed or
                                   wrong */
    uint64_t floor_hit_steps; /**< steps with overlap pushed apart instead
                                   of resolved (rbs_step_info.floor_hits >
                                   0: the rollback floor, a rollback the
                                   work cap refused, or a body jammed in a
                                   selective step), all steps so far */
    uint64_t sweep_limited;   /**< steps with a contact pass that hit
                                   max_sweeps (rbs_step_info.sweep_limit >
                                   0: impulses not converged), all steps so
                                   far */
    uint64_t rounded_steps;   /**< steps in which slow motion was partly
                                   lost to the rounding of coordinates
                                   (rbs_world_rounded_steps: far from the
                                   origin, or a tiny dt), all steps so far */
    double max_overlap;       /**< the deepest overlap at the end of any
                                   step so far (rbs_step_info.max_overlap),
                                   m */
} rbs_run_info;

/** A run: owns a reel, the renderer instances and two threads.  Opaque. */
typedef struct rbs_projector rbs_projector;

/** Make a projector for a world and create its renderers: configs[i].type
 * is looked up in the registry (count <= RBS_RENDERERS_MAX, configs may be
 * NULL when count is 0).  Every renderer's check() runs before any create(),
 * so a rejected configuration writes nothing.  The projector borrows the
 * world and the registry: both must outlive it.  From rbs_projector_start()
 * until rbs_projector_wait() returns, the world belongs to the simulation
 * thread: no other thread may call anything on it.
 * configs is read with configs[0].struct_size as its element size (set
 * every struct_size to sizeof(rbs_renderer_config)).  On error *out is NULL
 * when the arguments are unusable (NULL world or def, count too large, an
 * uninitialised def) or memory ran out; otherwise (bad def values, an unset
 * struct_size, an unknown type, a renderer's check or create failing) *out is
 * set, explains the error in rbs_projector_last_error(), cannot start, and
 * must be destroyed.  Not thread-safe. */
RBS_API rbs_status rbs_projector_create(rbs_world *world,
                                        const rbs_renderer_registry *registry,
                                        const rbs_renderer_config *configs,
                                        uint32_t count,
                                        const rbs_projector_def *def,
                                        rbs_projector **out);

/** Capture frame 0 (the initial state) into the reel on the calling thread,
 * then start the simulation and renderer threads; from here the world
 * belongs to the simulation thread.  Once only (RBS_E_INVALID again, or on a
 * projector whose create failed).  One run of a world at a time: while
 * another projector's run holds the world (from its start until its
 * rbs_projector_wait returns) this returns RBS_E_INVALID, says so in
 * rbs_projector_last_error(), and may be called again once that run is
 * over.  Thread-safe with respect to other projectors' starts. */
RBS_API rbs_status rbs_projector_start(rbs_projector *projector);

/** Send a command line, as typed by a user.  Thread-safe (any thread, also
 * from a renderer's control hook), also before start and after the end.
 * Commands: "pause", "resume", "step [N]" (make N more frames, default 1,
 * then pause; sums up if repeated), "speed X" (real-time factor, 0 < X <=
 * 1e6, in the "C" locale's notation whatever the caller's: "0.5", never
 * "0,5"), "quit" (stop after the frame being made, which is still
 * published, so the world ends at the last frame published; frames already
 * in the reel are still drawn and every output finished), "status" (a
 * one-line summary: "frame K of N, ..." or, endless, "frame K (endless
 * run), ...").  "quit", "pause", "resume" and "status" take no argument;
 * "pause" when paused (no step in progress) and "resume" when running change
 * nothing and say so ("already paused at frame K", "not paused: running at
 * frame K"), RBS_OK.
 * Any other line is offered to each renderer's command hook: on the renderer
 * thread while it runs (this call waits for the answer, unless it comes from
 * the renderer thread itself), directly otherwise.  A reply (one line, no
 * newline) is written into reply (reply_size bytes; reply may be NULL).
 * Lines are at most 255 bytes.  Returns RBS_OK, RBS_E_INVALID for bad
 * arguments (the reply says why), RBS_E_NOT_FOUND if no one knows the
 * command, or RBS_E_CLOSED if the renderer thread ended before it could
 * answer, or for "pause" and "resume" once the run is over. */
RBS_API rbs_status rbs_projector_command(rbs_projector *projector,
                                         const char *line, char *reply,
                                         size_t reply_size);

/** Wait up to timeout seconds (0: just look) for the run to end; nonzero if
 * it has ended (then rbs_projector_wait() returns at once).  Thread-safe. */
RBS_API int32_t rbs_projector_finished(rbs_projector *projector,
                                       double timeout);

/** Wait for the run to end and join its threads.  Returns RBS_OK when all
 * steps were made and every renderer finished, RBS_E_CLOSED when stopped by
 * "quit" (outputs are complete up to the last frame drawn), or the first
 * error (a step's failure, RBS_E_RENDERER, RBS_E_IO, ...; see
 * rbs_projector_last_error()).  Call from one thread; repeat calls return
 * the same status.  A projector never started returns RBS_E_INVALID. */
RBS_API rbs_status rbs_projector_wait(rbs_projector *projector);

/** rbs_projector_start() then rbs_projector_wait(). */
RBS_API rbs_status rbs_projector_run(rbs_projector *projector);

/** A snapshot of the run.  Thread-safe.  Prefer the macro. */
RBS_API rbs_status rbs_projector_status_sized(rbs_projector *projector,
                                              rbs_run_info *out,
                                              size_t out_size);
#define rbs_projector_status(projector, out) \
    rbs_projector_status_sized((projector), (out), sizeof *(out))

/** The first error's detail, e.g. "csv renderer 'out.csv': write failed:
 * No space left on device" ("" if none).  Owned by the projector; stable
 * once rbs_projector_wait() has returned (or after a failed create). */
RBS_API const char *rbs_projector_last_error(const rbs_projector *projector);

/** Stop the run if running (as "quit"), join the threads, destroy every
 * renderer and free the projector.  NULL ok.  Not thread-safe. */
RBS_API void rbs_projector_destroy(rbs_projector *projector);

#ifdef __cplusplus
}
#endif

#endif /* RBSIM_REEL_H */
