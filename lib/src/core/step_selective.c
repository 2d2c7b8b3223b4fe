/*
 * step_selective.c - semi-implicit Euler with selective rollback
 * (RBS_METHOD_SELECTIVE, the seed's "selective rollback" improvement).
 *
 * The whole world takes one Euler step of dt (contacts, forces, resting
 * contact, positions).  Then, instead of undoing the step for everyone when
 * two bodies overlap, only the bodies of each overlapping pair go back: each
 * body's motion over the step is the straight Euler path x0 + s h v, so the
 * pair is moved back along its own path to the fraction s* of the step where
 * it first touches, the collision impulse is applied there (the same
 * restitution and Coulomb friction as every method), and the pair goes on
 * with its new velocities for the rest of the step.  The rest of the world
 * keeps its full step.  New overlaps this creates are found and handled the
 * same way, earliest first, in at most max_sweeps rounds; anything left is
 * pushed apart and reported (floor_hits, sweep_limit).
 *
 * Each body keeps the start of its current straight path: its position and
 * orientation there (in w->sub_save) and the fraction t0 where it starts
 * (w->ev_alpha[i], scratch this method borrows from the event method).
 * Cost: one step plus O(1) per impact, instead of a whole-world sub-step per
 * halving.  Accuracy: first order, like Euler.  The impact point lies
 * exactly on the Euler path; the impulse acts on the velocity the body has at
 * that time (the part of the step's force kick a dt after the impact is taken
 * away first and given back after), so a bounce neither gains nor is
 * inflated by the forces of the rest of the step.  Approaches slower than
 * one step of the forces builds are resting contact, left to the
 * warm-started resting pass and the end-of-step separation.
 */
#include <string.h>

#include "core/world_internal.h"

#define S RBS__SAVE_STRIDE
#define T0(w, i) ((w)->ev_alpha[i]) /* (dense: one double a body made resident, not three) */

/* A violation found by the search: a pair and the fraction it first touches. */
typedef struct violation {
    uint32_t a, b;
    double s;
} violation;

/* The fix-up rounds' neighbour list (Verlet's "neighbour list" of molecular
 * dynamics, L. Verlet, Phys. Rev. 159, 98, 1967).  The first round's broad
 * phase gives each sphere item a ball: the middle of its path (bp_center)
 * and a reach (bp_reach) of its radius, half its path and a skin of
 * SKIN radii; every pair whose balls meet is kept in the list.  While each
 * body's path, cut and re-aimed by fix-ups, stays inside its ball, two
 * bodies not on the list cannot touch, so a round only tests listed pairs
 * with a moved body instead of rebuilding the grid.  A body whose path
 * leaves its ball (or a list too long for its scratch) sends the rest of
 * the step back to the grid: the list saves work, it never decides. */
#define SKIN 0.1

typedef struct search_ctx {
    rbs_world *w;
    double h;
    uint32_t count, cap;
    violation *out;
    uint32_t *list;             /* item pairs, 2 per pair */
    uint32_t list_count, list_cap;
    int building, list_full;    /* round 0 appends to the list */
} search_ctx;

/* Position of body i at fraction s of the step (on its current path). */
static v3 pos_at(const rbs_world *w, uint32_t i, double s, double h)
{
    if (w->fixed[i] || w->type[i] != RBS_BODY_SPHERE)
        return v3_load(&w->pos[3 * i]);
    return v3_mad(v3_load(&w->sub_save[S * i]), v3_load(&w->vel[3 * i]), (s - T0(w, i)) * h);
}

static void record(search_ctx *ctx, uint32_t a, uint32_t b, double s)
{
    if (ctx->count < ctx->cap) {
        ctx->out[ctx->count].a = a;
        ctx->out[ctx->count].b = b;
        ctx->out[ctx->count].s = s;
    }
    ctx->count++;
}

/* Did the sphere pair (a, b) hold a load in the last resting pass (an
 * entry of the warm table, in key order since rbs__detect)?  Else its
 * resting threshold is only the press along n (contact.c, unloaded_pairs). */
