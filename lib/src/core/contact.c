/*
 * contact.c - sphere-plane and sphere-sphere detection, the swept overlap
 * test that triggers rollback, and separation of leftover overlap.
 *
 * Tolerances: a pair's slop is def.slop times the smaller radius.  Bodies
 * whose gap is at most the slop touch (a contact); an overlap deeper than the
 * slop that was not there at the start of the sub-step makes it roll back.
 *
 * Speculative contacts (for the rollback methods, whose resting pass takes
 * them; verlet's and rk4's reach is rbs__trapezoid_reach's): a pair apart by more than the slop but by at most its creep reach
 * thr * dt -- the distance an approach slower than the resting threshold
 * closes in one step -- is a contact too, with a positive gap.  The
 * collision pass leaves it alone (it does not touch), and so does the
 * resting pass when it approaches faster than thr (an impact: the method's
 * rollback finds it and it bounces with restitution).  Otherwise the resting
 * pass lets it close its gap down to the slop within the sub-step and no
 * further (Catto's speculative contacts, "Continuous Collision", GDC 2013).
 * Without them, a pile's contacts opened by a push or a sweep's rounding by
 * more than the slop (50 nm for 5 cm spheres) dropped out of the resting
 * pass and lost their warm start, and came back the next step as creeping
 * overlaps: the pile flickered and never settled.
 *
 * Swept contacts (the soft step): every pair within the slop plus both
 * bodies' sweeps over the frame; a closing pair of spheres that is apart
 * takes the normal of its touch on the straight paths (impact_normal); and
 * guards for the pairs only a kick within the frame can close
 * (detect_kicked).
 */
#include <string.h>

#include "core/world_internal.h"

/* Inverse effective mass along unit u: u . K u. */
static double inv_mass_along(const rbs_world *w, uint32_t a, v3 ra, uint32_t b, v3 rb, v3 u)
{
    double k = w->inv_mass[a] + w->inv_mass[b];
    v3 t, x;
    if (w->inv_mass[a] != 0.0) {
        x = v3_cross(ra, u);
        rbs__body_inv_inertia_world(w, a, x, &t);
        k += v3_dot(x, t);
    }
    if (w->inv_mass[b] != 0.0) {
        x = v3_cross(rb, u);
        rbs__body_inv_inertia_world(w, b, x, &t);
        k += v3_dot(x, t);
    }
    return k;
}

/* Resting threshold: the approach speed one step of the applied forces can
 * build.  Along the normal when the forces press the pair together
 * (-(a_a - a_b).n > 0, n from b to a); and, for two bodies that are both
 * driven (a ball in a pile is pressed sideways by its neighbours with forces
 * of the order of their weight), the smaller of their accelerations.  Forces
 * that pull a pair apart (a ball under a ceiling) give no threshold: every
 * approach there is an impact. */
double rbs__resting_threshold(v3 aa, v3 ab, v3 n, double dt)
{
    double press = -v3_dot(v3_sub(aa, ab), n), la = v3_len(aa), lb = v3_len(ab);
    double both = la < lb ? la : lb, thr = press > both ? press : both;
    return thr > 0.0 ? thr * dt : 0.0;
}

double rbs__press_threshold(v3 aa, v3 ab, v3 n, double dt)
{
    double press = -v3_dot(v3_sub(aa, ab), n);
    return press > 0.0 ? press * dt : 0.0;
}

void rbs__mark_pressed(rbs_world *w)
{
    uint32_t k;
    memset(w->pressed, 0, w->slots);
    for (k = 0; k < w->warm_used; ++k) {
        uint64_t key = w->warm[k].key;
        uint32_t a = (uint32_t)(key >> 32) & 0x7fffffffu, b = (uint32_t)key;
        /* a pair of moving spheres (rbs__warm_key_of); a load against a
         * fixed sphere is a floor's, not a neighbour's: two balls resting
         * on a dome of one met plastically (a review of session 43) */
        if ((key >> 63) && !w->fixed[a] && !w->fixed[b])
            w->pressed[a] = w->pressed[b] = 1;
    }
}

double rbs__pressed_threshold(const rbs_world *w, uint32_t i, v3 a, double thr, double dt)
{
    double side;
    if (!w->pressed[i])
        return thr;
    side = v3_len(a) * dt;
    return side > thr ? side : thr;
}

void rbs__pressed_plane(const rbs_world *w, rbs__contact *c, double dt)
{
    v3 a, t;
    if (w->type[c->b] != RBS_BODY_PLANE || !w->pressed[c->a])
        return;
    rbs__accelerations_all(w, c->a, &a, &t);
    c->thr = rbs__pressed_threshold(w, c->a, a, c->thr, dt);
}

int rbs__pair_pressed(const rbs_world *w, uint32_t a, uint32_t b)
{
    uint32_t at = 0;
    return (w->pressed[a] && w->pressed[b]) || rbs__warm_find(w, rbs__warm_key_of(0, a, b), &at) != NULL ||
           rbs__warm_find(w, rbs__warm_key_of(0, b, a), &at) != NULL;
}

/* The sideways part of the threshold is for neighbours that press each
 * other: a sphere pair that held no load in the last resting pass (no
 * entry in the warm table), one of whose spheres held none against any
 * other sphere either, keeps only the applied forces' press along n.  Two
 * free spheres meeting slower than g dt -- a Newton's cradle on a table,
 * re-colliding slowly -- met plastically in every method: two 1 kg balls on
 * a frictionless floor, e = 1, moved on together at u/2 below 9.8 mm/s (a
 * probe of session 41).  Neighbours in a pile keep the whole threshold
 * whether or not their own contact held a load: a pair that a collision
 * pass had bounced held none, its next slow approach was an impact again,
 * and settling piles chattered (the 288-ball euler pile took 3.5 times the
 * impacts; a probe of session 43). */
