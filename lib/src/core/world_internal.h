/*
 * world_internal.h - the world's layout (internal; never installed).
 *
 * A world lives in one block: this struct, then structure-of-arrays pools
 * carved from the same block by rbs__world_layout().  Nothing is allocated
 * after creation.  Body state is kept per slot:
 *   pos     geometric centre (sphere) or point (plane)
 *   vel     velocity of the centre of mass
 *   avel    angular velocity, world frame
 *   orient  unit quaternion body -> world
 * For spheres with an off-centre COM, com = pos + R(orient) * com_body.
 */
#ifndef RBS_CORE_WORLD_INTERNAL_H
#define RBS_CORE_WORLD_INTERNAL_H

#include "rbsim/rbsim.h"
#include "core/c_locale.h" /* numbers in messages, in the "C" locale */
#include "core/vec.h"

#define RBS__ERROR_MAX 256

/* A contact between body a (sphere) and body b (sphere or plane); the normal
 * points from b towards a. */
typedef struct rbs__contact {
    uint32_t a, b;
    uint32_t row;  /* material-pair row (w->pair[row]: friction, rolling,
                      spinning); w->def.max_pairs, the world's default row
                      (frictionless), when no row matches the pair */
    uint32_t flags; /* RBS__OFF_A | RBS__OFF_B: that body's centre of mass
                       is off its centre (the lever needs its rotation);
                       RBS__APART: gap > the pair's slop (a speculative
                       contact, not touching); RBS__INELASTIC: restitution
                       0 for this contact (rbs__contact_e) */
    v3 n;          /* unit normal, from b to a */
    double lb;     /* lever along n: rb = lb n from b's centre to the contact
                      point (minus the centre of mass offset R c when off;
                      rbs__contact_rb); a's is la = -r_a (rbs__contact_la),
                      looked up rather than kept, for a 128-byte contact */
    double gap;    /* signed distance between surfaces, m (< 0: overlap);
                      verlet and rk4 replace a speculative contact's by the
                      slop plus its reach (rbs__trapezoid_reach) */
    double thr;    /* approach speed below which the contact is resting, m/s
                      (the soft step takes its test at the frame's start and
                      then keeps the effective mass 1 / kn here, kg) */
    double bias;   /* speculative contact (gap > slop): the approach speed
                      the resting pass allows, (gap - slop) / h (gap as
                      above), or -1 when
                      the pair approaches as an impact (left to the
                      method's rollback); 0 for a touching contact
                      (verlet and rk4: the approach its path's bend
                      needs between two spheres, rbs__trapezoid_reach) */
    double kn;     /* n . K n : inverse effective mass along n */
    double kt_inv; /* 1 / (t . K t), the same for every tangent t when K is
                      isotropic in the tangent plane (centred isotropic
                      spheres); else 0 */
    /* accumulated impulses in the resting pass */
    double jn;
    v3 jt;
    double jslip;  /* the friction impulse that would stop the contact's slip
                      as the collision pass leaves it (before the sub-step's
                      forces), N s; while it is over mu_k Jn the contact
                      slides all the sub-step and only kinetic friction acts
                      (rbs__friction_cap); 0 when mu_s == mu_k, and in the
                      soft step */
} rbs__contact;

#define RBS__OFF_A 1u
#define RBS__OFF_B 2u
#define RBS__OFF (RBS__OFF_A | RBS__OFF_B)
#define RBS__APART 4u
#define RBS__TOUCHED 8u  /* soft step: it took a normal impulse this frame */
#define RBS__BOUNCE 16u  /* soft step: it approached faster than thr at the frame's
                            start, with e > 0 (the restitution pass takes it) */
#define RBS__INELASTIC 32u /* restitution 0 whatever its pair's (the event and
                              selective methods: a resting approach) */
#define RBS__GUARD 64u   /* soft step: a pair only a kick within the frame can
                            close (rbs__detect_swept's second pass); its rows
                            let it overlap by RBS__GUARD_DEPTH of the smaller
                            radius before they act */
#define RBS__WARM 128u   /* soft step: it came in with a normal impulse (the
                            last frame's load) and is not lone; its relax
                            rows over-relax (soft.h, RBS__SOFT_OVER) */
#define RBS__GUARD_DEPTH 0.5 /* of the smaller radius (of the smallest sphere
                                 for the kicks detection takes) */

/* The rolling and spinning resistance of contact i, beside the contact
 * array (w->contact_resist[i] for w->contact[i]) so that the contacts the
 * sweeps stream stay small; written only for a contact whose pair has
 * resistance (rolling or spinning > 0), read only then. */
typedef struct rbs__resist {
    double radius; /* lever for rolling resistance, m */
    v3 jroll;      /* accumulated rolling and spinning impulses */
    double jspin;
    double impact; /* soft step: the normal impulse of the frame's impact --
                      m_eff times the approach at the frame's start, when
                      faster than its resting threshold, plus the
                      restitution's -- not yet taken by a sub-step, N s: no
                      load for the resistance rows (rbs__soft's
                      resist_loaded) */
} rbs__resist;

/* A material-pair row. */
typedef struct rbs__pair {
    uint32_t a, b; /* material index + 1; 0 = "*" */
    double mu_s, mu_k, e, rolling, spinning;
} rbs__pair;

/* A warm-start entry: resting impulse rates of a body pair (N). */
typedef struct rbs__warm {
    uint64_t key; /* the pair's key (rbs__warm_key) */
    double n;
    v3 t;
} rbs__warm;

/* Which stages a step runs (see rbs__world_plan). */
typedef struct rbs__plan {
    int angular;      /* integrate angular velocity and orientation */
    int gyroscopic;   /* some body needs the w x Iw term */
    int friction;     /* some pair has friction or resistance */
    int sphere_pairs; /* two or more spheres, at least one moving */
    int mutual;       /* mutual gravity */
    int mutual_acts;  /* mutual gravity is on and can act: a moving sphere
                         and another sphere (from the bodies alone, never
                         pruned; the soft layout and event's scope read it) */
    double min_radius; /* smallest sphere radius (0 if none), m */
    double mass_ratio; /* the moving spheres' largest mass over their
                          smallest (1 with none; from the bodies alone,
                          never pruned): RBS_METHOD_AUTO's second test */
    double soft_sink;  /* the deepest soft could sink a contact of the
                          moving spheres, of their smallest radius: the
                          largest load |m a| (gravity and applied force)
                          on the lightest, max |m a| / (m_min omega^2
                          r_min) (0 with none; never pruned):
                          RBS_METHOD_AUTO's third test, at
                          def.soft_substeps */
    uint32_t soft_substeps; /* the soft step's sub-steps a frame:
                               def.soft_substeps, or more when
                               RBS_METHOD_AUTO raised them (soft_sink) */
    int applied;       /* some moving sphere has an applied force or torque
                          (not a stage: never set by pruning off) */
    rbs_method method; /* the method a step takes (RBS_METHOD_AUTO resolved;
                          never pruned: the same with pruning off) */
    int gather;        /* the soft step may gather body records: every sphere
                          centred and isotropic, no pair with rolling or
                          spinning resistance, no mutual gravity that can
                          act (mutual_acts; from the
                          bodies alone, never pruned: a pruned and a full
                          pipeline take the same layout, bit for bit) */
    int uneven;        /* some moving sphere is anisotropic or has its centre
                          of mass off its centre: selective steps as euler
                          (never pruned) */
    int fixed_spheres; /* some sphere is fixed (from the bodies alone, never
                          pruned): the soft step takes a moving sphere's
                          contacts with fixed spheres touching ones first,
                          apart ones last (docs/methods.md, "soft") */
    int consecutive;   /* the spheres hold consecutive slots (spheres[k] =
                          spheres[0] + k: a scene of planes then spheres,
                          every pile): detection reads their centres from
                          pos in place instead of copying them (never
                          pruned) */
} rbs__plan;