static int pair_loaded(const rbs_world *w, uint32_t a, uint32_t b)
{
    uint32_t at = 0, at2 = 0;
    return rbs__warm_find(w, rbs__warm_key_of(0, a, b), &at) != NULL ||
           rbs__warm_find(w, rbs__warm_key_of(0, b, a), &at2) != NULL;
}

/* Is the approach along n slower than one step of the applied forces can
 * build (a resting contact creeping, not an impact)?  Such overlap is left
 * to the warm-started resting pass and the end-of-step separation: pairwise
 * fix-ups cannot hold a stack whose masses differ by orders of magnitude. */
static int creeping(const rbs_world *w, uint32_t a, uint32_t b, v3 n, double s)
{
    v3 aa, ab, ta, vrel;
    double vn;
    rbs__accelerations_all(w, a, &aa, &ta);
    rbs__accelerations_all(w, b, &ab, &ta);
    /* the relative velocity at the time of touch: without the part of the
     * step's force kick that comes after it */
    vrel = v3_sub(v3_load(&w->vel[3 * a]),
                  w->type[b] == RBS_BODY_SPHERE ? v3_load(&w->vel[3 * b]) : v3_make(0, 0, 0));
    vrel = v3_mad(vrel, v3_sub(aa, ab), -(1.0 - s) * w->def.dt);
    vn = v3_dot(vrel, n);
    /* the same threshold as a detected contact's (contact.c: a sphere pair
     * that held no load in the last pass has only the press along n) */
    if (w->type[b] == RBS_BODY_SPHERE && !pair_loaded(w, a, b))
        return -vn <= rbs__press_threshold(aa, ab, n, w->def.dt);
    return -vn <= rbs__resting_threshold(aa, ab, n, w->def.dt);
}

/* Take away (sign -1) or give back (+1) the part of the step's force kick
 * a dt that comes after fraction s, so an impact sees the velocity it has
 * when it happens and only the rest of the step's forces act after it. */
static void late_kick(rbs_world *w, uint32_t i, double s, double sign)
{
    v3 a, t;
    if (w->type[i] != RBS_BODY_SPHERE || w->fixed[i])
        return;
    rbs__accelerations_all(w, i, &a, &t); /* (the kick the step gave: mutual gravity too) */
    v3_store(&w->vel[3 * i], v3_mad(v3_load(&w->vel[3 * i]), a, sign * (1.0 - s) * w->def.dt));
}

/* Sphere-sphere: does the pair overlap deeper along its paths than at their
 * common start, and when does it first touch?  Returns 1 and *s if so. */
static int pair_violates(const rbs_world *w, uint32_t a, uint32_t b, double h, double *s)
{
    double tl = T0(w, a) > T0(w, b) ? T0(w, a) : T0(w, b), R = w->radius[a] + w->radius[b];
    double rmin = w->radius[a] < w->radius[b] ? w->radius[a] : w->radius[b];
    double slop = w->def.slop * rmin, l2, u = 0.0, dmin, pen0, path, first = 0.0;
    v3 d0 = v3_sub(pos_at(w, a, tl, h), pos_at(w, b, tl, h));
    v3 d1 = v3_sub(v3_load(&w->pos[3 * a]), v3_load(&w->pos[3 * b]));
    v3 dd = v3_sub(d1, d0);
    l2 = v3_dot(dd, dd);
    if (l2 > 0.0) {
        u = -v3_dot(d0, dd) / l2;
        u = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);
    }
    dmin = v3_len(v3_mad(d0, dd, u));
    pen0 = R - v3_len(d0);
    path = R - dmin;
    if (!(path > slop && path > pen0 + slop))
        return 0;
    /* touching when the step began and untouched by a fix-up since: its
     * impact (if any) was resolved at the step's start; what is left is
     * resting contact creeping, for the resting pass */
    if (T0(w, a) == 0.0 && T0(w, b) == 0.0 && pen0 >= -slop)
        return 0;
    if (pen0 < 0.0 && l2 > 0.0) {
        double bq = v3_dot(d0, dd), cq = v3_dot(d0, d0) - R * R, disc = bq * bq - l2 * cq;
        if (disc >= 0.0) {
            first = (-bq - sqrt(disc)) / l2;
            first = first < 0.0 ? 0.0 : (first > 1.0 ? 1.0 : first);
        }
    }
    *s = tl + (1.0 - tl) * first;
    {
        v3 dt_ = v3_mad(d0, dd, first);
        double dl = v3_len(dt_);
        if (dl > 0.0 && creeping(w, a, b, v3_scale(dt_, 1.0 / dl), *s))
            return 0;
    }
    return 1;
}