static void unloaded_pairs(rbs_world *w, double dt)
{
    uint32_t i, at = 0;
    for (i = 0; i < w->contact_count; ++i) {
        rbs__contact *c = &w->contact[i];
        v3 aa, ab, t;
        /* (the contacts come in key order: the search gallops on from the
         * last, O(1) a contact, as the resting pass's does) */
        if (w->type[c->b] != RBS_BODY_SPHERE || c->thr == 0.0 || (w->pressed[c->a] && w->pressed[c->b]) ||
            rbs__warm_find(w, rbs__warm_key(w, c), &at) != NULL)
            continue;
        rbs__accelerations_all(w, c->a, &aa, &t);
        rbs__accelerations_all(w, c->b, &ab, &t);
        c->thr = rbs__press_threshold(aa, ab, c->n, dt);
    }
}

/* Body i of a contact has its centre of mass off its centre: a moving
 * sphere with com_body != 0 (a fixed body's lever is from its centre). */
static int com_off(const rbs_world *w, uint32_t i)
{
    return w->type[i] == RBS_BODY_SPHERE && !w->fixed[i] &&
           (w->com_body[3 * i] != 0.0 || w->com_body[3 * i + 1] != 0.0 || w->com_body[3 * i + 2] != 0.0);
}

/* The contact point is a's surface point pa - r_a n: r_a behind a's centre
 * along n, and dist - r_a ahead of b's centre (a sphere; a plane takes no
 * lever: it never moves). */
void rbs__contact_set(const rbs_world *w, rbs__contact *c, double dist, double gap)
{
    /* (no row for this pair: the default row, frictionless with the world's
     * restitution; documented in rbsim.h, scenes reject this case) */
    c->row = rbs__pair_row(w, c->a, c->b);
    c->lb = w->type[c->b] == RBS_BODY_PLANE ? 0.0 : dist - w->radius[c->a];
    c->gap = gap;
    /* (the plan's gather: every sphere centred, no body off) */
    c->flags = gap > rbs__contact_slop(w, c) ? RBS__APART : 0u;
    if (!w->plan.gather)
        c->flags |= (com_off(w, c->a) ? RBS__OFF_A : 0u) | (com_off(w, c->b) ? RBS__OFF_B : 0u);
}

/* rbs__contact_finish with the bodies' accelerations aa, ab given. */
static void contact_finish(rbs_world *w, rbs__contact *c, double dt, v3 aa, v3 ab)
{
    v3 ra = rbs__contact_ra(w, c), rb = rbs__contact_rb(w, c);
    c->thr = rbs__resting_threshold(aa, ab, c->n, dt);
    c->kn = inv_mass_along(w, c->a, ra, c->b, rb, c->n);
    /* Isotropic bodies with both levers along n (no RBS__OFF flag: a fixed
     * body's lever runs from its centre): K is isotropic in the tangent
     * plane, 1/ma + 1/mb + |ra|^2/Ia + |rb|^2/Ib (0 for fixed); kept as its
     * inverse, which the sweeps multiply by. */
    c->kt_inv = 0.0;
    if (w->isotropic[c->a] && w->isotropic[c->b] && !(c->flags & RBS__OFF)) {
        double kt = w->inv_mass[c->a] + w->inv_mass[c->b] + v3_dot(ra, ra) * w->iso_inv_inertia[c->a] +
                    v3_dot(rb, rb) * w->iso_inv_inertia[c->b];
        c->kt_inv = kt > 0.0 ? 1.0 / kt : 0.0;
    }
    c->bias = 0.0;
    c->jn = 0.0;
    c->jt = v3_make(0, 0, 0);
    c->jslip = 0.0;
}

void rbs__contact_finish(rbs_world *w, rbs__contact *c, double dt)
{
    v3 aa, ab, t;
    rbs__accelerations_all(w, c->a, &aa, &t);
    rbs__accelerations_all(w, c->b, &ab, &t);
    contact_finish(w, c, dt, aa, ab);
}

/* A new contact's accelerations: from the swept detection's table (6
 * doubles a slot: acceleration, torque) or computed. */
static void finish_new(rbs_world *w, rbs__contact *c, double dt, const double *acc)
{
    if (acc != NULL)
        contact_finish(w, c, dt, v3_load(&acc[6 * c->a]), v3_load(&acc[6 * c->b]));
    else
        rbs__contact_finish(w, c, dt);
}

/* A detected contact with rolling or spinning resistance: its lever and
 * impulses beside it (see rbs__resist). */
static void resist_init(rbs_world *w, const rbs__contact *c, double radius)
{
    const rbs__pair *p = rbs__contact_pair(w, c);
    if (p->rolling > 0.0 || p->spinning > 0.0) {
        rbs__resist *r = &w->contact_resist[c - w->contact];
        r->radius = radius;
        r->jroll = v3_make(0, 0, 0);
        r->jspin = 0.0;
        r->impact = 0.0;
    }
}

/* A speculative contact farther apart than its creep reach thr * dt: not a
 * contact after all (its thr is known only once it is finished). */
static int beyond_reach(const rbs__contact *c, double slop, double dt)
{
    return (c->flags & RBS__APART) && !(c->gap <= slop + c->thr * dt);
}

/* The largest acceleration of a moving sphere times dt^2, m: a bound on
 * half of any pair's creep reach (thr <= (|a_a| + |a_b|) dt, contact.c's
 * rbs__resting_threshold). */
static double creep_bound(const rbs_world *w, double dt)
{
    uint32_t i;
    double most = 0.0;
    for (i = 0; i < w->sphere_count; ++i) {
        v3 a, t;
        double l;
        rbs__accelerations_all(w, w->spheres[i], &a, &t);
        l = v3_len(a);
        if (l > most)
            most = l;
    }
    most *= dt * dt;
    return isfinite(most) ? most : 0.0;
}