struct rbs_world {
    uint32_t magic;
    int owns_memory;
    int in_run; /* 1 while a projector's run holds the world (from its
                   rbs_projector_start until its rbs_projector_wait):
                   rbs__world_claim, rbs__world_release */
    size_t bytes;
    rbs_world_def def;
    char error[RBS__ERROR_MAX];

    uint64_t step_count;
    uint64_t rounded_steps; /* steps with slow motion partly lost to rounding (step.c) */
    double time_base;   /* simulated time at step step_base, s: the time is
                           time_base + (step_count - step_base) dt, so that
                           rbs_world_set_dt changes only the steps after it */
    uint64_t step_base;
    uint32_t slots;       /* high-water mark of used slots */
    uint32_t bodies;      /* live bodies */
    uint32_t free_count;  /* entries in free_list */
    uint32_t materials;
    uint32_t pairs;
    uint32_t contact_count;
    uint32_t contacts_high;
    rbs__plan plan;
    int plan_dirty;
    int acc_fresh;             /* w->acc is rbs__detect's, at the positions the
                                  sub-step starts from (rbs__mutual_gravity_start) */
    int rows_dirty;            /* bodies or pair rows changed: row_friction and
                                  row_resist to be found again (step.c) */
    int32_t row_friction, row_resist; /* rbs__row_in_use's answers, cached */
    int overlap_unmeasured; /* set by a method that leaves info->max_overlap to rbs_world_step */
    int step_saved; /* step_save holds the state at this step's start (a failed
                       step restores it); the soft step's gathered layout
                       needs no save and leaves it 0 */
    int step_checked; /* the method found every value it wrote this step
                         finite (the soft step's gathered layout, which
                         checks before it writes), so rbs_world_step skips
                         its own scan */
    uint64_t spin_left; /* rotation sub-steps this step may still take (rbs__spin_substeps) */

    /* per body (capacity def.max_bodies) */
    int32_t *type;
    uint32_t *generation;
    int32_t *fixed;
    uint32_t *material;   /* material index + 1, 0 = none */
    uint32_t *color;
    int32_t *texture;
    char (*name)[RBS_NAME_MAX];
    uint32_t *name_index;                 /* named bodies by name: open addressing,
                                             linear probing, name_index_size
                                             entries of slot + 1 (0: empty) */
    uint32_t name_index_size;             /* power of two >= 2 * max_bodies */
    double *pos, *vel, *avel, *orient;    /* 3, 3, 3, 4 per slot */
    double *force, *torque, *normal;      /* 3 per slot */
    double *radius, *mass, *inv_mass;
    double *com_body;                     /* 3 per slot, body frame */
    double *inertia, *inv_inertia;        /* 9 per slot, about COM, body frame;
                                             written for anisotropic bodies only */
    double *iso_inertia, *iso_inv_inertia; /* per slot: an isotropic body's moment
                                             (and inverse) as one number */
    int32_t *isotropic;                   /* inertia is a multiple of identity */
    uint32_t *free_list;
    /* backups: start of step, start of sub-step */
    double *step_save;                    /* 13 per slot */
    double *sub_save;                     /* 13 per slot */
    uint32_t *spheres;                    /* slots of moving and fixed spheres */
    uint32_t sphere_count;
    uint32_t *item;                       /* per slot: its index in spheres */
    uint32_t *planes;                     /* slots of planes */
    uint32_t plane_count;
    double *acc;                          /* 3 per slot: scratch accelerations */

    /* materials */
    char (*material_name)[RBS_NAME_MAX];
    rbs__pair *pair;                      /* max_pairs rows, then the default row
                                             (frictionless; e < 0: the world's) */
    int32_t *pair_table;                  /* (max_materials+1)^2 -> pair row or -1 */

    /* contacts */
    rbs__contact *contact;
    rbs__resist *contact_resist;          /* one per contact slot (resistance only) */
    rbs__warm *warm;                      /* warm-start entries: sorted by key, or
                                             (warm_ranked) the soft step's
                                             buckets (soft_detect.c) */
    uint32_t *warm_at;                    /* 2 per slot: the first entry of the
                                             slot's bucket of planes [0] and of
                                             pairs [1]; for a slot with none,
                                             UINT32_MAX or an entry of another
                                             bucket; valid when warm_indexed
                                             (soft_detect.c) */
    double *solver_body;                  /* RBS__SOLVER_STRIDE per slot: the resting
                                             pass's compact copy of v, w, 1/m, 1/I
                                             (solver.c) */
    rbs__warm *warm_save;                 /* max_contacts: the table as a step of a
                                             rollback method found it, put back
                                             if the step fails (rbs_world_step) */
    uint32_t warm_size;                   /* max_contacts */
    uint32_t warm_used;                   /* entries the last warm pass stored (0: none) */
    int warm_ranked;                      /* the table is in the soft step's
                                             buckets, not in key order
                                             (rbs__warm_sort puts it back) */
    int warm_indexed;                     /* warm_at holds the table's buckets */

    /* broad phase (broadphase.c): per sphere item, and a grid (dense or hashed) */
    double *bp_center;                    /* 3 per item */
    double *bp_reach;
    uint32_t *bp_key, *bp_item, *bp_big;
    uint32_t *bp_start, *bp_fill;         /* bp_table_size + 1, bp_table_size */
    uint32_t bp_table_size;               /* power of two >= 2 * max_bodies */
    uint8_t *bp_query;                    /* per item: query mask (selective) */
    uint8_t *pressed;                     /* per slot: a sphere that held a load
                                             against another sphere in the last
                                             resting pass (rbs__mark_pressed) */
    int32_t *bp_cell;                     /* 3 per item: grid cell */
    /* the candidate-pair list (broadphase.c, rbs__broadphase_pairs) */
    double *vl_pos;                       /* 3 per item: centres at its build */
    double *vl_reach;                     /* per item: list reach (reach at its build + skin) */
    uint32_t *vl_pair;                    /* 2 per pair, vl_cap pairs, sorted */
    uint32_t *vl_start;                   /* per item + 1: where its pairs (as the
                                             first item) start in vl_pair */
    uint32_t vl_cap;                      /* max_contacts */
    uint32_t vl_count;                    /* pairs on the list */
    uint32_t vl_items;                    /* items it was built for */
    int vl_valid;                         /* 0: none (cleared when items change) */

