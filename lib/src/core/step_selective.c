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
 * keeps its full step.
 *
 * Impacts are taken in the order they happen, as an event-driven simulation
 * within the step: every candidate impact (a pair and its first touch) waits
 * in a queue by time, the earliest is resolved, and then only the pairs of
 * the two re-aimed bodies are tested again, from that time on, on their new
 * paths.  So every body's path is final up to the time of the impact being
 * resolved, and a pair's first touch is never looked for before its later
 * body's last re-aim: nothing earlier is left to find.  (Rounds of fix-ups,
 * each sorted by time, as the method first did, resolved a pair at a late
 * touch when one of its bodies had been re-aimed later in the step than the
 * pair really met: four balls lost 1.3 % of their angular momentum in one
 * 1 ms step.)  A candidate whose pair was re-aimed after it was found is
 * dropped when it comes up; the re-test after that re-aim queued the pair's
 * new first touch, if any.  A body takes at most MOST x max_sweeps impacts
 * in a step (see MOST), and the queue has a fixed room; what is left is
 * pushed apart and reported (floor_hits, sweep_limit).
 *
 * Each body keeps the start of its current straight path: its position and
 * orientation there (in w->sub_save) and the fraction t0 where it starts
 * (w->ev_alpha[i], scratch this method borrows from the event method, as
 * it does for the impacts each body took, after them).  The queue and the
 * first search's pair list fill the contact array (free after the solve),
 * the neighbour adjacency the other methods' w->method_scratch.
 * Cost: one step plus O(neighbours) per impact, instead of a whole-world
 * sub-step per halving.  Accuracy: first order, like Euler.  The impact
 * point lies exactly on the bodies' piecewise Euler paths; the impulse acts
 * on the velocity the body has at that time (the part of the step's force
 * kick a dt after the impact is taken away first and given back after), so
 * a bounce neither gains nor is inflated by the forces of the rest of the
 * step.  Approaches slower than one step of the forces builds are resting
 * contact, left to the warm-started resting pass and the end-of-step
 * separation.
 */
#include <string.h>

#include "core/world_internal.h"

#define S RBS__SAVE_STRIDE
#define T0(w, i) ((w)->ev_alpha[i]) /* (dense: one double a body made resident, not three) */
#define HITS(w, i) ((w)->ev_alpha[(w)->slots + (i)]) /* impacts body i took this step */

/* A candidate impact: a pair (b may be a plane), the fraction of the
 * step it first touches on the paths it was found on, and the paths'
 * versions then (the impacts each moving sphere had taken, HITS): an entry
 * whose body has been re-aimed since is stale, its re-test having queued
 * what is left of the pair. */
typedef struct impact {
    uint32_t a, b;
    uint32_t va, vb;
    double s;
} impact;

/* The neighbour list (Verlet's "neighbour list" of molecular dynamics,
 * L. Verlet, Phys. Rev. 159, 98, 1967).  The first search's broad phase
 * gives each sphere item a ball: the middle of its path (bp_center) and a
 * reach (bp_reach) of its radius, half its path and a skin of SKIN radii;
 * every pair whose balls meet is kept in the list, and then in an
 * adjacency (every item's neighbours).  While each body's path, cut and
 * re-aimed by fix-ups, stays inside its ball, two bodies not on the list
 * cannot touch, so the re-test after an impact only tests the two bodies'
 * neighbours instead of querying the grid.  A body whose path leaves its
 * ball (or a list too long for its scratch) sends the rest of the step back
 * to the grid: the list saves work, it never decides. */
#define SKIN 0.1

/* The impacts a body may take in one step: MOST x max_sweeps, as the
 * collision pass's sweeps (solver.c).  A light ball between a floor and a
 * heavy ball falling on it takes about pi sqrt(M/m) impacts (half of them
 * from the floor) before the heavy one turns back (the pi billiard), most
 * of them at one time;
 * a body struck more often than this is jammed, and what is left of its
 * impacts goes to the separation pass (reported). */
#define MOST 100u

typedef struct search_ctx {
    rbs_world *w;
    double h;
    impact *heap;               /* the queue: a binary heap, earliest first */
    uint32_t count, cap;
    double late;                /* the earliest impact turned away for room
                                   (HUGE_VAL: none): the queue holds every
                                   live impact before it */
    double most;                /* impacts a body may take (see MOST) */
    int left;                   /* an impact was left (a body jammed) */
    uint32_t *list;             /* item pairs, 2 per pair (the first search) */
    uint32_t list_count, list_cap;
    int building, list_full;    /* the first search appends to the list */
    uint32_t *adj_start, *adj;  /* item i's neighbours: adj[adj_start[i]] ..
                                   adj[adj_start[i + 1] - 1] */
} search_ctx;