/* Detection state passed through the broad phase. */
typedef struct detect_ctx {
    rbs_world *w;
    double dt;
    double reach; /* speculative: a bound on every pair's creep reach, m (0: none) */
    int swept;    /* rbs__detect_swept: every pair the broad phase reports */
    const double *acc; /* swept: the bodies' accelerations (6 a slot), else NULL */
    double *kick;      /* swept, first pass: per slot, the sum of the kicks
                          its closing pairs can give it, m/s (else NULL) */
    const double *first; /* swept, second pass: the first pass's margins
                            (per slot), whose pairs it skips; else NULL */
    const double *centres; /* the broad phase's centres (the second pass) */
    rbs__contact_sink sink; /* swept: where contacts go instead of w->contact
                               (NULL: there), with sink_ctx */
    void *sink_ctx;
    rbs_status status;
} detect_ctx;

/* A detection's context: no reach, no kicks, no first pass yet; contacts
 * to sink (NULL: w->contact). */
static void ctx_init(detect_ctx *ctx, rbs_world *w, double dt, const double *acc, rbs__contact_sink sink,
                     void *sink_ctx)
{
    ctx->w = w;
    ctx->dt = dt;
    ctx->reach = 0.0;
    ctx->swept = 0;
    ctx->acc = acc;
    ctx->kick = NULL;
    ctx->first = NULL;
    ctx->centres = NULL;
    ctx->sink = sink;
    ctx->sink_ctx = sink_ctx;
    ctx->status = RBS_OK;
}

/* The spheres' centres for the broad phase, 3 doubles an item: their
 * positions in place when they hold consecutive slots (plan.consecutive),
 * else copied into bp_center (24 bytes a sphere made resident). */
static const double *sphere_centres(rbs_world *w)
{
    uint32_t i;
    if (w->plan.consecutive)
        return &w->pos[3 * w->spheres[0]];
    for (i = 0; i < w->sphere_count; ++i)
        memcpy(&w->bp_center[3 * i], &w->pos[3 * w->spheres[i]], 3 * sizeof(double));
    return w->bp_center;
}

/* A new contact: the next of w->contact, or with a sink the caller's tmp
 * (counted all the same); NULL when max_contacts are taken. */
static rbs__contact *contact_new(rbs_world *w, detect_ctx *ctx, rbs__contact *tmp)
{
    if (w->contact_count >= w->def.max_contacts) {
        if (ctx->status == RBS_OK)
            ctx->status = (rbs_status)rbs__world_set_error(w, RBS_E_CAPACITY,
                "more than max_contacts = %u contacts in one step (raise it: rbs_world_def.max_contacts, "
                "a scene's simulation.max_contacts, default 4 x bodies + 16; or shorten dt, as pairs "
                "within the bodies' reach over a step are contacts)",
                (unsigned)w->def.max_contacts);
        return NULL;
    }
    if (ctx->sink != NULL) {
        w->contact_count++;
        return tmp;
    }
    return &w->contact[w->contact_count++];
}

/* A new contact is complete: to the sink, or finished in place (its
 * material, thresholds and effective masses); 0 when it is not a contact
 * after all (a speculative contact beyond its creep reach, taken back) or
 * the sink failed. */
static int contact_done(rbs_world *w, detect_ctx *ctx, rbs__contact *c, double slop)
{
    if (ctx->sink != NULL) {
        rbs_status st = ctx->sink(ctx->sink_ctx, c);
        if (st != RBS_OK && ctx->status == RBS_OK)
            ctx->status = st;
        return 0;
    }
    finish_new(w, c, ctx->dt, ctx->acc);
    if (!ctx->swept)
        rbs__pressed_plane(w, c, ctx->dt);
    if (!ctx->swept && beyond_reach(c, slop, ctx->dt)) {
        w->contact_count--;
        return 0;
    }
    return 1;
}

/* The normal of a swept pair apart at the frame's start (d: from b's centre
 * to a's, ra + rb the sum of the radii) from the straight paths of the
 * frame-start velocities over the frame (u = v_a - v_b, 0 <= t <= dt):
 * where they first bring the spheres into touch, the unit n* of d + u t*
 * with t* the smaller root of |d + u t| = ra + rb; otherwise the unit of
 * d + u t at their closest approach within the frame (t = -d.u / u.u, or dt
 * if they are still closing then).  *gap is n* . d - ra - rb, the
 * separation along n* at the frame's start: along the straight paths it
 * reaches 0 at t* and no sooner, and it is never more than the true gap
 * (|d| >= n* . d).  *lb is b's lever at that moment: r_b at the touch,
 * else to a's surface point (as rbs__contact_set's).  Returns 0 (nothing
 * written) for a pair that is not closing. */
int rbs__impact_normal(const rbs_world *w, uint32_t a, uint32_t b, v3 d, double ra, double rb, double dt, v3 *n,
                       double *gap, double *lb)
{
    v3 u = v3_sub(v3_load(&w->vel[3 * a]), v3_load(&w->vel[3 * b])), at;
    double rsum = ra + rb, uu = v3_dot(u, u), du = v3_dot(d, u), dd = v3_dot(d, d) - rsum * rsum;
    double disc, touch, closest, len;
    int hit;
    if (!(du < 0.0 && dd > 0.0))
        return 0; /* not closing, or touching already */
    disc = du * du - uu * dd;
    /* (-du - sqrt(disc)) / uu without cancellation; no root: they pass */
    touch = disc >= 0.0 ? dd / (sqrt(disc) - du) : INFINITY;
    closest = -du / uu;
    hit = touch <= dt;
    at = v3_mad(d, u, hit ? touch : (closest < dt ? closest : dt));
    len = v3_len(at);
    if (!(len > 0.0 && isfinite(len)))
        return 0;
    *n = v3_scale(at, 1.0 / len);
    *gap = v3_dot(*n, d) - rsum;
    *lb = hit ? rb : rb + (len - rsum);
    return 1;
}

/* The kicks of a closing pair of spheres (d from b's centre to a's, dist
 * its length): an impact at the normal closing speed u changes a's velocity
 * by (1 + e) m_b / (m_a + m_b) u <= 2 m_b / (m_a + m_b) u (the impact law,
 * frictionless), and b's by 2 m_a / (m_a + m_b) u; each is added to its
 * body's sum in kick (m/s). */
