/*
 * explain.c - rbs_world_explain(): the pipeline a step runs, as text.
 *
 * The stages in or out are read from the same plan the step uses
 * (rbs__plan_compute in step.c); this file only finds, for each decision,
 * the body or pair that causes it, so that a user can see why a stage runs.
 */
#include <stdarg.h>
#include <stdio.h>

#include "core/world_internal.h"

/* Text written into a caller buffer, counting what did not fit. */
typedef struct text {
    char *buf;
    size_t size, len;
} text;

static void put(text *t, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void put(text *t, const char *fmt, ...)
{
    va_list ap;
    int n;
    size_t room = t->len < t->size ? t->size - t->len : 0;
    va_start(ap, fmt);
    n = rbs__vsnprintf_c(room > 0 ? t->buf + t->len : NULL, room, fmt, ap);
    va_end(ap);
    if (n > 0)
        t->len += (size_t)n;
}

/* "s" after a count other than 1 ("1 plane", "2 planes", "0 planes"). */
static const char *plural(uint32_t n) { return n == 1 ? "" : "s"; }

static void stage(text *t, int in, const char *name)
{
    put(t, "  %-4s %s: ", in ? "in" : "out", name);
}

/* "name" or "#slot" for unnamed bodies. */
static void body_name(text *t, const rbs_world *w, uint32_t i)
{
    if (w->name[i][0] != '\0')
        put(t, "sphere \"%s\"", w->name[i]);
    else
        put(t, "sphere #%u", (unsigned)i);
}

static int nonzero3(const double *p) { return p[0] != 0.0 || p[1] != 0.0 || p[2] != 0.0; }

static const char *method_summary(rbs_method m)
{
    switch (m) {
    case RBS_METHOD_EULER:
        return "semi-implicit Euler sub-steps (v += a h, then x += v h); 1 force evaluation per sub-step";
    case RBS_METHOD_SELECTIVE:
        return "one semi-implicit Euler step; each pair that overlaps is moved back along its path "
               "to its first touch and struck there, impacts in time order";
    case RBS_METHOD_EVENT:
        return "exact event-driven motion between impacts (closed-form trajectories, root-found events)";
    case RBS_METHOD_VERLET:
        return "velocity Verlet sub-steps (kick h/2, drift h, kick h/2); 2 force evaluations per sub-step";
    case RBS_METHOD_RK4:
        return "classical Runge-Kutta sub-steps; 4 force evaluations per sub-step";
    case RBS_METHOD_ADAPTIVE:
        return "GSL odeiv2 rk8pd with error control between contacts; contact times by Brent root "
               "finding (GSL roots); frames with resting contact use RK4 sub-steps";
    case RBS_METHOD_SOFT:
        return "the soft step: fixed semi-implicit Euler sub-steps with soft contacts (one solve and "
               "one relax pass each), restitution at the frame's end";
    default:
        return "unknown";
    }
}

rbs_status rbs_world_explain(const rbs_world *w, char *buf, size_t size, size_t *needed)
{
    text t;
    rbs__plan p;
    uint32_t k, moving = 0, fixed = 0;
    int32_t row;
    const char *why;
    rbs_method m;
    if (needed)
        *needed = 0;
    if (w == NULL || w->magic != 0x72627377u || (buf == NULL && size > 0))
        return RBS_E_INVALID;
    t.buf = buf;
    t.size = size;
    t.len = 0;
    rbs__plan_compute(w, &p);
    m = p.method;
    for (k = 0; k < w->sphere_count; ++k) {
        if (w->fixed[w->spheres[k]])
            fixed++;
        else
            moving++;
    }

    /* The world and the method. */
    put(&t, "world: %u sphere%s (%u moving, %u fixed), %u plane%s, %u material pair%s\n",
        (unsigned)w->sphere_count, plural(w->sphere_count), (unsigned)moving, (unsigned)fixed,
        (unsigned)w->plane_count, plural(w->plane_count), (unsigned)w->pairs, plural(w->pairs));
    put(&t, "method: %s, dt = %g s, slop = %g of the smaller radius, tolerance = %g, pruning %s\n",
        rbs_method_name(w->def.method), w->def.dt, w->def.slop, w->def.tolerance,
        w->def.prune ? "on" : "off (every stage runs)");
    if (w->def.method == RBS_METHOD_AUTO) {
        if (m == RBS_METHOD_SOFT && p.soft_substeps > w->def.soft_substeps)
            put(&t, "  auto: soft on %u sub-steps, since %u spheres move (soft from %u on, without mutual "
                    "gravity), and on soft_substeps %u it could sink a contact by %.3g of the smallest "
                    "moving radius (the largest load on the lightest sphere over its mass x omega^2; "
                    "within %g on %u)\n",
                (unsigned)p.soft_substeps, (unsigned)moving, (unsigned)RBS_METHOD_AUTO_SOFT_BODIES,
                (unsigned)w->def.soft_substeps, p.soft_sink, RBS_METHOD_AUTO_SOFT_SINK, (unsigned)p.soft_substeps);
        else if (m == RBS_METHOD_SOFT)
            put(&t, "  auto: soft, since %u spheres move (soft from %u on, without mutual gravity)\n",
                (unsigned)moving, (unsigned)RBS_METHOD_AUTO_SOFT_BODIES);
        else if (w->def.mutual_gravity)
            put(&t, "  auto: euler, since there is mutual gravity\n");
        else if (moving >= RBS_METHOD_AUTO_SOFT_BODIES && p.mass_ratio <= RBS_METHOD_AUTO_SOFT_MASS_RATIO)
            put(&t, "  auto: euler, since soft could sink a contact by %.3g of the smallest moving radius (the "
                    "largest load, gravity and applied force, on the lightest sphere over its mass x "
                    "omega^2), and within %g it would take more than %u x soft_substeps sub-steps: a "
                    "shorter dt or more soft_substeps lets it)\n",
                p.soft_sink, RBS_METHOD_AUTO_SOFT_SINK, (unsigned)RBS_METHOD_AUTO_SOFT_MORE_SUBSTEPS);
        else if (moving >= RBS_METHOD_AUTO_SOFT_BODIES)
            put(&t, "  auto: euler, since the moving spheres' masses span a ratio of %.3g (soft only within "
                    "%g: it sinks a heavy sphere into a light one by its load)\n",
                p.mass_ratio, (double)RBS_METHOD_AUTO_SOFT_MASS_RATIO);
        else
            put(&t, "  auto: euler, since %u sphere%s move%s (soft from %u on)\n", (unsigned)moving,
                moving == 1 ? "" : "s", moving == 1 ? "s" : "", (unsigned)RBS_METHOD_AUTO_SOFT_BODIES);
    }
    put(&t, "  %s\n", method_summary(m));
    if (m == RBS_METHOD_SOFT) {
        put(&t, "  %u sub-steps of dt/%u; contacts found once a frame within each body's sweep (and "
                "guards, acting from half a radius deep, where a kick within the frame can "
                "reach further); no rollback: overlap beyond the slop is pushed out by springs of "
                "omega = 2 pi/(3h)\n",
            (unsigned)p.soft_substeps, (unsigned)p.soft_substeps);
        if (w->def.soft_tolerance > 0.0 && p.gather)
            put(&t, "  soft_tolerance %g: a frame takes fewer (halved, down to 1) while no contact can "
                    "reach an overlap of %g x n/%u of its radius\n",
                w->def.soft_tolerance, w->def.soft_tolerance, (unsigned)p.soft_substeps);
        else if (w->def.soft_tolerance > 0.0)
            put(&t, "  soft_tolerance %g: not used, every frame takes all sub-steps (this world steps "
                    "in the general layout: mutual gravity, rolling or spinning resistance, or an "
                    "anisotropic or off-centre sphere)\n", w->def.soft_tolerance);
    } else if (m == RBS_METHOD_SELECTIVE && p.uneven) {
        put(&t, "  selective: this world steps as euler (sub-steps, whole-world rollback): a moving "
                "sphere is anisotropic or has its centre of mass off its centre, which a fix-up's "
                "straight path cannot follow\n");
        put(&t, "  overlap check after every sub-step; rollback with h/2 down to dt/2^%u\n",
            (unsigned)w->def.max_halvings);
    } else if (m == RBS_METHOD_SELECTIVE) {
        put(&t, "  impacts found on the step's straight paths; each pair moved back to its first touch "
                "(at most %u impacts a body a step)\n", (unsigned)(100u * w->def.max_sweeps));
    } else if (m != RBS_METHOD_EVENT) {
        put(&t, "  overlap check after every sub-step; rollback with h/2 down to dt/2^%u\n",
            (unsigned)w->def.max_halvings);
    }
    why = w->def.prune ? "" : " (pruning off)";
    put(&t, "stages:\n");

    /* Detection. */
    stage(&t, moving > 0 && w->plane_count > 0, "contacts sphere-plane");
    if (moving == 0)
        put(&t, "no sphere moves\n");
    else if (w->plane_count == 0)
        put(&t, "no planes\n");
    else
        put(&t, "%u moving sphere%s x %u plane%s\n", (unsigned)moving, plural(moving), (unsigned)w->plane_count,
            plural(w->plane_count));
    stage(&t, p.sphere_pairs, "contacts sphere-sphere");
    if (w->sphere_count < 2)
        put(&t, "fewer than two spheres%s\n", why);
    else if (moving == 0)
        put(&t, "no sphere moves%s\n", why);
    else
        put(&t, "%u spheres, %u moving\n", (unsigned)w->sphere_count, (unsigned)moving);
    stage(&t, moving > 0, "collision impulses (restitution)");
    put(&t, moving > 0 ? "contacts approaching faster than one frame of forces builds\n" : "no sphere moves\n");

    /* Friction. */
    stage(&t, p.friction, "friction, rolling and spinning resistance");
    row = rbs__row_in_use(w, 0);
    if (row >= 0) {
        const rbs__pair *r = &w->pair[row];
        put(&t, "pair \"%s\"/\"%s\" has mu_s %g, mu_k %g, rolling %g, spinning %g m\n",
            r->a ? w->material_name[r->a - 1] : "*", r->b ? w->material_name[r->b - 1] : "*", r->mu_s,
            r->mu_k, r->rolling, r->spinning);
    } else {
        put(&t, "no material pair has friction or resistance on its bodies' materials (pairs "
                "without a row are frictionless)%s\n", why);
    }

    /* Angular motion. */
    stage(&t, p.angular, "angular velocity and orientation");
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t s = w->spheres[k];
        if (w->fixed[s])
            continue;
        if (nonzero3(&w->avel[3 * s]) || nonzero3(&w->torque[3 * s]) || nonzero3(&w->com_body[3 * s]) ||
            !w->isotropic[s])
            break;
    }
    if (k < w->sphere_count) {
        uint32_t s = w->spheres[k];
        body_name(&t, w, s);
        put(&t, nonzero3(&w->avel[3 * s]) ? " spins\n"
                : nonzero3(&w->torque[3 * s]) ? " has an applied torque\n"
                : nonzero3(&w->com_body[3 * s]) ? " has an off-centre mass\n"
                : " has anisotropic inertia (contacts can make it spin)\n");
    } else if (p.friction && w->def.prune) {
        put(&t, "friction can make spheres spin\n");
    } else {
        put(&t, "no moving sphere spins, has a torque, an off-centre mass or anisotropic inertia, and no "
                "friction%s\n", why);
    }
    stage(&t, p.gyroscopic, "gyroscopic torque -w x I w");
    for (k = 0; k < w->sphere_count; ++k) {
        uint32_t s = w->spheres[k];
        if (!w->fixed[s] && (!w->isotropic[s] || nonzero3(&w->com_body[3 * s])))
            break;
    }
    if (k < w->sphere_count) {
        body_name(&t, w, w->spheres[k]);
        put(&t, " has anisotropic inertia about its centre of mass\n");
    } else {
        put(&t, "every moving sphere has isotropic inertia about its centre of mass, so the term is "
                "zero%s\n", why);
    }

    /* Forces. */
    stage(&t, moving > 0, "uniform gravity and applied forces");
    put(&t, "g = (%g, %g, %g) %s, evaluated for every moving sphere\n", w->def.gravity.x, w->def.gravity.y,
        w->def.gravity.z, w->def.gravity_mode == RBS_GRAVITY_FORCE ? "N" : "m/s^2");
    stage(&t, p.mutual, "mutual gravity");
    if (!w->def.mutual_gravity)
        put(&t, "def.mutual_gravity is 0\n");
    else if (!p.mutual)
        put(&t, "fewer than two spheres or none moves\n");
    else
        put(&t, "G = %g m^3/(kg s^2), softening %g m, %u pair%s\n", w->def.gravity_constant, w->def.softening,
            (unsigned)(w->sphere_count * (w->sphere_count - 1) / 2),
            plural(w->sphere_count * (w->sphere_count - 1) / 2));

    /* Resting contact. */
    stage(&t, moving > 0 && m != RBS_METHOD_EVENT, "resting-contact pass");
    if (m == RBS_METHOD_VERLET || m == RBS_METHOD_RK4)
        put(&t, "once per sub-step, on the end velocities (positions move by half of its change)\n");
    else if (m == RBS_METHOD_ADAPTIVE)
        put(&t, "in frames with lasting contact, on RK4 sub-steps\n");
    else if (m == RBS_METHOD_EVENT)
        put(&t, "the event method keeps rolling and sliding in closed form\n");
    else if (m == RBS_METHOD_SOFT)
        put(&t, "a solve and a relax pass per sub-step, warm-started (the soft step's own rows)\n");
    else
        put(&t, "once per sub-step, after the forces\n");
    if (moving > 0 && m != RBS_METHOD_EVENT) {
        /* the compact sweep (solver.c) decides per pass, from the pass's
         * contacts; here: whether every pass can take it */
        uint32_t odd = UINT32_MAX;
        for (k = 0; k < w->sphere_count && odd == UINT32_MAX; ++k)
            if (!w->isotropic[w->spheres[k]] || nonzero3(&w->com_body[3 * w->spheres[k]]))
                odd = w->spheres[k];
        row = rbs__row_in_use(w, 1);
        if (m == RBS_METHOD_SOFT) {
            /* the soft step's layout follows the bodies alone (the plan's
             * gather; the lines below name what keeps it off) */
            stage(&t, p.gather, "gathered body records");
            if (p.mutual_acts) {
                /* (switched on with one sphere, or none moving, it keeps
                 * the gathered layout: the line said "in" and blamed it) */
                put(&t, "mutual gravity: the general rows on the world's arrays\n");
            } else if (odd != UINT32_MAX) {
                body_name(&t, w, odd);
                put(&t, " has anisotropic inertia or an off-centre mass: the general rows\n");
            } else if (row >= 0) {
                const rbs__pair *r = &w->pair[row];
                put(&t, "pair \"%s\"/\"%s\" has rolling or spinning resistance: the general rows\n",
                    r->a ? w->material_name[r->a - 1] : "*", r->b ? w->material_name[r->b - 1] : "*");
            } else {
                put(&t, "centred isotropic spheres: v, w, 1/m, 1/I and the frame's motion in one "
                        "record per body\n");
            }
        } else {
        stage(&t, w->def.prune && odd == UINT32_MAX && row < 0, "compact resting sweep");
        if (!w->def.prune) {
            put(&t, "every impulse through the general sweep (pruning off)\n");
        } else if (odd != UINT32_MAX) {
            body_name(&t, w, odd);
            put(&t, " has anisotropic inertia or an off-centre mass: its contacts need the general "
                    "sweep (passes without them still take the compact one)\n");
        } else if (row >= 0) {
            const rbs__pair *r = &w->pair[row];
            put(&t, "pair \"%s\"/\"%s\" has rolling or spinning resistance: its contacts need the "
                    "general sweep\n", r->a ? w->material_name[r->a - 1] : "*",
                r->b ? w->material_name[r->b - 1] : "*");
        } else {
            put(&t, "centred isotropic spheres without rolling or spinning resistance: the sweeps read "
                    "v, w, 1/m and 1/I from one compact record per body\n");
        }
        }
    }

    if (needed)
        *needed = t.len + 1;
    if (size > 0 && t.len >= size) {
        buf[size - 1] = '\0';
        return RBS_E_MEMORY;
    }
    if (size == 0)
        return RBS_E_MEMORY;
    return RBS_OK;
}