/* Sphere-plane: the same question for a sphere and a half-space. */
static int plane_violates(const rbs_world *w, uint32_t a, uint32_t p, double h, double *s)
{
    v3 n = v3_load(&w->normal[3 * p]), pt = v3_load(&w->pos[3 * p]);
    double r = w->radius[a], t0 = T0(w, a), slop = w->def.slop * r;
    double pen0 = r - v3_dot(v3_sub(pos_at(w, a, t0, h), pt), n);
    double pen1 = r - v3_dot(v3_sub(v3_load(&w->pos[3 * a]), pt), n);
    if (!(pen1 > slop && pen1 > pen0 + slop))
        return 0;
    if (t0 == 0.0 && pen0 >= -slop)
        return 0; /* resting contact creeping (see pair_violates) */
    *s = pen0 < 0.0 ? t0 + (1.0 - t0) * (-pen0 / (pen1 - pen0)) : t0;
    return !creeping(w, a, p, n, *s);
}

static void search_pair(void *vctx, uint32_t i, uint32_t j)
{
    search_ctx *ctx = (search_ctx *)vctx;
    rbs_world *w = ctx->w;
    uint32_t a = w->spheres[i], b = w->spheres[j];
    double s;
    if (w->fixed[a] && w->fixed[b])
        return;
    if (ctx->building) {
        if (ctx->list_count < ctx->list_cap) {
            ctx->list[2 * ctx->list_count] = i;
            ctx->list[2 * ctx->list_count + 1] = j;
            ctx->list_count++;
        } else {
            ctx->list_full = 1;
        }
    }
    if (pair_violates(w, a, b, ctx->h, &s))
        record(ctx, a, b, s);
}

/* Find every pair whose overlap grew along the current paths.  Round 0
 * (masked == 0) searches every sphere and builds the neighbour list;
 * later rounds only pairs with a sphere marked in w->bp_query, from the list
 * when *list_ok, else from a grid rebuilt at the current paths. */
static uint32_t search(search_ctx *ctx, int masked, int *list_ok)
{
    rbs_world *w = ctx->w;
    double h = ctx->h, skin = masked ? 0.0 : SKIN; /* (of the radius, in the reach) */
    uint32_t i, k;
    ctx->count = 0;
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        double s;
        if (w->fixed[a] || (masked && !w->bp_query[i]))
            continue;
        for (k = 0; k < w->plane_count; ++k)
            if (plane_violates(w, a, w->planes[k], h, &s))
                record(ctx, a, w->planes[k], s);
    }
    if (!w->plan.sphere_pairs)
        return ctx->count;
    if (masked && *list_ok) {
        for (k = 0; k < ctx->list_count; ++k) {
            uint32_t p = ctx->list[2 * k], q = ctx->list[2 * k + 1];
            if (w->bp_query[p] || w->bp_query[q])
                search_pair(ctx, p, q);
        }
        return ctx->count;
    }
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        v3 p0 = pos_at(w, a, T0(w, a), h), p1 = v3_load(&w->pos[3 * a]);
        v3_store(&w->bp_center[3 * i], v3_scale(v3_add(p0, p1), 0.5));
        w->bp_reach[i] = w->radius[a] * (1.0 + skin) + 0.5 * v3_len(v3_sub(p1, p0));
    }
    ctx->building = !masked;
    rbs__broadphase_pairs(w, NULL, w->sphere_count, masked ? w->bp_query : NULL, skin, search_pair, ctx);
    ctx->building = 0;
    *list_ok = !masked && !ctx->list_full;
    return ctx->count;
}