    /* event method (step_event.c): per body motion between events */
    double *ev_alpha;                     /* 3 per slot: angular acceleration */
    int32_t *ev_mode;                     /* free / on a plane */
    uint32_t *ev_plane;                   /* the plane a body rolls or slides on */
    uint32_t *shock_order;                /* max_contacts + max_bodies + 2: shock
                                             propagation's contacts by level and
                                             its per-level counts (solver.c) */

    /* the soft step's gathered layout (soft.h) */
    struct rbs__chunk *chunk;             /* chunk_cap chunks of four contacts
                                             (64-byte aligned; soft_detect.h) */
    uint32_t chunk_cap;
    uint16_t *chunk_member;               /* per slot, RBS__LEVELS_MAX + 1 runs: the
                                             open chunks holding it (soft_chunks.c;
                                             zero between frames) */
    uint8_t *soft_slab;                   /* per item: its slab this frame (soft_detect.c) */
    uint32_t *soft_order;                 /* the items slab by slab: the frame's records */
    uint32_t *soft_rank;                  /* per item: its record (place in soft_order) */
    uint32_t *soft_aside;                 /* max_contacts: the candidate pairs in
                                             contact, slab by slab */
    uint8_t *soft_planes;                 /* per record: its planes in contact (bits) */
    const struct rbs__soft_kernels *soft_kernels; /* the rows' kernels (soft.h):
                                             chosen for the processor at creation */
    rbs_workers workers;                  /* threads lent by the caller (team.c);
                                             count 1: none */
    unsigned char *team_mem;              /* rbs__team_size() bytes: the step's
                                             threads' synchronisation (team.c) */

    /* methods (step_verlet.c, step_rk4.c, step_adaptive.c, step_soft.c) */
    double *method_scratch;               /* RBS__SCRATCH_STRIDE per slot, and
                                             RBS__SCRATCH_EXTRA more (also
                                             selective's neighbour adjacency) */
    double *method_state;                 /* 8: adaptive's step-size suggestion, ... */
    struct rbs__adaptive *adaptive;       /* GSL workspaces (malloc'd); NULL unless reserved */
};

/* Layout and creation (world.c). */
size_t rbs__team_size(void); /* bytes of team_mem (team.c) */
size_t rbs__world_layout(rbs_world *w, const rbs_world_def *def, unsigned char *base);
/* The world's last error (printf-style, numbers in the "C" locale); returns
 * status. */
int rbs__world_set_error(rbs_world *w, rbs_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* A projector's run takes the world (rbs__world_claim: 0, or -1 when
 * another run holds it) and gives it back once its threads are joined
 * (rbs__world_release).  Two projectors may be started from two threads at
 * once, so the claim is one compare-and-exchange (GCC's and Clang's
 * __atomic built-ins; other compilers: a plain test, which catches a second
 * start from the same thread only).  Acquire on the claim and release on
 * the give-back: a run started after another ended sees every write that
 * run's threads made to the world. */
int rbs__world_claim(rbs_world *w);
void rbs__world_release(rbs_world *w);
void rbs__world_plan(rbs_world *w);
void rbs__rebuild_lists(rbs_world *w); /* spheres, planes, item */
/* The best row for every pair of material codes (world.c): exact pair, then
 * one wildcard (the first set of two), then "*" with "*".  Derived data,
 * rebuilt when materials or rows change and when a checkpoint is read (a
 * file written before session 38 holds a table whose "*"/"*" row missed
 * pairs of two named materials). */
void rbs__rebuild_pair_table(rbs_world *w);
void rbs__plan_compute(const rbs_world *w, rbs__plan *out);
/* The first material-pair row some contact of the world can take -- a
 * moving sphere's material with any body's -- that has friction (resist
 * 0: mu_s, mu_k, rolling or spinning > 0) or resistance (resist 1:
 * rolling or spinning > 0); -1 when none.  A row no such pair takes (a
 * material defined but on no body) changes nothing, so it must not change
 * the stages or the layout either (step.c). */
int32_t rbs__row_in_use(const rbs_world *w, int resist); /* pure (step.c) */

/* Body helpers (world.c; the inline ones here). */
v3 rbs__body_com(const rbs_world *w, uint32_t i);
/* Whether body i moves: a sphere that is not fixed.  Inline, as the
 * accelerations below: detection asks it for both bodies of every contact. */
static inline int rbs__body_moves(const rbs_world *w, uint32_t i)
{
    return w->type[i] == RBS_BODY_SPHERE && !w->fixed[i];
}
/* I^-1 u in world axes (scalar for isotropic bodies).  Inline: the contact
 * solver's inner loop calls it and the two below for every impulse. */
static inline void rbs__body_inv_inertia_world(const rbs_world *w, uint32_t i, v3 u, v3 *out)
{
    if (w->isotropic[i])
        *out = v3_scale(u, w->iso_inv_inertia[i]);
    else
        *out = m3_mul_world(&w->inv_inertia[9 * i], q_load(&w->orient[4 * i]), u);
}

/* The (x, x) moment of body i and its inverse entry (the moment of an
 * isotropic body). */
static inline double rbs__inertia_xx(const rbs_world *w, uint32_t i)
{
    return w->isotropic[i] ? w->iso_inertia[i] : w->inertia[9 * i];
}
static inline double rbs__inv_inertia_xx(const rbs_world *w, uint32_t i)
{
    return w->isotropic[i] ? w->iso_inv_inertia[i] : w->inv_inertia[9 * i];
}

/* I(q) w in world axes: the scalar moment times w for an isotropic body
 * (computed as the diagonal matrix it is, so results match the general
 * case bit for bit), the 3x3 otherwise. */
static inline v3 rbs__inertia_times(const rbs_world *w, uint32_t i, quat q, v3 om)
{
    if (w->isotropic[i]) {
        double s = w->iso_inertia[i], I[9] = {0};
        I[0] = I[4] = I[8] = s;
        return m3_mul_world(I, q, om);
    }
    return m3_mul_world(&w->inertia[9 * i], q, om);
}