double rbs__kick_speed(const rbs_world *w, uint32_t a, uint32_t b, v3 d, double dist)
{
    double du = v3_dot(d, v3_sub(v3_load(&w->vel[3 * a]), v3_load(&w->vel[3 * b])));
    double ia = w->inv_mass[a], ib = w->inv_mass[b];
    if (!(du < 0.0) || !(ia + ib > 0.0))
        return 0.0; /* (most pairs: not closing) */
    return -du / (dist * (ia + ib));
}

static void kick_add(const rbs_world *w, double *kick, uint32_t a, uint32_t b, v3 d, double dist)
{
    double u = rbs__kick_speed(w, a, b, d, dist);
    if (u == 0.0)
        return;
    kick[a] += 2.0 * w->inv_mass[a] * u;
    kick[b] += 2.0 * w->inv_mass[b] * u;
}

void rbs__pair_contact(const rbs_world *w, rbs__contact *c, uint32_t a, uint32_t b, v3 d, double dist, double dt,
                       int swept)
{
    c->a = a;
    c->b = b;
    rbs__contact_set(w, c, dist, dist - w->radius[a] - w->radius[b]); /* (the flags) */
    /* Swept (the soft step): a closing pair that is apart takes the normal
     * of the moment its straight paths touch within the frame (or, if they
     * do not, come closest in it), with the separation along it and the
     * levers of that moment, so that an oblique impact pushes along the
     * line of centres at impact and a pair that passes is not stopped short
     * (exact for straight paths: two spheres under one uniform gravity
     * have no relative acceleration).  The frame-start normal, as Catto's
     * speculative contacts take it, turned a 30-degree hit at 2 m/s by 0.1
     * degree, and stopped glancing pairs before they touched (a third of
     * the speed wrong at dt = 10 ms).  The prediction stops at the frame's
     * end: beyond it the frame's other impulses make it a guess (the whole
     * path's closest approach let a falling heap of 27 balls overlap by
     * 1.1 % of a radius instead of 0.15 %).  Spheres with the centre of
     * mass off the centre keep the frame-start normal (their centres do
     * not move straight); the flags keep the true gap. */
    rbs__pair_touch(w, a, b, d, dist, dt, swept && !(c->flags & RBS__OFF), &c->n, &c->gap, &c->lb);
}

void rbs__plane_contact(const rbs_world *w, rbs__contact *c, uint32_t a, uint32_t p, double gap)
{
    c->a = a;
    c->b = p;
    c->n = v3_load(&w->normal[3 * p]);
    rbs__contact_set(w, c, 0.0, gap);
}

static void detect_pair(void *vctx, uint32_t i, uint32_t j)
{
    detect_ctx *ctx = (detect_ctx *)vctx;
    rbs_world *w = ctx->w;
    uint32_t a = w->spheres[i], b = w->spheres[j];
    double ra = w->radius[a], rb = w->radius[b], rmin = ra < rb ? ra : rb, slop, dist, gap;
    v3 pa, d;
    rbs__contact *c, tmp;
    if (w->fixed[a] && w->fixed[b])
        return;
    if (ctx->first != NULL) {
        /* the second pass: a pair within the first pass's reaches is one
         * of its contacts (the broad phase's own test, the same bits) */
        const double *C = ctx->centres;
        double ex = C[3 * i] - C[3 * j], ey = C[3 * i + 1] - C[3 * j + 1], ez = C[3 * i + 2] - C[3 * j + 2];
        double sr = rbs__sphere_reach(w, a, ctx->first[a]) + rbs__sphere_reach(w, b, ctx->first[b]);
        if (ex * ex + ey * ey + ez * ez <= sr * sr)
            return;
    }
    pa = v3_load(&w->pos[3 * a]);
    d = v3_sub(pa, v3_load(&w->pos[3 * b]));
    slop = w->def.slop * rmin;
    dist = v3_len(d);
    gap = dist - ra - rb;
    if (ctx->kick != NULL && dist > 0.0)
        kick_add(w, ctx->kick, a, b, d, dist);
    /* (a full list takes touching contacts only; swept: the broad phase's
     * reaches are the bodies' sweeps, so every pair it reports is one) */
    if (gap > slop && !((ctx->swept || gap <= slop + ctx->reach) && w->contact_count < w->def.max_contacts))
        return;
    c = contact_new(w, ctx, &tmp);
    if (c == NULL)
        return;
    rbs__pair_contact(w, c, a, b, d, dist, ctx->dt, ctx->swept);
    if (ctx->first != NULL)
        c->flags |= RBS__GUARD;
    if (contact_done(w, ctx, c, slop))
        resist_init(w, c, ra * rb / (ra + rb));
}

/* The contacts of sphere a (slot) with the planes: those within the slop
 * plus reach; with skip >= 0 (the second pass) only those beyond the slop
 * plus skip, the first pass's reach, as guards.  RBS_OK, or the capacity
 * error. */
static rbs_status plane_contacts(rbs_world *w, detect_ctx *ctx, uint32_t a, double reach, double skip)
{
    v3 pa = v3_load(&w->pos[3 * a]);
    double ra = w->radius[a], slop = w->def.slop * ra;
    uint32_t k;
    for (k = 0; k < w->plane_count; ++k) {
        uint32_t b = w->planes[k];
        v3 n = v3_load(&w->normal[3 * b]);
        double gap = v3_dot(v3_sub(pa, v3_load(&w->pos[3 * b])), n) - ra;
        rbs__contact *c, tmp;
        /* (a plane does not accelerate: thr <= |a_a| dt; a full list
         * takes touching contacts only) */
        if (gap > slop && !(gap <= slop + reach && w->contact_count < w->def.max_contacts))
            continue;
        if (skip >= 0.0 && (gap <= slop || gap <= slop + skip))
            continue;
        c = contact_new(w, ctx, &tmp);
        if (c == NULL)
            return ctx->status;
        rbs__plane_contact(w, c, a, b, gap);
        if (skip >= 0.0)
            c->flags |= RBS__GUARD;
        if (contact_done(w, ctx, c, slop))
            resist_init(w, c, ra);
        if (ctx->status != RBS_OK)
            return ctx->status;
    }
    return RBS_OK;
}