/* Is body i's current path inside its ball of round 0 (see SKIN)?  Its
 * start is on an earlier path that was; the end decides. */
static int inside_ball(const rbs_world *w, uint32_t i)
{
    uint32_t k = w->item[i];
    v3 c = v3_load(&w->bp_center[3 * k]);
    return v3_len(v3_sub(v3_load(&w->pos[3 * i]), c)) + w->radius[i] <= w->bp_reach[k];
}

/* Later first touch, for ordering violations by it (rbs__heap_sort). */
static int later(const void *x, const void *y)
{
    return ((const violation *)x)->s > ((const violation *)y)->s;
}

/* Move body i back along its path to fraction s and start a new path there. */
static void cut_path(rbs_world *w, uint32_t i, double s, double h)
{
    v3 x;
    quat q;
    v3 om;
    if (w->fixed[i] || w->type[i] != RBS_BODY_SPHERE)
        return;
    x = pos_at(w, i, s, h);
    om = v3_load(&w->avel[3 * i]);
    q = q_load(&w->sub_save[S * i + 9]);
    if (om.x != 0.0 || om.y != 0.0 || om.z != 0.0)
        q = q_normalize(q_mul(q_from_rotation(om, (s - T0(w, i)) * h), q));
    v3_store(&w->sub_save[S * i], x);
    q_store(&w->sub_save[S * i + 9], q);
    T0(w, i) = s;
    v3_store(&w->pos[3 * i], x);
    q_store(&w->orient[4 * i], q);
}

/* Finish body i's step from its path start with its current velocities. */
static void finish_path(rbs_world *w, uint32_t i, double h)
{
    v3 om;
    double rest;
    quat q;
    if (w->fixed[i] || w->type[i] != RBS_BODY_SPHERE)
        return;
    rest = (1.0 - T0(w, i)) * h;
    v3_store(&w->pos[3 * i], v3_mad(v3_load(&w->sub_save[S * i]), v3_load(&w->vel[3 * i]), rest));
    om = v3_load(&w->avel[3 * i]);
    q = q_load(&w->sub_save[S * i + 9]);
    if (om.x != 0.0 || om.y != 0.0 || om.z != 0.0)
        q = q_normalize(q_mul(q_from_rotation(om, rest), q));
    q_store(&w->orient[4 * i], q);
}

/* The collision impulse of a pair touching now (positions at its time). */
static void collide_now(rbs_world *w, uint32_t a, uint32_t b, double dt, rbs_step_info *info)
{
    rbs__contact c;
    v3 pa = v3_load(&w->pos[3 * a]);
    double ra = w->radius[a], vn, dist = 0.0, gap;
    memset(&c, 0, sizeof c);
    c.a = a;
    c.b = b;
    if (w->type[b] == RBS_BODY_PLANE) {
        c.n = v3_load(&w->normal[3 * b]);
        gap = v3_dot(v3_sub(pa, v3_load(&w->pos[3 * b])), c.n) - ra;
    } else {
        double rb = w->radius[b];
        v3 d = v3_sub(pa, v3_load(&w->pos[3 * b]));
        dist = v3_len(d);
        c.n = dist > 0.0 ? v3_scale(d, 1.0 / dist) : v3_make(0, 0, 1);
        gap = dist - ra - rb;
    }
    rbs__contact_set(w, &c, dist, gap);
    rbs__contact_finish(w, &c, dt);
    if (w->type[b] == RBS_BODY_SPHERE && !pair_loaded(w, a, b)) {
        v3 aa, ab, t;
        rbs__accelerations_all(w, a, &aa, &t);
        rbs__accelerations_all(w, b, &ab, &t);
        c.thr = rbs__press_threshold(aa, ab, c.n, dt);
    }
    vn = rbs__normal_velocity(w, &c);
    if (!(vn < 0.0))
        return;
    if (-vn <= c.thr)
        c.flags |= RBS__INELASTIC; /* slower than one step of the forces builds: resting */
    rbs__collide(w, &c, vn);
    info->colliding++;
}