/* Broad phase (broadphase.c): fn(ctx, i, j) for every pair of items i < j
 * (indexes into w->spheres) whose centres (centers, 3 doubles an item; NULL:
 * w->bp_center) are closer than
 * the sum of their reaches (w->bp_reach) and of which at least one is
 * queried (query[i] != 0; query NULL: every pair), in order of (i, j).  The
 * pairs come from a candidate list kept between passes while the items
 * move little, built from a uniform grid (see broadphase.c); the results do
 * not depend on when the list was built.  fixed: the part of each reach
 * that is not the item's motion, as a fraction of its radius (a reach is
 * r (1 + fixed) + motion); only the motion grows the list's skin. */
typedef void (*rbs__pair_fn)(void *ctx, uint32_t i, uint32_t j);
void rbs__broadphase_pairs(rbs_world *w, const double *centers, uint32_t n, const uint8_t *query, double fixed,
                           rbs__pair_fn fn, void *ctx);
/* The candidate list's upkeep in parts, for a caller that splits its loops
 * (rbs__broadphase_pairs does it in one; item i's candidates are vl_pair[2
 * k], k from vl_start[i] to vl_start[i + 1] - 1, pairs (i, j) with j > i in
 * order, to be tested with the pass's reaches): item
 * i's slack -- how much farther it may move before the list must be built
 * again, L_i - R_i - |c_i - c_Li| (read only while the list is valid for
 * these n items) -- and, from the items' largest coordinate (size), reach
 * (rmax) and least slack, whether the list may be kept; else it is built
 * again (rsum: the sum of the radii), 1 when it then holds every pair. */
static inline double rbs__broadphase_slack(const rbs_world *w, const double *C, uint32_t i)
{
    double dx = C[3 * i] - w->vl_pos[3 * i], dy = C[3 * i + 1] - w->vl_pos[3 * i + 1],
           dz = C[3 * i + 2] - w->vl_pos[3 * i + 2];
    return w->vl_reach[i] - w->bp_reach[i] - sqrt(dx * dx + dy * dy + dz * dz);
}
int rbs__broadphase_keep(const rbs_world *w, uint32_t n, double size, double rmax, double slack);
/* The grid's working arrays (bp_key, bp_item, bp_big, bp_cell, bp_start,
 * bp_fill), which nothing reads once a grid pass is over; and room for
 * pairs (pair_room of them; NULL: none, as the world's own arrays), which
 * lets the candidate list be built on the world's threads. */
typedef struct rbs__grid_mem {
    uint32_t *key, *item, *big, *start, *fill;
    int32_t *cell;
    uint32_t *pairs;
    size_t pair_room;
} rbs__grid_mem;
/* Grid arrays for n items carved from bytes at p (4-byte aligned), which
 * the caller does not need during the pass, the rest as room for pairs: 1,
 * or 0 when they do not fit. */
int rbs__grid_mem_in(const rbs_world *w, void *p, size_t bytes, uint32_t n, rbs__grid_mem *out);
int rbs__broadphase_build(rbs_world *w, const rbs__grid_mem *mem, const double *centers, uint32_t n, double fixed,
                          double size, double rmax, double rsum);

/* Contacts (contact.c). */
/* Contacts at the start of a step.  speculative: also pairs apart by more
 * than the slop but by at most the creep reach thr * dt, the distance a
 * resting approach (slower than thr) closes in one step (see contact.c);
 * only for methods whose resting pass takes them (euler, selective). */
rbs_status rbs__detect(rbs_world *w, double dt, int speculative);
/* Contacts for a method that steps with them for a whole frame (soft):
 * margin[slot] is how far a moving sphere may travel within the frame, m;
 * every pair whose gap is at most the slop plus the two margins is a
 * contact (speculative when apart), as long as max_contacts has room.
 * acc: 6 doubles a slot, each body's acceleration (m/s^2, the resting
 * threshold's) and then anything (the caller's).  kick: scratch, a double
 * a slot, for the guards against kicks within the frame (contact.c,
 * detect_kicked), or NULL for none.  sink (NULL: none): each contact's
 * geometry -- a, b, n, gap, lb, flags -- goes to sink(sink_ctx, c) instead
 * of w->contact (which it leaves untouched; contact_count still counts
 * them), and its first failure is the detection's. */
typedef rbs_status (*rbs__contact_sink)(void *ctx, const rbs__contact *c);
rbs_status rbs__detect_swept(rbs_world *w, double dt, const double *margin, const double *acc, double *kick,
                             rbs__contact_sink sink, void *sink_ctx);
/* Sphere a's reach for the broad phase: its radius and slop plus m, how
 * far it may move (one expression, so that every pass that repeats the
 * test takes it bit for bit). */
static inline double rbs__sphere_reach(const rbs_world *w, uint32_t a, double m)
{
    return w->radius[a] * (1.0 + w->def.slop) + m;
}
/* How far moving sphere a may travel within a frame of dt under the
 * acceleration acc, |v| dt + |a| dt^2, m (0 for a fixed one, or when that
 * is not finite): the soft step's sweep margin (both layouts). */
static inline double rbs__sweep_margin(const rbs_world *w, uint32_t a, v3 acc, double dt)
{
    const double m = v3_len(v3_load(&w->vel[3 * a])) * dt + v3_len(acc) * dt * dt;
    return w->fixed[a] || !isfinite(m) ? 0.0 : m;
}
/* The contact of spheres a and b (d = p_a - p_b, dist = |d|) into c: bodies,
 * normal, material row, levers, gap and flags; swept: a closing pair that is
 * apart takes the normal of its touch on the straight paths of the frame
 * (contact.c).  Its thresholds and effective masses are not set. */
void rbs__pair_contact(const rbs_world *w, rbs__contact *c, uint32_t a, uint32_t b, v3 d, double dist, double dt,
                       int swept);
/* The normal of the touch of spheres a and b apart at the frame's start (d
 * = p_a - p_b, radii ra and rb) on their straight paths within dt, or of
 * their closest approach in it, into *n, with the separation along it and
 * b's lever then; 0 (nothing written) for a pair that is not closing
 * (contact.c). */
int rbs__impact_normal(const rbs_world *w, uint32_t a, uint32_t b, v3 d, double ra, double rb, double dt, v3 *n,
                       double *gap, double *lb);
/* Where spheres a and b touch (d = p_a - p_b, dist = |d|): the unit normal
 * from b to a (+z for coincident centres, documented), the gap along it and
 * b's lever; swept and apart by more than the slop: those of the touch on
 * their straight paths within dt (rbs__impact_normal).  Both detections'
 * one expression of it (rbs__pair_contact, the soft step's emit_pair). */