/* The second pass of the swept detection: guards against kicks.  The
 * margins |v| dt + |a| dt^2 bound a sphere's path for its frame-start
 * velocity, but the frame's impacts change that velocity, and a sphere
 * kicked by a closing neighbour reaches pairs the margins left out.  Each
 * sphere's margin grows by dt times the sum of the kicks of the pairs
 * closing on it in the first pass (kick_add: one impact each; kicks passed
 * on through chains within the frame are not bounded), when that is more
 * than RBS__GUARD_DEPTH of the smallest sphere's radius (a shorter reach
 * cannot take a pair as deep as a guard lets it: leaving it out changes
 * nothing).  The pairs and planes the grown margins add follow the first
 * pass's contacts, flagged RBS__GUARD; step_soft.c's rows let them overlap
 * by RBS__GUARD_DEPTH of the smaller radius before they act, so that an
 * impact a kick brings about is still met whole in the next frame.  None of
 * the benchmark's piles has such a kick: their results are the same bits
 * as without this pass. */
static void detect_kicked(rbs_world *w, detect_ctx *ctx, const double *margin, double *kick, const double *centres)
{
    uint32_t i, kicked = 0;
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        double grow = w->fixed[a] || !isfinite(kick[a]) ? 0.0 : kick[a] * ctx->dt;
        int take = grow > RBS__GUARD_DEPTH * w->plan.min_radius;
        kick[a] = margin[a] + (take ? grow : 0.0); /* (from here the grown margin) */
        w->bp_query[i] = (uint8_t)take;
        kicked += (uint32_t)take;
        w->bp_reach[i] = rbs__sphere_reach(w, a, kick[a]);
    }
    if (kicked == 0)
        return;
    ctx->kick = NULL;
    ctx->first = margin;
    ctx->centres = centres;
    rbs__broadphase_pairs(w, centres, w->sphere_count, w->bp_query, w->def.slop, detect_pair, ctx);
    for (i = 0; i < w->sphere_count && ctx->status == RBS_OK; ++i)
        if (w->bp_query[i])
            (void)plane_contacts(w, ctx, w->spheres[i], kick[w->spheres[i]], margin[w->spheres[i]]);
}

/* The contacts of the state as it is.  margin (swept only): per slot, how
 * far the body may move within the step, m; a pair is a contact when its
 * gap is at most the slop plus both margins (a plane's is 0), and with kick
 * (per slot, scratch) the guards of detect_kicked follow.  Otherwise half
 * is half of the creep reach of speculative contacts (0: none). */
static rbs_status detect(rbs_world *w, double dt, double half, const double *margin, const double *acc,
                         double *kick, rbs__contact_sink sink, void *sink_ctx)
{
    uint32_t i;
    double slop_rel = w->def.slop;
    detect_ctx ctx;
    ctx_init(&ctx, w, dt, acc, sink, sink_ctx);
    ctx.reach = 2.0 * half;
    ctx.swept = margin != NULL;
    w->contact_count = 0;

    /* sphere - plane */
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        if (w->fixed[a])
            continue;
        if (plane_contacts(w, &ctx, a, margin != NULL ? margin[a] : half, -1.0) != RBS_OK)
            return ctx.status;
    }
    /* sphere - sphere, through the broad phase */
    if (w->plan.sphere_pairs) {
        const double *centres = sphere_centres(w);
        for (i = 0; i < w->sphere_count; ++i) {
            uint32_t a = w->spheres[i];
            w->bp_reach[i] = rbs__sphere_reach(w, a, margin != NULL ? margin[a] : half);
            if (kick != NULL)
                kick[a] = 0.0;
        }
        ctx.kick = margin != NULL ? kick : NULL;
        rbs__broadphase_pairs(w, centres, w->sphere_count, NULL, slop_rel, detect_pair, &ctx);
        if (ctx.kick != NULL && ctx.status == RBS_OK)
            detect_kicked(w, &ctx, margin, kick, centres);
    }
    if (w->contact_count > w->contacts_high)
        w->contacts_high = w->contact_count;
    return ctx.status;
}

rbs_status rbs__detect_guards(rbs_world *w, double dt, const double *margin, const double *acc, double *kick,
                              rbs__contact_sink sink, void *sink_ctx)
{
    detect_ctx ctx;
    ctx_init(&ctx, w, dt, acc, sink, sink_ctx);
    ctx.swept = 1;
    if (w->plan.sphere_pairs)
        detect_kicked(w, &ctx, margin, kick, sphere_centres(w));
    if (w->contact_count > w->contacts_high)
        w->contacts_high = w->contact_count;
    return ctx.status;
}

rbs_status rbs__detect(rbs_world *w, double dt, int speculative)
{
    /* (the sub-step that follows starts from these positions and takes
     * the same sum: rbs__mutual_gravity_start) */
    if (w->plan.mutual) {
        rbs__mutual_gravity(w);
        w->acc_fresh = 1;
    }
    rbs_status st;
    rbs__warm_sort(w);
    rbs__mark_pressed(w);
    st = detect(w, dt, speculative ? creep_bound(w, dt) : 0.0, NULL, NULL, NULL, NULL, NULL);
    if (st == RBS_OK)
        unloaded_pairs(w, dt);
    return st;
}

rbs_status rbs__detect_swept(rbs_world *w, double dt, const double *margin, const double *acc, double *kick,
                             rbs__contact_sink sink, void *sink_ctx)
{
    return detect(w, dt, 0.0, margin, acc, kick, sink, sink_ctx);
}

uint32_t rbs__touching(const rbs_world *w)
{
    uint32_t i, n = 0;
    for (i = 0; i < w->contact_count; ++i)
        n += !(w->contact[i].flags & RBS__APART);
    return n;
}

/* Penetration depth of a sphere pair from saved start and current centres:
 * the deepest along the straight path between them (swept test), and at the
 * start; *first is the fraction of the path where they first touch. */