rbs_status rbs__step_selective(rbs_world *w, rbs_step_info *info)
{
    const double dt = w->def.dt;
    /* scratch after the solve: the contact array, half for violations and
     * half for the neighbour list */
    size_t half = (size_t)w->def.max_contacts * sizeof(rbs__contact) / 2;
    violation *v = (violation *)(void *)w->contact;
    uint32_t cap = (uint32_t)(half / sizeof(violation));
    uint32_t round, i, n = 0, contacts;
    int list_ok = 0;
    search_ctx ctx;
    rbs_status st;

    /* the whole world: one Euler step */
    rbs__save_state(w, w->sub_save);
    st = rbs__detect(w, dt, 1);
    if (st != RBS_OK)
        return st;
    rbs__solve_collisions(w, info);
    rbs__integrate_velocities(w, dt);
    rbs__solve_resting_warm(w, info, dt);
    rbs__integrate_positions(w, dt);
    contacts = rbs__touching(w);
    for (i = 0; i < w->slots; ++i)
        T0(w, i) = 0.0;

    /* selective rollback: overlapping pairs only, earliest first */
    ctx.w = w;
    ctx.h = dt;
    ctx.cap = cap;
    ctx.out = v;
    ctx.list = (uint32_t *)(void *)((unsigned char *)w->contact + half);
    ctx.list_count = 0;
    ctx.list_cap = (uint32_t)(half / (2 * sizeof(uint32_t)));
    ctx.list_full = 0;
    ctx.building = 0;
    for (round = 0; round < w->def.max_sweeps; ++round) {
        /* after the first round only bodies moved by a fix-up can overlap anew */
        n = search(&ctx, round > 0, &list_ok);
        memset(w->bp_query, 0, w->sphere_count);
        if (n == 0)
            break;
        if (n > cap)
            n = cap;
        rbs__heap_sort(v, n, sizeof *v, later);
        for (i = 0; i < n; ++i) {
            double s;
            uint32_t a = v[i].a, b = v[i].b;
            int still = w->type[b] == RBS_BODY_PLANE ? plane_violates(w, a, b, dt, &s)
                                                     : pair_violates(w, a, b, dt, &s);
            if (!still)
                continue; /* an earlier fix-up already changed this pair */
            cut_path(w, a, s, dt);
            cut_path(w, b, s, dt);
            late_kick(w, a, s, -1.0);
            late_kick(w, b, s, -1.0);
            collide_now(w, a, b, dt, info);
            late_kick(w, a, s, 1.0);
            late_kick(w, b, s, 1.0);
            finish_path(w, a, dt);
            finish_path(w, b, dt);
            w->bp_query[w->item[a]] = 1;
            if (w->type[b] == RBS_BODY_SPHERE)
                w->bp_query[w->item[b]] = 1;
            if (list_ok && (!inside_ball(w, a) || (w->type[b] == RBS_BODY_SPHERE && !inside_ball(w, b))))
                list_ok = 0; /* a path left its ball: the grid from now on */
            info->rollbacks++;
        }
    }
    if (n > 0 && round == w->def.max_sweeps) {
        /* what is left is pushed apart by the separation pass that
         * rbs_world_step runs after every selective step */
        info->sweep_limit++;
        info->floor_hits++;
    }
    info->substeps = 1;
    info->contacts = contacts;
    /* the deepest overlap is left for rbs_world_step to measure, after the
     * separation pass it runs anyway whenever there is overlap to push
     * apart: measuring here too would cost one more broad phase a step */
    w->overlap_unmeasured = 1;
    return RBS_OK;
}