static inline void rbs__pair_touch(const rbs_world *w, uint32_t a, uint32_t b, v3 d, double dist, double dt,
                                   int swept, v3 *n, double *gap, double *lb)
{
    const double ra = w->radius[a], rb = w->radius[b];
    *n = dist > 0.0 ? v3_scale(d, 1.0 / dist) : v3_make(0, 0, 1);
    *gap = dist - ra - rb;
    *lb = dist - ra;
    if (swept && *gap > w->def.slop * (ra < rb ? ra : rb))
        (void)rbs__impact_normal(w, a, b, d, ra, rb, dt, n, gap, lb);
}
/* The material-pair row of bodies a and b (the default row when none). */
static inline uint32_t rbs__pair_row(const rbs_world *w, uint32_t a, uint32_t b)
{
    int32_t row = w->pair_table[w->material[a] * (w->def.max_materials + 1) + w->material[b]];
    return row >= 0 ? (uint32_t)row : w->def.max_pairs;
}
/* The contact of sphere a with plane p, gap apart, into c (as above). */
void rbs__plane_contact(const rbs_world *w, rbs__contact *c, uint32_t a, uint32_t p, double gap);
/* A pair of spheres' kick speed u, m/s per kg (0 when they are not
 * closing; d = p_a - p_b, dist = |d|): the normal closing speed over
 * 1/m_a + 1/m_b, so that one impact changes a's velocity by at most
 * 2 u / m_a and b's by 2 u / m_b (contact.c, detect_kicked). */
double rbs__kick_speed(const rbs_world *w, uint32_t a, uint32_t b, v3 d, double dist);
/* The swept detection's second pass alone (rbs__detect_swept's guards),
 * for a caller that made the first pass itself: kick[slot] holds the sum of
 * each sphere's kicks (and becomes its grown margin); the guards go to the
 * sink, counted on from w->contact_count. */
rbs_status rbs__detect_guards(rbs_world *w, double dt, const double *margin, const double *acc, double *kick,
                              rbs__contact_sink sink, void *sink_ctx);
/* Contacts of the current list that touch (gap <= slop). */
uint32_t rbs__touching(const rbs_world *w);
double rbs__max_overlap(const rbs_world *w);
/* A contact whose coordinates are too coarse for its slop (rbs__overlap_grew):
 * bodies a and b (a = UINT32_MAX: none), the largest coordinate magnitude
 * among them, m, and the pair's slop, m. */
typedef struct rbs__coarse {
    uint32_t a, b;
    double at, slop;
} rbs__coarse;
/* Whether an overlap deeper than the slop appeared since start (the
 * rollback methods' test); *max_pen the deepest overlap now, *first (may be
 * NULL) the earliest fraction of the sub-step a grown pair touched; coarse
 * (may be NULL): the first grown contact whose coordinates round by more
 * than its slop (rbs__coarse_at), where the growth may be rounding alone. */
int rbs__overlap_grew(rbs_world *w, const double *start, double *max_pen, double *first, rbs__coarse *coarse);
/* The spacing of doubles at magnitude x >= 0 (one unit in the last place;
 * 0 for 0 or a value not finite), m. */
static inline double rbs__spacing(double x)
{
    return x > 0.0 && isfinite(x) ? ldexp(1.0, ilogb(x) - 52) : 0.0;
}
/* The largest magnitude of a's coordinates. */
static inline double rbs__max_abs(v3 a)
{
    double m = fabs(a.x);
    m = fabs(a.y) > m ? fabs(a.y) : m;
    return fabs(a.z) > m ? fabs(a.z) : m;
}
/* Whether coordinates of magnitude up to at round by more than slop (half
 * their spacing): there a contact's gap is rounding, not geometry, and a
 * method that decides by the slop (rollback, events) cannot resolve it. */
static inline int rbs__coarse_at(double at, double slop)
{
    return 0.5 * rbs__spacing(at) > slop;
}
/* RBS_E_NUMERIC for a contact too coarse for its slop, c (step.c). */
rbs_status rbs__coarse_error(rbs_world *w, const rbs__coarse *c);
/* Whether bodies a and b (b may be a plane), apart by gap, touch within
 * slop and the rounding of their coordinates while those round by more
 * than the slop: then into *out, 1 (contact.c). */
int rbs__coarse_touch(const rbs_world *w, uint32_t a, uint32_t b, double gap, double slop, rbs__coarse *out);
/* The first sphere touching a plane, or pair among the world's current
 * contacts, so (rbs__coarse_touch), into *out: 1, else 0 (an error's path). */
int rbs__coarse_contact(const rbs_world *w, rbs__coarse *out);
/* Push apart overlap deeper than the slop (planes, then pairs); 1 if it
 * pushed anything.  *max_pen (may be NULL): the deepest overlap of the
 * state the pass leaves (what rbs__max_overlap_now would say). */
int rbs__separate(rbs_world *w, double *max_pen);
double rbs__max_overlap_now(rbs_world *w); /* deepest overlap of the state as it is */
/* Velocity of the point at r from body i's centre of mass. */
static inline v3 rbs__point_velocity(const rbs_world *w, uint32_t i, v3 r)
{
    return v3_add(v3_load(&w->vel[3 * i]), v3_cross(v3_load(&w->avel[3 * i]), r));
}

/* A contact's levers: from each body's centre of mass to the contact point.
 * Along n (la n, lb n) unless the body's centre of mass is off its centre,
 * whose offset R c then comes off (the lever from the centre is along n). */
static inline v3 rbs__contact_lever(const rbs_world *w, const rbs__contact *c, uint32_t i, double l, uint32_t off)
{
    v3 r = v3_scale(c->n, l);
    if (c->flags & off)
        r = v3_sub(r, q_rotate(q_load(&w->orient[4 * i]), v3_load(&w->com_body[3 * i])));
    return r;
}
/* Body a's lever along n: the contact point is a's surface point, r_a
 * behind its centre (a is always a sphere). */
static inline double rbs__contact_la(const rbs_world *w, const rbs__contact *c)
{
    return -w->radius[c->a];
}
static inline v3 rbs__contact_ra(const rbs_world *w, const rbs__contact *c)
{
    return rbs__contact_lever(w, c, c->a, rbs__contact_la(w, c), RBS__OFF_A);
}
static inline v3 rbs__contact_rb(const rbs_world *w, const rbs__contact *c)
{
    return rbs__contact_lever(w, c, c->b, c->lb, RBS__OFF_B);
}
/* The allowed overlap of a contact's pair, m: def.slop times the smaller
 * radius (a's against a plane). */
static inline double rbs__contact_slop(const rbs_world *w, const rbs__contact *c)
{
    double ra = w->radius[c->a], rb = w->radius[c->b];
    return w->def.slop * (w->type[c->b] == RBS_BODY_PLANE || ra < rb ? ra : rb);
}
/* The material-pair row of a contact: its friction and resistance. */
static inline const rbs__pair *rbs__contact_pair(const rbs_world *w, const rbs__contact *c)
{
    return &w->pair[c->row];
}

/* A contact's coefficient of restitution: its pair row's (e < 0 there: the
 * world's), 0 when it is marked RBS__INELASTIC.  Looked up rather than kept
 * in the contact, so that a contact is 128 bytes (two cache lines). */