static void sphere_pair_pen(v3 a0, v3 a1, v3 b0, v3 b1, double rsum, double *path, double *start,
                            double *end, double *first)
{
    v3 d0 = v3_sub(a0, b0), d1 = v3_sub(a1, b1), dd = v3_sub(d1, d0);
    double l2 = v3_dot(dd, dd), s = 0.0, dmin;
    if (l2 > 0.0) {
        s = -v3_dot(d0, dd) / l2;
        s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
    }
    dmin = v3_len(v3_mad(d0, dd, s));
    *start = rsum - v3_len(d0);
    *end = rsum - v3_len(d1);
    *path = rsum - dmin;
    if (*end > *path)
        *path = *end;
    /* |d0 + t dd| = rsum: the smaller root of a quadratic in t */
    *first = 0.0;
    if (l2 > 0.0 && *start < 0.0) {
        double bq = v3_dot(d0, dd), cq = v3_dot(d0, d0) - rsum * rsum, disc = bq * bq - l2 * cq;
        if (disc >= 0.0) {
            double t = (-bq - sqrt(disc)) / l2;
            *first = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        }
    }
}

typedef struct overlap_ctx {
    rbs_world *w;
    const double *save;
    int grew;
    double worst, first;
    rbs__coarse coarse;     /* the first grown contact too coarse for its slop */
} overlap_ctx;

/* A grown contact of bodies a and b whose coordinates (magnitudes up to at)
 * round by more than its slop: the first one kept. */
static void note_coarse(overlap_ctx *ctx, uint32_t a, uint32_t b, double at, double slop)
{
    if (ctx->coarse.a == UINT32_MAX && rbs__coarse_at(at, slop)) {
        ctx->coarse.a = a;
        ctx->coarse.b = b;
        ctx->coarse.at = at;
        ctx->coarse.slop = slop;
    }
}

static void overlap_pair(void *vctx, uint32_t i, uint32_t j)
{
    overlap_ctx *ctx = (overlap_ctx *)vctx;
    rbs_world *w = ctx->w;
    const uint32_t S = RBS__SAVE_STRIDE;
    uint32_t a = w->spheres[i], b = w->spheres[j];
    double ra = w->radius[a], rb = w->radius[b], rmin = ra < rb ? ra : rb, slop = w->def.slop * rmin;
    double path, start, end, first;
    if (w->fixed[a] && w->fixed[b])
        return;
    sphere_pair_pen(v3_load(&ctx->save[S * a]), v3_load(&w->pos[3 * a]), v3_load(&ctx->save[S * b]),
                    v3_load(&w->pos[3 * b]), ra + rb, &path, &start, &end, &first);
    if (end > ctx->worst)
        ctx->worst = end;
    if (path > slop && path > start + slop) {
        /* (where the sub-step started, which a rollback goes back to: a 1
         * mm ball at 1e8 m/s meeting a ball 1 m away in a frame of 1 s was
         * refused as a contact 1e8 m out, its trial's end; a probe of
         * session 45) */
        double at = rbs__max_abs(v3_load(&ctx->save[S * a]));
        at = fmax(at, rbs__max_abs(v3_load(&ctx->save[S * b])));
        ctx->grew = 1;
        if (first < ctx->first)
            ctx->first = first;
        note_coarse(ctx, a, b, at, slop);
    }
}

int rbs__overlap_grew(rbs_world *w, const double *save, double *max_pen, double *first, rbs__coarse *coarse)
{
    uint32_t i, k;
    const uint32_t S = RBS__SAVE_STRIDE;
    overlap_ctx ctx;
    ctx.w = w;
    ctx.save = save;
    ctx.grew = 0;
    ctx.worst = 0.0;
    ctx.first = 1.0;
    ctx.coarse.a = ctx.coarse.b = UINT32_MAX;
    ctx.coarse.at = ctx.coarse.slop = 0.0;
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        v3 a1 = v3_load(&w->pos[3 * a]), a0 = v3_load(&save[S * a]);
        double ra = w->radius[a];
        if (w->fixed[a])
            continue;
        for (k = 0; k < w->plane_count; ++k) {
            uint32_t b = w->planes[k];
            v3 n = v3_load(&w->normal[3 * b]), p = v3_load(&w->pos[3 * b]);
            double pen1 = ra - v3_dot(v3_sub(a1, p), n);
            double pen0 = ra - v3_dot(v3_sub(a0, p), n);
            double slop = w->def.slop * ra;
            if (pen1 > ctx.worst)
                ctx.worst = pen1;
            if (pen1 > slop && pen1 > pen0 + slop) {
                ctx.grew = 1;
                /* the fraction of the sub-step where it first touched */
                if (pen0 < 0.0 && -pen0 / (pen1 - pen0) < ctx.first)
                    ctx.first = -pen0 / (pen1 - pen0);
                else if (pen0 >= 0.0)
                    ctx.first = 0.0;
                note_coarse(&ctx, a, b, fmax(rbs__max_abs(a0), rbs__max_abs(p)), slop); /* (the start's) */
            }
        }
    }
    if (w->plan.sphere_pairs) {
        /* swept: items at the middle of their path, reaching half of it */
        for (i = 0; i < w->sphere_count; ++i) {
            uint32_t a = w->spheres[i];
            v3 a1 = v3_load(&w->pos[3 * a]), a0 = v3_load(&save[S * a]);
            v3_store(&w->bp_center[3 * i], v3_scale(v3_add(a0, a1), 0.5));
            w->bp_reach[i] = w->radius[a] + 0.5 * v3_len(v3_sub(a1, a0));
        }
        rbs__broadphase_pairs(w, NULL, w->sphere_count, NULL, 0.0, overlap_pair, &ctx);
    }
    *max_pen = ctx.worst;
    if (first)
        *first = ctx.first;
    if (coarse)
        *coarse = ctx.coarse;
    return ctx.grew;
}