/* HITS of a body held where an impact of a jammed body found it: it stays
 * there, its velocities kept, for the rest of the step (see MOST).  Above
 * any MOST x max_sweeps, and a version of its own. */
#define HELD 2147483648.0

/* Position of body i at fraction s of the step (on its current path). */
static v3 pos_at(const rbs_world *w, uint32_t i, double s, double h)
{
    if (w->fixed[i] || w->type[i] != RBS_BODY_SPHERE)
        return v3_load(&w->pos[3 * i]);
    if (HITS(w, i) >= HELD)
        return v3_load(&w->sub_save[S * i]);
    return v3_mad(v3_load(&w->sub_save[S * i]), v3_load(&w->vel[3 * i]), (s - T0(w, i)) * h);
}

/* Does x come before y (time, then bodies, so that ties are resolved in
 * one order on every machine)? */
static int earlier(const impact *x, const impact *y)
{
    if (x->s != y->s)
        return x->s < y->s;
    if (x->a != y->a)
        return x->a < y->a;
    return x->b < y->b;
}

/* Is body i a sphere that moves (one that an impact re-aims)? */
static int moving_sphere(const rbs_world *w, uint32_t i)
{
    return w->type[i] == RBS_BODY_SPHERE && !w->fixed[i];
}

/* The version of body i's path (0 for a body no impact re-aims). */
static uint32_t version(const rbs_world *w, uint32_t i)
{
    return moving_sphere(w, i) ? (uint32_t)HITS(w, i) : 0u;
}

static int stale(const rbs_world *w, const impact *e)
{
    return e->va != version(w, e->a) || e->vb != version(w, e->b);
}

/* Move H[k] down to its place in the heap of n entries. */
static void sift_down(impact *H, uint32_t k, uint32_t n)
{
    impact x = H[k];
    for (;;) {
        uint32_t c = 2 * k + 1;
        if (c >= n)
            break;
        if (c + 1 < n && earlier(&H[c + 1], &H[c]))
            c++;
        if (!earlier(&H[c], &x))
            break;
        H[k] = H[c];
        k = c;
    }
    H[k] = x;
}

/* Put e at H[k] (a hole) and move it up to its place. */
static void sift_up(impact *H, uint32_t k, impact e)
{
    for (; k > 0 && earlier(&e, &H[(k - 1) / 2]); k = (k - 1) / 2)
        H[k] = H[(k - 1) / 2];
    H[k] = e;
}

/* A full queue: drop its stale entries and make it a heap again. */
static void compact(search_ctx *ctx)
{
    impact *H = ctx->heap;
    uint32_t k, n = 0;
    for (k = 0; k < ctx->count; ++k)
        if (!stale(ctx->w, &H[k]))
            H[n++] = H[k];
    ctx->count = n;
    for (k = n / 2; k-- > 0;)
        sift_down(H, k, n);
}

/* Queue the impact of a and b at s (a jammed body's too: it holds the pair
 * when it comes up, see MOST).  With no room even without stale entries, the latest impact (the
 * new one or a queued one) is turned away and the time of the earliest
 * turned away kept: impacts before it are resolved from the queue, and
 * then every pair is searched again (rbs__step_selective), so no impact is
 * lost and none is taken out of order. */
static void push(search_ctx *ctx, uint32_t a, uint32_t b, double s)
{
    const rbs_world *w = ctx->w;
    impact e, *H = ctx->heap;
    e.a = a;
    e.b = b;
    e.va = version(w, a);
    e.vb = version(w, b);
    e.s = s;
    if (ctx->count == ctx->cap)
        compact(ctx);
    if (ctx->count == ctx->cap) {
        uint32_t k, last = ctx->count / 2; /* the latest is a leaf */
        for (k = last + 1; k < ctx->count; ++k)
            if (earlier(&H[last], &H[k]))
                last = k;
        if (earlier(&e, &H[last])) {
            if (ctx->late > H[last].s)
                ctx->late = H[last].s;
            sift_up(H, last, e); /* (e in the latest's place: a leaf) */
        } else if (ctx->late > e.s) {
            ctx->late = e.s;
        }
        return;
    }
    sift_up(H, ctx->count++, e);
}

/* Take the earliest impact off the queue (count > 0). */
static impact pop(search_ctx *ctx)
{
    impact *H = ctx->heap, top = H[0];
    if (--ctx->count > 0) {
        H[0] = H[ctx->count];
        sift_down(H, 0, ctx->count);
    }
    return top;
}