static inline double rbs__contact_e(const rbs_world *w, const rbs__contact *c)
{
    const rbs__pair *p;
    if (c->flags & RBS__INELASTIC)
        return 0.0;
    p = rbs__contact_pair(w, c);
    return p->e >= 0.0 ? p->e : w->def.restitution;
}

/* Impulse j and angular impulse tau (= r x j) on body i (nothing for fixed
 * bodies): for a caller that has r x j in a cheaper form. */
static inline void rbs__apply_impulse_torque(rbs_world *w, uint32_t i, v3 j, v3 tau)
{
    v3 dw;
    if (w->inv_mass[i] == 0.0)
        return;
    v3_store(&w->vel[3 * i], v3_mad(v3_load(&w->vel[3 * i]), j, w->inv_mass[i]));
    rbs__body_inv_inertia_world(w, i, tau, &dw);
    v3_store(&w->avel[3 * i], v3_add(v3_load(&w->avel[3 * i]), dw));
}

/* Impulse j at r from body i's centre of mass (nothing for fixed bodies). */
static inline void rbs__apply_impulse(rbs_world *w, uint32_t i, v3 r, v3 j)
{
    rbs__apply_impulse_torque(w, i, j, v3_cross(r, j));
}

/* Solver (solver.c). */
void rbs__solve_collisions(rbs_world *w, rbs_step_info *info);
void rbs__collide(rbs_world *w, const rbs__contact *c, double vn);
double rbs__normal_velocity(const rbs_world *w, const rbs__contact *c);
/* Whether contact c's approach at normal velocity vn (< 0) is rounding,
 * left to the resting pass: it closes less than a millionth of the slop in
 * a frame and is below 2^-40 of the bodies' own speeds (|v|, r |omega|, and
 * |a| dt, what a frame of their forces builds).  A settled pile's balls met
 * the walls at 1e-22 m/s, ten "impacts" a frame (a probe of session 43);
 * the millionth of the slop alone also took a 1e-8 m/s approach at dt =
 * 1e-6 s, in zero gravity, as rounding: the ball stopped at the wall with
 * e = 1 (euler) or flew into it (event; a probe of session 45). */
int rbs__rounding_approach(const rbs_world *w, const rbs__contact *c, double vn);
void rbs__contact_finish(rbs_world *w, rbs__contact *c, double dt);
/* Material-pair row, levers, gap and flags of contact c (a, b, n set) whose centres are dist
 * apart (a sphere pair; unused for a plane) and whose surfaces gap. */
void rbs__contact_set(const rbs_world *w, rbs__contact *c, double dist, double gap);
double rbs__resting_threshold(v3 aa, v3 ab, v3 n, double dt);
/* Its part along n alone: the approach one step of the forces that press
 * the pair together builds, m/s (0 if they pull it apart). */
double rbs__press_threshold(v3 aa, v3 ab, v3 n, double dt);
/* w->pressed from the warm table as it is (contact.c). */
void rbs__mark_pressed(rbs_world *w);
/* Does the sphere pair a, b keep the whole resting threshold: it held a
 * load in the last resting pass (its warm entry, in key order), or both
 * spheres held one against other spheres (w->pressed: neighbours in a
 * pile)?  Else only the forces' press along n (contact.c). */
int rbs__pair_pressed(const rbs_world *w, uint32_t a, uint32_t b);
/* A plane contact of a sphere that held a load against another sphere
 * (w->pressed) keeps, besides the press along n, the sphere's acceleration
 * times dt as its resting threshold: its neighbours press it against walls
 * whatever their direction, as in a pile (contact.c). */
void rbs__pressed_plane(const rbs_world *w, rbs__contact *c, double dt);
/* That rule on a plane contact's threshold thr of sphere i, whose
 * acceleration is a: thr, or |a| dt if larger and i is pressed. */
double rbs__pressed_threshold(const rbs_world *w, uint32_t i, v3 a, double thr, double dt);
void rbs__solve_resting(rbs_world *w, rbs_step_info *info);
/* Rolling and spinning resistance at contact i, Jn > 0 (solver.c); returns
 * the square of the velocity change it made, 0 if none. */
double rbs__resist_row(rbs_world *w, uint32_t i);
/* The resting pass warm-started from the last warm pass, for a sub-step of h
 * seconds (h <= 0: cold, like rbs__solve_resting); stores its impulses. */
void rbs__solve_resting_warm(rbs_world *w, rbs_step_info *info, double h);
/* The linear acceleration (m/s^2) the warm start of a pass for a sub-step
 * of h seconds (> 0) predicts for each moving sphere -- its contacts' warm
 * impulses as the pass would apply them (impacts left out), over h and its
 * mass -- into
 * method_scratch[RBS__SCRATCH_STRIDE * i + at_slot .. + 2], 0 for a sphere
 * with none; call after the collision pass.  Returns whether any is not 0
 * (rk4's stages take it: step_rk4.c; solver.c). */
int rbs__warm_accelerations(rbs_world *w, double h, uint32_t at_slot);
/* verlet's and rk4's speculative contacts: each one's gap becomes the
 * reach the resting pass may let its end velocity close in the sub-step of
 * h seconds, given the trapezoid drift, and a touching sphere pair's bias
 * the approach the bend of its path needs (solver.c); call on the
 * sub-step's start velocities, after the collision pass. */
void rbs__trapezoid_reach(rbs_world *w, double h);
/* verlet's and rk4's resting pass takes an off-centre sphere's contact
 * rows at the sub-step's middle orientation: call after the start state
 * and the rotation's end are in method_scratch (per slot: q0 at q0_at, the
 * end qe at qe_at, spun_at nonzero when the rotation was sub-stepped) and
 * before the pass; w->orient of those spheres is left at the middle, for
 * the drift to replace (solver.c). */
void rbs__levers_at_middle(rbs_world *w, double h, uint32_t q0_at, uint32_t qe_at, uint32_t spun_at);
/* verlet's and rk4's drift moves positions by half of a resting pass's
 * impulses: after it, the other half of each sphere pair's impulse is
 * turned onto the pair's end normal (solver.c). */
void rbs__turn_second_halves(rbs_world *w);

/* The warm-start table (solver.c): the key of a contact's body pair; store
 * the resting impulse rates of the current contacts (those with jn != 0)
 * for a pass of h seconds, sorted by key; find key k's entry (NULL: none),
 * searching from *at, where the previous search ended (0 to start). */
uint64_t rbs__warm_key(const rbs_world *w, const rbs__contact *c);
/* The key of the pair of slots a, b (plane: b is a plane): planes before
 * pairs of spheres, each by (a, b). */