/* Separation: a Gauss-Seidel projection of positions (the position pass of
 * Catto, "Modeling and Solving Constraints", GDC 2009; Jakobsen, "Advanced
 * Character Physics", GDC 2001).  Each overlap deeper than the slop is
 * pushed to zero along its normal, split by inverse mass (a plane does not
 * move), and the pushes are iterated, because in a pile one push closes the
 * gap of the next pair: a single pass can leave a packing deeper than it
 * found it.  The pairs are gathered once (one broad phase) into a list kept
 * in the contact array, which is free scratch once a method has solved its
 * contacts; the list holds every pair within SEP_MARGIN of touching, so a
 * push into a neighbour is seen too.  At most max_sweeps iterations, fewer
 * when no overlap is deeper than the slop.  Pushes move positions only:
 * velocities, and so energy, are untouched. */
#define SEP_MARGIN 0.05 /* of the smaller radius */

typedef struct sep_pair {
    uint32_t a, b; /* sphere, and sphere or plane */
} sep_pair;

typedef struct separate_ctx {
    rbs_world *w;
    double worst;
    sep_pair *list;
    uint32_t count, cap;
    int pushed;
    int overflow; /* a pair did not fit the list (pushed once, unlisted) */
} separate_ctx;

/* Push a and b (b a sphere) apart if they overlap deeper than the slop;
 * 1 if it pushed. */
static int push_pair(rbs_world *w, uint32_t a, uint32_t b, double *moved_by)
{
    double ra = w->radius[a], rb = w->radius[b], rmin = ra < rb ? ra : rb, pen, dist, wa, wb, wsum;
    v3 pa = v3_load(&w->pos[3 * a]), pb = v3_load(&w->pos[3 * b]), d, n;
    double sr = ra + rb, d2;
    d = v3_sub(pa, pb);
    d2 = v3_dot(d, d);
    /* Apart (most listed pairs, most iterations): d2 above sr^2 with room
     * for the rounding of sr * sr means |d| >= sr, so the overlap computed
     * below would be <= 0 and push nothing; skip its square root. */
    if (d2 > sr * sr * (1.0 + 1e-14))
        return 0;
    dist = sqrt(d2);
    pen = sr - dist;
    if (!(pen > w->def.slop * rmin))
        return 0;
    /* Coincident centres have no normal: pick +z (documented). */
    n = dist > 0.0 ? v3_scale(d, 1.0 / dist) : v3_make(0, 0, 1);
    wa = w->inv_mass[a];
    wb = w->inv_mass[b];
    wsum = wa + wb;
    v3_store(&w->pos[3 * a], v3_mad(pa, n, pen * wa / wsum));
    v3_store(&w->pos[3 * b], v3_mad(pb, n, -pen * wb / wsum));
    if (moved_by) {
        moved_by[w->item[a]] += pen * wa / wsum;
        moved_by[w->item[b]] += pen * wb / wsum;
    }
    return 1;
}

/* Push sphere a out of plane p if it is deeper than the slop; 1 if it
 * pushed.  moved_by (may be NULL): per sphere item, the distance pushed so
 * far, increased by this push (push_pair likewise). */
static int push_plane(rbs_world *w, uint32_t a, uint32_t p, double *moved_by)
{
    v3 n = v3_load(&w->normal[3 * p]), pa = v3_load(&w->pos[3 * a]);
    double ra = w->radius[a], pen = ra - v3_dot(v3_sub(pa, v3_load(&w->pos[3 * p])), n);
    if (!(pen > w->def.slop * ra))
        return 0;
    v3_store(&w->pos[3 * a], v3_mad(pa, n, pen));
    if (moved_by)
        moved_by[w->item[a]] += pen;
    return 1;
}

static int push(rbs_world *w, uint32_t a, uint32_t b, double *moved_by)
{
    return w->type[b] == RBS_BODY_SPHERE ? push_pair(w, a, b, moved_by) : push_plane(w, a, b, moved_by);
}

static void separate_keep(separate_ctx *ctx, uint32_t a, uint32_t b, double pen)
{
    if (pen > ctx->worst)
        ctx->worst = pen;
    if (ctx->count < ctx->cap) {
        ctx->list[ctx->count].a = a;
        ctx->list[ctx->count].b = b;
        ctx->count++;
    } else {
        /* the list is full (only when very many spheres overlap one
         * another): this pair gets the single push of the first pass */
        ctx->overflow = 1;
        if (push(ctx->w, a, b, NULL))
            ctx->pushed = 1;
    }
}

static void separate_pair(void *vctx, uint32_t i, uint32_t j)
{
    separate_ctx *ctx = (separate_ctx *)vctx;
    rbs_world *w = ctx->w;
    uint32_t a = w->spheres[i], b = w->spheres[j];
    double ra = w->radius[a], rb = w->radius[b], rmin = ra < rb ? ra : rb;
    v3 d;
    double pen;
    if (w->fixed[a] && w->fixed[b])
        return;
    d = v3_sub(v3_load(&w->pos[3 * a]), v3_load(&w->pos[3 * b]));
    pen = ra + rb - v3_len(d);
    if (pen > -SEP_MARGIN * rmin)
        separate_keep(ctx, a, b, pen);
}

/* The deepest overlap of the state after the pushes, from the list alone
 * when that is exact: a pair left off the list had a gap of more than
 * SEP_MARGIN of its smaller radius, and closes by at most what its two
 * bodies were pushed; while every body moved less than a quarter of that
 * margin, no unlisted pair can touch, and the listed ones give the same
 * answer as measuring the whole world (the same expressions as
 * rbs__overlap_grew's, with its broad phase's candidate test), one broad
 * phase cheaper.  Otherwise the whole world is measured. */
