/*
 * fuzz_api.c - libFuzzer harness for random sequences of public API calls.
 *
 * The input is decoded as a byte program: a header picks the world's
 * settings, then each op byte picks a call (add material / pair / sphere /
 * plane, remove, setters, step, dt and method changes, checkpoint write and
 * read, queries) whose arguments come from the following bytes.  Numbers are
 * either raw 8-byte doubles (anything, NaN and infinities included) or picks
 * from a table of edge values.  Invariants checked after every call:
 *  - the status is RBS_OK or a listed error code;
 *  - a refused call or a failed step leaves the world's hash unchanged;
 *  - after any call the state view holds only finite numbers;
 *  - a checkpoint restores the same hash; a damaged one is refused.
 * Running out of input ends the program.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "fuzz_common.h"

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static uint8_t u8(reader *r)
{
    uint8_t b;
    if (r->n == 0)
        return 0;
    b = *r->p++;
    r->n--;
    return b;
}

static const double edge[] = {
    0.0, -0.0, 1.0, -1.0, 0.1, 0.5, 2.0, 1e-3, 1e-7, 1e-310, -1e-310, 4.9406564584124654e-324,
    1e-300, 1e6, -1e6, 1e9, 1e154, 1e155, 1e300, 1e308, -1e308, DBL_MAX, -DBL_MAX, DBL_MIN,
    9.81, -9.81, 0.05, 100.0, 1000.0, 1e-12};

/* A number: mostly edge values, sometimes raw bits, sometimes NaN/inf. */
static double num(reader *r)
{
    uint8_t sel = u8(r);
    if (sel < 200)
        return edge[sel % (sizeof edge / sizeof edge[0])];
    if (sel < 220) {
        uint64_t bits = 0;
        double d;
        int k;
        for (k = 0; k < 8; ++k)
            bits = (bits << 8) | u8(r);
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    if (sel < 235)
        return NAN;
    if (sel < 245)
        return INFINITY;
    return -INFINITY;
}

/* A positive size-like number: small values mostly. */
static double pos(reader *r)
{
    static const double p[] = {0.1, 0.05, 1.0, 0.01, 1e-3, 2.0, 10.0, 1e-6};
    uint8_t sel = u8(r);
    if (sel < 224)
        return p[sel % (sizeof p / sizeof p[0])];
    return num(r);
}

static rbs_vec3 vec(reader *r)
{
    rbs_vec3 v;
    uint8_t kind = u8(r);
    if (kind < 128) { /* small: each component from the edge table's first entries */
        v.x = edge[u8(r) % 9];
        v.y = edge[u8(r) % 9];
        v.z = edge[u8(r) % 9];
    } else {
        v.x = num(r);
        v.y = num(r);
        v.z = num(r);
    }
    return v;
}

#define MAX_IDS 32

typedef struct fuzz_state {
    rbs_world *w;
    rbs_body_id bodies[MAX_IDS];
    uint32_t nb;
    rbs_material_id mats[MAX_IDS];
    uint32_t nm;
    int step_failed; /* the last step failed and no other call came since */
    int failures;    /* failed steps so far */
    uint64_t work;   /* (sub-steps + rollbacks + events) x (bodies + 1) so far */
} fuzz_state;

/* Bounds on one input's stepping, so that an input ends in seconds under
 * ASan: a frame at the library's work caps (euler's 4096 sub-steps,
 * adaptive's 1e5 steps) is legitimate but slow, and a program of 64 calls
 * could ask for a hundred of them.  Past either bound steps are skipped
 * (deterministically: the bounds count work, not time). */
#define FUZZ_WORK_BUDGET 4000000u
#define FUZZ_MAX_SUBSTEPS 256u
#define FUZZ_MAX_FAILURES 4

static rbs_body_id pick_body(fuzz_state *s, reader *r)
{
    uint8_t b = u8(r);
    rbs_body_id none = {0, 0}, forged;
    if (b == 255)
        return none;
    if (b == 254) {
        forged.index = u8(r);
        forged.generation = u8(r);
        return forged;
    }
    if (s->nb == 0)
        return none;
    return s->bodies[b % s->nb];
}

static rbs_material_id pick_material(fuzz_state *s, reader *r)
{
    uint8_t b = u8(r);
    rbs_material_id none = {0, 0};
    if (b >= 250 || s->nm == 0)
        return none;
    return s->mats[b % s->nm];
}

static void check_world(const fuzz_state *s, const char *after)
{
    rbs_state_view v;
    uint32_t i;
    FUZZ_CHECK(rbs_world_state(s->w, &v) == RBS_OK, "state view after %s", after);
    for (i = 0; i < 3 * v.slots; ++i)
        FUZZ_CHECK(isfinite(v.position[i]) && isfinite(v.velocity[i]) && isfinite(v.angular_velocity[i]),
                   "non-finite state after %s", after);
    for (i = 0; i < 4 * v.slots; ++i)
        FUZZ_CHECK(isfinite(v.orientation[i]), "non-finite orientation after %s", after);
}

/* A call that failed must not have changed the world. */
static void check_call(const fuzz_state *s, rbs_status st, uint64_t before, const char *what)
{
    FUZZ_CHECK(fuzz_status_valid(st), "%s returned %d", what, (int)st);
    if (st != RBS_OK)
        FUZZ_CHECK(rbs_world_hash(s->w) == before, "failed %s (%s) changed the world", what,
                   rbs_status_name(st));
    check_world(s, what);
}

static void op_checkpoint(fuzz_state *s, reader *r)
{
    size_t n = rbs_world_checkpoint_size(s->w), written = 0;
    uint8_t *buf;
    rbs_world *b = NULL;
    rbs_status st;
    FUZZ_CHECK(n > 0, "checkpoint size 0");
    buf = malloc(n);
    if (buf == NULL)
        return;
    st = rbs_world_checkpoint_write(s->w, buf, n, &written);
    FUZZ_CHECK(st == RBS_OK && written == n, "checkpoint write %s", rbs_status_name(st));
    st = rbs_world_create_from_checkpoint(buf, n, &b);
    FUZZ_CHECK(st == RBS_OK, "checkpoint read %s", rbs_status_name(st));
    FUZZ_CHECK(rbs_world_hash(b) == rbs_world_hash(s->w), "checkpoint changed the state");
    rbs_world_destroy(b);
    b = NULL;
    /* damage one byte (or cut the buffer): refused, never a crash */
    if (u8(r) & 1) {
        size_t at = ((size_t)u8(r) << 8 | u8(r)) % n;
        uint8_t x = (uint8_t)(u8(r) | 1);
        buf[at] ^= x;
        st = rbs_world_create_from_checkpoint(buf, n, &b);
        FUZZ_CHECK(st == RBS_E_CORRUPT || st == RBS_E_VERSION, "damaged checkpoint (byte %zu ^ %u) gave %s",
                   at, (unsigned)x, rbs_status_name(st));
        FUZZ_CHECK(b == NULL, "refused checkpoint left a world");
    } else {
        size_t cut = ((size_t)u8(r) << 8 | u8(r)) % n;
        st = rbs_world_create_from_checkpoint(buf, cut, &b);
        FUZZ_CHECK(st == RBS_E_CORRUPT || st == RBS_E_VERSION, "truncated checkpoint (%zu of %zu) gave %s",
                   cut, n, rbs_status_name(st));
    }
    free(buf);
}

static int nan3(rbs_vec3 v) { return isnan(v.x) || isnan(v.y) || isnan(v.z); }

static void op_queries(fuzz_state *s, reader *r)
{
    rbs_body_state bs;
    rbs_energy e;
    rbs_vec3 p, l;
    rbs_usage u;
    rbs_world_def d;
    rbs_body_id id = pick_body(s, r), found;
    rbs_status st = rbs_body_get_state(s->w, id, &bs);
    FUZZ_CHECK(fuzz_status_valid(st), "get_state %d", (int)st);
    if (st == RBS_OK && bs.name[0] != '\0') {
        FUZZ_CHECK(rbs_world_find_body(s->w, bs.name, &found) == RBS_OK, "find_body(\"%s\")", bs.name);
        FUZZ_CHECK(found.index == id.index && found.generation == id.generation, "find_body found another");
    }
    st = rbs_world_body_at(s->w, u8(r), &found);
    FUZZ_CHECK(st == RBS_OK || st == RBS_E_NOT_FOUND || st == RBS_E_INVALID, "body_at %d", (int)st);
    /* diagnostics: a number that is not NaN, or RBS_E_NUMERIC */
    st = rbs_world_energy(s->w, &e);
    FUZZ_CHECK(st == RBS_E_NUMERIC || (st == RBS_OK && !isnan(e.kinetic) && !isnan(e.potential) && !isnan(e.total)),
               "energy: %s, %g %g %g", rbs_status_name(st), e.kinetic, e.potential, e.total);
    st = rbs_world_momentum(s->w, &p, &l);
    FUZZ_CHECK(st == RBS_E_NUMERIC || (st == RBS_OK && !nan3(p) && !nan3(l)),
               "momentum: %s", rbs_status_name(st));
    FUZZ_CHECK(rbs_world_usage(s->w, &u) == RBS_OK, "usage");
    rbs_world_def_init(&d);
    FUZZ_CHECK(rbs_world_get_def(s->w, &d) == RBS_OK, "get_def");
    FUZZ_CHECK(rbs_world_last_error(s->w) != NULL, "last_error NULL");
    (void)rbs_world_time(s->w);
}

/* Print every live body (RBS_FUZZ_TRACE). */
static void trace_world(const fuzz_state *s)
{
    rbs_world_def d;
    uint32_t i;
    rbs_world_def_init(&d);
    rbs_world_get_def(s->w, &d);
    fprintf(stderr, "world: method %s dt %.17g g %.17g %.17g %.17g e %.17g mutual %d halvings %u\n",
            rbs_method_name(d.method), d.dt, d.gravity.x, d.gravity.y, d.gravity.z, d.restitution,
            (int)d.mutual_gravity, (unsigned)d.max_halvings);
    for (i = 0; i < d.max_bodies; ++i) {
        rbs_body_id id;
        rbs_body_state b;
        if (rbs_world_body_at(s->w, i, &id) != RBS_OK || rbs_body_get_state(s->w, id, &b) != RBS_OK)
            continue;
        fprintf(stderr, "  body %u type %d r %.17g m %.17g fixed %d x %.17g %.17g %.17g v %.17g %.17g %.17g "
                "w %.17g %.17g %.17g q %.17g %.17g %.17g %.17g n %.17g %.17g %.17g f %.17g %.17g %.17g\n",
                (unsigned)i, (int)b.type, b.radius, b.mass, (int)b.fixed, b.position.x, b.position.y,
                b.position.z, b.velocity.x, b.velocity.y, b.velocity.z, b.angular_velocity.x,
                b.angular_velocity.y, b.angular_velocity.z, b.orientation.w, b.orientation.x, b.orientation.y,
                b.orientation.z, b.normal.x, b.normal.y, b.normal.z, b.force.x, b.force.y, b.force.z);
    }
}

static void run_ops(fuzz_state *s, reader *r)
{
    int ops = 0, trace = getenv("RBS_FUZZ_TRACE") != NULL; /* print each call */
    char name[12];
    while (r->n > 0 && ops++ < 64) {
        uint8_t op = u8(r) % 12;
        uint64_t before = rbs_world_hash(s->w);
        rbs_status st;
        if (trace)
            fprintf(stderr, "op %d: %u (%zu bytes left)\n", ops, (unsigned)op, r->n);
        if (op != 7 && op != 8)
            s->step_failed = 0;
        switch (op) {
        case 0: { /* material */
            rbs_material_id m;
            size_t len = u8(r) % 10, k;
            for (k = 0; k < len; ++k)
                name[k] = (char)('a' + u8(r) % 4);
            name[len] = '\0';
            st = rbs_world_add_material(s->w, name, &m);
            check_call(s, st, before, "add_material");
            if (st == RBS_OK && s->nm < MAX_IDS)
                s->mats[s->nm++] = m;
            break;
        }
        case 1: { /* pair */
            rbs_pair_def p;
            rbs_pair_def_init(&p);
            p.a = pick_material(s, r);
            p.b = pick_material(s, r);
            p.static_friction = num(r);
            p.kinetic_friction = num(r);
            p.restitution = num(r);
            if (u8(r) & 1) {
                p.rolling = num(r);
                p.spinning = num(r);
            }
            check_call(s, rbs_world_set_pair(s->w, &p), before, "set_pair");
            break;
        }
        case 2:
        case 3: { /* sphere (twice as likely) */
            rbs_sphere_def d;
            rbs_body_id id;
            uint8_t flags = u8(r);
            rbs_sphere_def_init(&d);
            d.radius = pos(r);
            d.mass = pos(r);
            d.position = vec(r);
            d.velocity = vec(r);
            if (flags & 1)
                d.angular_velocity = vec(r);
            if (flags & 2)
                d.force = vec(r);
            if (flags & 4) {
                d.center_of_mass = vec(r);
                d.inertia_kind = (rbs_inertia_kind)(u8(r) % 4);
                d.inertia = vec(r);
            }
            if (flags & 8)
                d.fixed = 1;
            if (flags & 16)
                d.density = num(r);
            if (flags & 32) {
                snprintf(name, sizeof name, "b%u", (unsigned)(u8(r) % 8));
                d.name = name;
            }
            d.material = pick_material(s, r);
            st = rbs_world_add_sphere(s->w, &d, &id);
            check_call(s, st, before, "add_sphere");
            if (st == RBS_OK && s->nb < MAX_IDS)
                s->bodies[s->nb++] = id;
            break;
        }
        case 4: { /* plane */
            rbs_plane_def d;
            rbs_body_id id;
            rbs_plane_def_init(&d);
            d.point = vec(r);
            d.normal = vec(r);
            d.material = pick_material(s, r);
            st = rbs_world_add_plane(s->w, &d, &id);
            check_call(s, st, before, "add_plane");
            if (st == RBS_OK && s->nb < MAX_IDS)
                s->bodies[s->nb++] = id;
            break;
        }
        case 5: /* remove (ids stay in the list: later uses are stale) */
            check_call(s, rbs_world_remove_body(s->w, pick_body(s, r)), before, "remove_body");
            break;
        case 6: { /* setters */
            rbs_body_id id = pick_body(s, r);
            uint8_t which = u8(r) % 6;
            rbs_vec3 v = vec(r);
            if (which == 0)
                st = rbs_body_set_position(s->w, id, v);
            else if (which == 1)
                st = rbs_body_set_velocity(s->w, id, v);
            else if (which == 2)
                st = rbs_body_set_angular_velocity(s->w, id, v);
            else if (which == 3)
                st = rbs_body_set_force(s->w, id, v);
            else if (which == 4)
                st = rbs_body_set_torque(s->w, id, v);
            else {
                rbs_quat q;
                q.w = num(r);
                q.x = v.x;
                q.y = v.y;
                q.z = v.z;
                st = rbs_body_set_orientation(s->w, id, q);
            }
            check_call(s, st, before, "setter");
            break;
        }
        case 7:
        case 8: { /* steps */
            int k, n = 1 + u8(r) % FUZZ_STEPS;
            /* A step is a function of the world alone: after a failure,
             * with no call in between, it would fail again the same way
             * after the same work (a frame at the work cap can take
             * seconds under ASan), so it is skipped.  That it does fail
             * again is checked by tests/extremes/test_badvalues.c. */
            if (s->step_failed || s->failures >= FUZZ_MAX_FAILURES || s->work >= FUZZ_WORK_BUDGET)
                break;
            for (k = 0; k < n; ++k) {
                uint64_t c = rbs_world_step_count(s->w);
                rbs_step_info info;
                before = rbs_world_hash(s->w);
                if (trace)
                    trace_world(s);
                {
                    st = rbs_world_step(s->w, &info);
                    if (trace)
                        fprintf(stderr, "step %llu: %s substeps %u rollbacks %u floor %u sweep_limit %u events %u "
                                "contacts %u overlap %g %s\n", (unsigned long long)c + 1, rbs_status_name(st),
                                (unsigned)info.substeps, (unsigned)info.rollbacks, (unsigned)info.floor_hits,
                                (unsigned)info.sweep_limit, (unsigned)info.events, (unsigned)info.contacts,
                                info.max_overlap, rbs_world_last_error(s->w));
                    if (trace)
                        trace_world(s);
                }
                check_call(s, st, before, "step");
                if (st != RBS_OK) {
                    FUZZ_CHECK(rbs_world_step_count(s->w) == c, "failed step counted");
                    FUZZ_CHECK(rbs_world_last_error(s->w)[0] != '\0', "failed step without message");
                    s->step_failed = 1;
                    s->failures++;
                    break;
                }
                s->work += ((uint64_t)info.substeps + info.rollbacks + info.events) * (s->nb + 1u);
                FUZZ_CHECK(rbs_world_step_count(s->w) == c + 1, "step not counted");
            }
            break;
        }
        case 9: /* dt or method */
            if (u8(r) & 1)
                check_call(s, rbs_world_set_dt(s->w, num(r)), before, "set_dt");
            else
                check_call(s, rbs_world_set_method(s->w, (rbs_method)(u8(r) % 8), num(r)), before,
                           "set_method");
            break;
        case 10:
            op_checkpoint(s, r);
            break;
        default:
            op_queries(s, r);
            break;
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r;
    fuzz_state s;
    rbs_world_def d;
    rbs_status st;
    char msg[256];
    r.p = data;
    r.n = size;
    memset(&s, 0, sizeof s);
    rbs_world_def_init(&d);
    d.max_bodies = 1 + u8(&r) % 16;
    d.max_materials = u8(&r) % 6;
    d.max_pairs = u8(&r) % 8;
    d.dt = pos(&r) * 1e-2;
    d.gravity = vec(&r);
    d.gravity_mode = (rbs_gravity_mode)(u8(&r) % 3);
    d.restitution = num(&r);
    d.method = (rbs_method)(u8(&r) % 7); /* every method (6 = soft); set_method tries an invalid one */
    {
        /* one byte for both, so that inputs kept from before soft_substeps
         * read as they did: halvings 0..31, soft sub-steps 1..8 */
        uint8_t b = u8(&r);
        d.max_halvings = b % 32u;
        d.soft_substeps = 1u + b / 32u;
    }
    d.mutual_gravity = u8(&r) & 1;
    d.prune = u8(&r) & 1;
    /* every method's work per step is bounded by max_substeps; a small cap
     * keeps one input's steps to seconds under ASan (the default's frames
     * are legitimate but can take a minute here; tests cover the caps) */
    d.max_substeps = FUZZ_MAX_SUBSTEPS;
    st = rbs_world_def_validate(&d, msg, sizeof msg);
    FUZZ_CHECK(fuzz_status_valid(st), "validate %d", (int)st);
    st = rbs_world_create(&d, &s.w);
    FUZZ_CHECK(fuzz_status_valid(st), "create %d", (int)st);
    if (st != RBS_OK) {
        FUZZ_CHECK(s.w == NULL, "failed create left a world");
        /* fall back to defaults so the program still runs */
        rbs_world_def_init(&d);
        d.max_bodies = 8;
        d.max_substeps = FUZZ_MAX_SUBSTEPS;
        st = rbs_world_create(&d, &s.w);
        FUZZ_CHECK(st == RBS_OK, "default world %s", rbs_status_name(st));
    }
    run_ops(&s, &r);
    rbs_world_destroy(s.w);
    return 0;
}