static inline uint64_t rbs__warm_key_of(int plane, uint32_t a, uint32_t b)
{
    return ((uint64_t)(plane == 0) << 63) | ((uint64_t)a << 32) | (uint64_t)b;
}
void rbs__warm_store(rbs_world *w, double h);
/* The table in key order again, if the soft step left it in its buckets
 * (before rbs__warm_find; solver.c). */
void rbs__warm_sort(rbs_world *w);
/* The table's first n entries are written (sorted: in key order; else they
 * are sorted now). */
void rbs__warm_finish(rbs_world *w, uint32_t n, int sorted);
const rbs__warm *rbs__warm_find(const rbs_world *w, uint64_t k, uint32_t *at);
/* A warm start's tangent impulse jt kept in the static cone of its normal
 * impulse, lim = mu_s jn >= 0: as it is inside the cone or on its edge,
 * else scaled back onto the edge (same direction, length lim).  (Before
 * sessions 37 (soft) and 38 (euler, selective) it was dropped outside the
 * cone; with mu_s = mu_k a sliding contact's stored friction lies on the
 * edge, and rounding kept or dropped it.)  Every warm start: the resting
 * pass (solver.c) and both of the soft step's layouts (soft_detect.c,
 * step_soft.c). */
static inline v3 rbs__warm_tangent(v3 jt, double lim)
{
    const double l2 = v3_dot(jt, jt);
    return l2 > lim * lim ? v3_scale(jt, lim / sqrt(l2)) : jt;
}

/* In-place heap sort of n elements of size bytes into ascending order of
 * greater (greater(x, y): x goes after y), with no allocation (sort.c). */
typedef int (*rbs__greater_fn)(const void *x, const void *y);
void rbs__heap_sort(void *base, uint32_t n, size_t size, rbs__greater_fn greater);

/* The file a chain of symbolic links ends at (malloc'd, the caller frees;
 * it need not exist yet), or NULL for a loop (more than 40 links) or no
 * memory.  A relative link is taken from its own folder.  For writers that
 * replace a file by renaming a temporary onto it (checkpoints, scenes): the
 * rename then lands on the link's target and the link stays. */
char *rbs__link_target(const char *path);

/* Length in bytes of the well-formed UTF-8 sequence at text[i] (i < len),
 * or 0 if it is not one (RFC 3629: no overlong forms, surrogates or code
 * points above U+10FFFF).  Body and material names (world.c) and scene
 * text (scene_json.c, scene_text.c) are checked with it. */
size_t rbs__utf8_seq(const char *text, size_t len, size_t i);

/* Largest size of each of a movable sphere's energies at the start, J (and
 * of its momenta, in their units): seven terms for each of 2^24 bodies then
 * sum to less than DBL_MAX. */
#define RBS__ENERGY_MAX 1e300

/* The terms rbs__sphere_energy bounds. */
#define RBS__SPHERE_LIMITS 7

/* A movable sphere's energies and momenta at the start into
 * e[RBS__SPHERE_LIMITS]: e[0] kinetic energy m |v|^2 / 2, e[1] rotational
 * (a bound: |w|^2 trace / 2, trace that of the inertia about the centre of
 * mass), e[2] potential in gravity g (m g.x, or g.x when g is a force),
 * e[3] potential of its force f (f.x), J; e[4] momentum |m v|, kg m/s;
 * e[5] angular momentum about the origin |x × m v|, and e[6] its spin
 * part (a bound: trace |w|), kg m^2/s; x the centre of mass in the world,
 * p + q c q* (q a unit quaternion, c the offset in the body frame).
 * Returns the index of the first whose size is beyond RBS__ENERGY_MAX (a
 * NaN is), or -1.  The one rule of rbs_world_add_sphere and the scene's
 * check (which names the key). */
int rbs__sphere_energy(double mass, double trace, rbs_vec3 v, rbs_vec3 w, rbs_vec3 p, rbs_quat q,
                       rbs_vec3 c, rbs_vec3 g, int g_is_force, rbs_vec3 f,
                       double e[RBS__SPHERE_LIMITS]);
/* Term k's unit ("J", "kg m/s", "kg m^2/s") and the world's sum it would
 * overflow ("energy", "momentum", "angular momentum"), for the messages of
 * both. */
const char *rbs__sphere_limit_unit(int k);
const char *rbs__sphere_limit_sum(int k);

/* Which body's momentum, or which sum, overflows in rbs_world_momentum,
 * said in buf (n bytes), e.g. "sphere 0 (\"ball\"): its angular momentum
 * r x m v overflows (|r| = 1.41e+300 m, |m v| = 1e+100 kg m/s)"; "" if
 * none does. */
void rbs__momentum_failure(const rbs_world *w, char *buf, size_t n);

/* Forces: body i's linear acceleration (gravity, and its applied force over
 * its mass) and its applied torque; zero for a body that does not move.
 * Inline: detection takes it for both bodies of every contact. */
static inline void rbs__accelerations(const rbs_world *w, uint32_t i, v3 *lin, v3 *torque)
{
    v3 g = v3_make(w->def.gravity.x, w->def.gravity.y, w->def.gravity.z);
    if (!rbs__body_moves(w, i)) {
        *lin = v3_make(0, 0, 0);
        *torque = v3_make(0, 0, 0);
        return;
    }
    if (w->def.gravity_mode == RBS_GRAVITY_FORCE)
        g = v3_scale(g, w->inv_mass[i]);
    *lin = v3_mad(g, v3_load(&w->force[3 * i]), w->inv_mass[i]);
    *torque = v3_load(&w->torque[3 * i]);
}

/* rbs__accelerations plus, with mutual gravity, the body's share of it as
 * w->acc holds it (rbs__detect computes it at the positions it detects
 * at).  Contacts' resting thresholds, the creep reach and selective's
 * late kicks take it: left out, two balls held together by their
 * attraction alone were bounced at every approach (rk4 and selective then
 * gained energy at e = 1, adaptive let them sink 4.6e-5 m between its
 * frame ends; probes of sessions 39 and 40). */
static inline void rbs__accelerations_all(const rbs_world *w, uint32_t i, v3 *lin, v3 *torque)
{
    rbs__accelerations(w, i, lin, torque);
    if (w->plan.mutual && rbs__body_moves(w, i))
        *lin = v3_add(*lin, v3_load(&w->acc[3 * i]));
}

/* State save/restore (step.c). */
void rbs__save_state(const rbs_world *w, double *save);
void rbs__restore_state(rbs_world *w, const double *save);
/* RBS_E_NUMERIC for slot bad, with the message of a step that made it NaN
 * or infinite (step.c). */
rbs_status rbs__numeric_error(rbs_world *w, uint32_t bad);