static double overlap_after(rbs_world *w, const separate_ctx *ctx, const double *moved_by)
{
    uint32_t i;
    double most = 0.0, worst = 0.0;
    if (ctx->overflow)
        return rbs__max_overlap_now(w);
    for (i = 0; i < w->sphere_count; ++i)
        if (!(moved_by[i] <= most)) /* (NaN too) */
            most = moved_by[i];
    if (!(4.0 * most < SEP_MARGIN * w->plan.min_radius))
        return rbs__max_overlap_now(w);
    for (i = 0; i < ctx->count; ++i) {
        const sep_pair *p = &ctx->list[i];
        v3 pa = v3_load(&w->pos[3 * p->a]);
        double ra = w->radius[p->a], pen;
        if (w->type[p->b] == RBS_BODY_SPHERE) {
            v3 d = v3_sub(pa, v3_load(&w->pos[3 * p->b]));
            double sr = ra + w->radius[p->b];
            if (!(v3_dot(d, d) <= sr * sr))
                continue; /* not a candidate of the broad phase */
            pen = sr - v3_len(d);
        } else {
            pen = ra - v3_dot(v3_sub(pa, v3_load(&w->pos[3 * p->b])), v3_load(&w->normal[3 * p->b]));
        }
        if (pen > worst)
            worst = pen;
    }
    return worst;
}

int rbs__separate(rbs_world *w, double *max_pen)
{
    uint32_t i, k, it;
    int32_t *moved;
    double *moved_by;
    separate_ctx ctx;
    ctx.w = w;
    ctx.worst = 0.0;
    ctx.pushed = 0;
    ctx.overflow = 0;
    ctx.list = (sep_pair *)(void *)w->contact;
    ctx.count = 0;
    ctx.cap = (uint32_t)((size_t)w->def.max_contacts * sizeof(rbs__contact) / sizeof(sep_pair));
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        double ra = w->radius[a];
        v3 pa;
        if (w->fixed[a])
            continue;
        pa = v3_load(&w->pos[3 * a]);
        for (k = 0; k < w->plane_count; ++k) {
            uint32_t b = w->planes[k];
            double pen = ra - v3_dot(v3_sub(pa, v3_load(&w->pos[3 * b])), v3_load(&w->normal[3 * b]));
            if (pen > -SEP_MARGIN * ra)
                separate_keep(&ctx, a, b, pen);
        }
    }
    if (w->plan.sphere_pairs) {
        const double *centres = sphere_centres(w);
        for (i = 0; i < w->sphere_count; ++i)
            w->bp_reach[i] = w->radius[w->spheres[i]] * (1.0 + SEP_MARGIN);
        rbs__broadphase_pairs(w, centres, w->sphere_count, NULL, SEP_MARGIN, separate_pair, &ctx);
    }
    if (max_pen)
        *max_pen = ctx.worst;
    /* nothing deeper than the slop: nothing to push (the common case) */
    if (!(ctx.worst > w->def.slop * w->plan.min_radius) && !ctx.pushed)
        return 0;
    /* An entry whose bodies have not moved since it was last looked at has
     * the overlap it was left with, at most the slop: it is skipped.  Each
     * sphere item's last move is stamped (iteration + 1) in bp_cell, free
     * scratch once the broad phase has run; an entry is looked at in
     * iteration it when a body of it moved in iteration it - 1 or it. */
    moved = w->bp_cell;
    moved_by = w->bp_reach; /* free too: what each item was pushed, m */
    for (i = 0; i < w->sphere_count; ++i) {
        moved[3 * i] = 0;
        moved_by[i] = 0.0;
    }
    for (it = 0; it < w->def.max_sweeps; ++it) {
        int pushed = 0;
        for (i = 0; i < ctx.count; ++i) {
            const sep_pair *p = &ctx.list[i];
            int sphere = w->type[p->b] == RBS_BODY_SPHERE;
            uint32_t ia = w->item[p->a], ib = sphere ? w->item[p->b] : 0;
            if (it > 0 && moved[3 * ia] < (int32_t)it && !(sphere && moved[3 * ib] >= (int32_t)it))
                continue;
            if (push(w, p->a, p->b, moved_by)) {
                moved[3 * ia] = (int32_t)it + 1;
                if (sphere)
                    moved[3 * ib] = (int32_t)it + 1;
                pushed = 1;
            }
        }
        if (!pushed)
            break;
        ctx.pushed = 1;
    }
    if (max_pen && ctx.pushed)
        *max_pen = overlap_after(w, &ctx, moved_by);
    return ctx.pushed;
}

int rbs__coarse_touch(const rbs_world *w, uint32_t a, uint32_t b, double gap, double slop, rbs__coarse *out)
{
    const double at = fmax(rbs__max_abs(v3_load(&w->pos[3 * a])), rbs__max_abs(v3_load(&w->pos[3 * b])));
    if (!(gap <= slop + 4.0 * rbs__spacing(at)) || !rbs__coarse_at(at, slop))
        return 0;
    out->a = a;
    out->b = b;
    out->at = at;
    out->slop = slop;
    return 1;
}

int rbs__coarse_contact(const rbs_world *w, rbs__coarse *out)
{
    uint32_t i, k;
    for (i = 0; i < w->sphere_count; ++i) {
        const uint32_t a = w->spheres[i];
        const v3 x = v3_load(&w->pos[3 * a]);
        if (w->fixed[a])
            continue;
        for (k = 0; k < w->plane_count; ++k) {
            const uint32_t p = w->planes[k];
            const double gap = v3_dot(v3_sub(x, v3_load(&w->pos[3 * p])), v3_load(&w->normal[3 * p])) - w->radius[a];
            if (rbs__coarse_touch(w, a, p, gap, w->def.slop * w->radius[a], out))
                return 1;
        }
    }
    for (i = 0; i < w->contact_count; ++i) {
        const rbs__contact *c = &w->contact[i];
        if (rbs__coarse_touch(w, c->a, c->b, c->gap, rbs__contact_slop(w, c), out))
            return 1;
    }
    return 0;
}

double rbs__max_overlap_now(rbs_world *w)
{
    double pen = 0.0;
    rbs__save_state(w, w->sub_save); /* start = end: no motion, only depth */
    rbs__overlap_grew(w, w->sub_save, &pen, NULL, NULL);
    return pen;
}

double rbs__max_overlap(const rbs_world *w)
{
    uint32_t i;
    double worst = 0.0;
    for (i = 0; i < w->contact_count; ++i)
        if (-w->contact[i].gap > worst)
            worst = -w->contact[i].gap;
    return worst;
}