/* Is the approach along n slower than one step of the applied forces can
 * build (a resting contact creeping, not an impact)?  Such overlap is left
 * to the warm-started resting pass and the end-of-step separation: pairwise
 * fix-ups cannot hold a stack whose masses differ by orders of magnitude. */
static int creeping(const rbs_world *w, uint32_t a, uint32_t b, v3 n, double s)
{
    v3 aa, ab, ta, vrel;
    double vn, thr;
    rbs__accelerations_all(w, a, &aa, &ta);
    rbs__accelerations_all(w, b, &ab, &ta);
    /* the relative velocity at the time of touch: without the part of the
     * step's force kick that comes after it */
    vrel = v3_sub(v3_load(&w->vel[3 * a]),
                  w->type[b] == RBS_BODY_SPHERE ? v3_load(&w->vel[3 * b]) : v3_make(0, 0, 0));
    vrel = v3_mad(vrel, v3_sub(aa, ab), -(1.0 - s) * w->def.dt);
    vn = v3_dot(vrel, n);
    /* the same threshold as a detected contact's (contact.c: a sphere pair
     * that is not pressed -- w->pressed, marked after this step's resting
     * pass -- has only the press along n; a pressed sphere's plane contact
     * keeps |a| dt) */
    if (w->type[b] == RBS_BODY_SPHERE && !rbs__pair_pressed(w, a, b))
        return -vn <= rbs__press_threshold(aa, ab, n, w->def.dt);
    thr = rbs__resting_threshold(aa, ab, n, w->def.dt);
    if (w->type[b] == RBS_BODY_PLANE)
        thr = rbs__pressed_threshold(w, a, aa, thr, w->def.dt);
    return -vn <= thr;
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

/* Test spheres items i < j and queue their impact, if any. */
static void test_pair(search_ctx *ctx, uint32_t i, uint32_t j)
{
    rbs_world *w = ctx->w;
    uint32_t a = w->spheres[i], b = w->spheres[j];
    double s;
    if (w->fixed[a] && w->fixed[b])
        return;
    if (pair_violates(w, a, b, ctx->h, &s))
        push(ctx, a, b, s);
}

/* The broad phase's pairs: tested, and on the first search listed. */
static void search_pair(void *vctx, uint32_t i, uint32_t j)
{
    search_ctx *ctx = (search_ctx *)vctx;
    if (ctx->building) {
        if (ctx->list_count < ctx->list_cap) {
            ctx->list[2 * ctx->list_count] = i;
            ctx->list[2 * ctx->list_count + 1] = j;
            ctx->list_count++;
        } else {
            ctx->list_full = 1;
        }
    }
    test_pair(ctx, i, j);
}

/* Test sphere a against every plane. */
static void test_planes(search_ctx *ctx, uint32_t a)
{
    rbs_world *w = ctx->w;
    uint32_t k;
    double s;
    for (k = 0; k < w->plane_count; ++k)
        if (plane_violates(w, a, w->planes[k], ctx->h, &s))
            push(ctx, a, w->planes[k], s);
}

/* The grid's pairs at the current paths: every sphere (masked == 0; the
 * first search, which also builds the list, with the skin) or the pairs
 * with a sphere marked in w->bp_query. */
static void search_grid(search_ctx *ctx, int masked)
{
    rbs_world *w = ctx->w;
    double h = ctx->h, skin = masked ? 0.0 : SKIN; /* (of the radius, in the reach) */
    uint32_t i;
    for (i = 0; i < w->sphere_count; ++i) {
        uint32_t a = w->spheres[i];
        v3 p0 = pos_at(w, a, T0(w, a), h), p1 = v3_load(&w->pos[3 * a]);
        v3_store(&w->bp_center[3 * i], v3_scale(v3_add(p0, p1), 0.5));
        w->bp_reach[i] = w->radius[a] * (1.0 + skin) + 0.5 * v3_len(v3_sub(p1, p0));
    }
    ctx->building = !masked;
    rbs__broadphase_pairs(w, NULL, w->sphere_count, masked ? w->bp_query : NULL, skin, search_pair, ctx);
    ctx->building = 0;
}

/* The list as an adjacency in words uint32_t of scratch at mem: 1, or 0
 * when it does not fit (or the list was full). */
static int build_adjacency(search_ctx *ctx, uint32_t *mem, size_t words)
{
    const rbs_world *w = ctx->w;
    uint32_t n = w->sphere_count, k, i, *start = mem, *adj = mem + n + 1;
    if (ctx->list_full || (size_t)n + 1 + 2 * (size_t)ctx->list_count > words)
        return 0;
    memset(start, 0, ((size_t)n + 1) * sizeof *start);
    for (k = 0; k < 2 * ctx->list_count; ++k)
        start[ctx->list[k] + 1]++;
    for (i = 0; i < n; ++i)
        start[i + 1] += start[i];
    /* fill with start[i] as item i's cursor, then shift the cursors back */
    for (k = 0; k < ctx->list_count; ++k) {
        uint32_t p = ctx->list[2 * k], q = ctx->list[2 * k + 1];
        adj[start[p]++] = q;
        adj[start[q]++] = p;
    }
    for (i = n; i > 0; --i)
        start[i] = start[i - 1];
    start[0] = 0;
    ctx->adj_start = start;
    ctx->adj = adj;
    return 1;
}

/* Is body i's current path inside its ball of the first search (see
 * SKIN)?  Its start is on an earlier path that was; the end decides. */
static int inside_ball(const rbs_world *w, uint32_t i)
{
    uint32_t k = w->item[i];
    v3 c = v3_load(&w->bp_center[3 * k]);
    return v3_len(v3_sub(v3_load(&w->pos[3 * i]), c)) + w->radius[i] <= w->bp_reach[k];
}

/* After an impact of a and b re-aimed them: queue every impact of theirs on
 * their new paths, from the neighbour list when list_ok, else the grid. */
static void retest(search_ctx *ctx, uint32_t a, uint32_t b, int list_ok)
{
    rbs_world *w = ctx->w;
    const uint32_t body[2] = {a, b};
    int m;
    for (m = 0; m < 2; ++m)
        if (moving_sphere(w, body[m]))
            test_planes(ctx, body[m]);
    if (!w->plan.sphere_pairs)
        return;
    if (!list_ok) {
        for (m = 0; m < 2; ++m)
            if (moving_sphere(w, body[m]))
                w->bp_query[w->item[body[m]]] = 1;
        search_grid(ctx, 1);
        for (m = 0; m < 2; ++m)
            if (w->type[body[m]] == RBS_BODY_SPHERE)
                w->bp_query[w->item[body[m]]] = 0;
        return;
    }
    for (m = 0; m < 2; ++m) {
        uint32_t p, k;
        if (!moving_sphere(w, body[m]))
            continue;
        p = w->item[body[m]];
        for (k = ctx->adj_start[p]; k < ctx->adj_start[p + 1]; ++k) {
            uint32_t q = ctx->adj[k];
            if (m == 1 && q == w->item[a] && moving_sphere(w, a))
                continue; /* (tested from a's side) */
            if (p < q)
                test_pair(ctx, p, q);
            else
                test_pair(ctx, q, p);
        }
    }
}

/* Every impact on the current paths queued: each moving sphere against
 * the planes, and every sphere pair from the grid. */
static void search_all(search_ctx *ctx)
{
    rbs_world *w = ctx->w;
    uint32_t i;
    for (i = 0; i < w->sphere_count; ++i)
        if (!w->fixed[w->spheres[i]])
            test_planes(ctx, w->spheres[i]);
    if (!w->plan.sphere_pairs)
        return;
    memset(w->bp_query, 1, w->sphere_count);
    search_grid(ctx, 1);
    memset(w->bp_query, 0, w->sphere_count);
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

/* Hold body i where it is at fraction s of the step until the step's end
 * (a moving sphere not held yet): a path of length zero from s, its
 * velocities kept for the next step. */
static void hold(rbs_world *w, uint32_t i, double s, double h)
{
    if (!moving_sphere(w, i) || HITS(w, i) >= HELD)
        return;
    cut_path(w, i, s, h);
    HITS(w, i) = HELD;
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
    rbs__pressed_plane(w, &c, dt);
    if (w->type[b] == RBS_BODY_SPHERE && !rbs__pair_pressed(w, a, b)) {
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
    /* scratch after the solve: the contact array, half for the queue and
     * half for the neighbour list; method_scratch (the other methods')
     * for its adjacency */
    size_t half = (size_t)w->def.max_contacts * sizeof(rbs__contact) / 2;
    size_t words = ((size_t)RBS__SCRATCH_STRIDE * w->def.max_bodies + RBS__SCRATCH_EXTRA) * sizeof(double) /
                   sizeof(uint32_t);
    const double most = (double)MOST * w->def.max_sweeps;
    uint32_t i, contacts;
    int list_ok = 0;
    search_ctx ctx;
    rbs_status st;

    /* A fix-up moves a body along a straight path of its centre and turns
     * it by the spin it has: right for a centred isotropic sphere, not for
     * one whose centre of mass is off its centre (the centre circles the
     * centre of mass) or whose inertia is anisotropic (the spin changes
     * while it turns).  Such a world takes euler's whole-world rollback,
     * which integrates both (a probe of session 43: an off-centre ball
     * bouncing on a frictionless floor slid 5.6 mm sideways in 2 s, one
     * impact was replayed 2,000 times; an anisotropic ball's |L| grew 5 %
     * in 141 impacts that gave no torque). */
    if (w->plan.uneven)
        return rbs__step_euler(w, info);

    /* the whole world: one Euler step */
    rbs__save_state(w, w->sub_save);
    st = rbs__detect(w, dt, 1);
    if (st != RBS_OK)
        return st;
    rbs__solve_collisions(w, info);
    rbs__integrate_velocities(w, dt);
    rbs__solve_resting_warm(w, info, dt);
    rbs__integrate_positions(w, dt, info);
    contacts = rbs__touching(w);
    rbs__warm_sort(w); /* (in key order for rbs__pair_pressed) */
    rbs__mark_pressed(w);
    for (i = 0; i < w->slots; ++i) {
        T0(w, i) = 0.0;
        HITS(w, i) = 0.0;
    }

    /* selective rollback: the impacts on the Euler paths queued, and the
     * neighbour list built */
    memset(&ctx, 0, sizeof ctx);
    ctx.w = w;
    ctx.h = dt;
    ctx.late = HUGE_VAL;
    ctx.most = most;
    ctx.heap = (impact *)(void *)w->contact;
    ctx.cap = (uint32_t)(half / sizeof(impact));
    ctx.list = (uint32_t *)(void *)((unsigned char *)w->contact + half);
    ctx.list_cap = (uint32_t)(half / (2 * sizeof(uint32_t)));
    for (i = 0; i < w->sphere_count; ++i)
        if (!w->fixed[w->spheres[i]])
            test_planes(&ctx, w->spheres[i]);
    if (w->plan.sphere_pairs) {
        memset(w->bp_query, 0, w->sphere_count);
        search_grid(&ctx, 0);
        list_ok = build_adjacency(&ctx, (uint32_t *)(void *)w->method_scratch, words);
    }

    /* the earliest impact first, until none is left */
    for (;;) {
        impact e;
        uint32_t a, b;
        double s;
        int still;
        if (ctx.count == 0 ? ctx.late != HUGE_VAL : ctx.heap[0].s > ctx.late) {
            /* impacts were turned away for room, and the queue holds none
             * before them: every pair searched again, on the paths as they
             * are now */
            ctx.count = 0;
            ctx.late = HUGE_VAL;
            search_all(&ctx);
            list_ok = 0; /* (the search moved the balls the list was built in) */
            continue;
        }
        if (ctx.count == 0)
            break;
        e = pop(&ctx);
        a = e.a;
        b = e.b;
        if (stale(w, &e))
            continue; /* re-aimed since it was found: its re-test queued what is left */
        still = w->type[b] == RBS_BODY_PLANE ? plane_violates(w, a, b, dt, &s) : pair_violates(w, a, b, dt, &s);
        if (!still || s != e.s)
            continue; /* (cannot happen for an entry not stale; kept as the safe test) */
        if ((moving_sphere(w, a) && HITS(w, a) >= most) || (moving_sphere(w, b) && HITS(w, b) >= most)) {
            /* A body jammed (see MOST): this impact is left, and the pair
             * is held where it meets, for the rest of the step.  Left to
             * fly on, a jammed body went through what it could no longer
             * strike: a 1 kg ball under a 1e6 kg one on a floor, e = 1,
             * flew up through it at 2843 m/s (a probe of session 44).
             * Held, the pair takes up its impacts in the next step; others
             * meeting a held body are held too. */
            ctx.left = 1;
            hold(w, a, s, dt);
            hold(w, b, s, dt);
            retest(&ctx, a, b, list_ok);
            continue;
        }
        HITS(w, a) += 1.0;
        if (w->type[b] == RBS_BODY_SPHERE)
            HITS(w, b) += 1.0;
        cut_path(w, a, s, dt);
        cut_path(w, b, s, dt);
        late_kick(w, a, s, -1.0);
        late_kick(w, b, s, -1.0);
        collide_now(w, a, b, dt, info);
        late_kick(w, a, s, 1.0);
        late_kick(w, b, s, 1.0);
        finish_path(w, a, dt);
        finish_path(w, b, dt);
        if (list_ok && (!inside_ball(w, a) || (w->type[b] == RBS_BODY_SPHERE && !inside_ball(w, b))))
            list_ok = 0; /* a path left its ball: the grid from now on */
        info->rollbacks++;
        retest(&ctx, a, b, list_ok);
    }
    if (ctx.left) {
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