/* The shared rollback loop and Euler's pieces (step_euler.c).  An advance
 * function moves velocities and positions over one sub-step of h seconds,
 * after the collision pass; it may run the resting pass.  Every sub-step
 * detects speculative contacts too (all of the loop's methods take them
 * since session 45).  at_step_start:
 * the world is as rbs_world_step saved it in step_save (a whole frame),
 * which then serves as the first sub-steps' save instead of a copy.  span:
 * the time the sub-steps cover, s (def.dt for a frame; adaptive's rest of
 * one); the contacts' resting thresholds are the frame's, |a.n| def.dt,
 * whatever the span. */
typedef void (*rbs__advance_fn)(rbs_world *w, double h, rbs_step_info *info);
rbs_status rbs__step_rollback(rbs_world *w, rbs_step_info *info, rbs__advance_fn advance,
                              int at_step_start, double span);
/* An upper bound on the angle (rad) body i turns through over h from
 * orientation q and angular velocity om (world axes, rad/s) under the
 * world-frame torque tau (N m): |w| <= |L| |I^-1| with L = I(q) w, |L|
 * growing by at most |tau| h, and |I^-1| bounded by its largest row sum (a
 * constant of the body).  Torque-free it depends on |L| alone, an
 * invariant, so a part count taken from it stays the same from step to step
 * (verlet's, rk4's and euler's rotation parts). */
double rbs__spin_reach(const rbs_world *w, uint32_t i, quat q, v3 om, v3 tau, double h);
/* Rotation sub-steps for a body turning by reach rad over a sub-step (verlet,
 * rk4, and euler's turns past 1/2 rad): about reach / 0.25, 1 when the rotation is exact in one (torque-free
 * isotropic body), and within the step's budget (max_substeps * 256 in all).
 * Past the budget *stable is set, info->work_limit too, and the count is
 * the parts (the budget's rest, at least 1) to take with rbs__spin_stable. */
int rbs__spin_substeps(rbs_world *w, rbs_step_info *info, double reach, int exact, int *stable);
/* Body i's rotation over h from (*q, *om) under the world-frame torque tau
 * in n parts, each as euler takes it: L = I(q) w kicked by half the torque's
 * impulse, q turned by the part's middle angular velocity (wm = I(q_mid)^-1
 * L), the other half kick; then w = I(q')^-1 L.  Without torque |L| is kept
 * exactly, so the energy L.I^-1 L / 2 stays between |L|^2 / (2 I_max) and
 * |L|^2 / (2 I_min) at any angle per part: stable where verlet's and rk4's
 * rotation blow up.  The mean of the parts' turning velocities into *mean
 * (may be NULL). */
void rbs__spin_stable(const rbs_world *w, uint32_t i, v3 tau, double h, int n, quat *q, v3 *om, v3 *mean);
/* The angular velocity of a turn's middle for body i at orientation q with
 * angular momentum L over h: the fixed point wm = I(exp(wm h/2) q)^-1 L,
 * from the guess wm, iterated to convergence (a round changing it by at
 * most 1e-14 of itself; 32 rounds at most, step.c): euler's turn and
 * rbs__spin_stable's. */
v3 rbs__midpoint_spin(const rbs_world *w, uint32_t i, quat q, v3 L, v3 wm, double h);
/* Orientation at the end of a verlet or rk4 sub-step of h after the contact
 * impulses changed the angular velocity to om.  A body whose rotation was
 * sub-stepped (spun: it ended at qe, we) takes half of the impulses' change
 * as one more rotation; otherwise the spin was constant between contacts and
 * the rotation by the mean of the start (w0, from q0) and end velocities is
 * exact. */
static inline quat rbs__end_orientation(int spun, quat q0, v3 w0, quat qe, v3 we, v3 om, double h)
{
    v3 r = spun ? v3_scale(v3_sub(om, we), 0.5) : v3_add(w0, v3_scale(v3_sub(om, w0), 0.5));
    quat q = spun ? qe : q0;
    if (r.x != 0.0 || r.y != 0.0 || r.z != 0.0)
        q = q_normalize(q_mul(q_from_rotation(r, h), q));
    return q;
}

/* Angular acceleration I^-1 (tau - w x I w) of body i at unit orientation q
 * and angular velocity om (world axes); exactly zero when there is neither
 * torque nor a gyroscopic term.  For verlet and rk4's rotation sub-steps. */
static inline v3 rbs__angular_acceleration(const rbs_world *w, uint32_t i, v3 tau, v3 om, quat q)
{
    if (!w->isotropic[i])
        tau = v3_sub(tau, v3_cross(om, m3_mul_world(&w->inertia[9 * i], q, om)));
    if (tau.x == 0.0 && tau.y == 0.0 && tau.z == 0.0)
        return v3_make(0.0, 0.0, 0.0);
    if (w->isotropic[i])
        return v3_scale(tau, w->iso_inv_inertia[i]);
    return m3_mul_world(&w->inv_inertia[9 * i], q, tau);
}
void rbs__mutual_gravity(rbs_world *w);         /* fills w->acc */
/* The same at a sub-step's start: rbs__detect's sum when it is fresh (only
 * velocities changed since: the same numbers), else computed. */
void rbs__mutual_gravity_start(rbs_world *w);
void rbs__integrate_velocities(rbs_world *w, double h);
/* x += v h; the turn of step_euler.c (past 1/2 rad in parts, counted from
 * the step's rotation budget; info->work_limit when it is spent). */
void rbs__integrate_positions(rbs_world *w, double h, rbs_step_info *info);

/* Methods: one entry point each (step_<method>.c). */
rbs_status rbs__step_euler(rbs_world *w, rbs_step_info *info);
rbs_status rbs__step_verlet(rbs_world *w, rbs_step_info *info);
rbs_status rbs__step_rk4(rbs_world *w, rbs_step_info *info);
void rbs__rk4_advance(rbs_world *w, double h, rbs_step_info *info);
rbs_status rbs__step_adaptive(rbs_world *w, rbs_step_info *info);
/* GSL workspaces of the adaptive method: allocated once (creation or
 * set_method), freed by rbs_world_destroy (step_adaptive.c). */
typedef struct rbs__adaptive rbs__adaptive;
rbs_status rbs__adaptive_reserve(rbs_world *w);
void rbs__adaptive_release(rbs_world *w);
rbs_status rbs__step_event(rbs_world *w, rbs_step_info *info);
rbs_status rbs__step_selective(rbs_world *w, rbs_step_info *info);
rbs_status rbs__step_soft(rbs_world *w, rbs_step_info *info);

#define RBS__SAVE_STRIDE 13
#define RBS__SOFT_SUBSTEPS_MAX 1000u /* rbs_world_def.soft_substeps */
#define RBS__SOLVER_STRIDE 8   /* doubles per slot of solver_body */
#define RBS__SCRATCH_STRIDE 40 /* doubles per slot of method_scratch */
#define RBS__SCRATCH_EXTRA 8   /* doubles more: the alignment of the soft step's
                                  records */

#endif
