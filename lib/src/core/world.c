/*
 * world.c - world creation in one memory block, bodies, materials, state
 * access and diagnostics.
 */
#include <float.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <stddef.h>
#include <string.h>

#include "core/name.h"
#include "core/soft_detect.h"
#include "core/team.h"

#define WORLD_MAGIC 0x72627377u /* "rbsw" */
#define ALIGN 16u

/* ------------------------------------------------------------------------- */
/* Definitions                                                               */
/* ------------------------------------------------------------------------- */

/* Copy a caller's def (whose first member is its struct_size) over a fully
 * defaulted one, taking only the bytes the caller's header knew about. */
/* Every def holds doubles and pointers, so the sizeof of any version of
 * one is a multiple of their alignment; a struct_size that is not ends
 * inside a field (half a name pointer, half of dt) and is refused. */
struct def_align_double { char c; double d; };
struct def_align_pointer { char c; void *p; };
#define DEF_ALIGN                                                                              \
    (offsetof(struct def_align_double, d) > offsetof(struct def_align_pointer, p)              \
         ? offsetof(struct def_align_double, d)                                                \
         : offsetof(struct def_align_pointer, p))

static int def_read(void *dst, size_t dst_size, const void *src)
{
    uint32_t size;
    memcpy(&size, src, sizeof size);
    if (size < sizeof(uint32_t) || size > 65536u || size % DEF_ALIGN != 0)
        return 0;
    memcpy(dst, src, size < dst_size ? size : dst_size);
    ((uint32_t *)dst)[0] = (uint32_t)dst_size;
    return 1;
}

/* Give a caller the defaults d (of d_size bytes) for a struct of its
 * header's dst_size: the bytes it knows about, with struct_size the number
 * given. */
static void def_give(void *dst, size_t dst_size, const void *d, size_t d_size)
{
    const uint32_t n = (uint32_t)(dst_size < d_size ? dst_size : d_size);
    memcpy(dst, d, n);
    memcpy(dst, &n, sizeof n);
}

void rbs_world_def_init_sized(rbs_world_def *def, size_t def_size)
{
    rbs_world_def d;
    if (def == NULL || def_size < sizeof(uint32_t))
        return;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof d;
    d.max_bodies = 64;
    d.max_materials = 16;
    d.max_pairs = 64;
    d.max_contacts = 0;
    d.dt = 0.001;
    d.gravity.z = -9.81;
    d.gravity_mode = RBS_GRAVITY_ACCELERATION;
    d.restitution = 0.5;
    d.method = RBS_METHOD_AUTO;
    d.tolerance = 1e-9;
    d.slop = 1e-6;
    d.max_halvings = 30;
    d.max_sweeps = 20;
    d.mutual_gravity = 0;
    d.gravity_constant = 6.674e-11;
    d.softening = 0.0;
    d.prune = 1;
    d.max_substeps = 4096;
    d.soft_substeps = 3;
    d.soft_tolerance = 0.0;
    def_give(def, def_size, &d, sizeof d);
}

void rbs_sphere_def_init_sized(rbs_sphere_def *def, size_t def_size)
{
    rbs_sphere_def d;
    if (def == NULL || def_size < sizeof(uint32_t))
        return;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof d;
    d.radius = 0.1;
    d.mass = 1.0;
    d.inertia_kind = RBS_INERTIA_SOLID;
    d.orientation.w = 1.0;
    d.color = 0xd03030u;
    d.texture = RBS_TEXTURE_STRIPES;
    def_give(def, def_size, &d, sizeof d);
}

void rbs_plane_def_init_sized(rbs_plane_def *def, size_t def_size)
{
    rbs_plane_def d;
    if (def == NULL || def_size < sizeof(uint32_t))
        return;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof d;
    d.normal.z = 1.0;
    d.color = 0x808080u;
    d.texture = RBS_TEXTURE_CHECKER;
    def_give(def, def_size, &d, sizeof d);
}

void rbs_pair_def_init_sized(rbs_pair_def *def, size_t def_size)
{
    rbs_pair_def d;
    if (def == NULL || def_size < sizeof(uint32_t))
        return;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof d;
    d.static_friction = 0.5;
    d.kinetic_friction = 0.3;
    d.restitution = -1.0;
    def_give(def, def_size, &d, sizeof d);
}

/* The rules of the settings a world can change after it is built, one
 * each for the def (world_def_check) and its setter (rbs_world_set_dt,
 * rbs_world_set_method): 1 if x is taken, else 0 with the reason in msg. */
static int dt_ok(double dt, char *msg, size_t len)
{
    char nb[32]; /* (a number for a message) */
    if (dt > 0.0 && isfinite(dt))
        return 1;
    snprintf(msg, len, "dt must be finite and > 0, got %s", rbs__shortest(nb, dt));
    return 0;
}

static int tolerance_ok(double tolerance, char *msg, size_t len)
{
    char nb[32];
    if (tolerance >= 1e-15 && isfinite(tolerance))
        return 1;
    snprintf(msg, len, "tolerance must be finite and >= 1e-15 (double precision), got %s",
             rbs__shortest(nb, tolerance));
    return 0;
}

static int method_ok(rbs_method method, char *msg, size_t len)
{
    if ((int)method >= 0 && (int)method < RBS_METHOD_COUNT)
        return 1;
    snprintf(msg, len, "method %d is not a rbs_method", (int)method);
    return 0;
}

/* Read and check a world def; fills *out with defaults for fields the
 * caller's header did not have. */
static rbs_status world_def_check(const rbs_world_def *def, rbs_world_def *out,
                                  char *msg, size_t len)
{
    rbs_world_def d;
    char nb[32]; /* (a number for a message) */
    if (def == NULL) {
        snprintf(msg, len, "def is NULL");
        return RBS_E_INVALID;
    }
    rbs_world_def_init(&d);
    if (!def_read(&d, sizeof d, def)) {
        snprintf(msg, len, "def.struct_size is %u: initialise defs with rbs_world_def_init()",
                 (unsigned)def->struct_size);
        return RBS_E_INVALID;
    }
    if (d.max_bodies < 1 || d.max_bodies > (1u << 24)) {
        snprintf(msg, len, "max_bodies must be in [1, 16777216], got %u", (unsigned)d.max_bodies);
        return RBS_E_INVALID;
    }
    if (d.max_materials > (1u << 12)) {
        snprintf(msg, len, "max_materials must be <= 4096, got %u", (unsigned)d.max_materials);
        return RBS_E_INVALID;
    }
    if (d.max_pairs > (1u << 16)) {
        snprintf(msg, len, "max_pairs must be <= 65536, got %u", (unsigned)d.max_pairs);
        return RBS_E_INVALID;
    }
    if (d.max_contacts == 0)
        d.max_contacts = 4u * d.max_bodies + 16u;
    if (d.max_contacts > (1u << 26)) {
        snprintf(msg, len, "max_contacts must be <= 67108864, got %u", (unsigned)d.max_contacts);
        return RBS_E_INVALID;
    }
    if (!dt_ok(d.dt, msg, len))
        return RBS_E_INVALID;
    if (!isfinite(d.gravity.x) || !isfinite(d.gravity.y) || !isfinite(d.gravity.z)) {
        char nb2[32], nb3[32];
        snprintf(msg, len, "gravity must be finite, got (%s, %s, %s)", rbs__shortest(nb, d.gravity.x),
                 rbs__shortest(nb2, d.gravity.y), rbs__shortest(nb3, d.gravity.z));
        return RBS_E_INVALID;
    }
    if (d.gravity_mode != RBS_GRAVITY_ACCELERATION && d.gravity_mode != RBS_GRAVITY_FORCE) {
        snprintf(msg, len, "gravity_mode must be acceleration (0) or force (1), got %d", (int)d.gravity_mode);
        return RBS_E_INVALID;
    }
    if (!(d.restitution >= 0.0 && d.restitution <= 1.0)) {
        snprintf(msg, len, "restitution must be in [0, 1], got %s", rbs__shortest(nb, d.restitution));
        return RBS_E_INVALID;
    }
    if (!method_ok(d.method, msg, len) || !tolerance_ok(d.tolerance, msg, len))
        return RBS_E_INVALID;
    if (!(d.slop > 0.0 && d.slop < 0.1)) {
        snprintf(msg, len, "slop must be in (0, 0.1), got %s", rbs__shortest(nb, d.slop));
        return RBS_E_INVALID;
    }
    if (d.max_substeps < 1) {
        snprintf(msg, len, "max_substeps must be >= 1, got %u", (unsigned)d.max_substeps);
        return RBS_E_INVALID;
    }
    if (d.soft_substeps < 1 || d.soft_substeps > RBS__SOFT_SUBSTEPS_MAX) {
        snprintf(msg, len, "soft_substeps must be in [1, %u], got %u", (unsigned)RBS__SOFT_SUBSTEPS_MAX,
                 (unsigned)d.soft_substeps);
        return RBS_E_INVALID;
    }
    if (!(d.soft_tolerance >= 0.0 && d.soft_tolerance <= 1.0)) {
        snprintf(msg, len, "soft_tolerance must be in [0, 1] (a fraction of the radius), got %s", rbs__shortest(nb, d.soft_tolerance));
        return RBS_E_INVALID;
    }
    if (d.max_halvings > 60) {
        snprintf(msg, len, "max_halvings must be <= 60, got %u", (unsigned)d.max_halvings);
        return RBS_E_INVALID;
    }
    if (d.max_sweeps < 1 || d.max_sweeps > 100000) {
        snprintf(msg, len, "max_sweeps must be in [1, 100000], got %u", (unsigned)d.max_sweeps);
        return RBS_E_INVALID;
    }
    if (!(d.gravity_constant >= 0.0) || !isfinite(d.gravity_constant)) {
        snprintf(msg, len, "gravity_constant must be finite and >= 0, got %s",
                 rbs__shortest(nb, d.gravity_constant));
        return RBS_E_INVALID;
    }
    if (!(d.softening >= 0.0) || !isfinite(d.softening)) {
        snprintf(msg, len, "softening must be finite and >= 0, got %s", rbs__shortest(nb, d.softening));
        return RBS_E_INVALID;
    }
    if (d.mutual_gravity && !(d.gravity_constant > 0.0)) {
        /* (G = 0 would attract nothing, yet cost the pair sums and keep
         * auto from the soft step; a scene's mutual_gravity.G is > 0 too) */
        snprintf(msg, len, "gravity_constant must be > 0 with mutual_gravity on, got %s",
                 rbs__shortest(nb, d.gravity_constant));
        return RBS_E_INVALID;
    }
    if (out)
        *out = d;
    return RBS_OK;
}

rbs_status rbs_world_def_validate(const rbs_world_def *def, char *message, size_t message_size)
{
    char buf[RBS__ERROR_MAX];
    rbs_status st = world_def_check(def, NULL, buf, sizeof buf);
    if (message && message_size > 0)
        snprintf(message, message_size, "%s", st == RBS_OK ? "" : buf);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Layout                                                                    */
/* ------------------------------------------------------------------------- */

static size_t align_up(size_t n) { return (n + (ALIGN - 1)) & ~(size_t)(ALIGN - 1); }

/* Carve one array: advance *at, and if base is set, store the pointer. */
static void *carve(unsigned char *base, size_t *at, size_t bytes)
{
    void *p = base ? base + *at : NULL;
    *at = align_up(*at + bytes);
    return p;
}

size_t rbs__world_layout(rbs_world *w, const rbs_world_def *d, unsigned char *base)
{
    size_t at = align_up(sizeof(rbs_world));
    size_t B = d->max_bodies, M = d->max_materials, P = d->max_pairs, C = d->max_contacts;
    size_t T = (M + 1) * (M + 1);
    rbs_world dummy;
    rbs_world *x = w ? w : &dummy;

    x->type = carve(base, &at, B * sizeof(int32_t));
    x->generation = carve(base, &at, B * sizeof(uint32_t));
    x->fixed = carve(base, &at, B * sizeof(int32_t));
    x->material = carve(base, &at, B * sizeof(uint32_t));
    x->color = carve(base, &at, B * sizeof(uint32_t));
    x->texture = carve(base, &at, B * sizeof(int32_t));
    x->isotropic = carve(base, &at, B * sizeof(int32_t));
    x->free_list = carve(base, &at, B * sizeof(uint32_t));
    x->spheres = carve(base, &at, B * sizeof(uint32_t));
    x->planes = carve(base, &at, B * sizeof(uint32_t));
    x->item = carve(base, &at, B * sizeof(uint32_t));
    x->acc = carve(base, &at, 3 * B * sizeof(double));
    x->name = carve(base, &at, B * RBS_NAME_MAX);
    {
        size_t K = 2;
        while (K < 2 * B)
            K *= 2;
        x->name_index_size = (uint32_t)K;
        x->name_index = carve(base, &at, K * sizeof(uint32_t));
    }
    x->pos = carve(base, &at, 3 * B * sizeof(double));
    x->vel = carve(base, &at, 3 * B * sizeof(double));
    x->avel = carve(base, &at, 3 * B * sizeof(double));
    x->orient = carve(base, &at, 4 * B * sizeof(double));
    x->force = carve(base, &at, 3 * B * sizeof(double));
    x->torque = carve(base, &at, 3 * B * sizeof(double));
    x->normal = carve(base, &at, 3 * B * sizeof(double));
    x->radius = carve(base, &at, B * sizeof(double));
    x->mass = carve(base, &at, B * sizeof(double));
    x->inv_mass = carve(base, &at, B * sizeof(double));
    x->com_body = carve(base, &at, 3 * B * sizeof(double));
    x->inertia = carve(base, &at, 9 * B * sizeof(double));
    x->inv_inertia = carve(base, &at, 9 * B * sizeof(double));
    x->iso_inertia = carve(base, &at, B * sizeof(double));
    x->iso_inv_inertia = carve(base, &at, B * sizeof(double));
    x->step_save = carve(base, &at, RBS__SAVE_STRIDE * B * sizeof(double));
    x->sub_save = carve(base, &at, RBS__SAVE_STRIDE * B * sizeof(double));
    x->material_name = carve(base, &at, M * RBS_NAME_MAX);
    x->pair = carve(base, &at, (P + 1) * sizeof(rbs__pair)); /* + the default row */
    x->pair_table = carve(base, &at, T * sizeof(int32_t));
    {
        /* the contacts, or in the soft step's gathered layout its chunks
         * (soft.h, 64-byte aligned at use): a step takes one or the other,
         * and neither outlives it */
        size_t K = RBS__SOFT_CHUNKS(C, (uint32_t)B), chunks = K * sizeof(rbs__chunk) + 64;
        size_t contacts = C * sizeof(rbs__contact);
        unsigned char *p = carve(base, &at, chunks > contacts ? chunks : contacts);
        x->contact = (rbs__contact *)(void *)p;
        x->chunk_cap = (uint32_t)K;
        if (p != NULL)
            x->chunk = (rbs__chunk *)(void *)(p + (64u - (uintptr_t)p % 64u) % 64u);
        x->chunk_member = carve(base, &at, (RBS__LEVELS_MAX + 1) * B * sizeof(uint16_t));
        x->soft_slab = carve(base, &at, B);
        x->soft_order = carve(base, &at, B * sizeof(uint32_t));
        x->soft_rank = carve(base, &at, B * sizeof(uint32_t));
        x->soft_planes = carve(base, &at, B);
        x->soft_aside = carve(base, &at, C * sizeof(uint32_t));
    }
    x->contact_resist = carve(base, &at, C * sizeof(rbs__resist));
    {
        size_t W = C; /* an entry for every contact (solver.c) */
        x->warm_size = (uint32_t)W;
        x->warm = carve(base, &at, W * sizeof(rbs__warm));
        x->warm_save = carve(base, &at, W * sizeof(rbs__warm));
        x->warm_at = carve(base, &at, 2 * B * sizeof(uint32_t));
    }
    x->solver_body = carve(base, &at, RBS__SOLVER_STRIDE * B * sizeof(double));
    x->method_scratch = carve(base, &at, (RBS__SCRATCH_STRIDE * B + RBS__SCRATCH_EXTRA) * sizeof(double));
    x->method_state = carve(base, &at, 8 * sizeof(double));
    x->team_mem = carve(base, &at, rbs__team_size());
    {
        size_t T = 16;
        while (T < 2 * B)
            T <<= 1;
        x->bp_table_size = (uint32_t)T;
        x->bp_center = carve(base, &at, 3 * B * sizeof(double));
        x->bp_reach = carve(base, &at, B * sizeof(double));
        x->bp_key = carve(base, &at, B * sizeof(uint32_t));
        x->bp_item = carve(base, &at, B * sizeof(uint32_t));
        x->bp_big = carve(base, &at, B * sizeof(uint32_t));
        x->bp_start = carve(base, &at, (T + 1) * sizeof(uint32_t));
        x->bp_fill = carve(base, &at, T * sizeof(uint32_t));
        x->bp_query = carve(base, &at, B);
        x->bp_cell = carve(base, &at, 3 * B * sizeof(int32_t));
        x->vl_pos = carve(base, &at, 3 * B * sizeof(double));
        x->vl_reach = carve(base, &at, B * sizeof(double));
        x->vl_cap = (uint32_t)C;
        x->vl_pair = carve(base, &at, 2 * C * sizeof(uint32_t));
        x->vl_start = carve(base, &at, (B + 1) * sizeof(uint32_t));
    }
    x->ev_alpha = carve(base, &at, 3 * B * sizeof(double));
    x->ev_mode = carve(base, &at, B * sizeof(int32_t));
    x->pressed = carve(base, &at, B);
    x->ev_plane = carve(base, &at, B * sizeof(uint32_t));
    x->shock_order = carve(base, &at, (C + B + 2) * sizeof(uint32_t));
    return at;
}

size_t rbs_world_memory_size(const rbs_world_def *def)
{
    rbs_world_def d;
    char msg[RBS__ERROR_MAX];
    if (world_def_check(def, &d, msg, sizeof msg) != RBS_OK)
        return 0;
    return rbs__world_layout(NULL, &d, NULL);
}

/* Build a world in buffer; zeroed: the buffer is known to be all zero
 * bytes already (calloc), so it is not written over. */
static rbs_status world_build(void *buffer, size_t bytes, const rbs_world_def *def, rbs_world **out,
                              int zeroed)
{
    rbs_world_def d;
    char msg[RBS__ERROR_MAX];
    size_t need;
    rbs_world *w;
    rbs_status st;

    if (out == NULL)
        return RBS_E_INVALID;
    *out = NULL;
    st = world_def_check(def, &d, msg, sizeof msg);
    if (st != RBS_OK)
        return st;
    if (buffer == NULL || ((uintptr_t)buffer % ALIGN) != 0)
        return RBS_E_INVALID;
    need = rbs__world_layout(NULL, &d, NULL);
    if (bytes < need)
        return RBS_E_MEMORY;
    if ((int)d.method < 0 || (int)d.method >= RBS_METHOD_COUNT)
        return RBS_E_UNSUPPORTED;
    if (!zeroed)
        memset(buffer, 0, need);
    w = (rbs_world *)buffer;
    w->magic = WORLD_MAGIC;
    w->bytes = need;
    w->def = d;
    rbs__world_layout(w, &d, (unsigned char *)buffer);
    /* the default row (index max_pairs) of a contact no row matches:
     * frictionless (zeros), the world's restitution */
    w->pair[d.max_pairs].e = -1.0;
    w->soft_kernels = rbs__soft_kernels_best();
    rbs_workers_init(&w->workers);
    rbs__rebuild_pair_table(w);
    w->plan_dirty = 1;
    /* the adaptive method's GSL workspaces: the one allocation outside the
     * block (docs/methods.md) */
    if (d.method == RBS_METHOD_ADAPTIVE && rbs__adaptive_reserve(w) != RBS_OK) {
        w->magic = 0;
        return RBS_E_MEMORY;
    }
    *out = w;
    return RBS_OK;
}

rbs_status rbs_world_create_in(void *buffer, size_t bytes, const rbs_world_def *def,
                               rbs_world **out)
{
    return world_build(buffer, bytes, def, out, 0);
}

rbs_status rbs_world_create_in_zeroed(void *buffer, size_t bytes, const rbs_world_def *def,
                                      rbs_world **out)
{
    return world_build(buffer, bytes, def, out, 1);
}

rbs_status rbs_world_create(const rbs_world_def *def, rbs_world **out)
{
    size_t need;
    void *mem;
    rbs_status st;
    if (out == NULL)
        return RBS_E_INVALID;
    *out = NULL;
    need = rbs_world_memory_size(def);
    if (need == 0) {
        rbs_world_def d;
        char msg[RBS__ERROR_MAX];
        return world_def_check(def, &d, msg, sizeof msg);
    }
    /* The one allocation of a world's life.  calloc, not malloc and a
     * memset: the operating system gives a large block as zero pages that
     * take physical memory only when first written, so capacity a run never
     * reaches (contact slots, other methods' scratch) costs address space,
     * not memory (rbsim.h). */
    mem = calloc(1, need);
    if (mem == NULL)
        return RBS_E_MEMORY;
    st = world_build(mem, need, def, out, 1);
    if (st != RBS_OK) {
        free(mem);
        return st;
    }
    (*out)->owns_memory = 1;
    return RBS_OK;
}

void rbs_world_destroy(rbs_world *w)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return;
    rbs__adaptive_release(w);
    w->magic = 0;
    if (w->owns_memory)
        free(w);
}

int rbs__world_claim(rbs_world *w)
{
#if defined(__GNUC__)
    int expected = 0;
    return __atomic_compare_exchange_n(&w->in_run, &expected, 1, 0, __ATOMIC_ACQUIRE,
                                       __ATOMIC_RELAXED)
               ? 0
               : -1;
#else
    if (w->in_run)
        return -1;
    w->in_run = 1;
    return 0;
#endif
}

void rbs__world_release(rbs_world *w)
{
#if defined(__GNUC__)
    __atomic_store_n(&w->in_run, 0, __ATOMIC_RELEASE);
#else
    w->in_run = 0;
#endif
}

int rbs__world_set_error(rbs_world *w, rbs_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    rbs__vsnprintf_c(w->error, sizeof w->error, fmt, ap);
    va_end(ap);
    return (int)status;
}

#define FAIL(w, st, ...) return (rbs_status)rbs__world_set_error((w), (st), __VA_ARGS__)

const char *rbs_world_last_error(const rbs_world *w)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return "invalid world";
    return w->error;
}

rbs_status rbs_world_get_def(const rbs_world *w, rbs_world_def *out)
{
    if (w == NULL || out == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    if (out->struct_size < sizeof(uint32_t))
        return RBS_E_INVALID;
    memcpy(out, &w->def, out->struct_size < sizeof w->def ? out->struct_size : sizeof w->def);
    out->struct_size = out->struct_size < sizeof w->def ? out->struct_size : (uint32_t)sizeof w->def;
    return RBS_OK;
}

/* ------------------------------------------------------------------------- */
/* Materials                                                                 */
/* ------------------------------------------------------------------------- */

size_t rbs__utf8_seq(const char *text, size_t len, size_t i)
{
    const unsigned char *s = (const unsigned char *)text;
    unsigned char c = s[i], lo = 0x80, hi = 0xBF;
    size_t n, k;
    if (c < 0x80) {
        return 1;
    }
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80; /* no overlong forms */
        hi = c == 0xED ? 0x9F : 0xBF; /* no surrogates */
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF; /* at most U+10FFFF */
    } else {
        return 0;
    }
    if (len - i < n) {
        return 0;
    }
    for (k = 1; k < n; k++) {
        unsigned char b = s[i + k];
        if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xBF)) {
            return 0;
        }
    }
    return n;
}

/* The names scene files refuse, the API refuses (core/name.h): what of a
 * name's rule a message says before the fault (names are written to scene
 * files by rbs_scene_save and to JSON frames read by Python). */
#define NAME_RULE                                                                                  \
    "must have 1 to %d bytes of UTF-8 without spaces, control characters, '#', '\"', '=', ',' "  \
    "or invisible formatting characters, as in a scene file"

rbs_status rbs_world_add_material(rbs_world *w, const char *name, rbs_material_id *out)
{
    rbs_material_id id;
    rbs__name_fault fault;
    char why[96];
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (name == NULL)
        FAIL(w, RBS_E_INVALID, "material name is NULL");
    if (rbs__name_check(name, &fault) != RBS__NAME_OK) {
        rbs__name_fault_text(&fault, why, sizeof why);
        FAIL(w, RBS_E_INVALID, "material name " NAME_RULE ", got %s", RBS_NAME_MAX - 1, why);
    }
    if (strcmp(name, "*") == 0)
        FAIL(w, RBS_E_INVALID, "material name must not be \"*\", which means any material in a pair");
    if (rbs_world_find_material(w, name, &id) == RBS_OK)
        FAIL(w, RBS_E_INVALID, "material \"%s\" already exists", name);
    if (w->materials >= w->def.max_materials)
        FAIL(w, RBS_E_CAPACITY, "material \"%s\": world holds at most %u materials", name,
             (unsigned)w->def.max_materials);
    strcpy(w->material_name[w->materials], name);
    w->materials++;
    rbs__rebuild_pair_table(w);
    if (out) {
        out->index = w->materials - 1;
        out->generation = 1;
    }
    return RBS_OK;
}

rbs_status rbs_world_find_material(const rbs_world *w, const char *name, rbs_material_id *out)
{
    uint32_t i;
    if (w == NULL || name == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    for (i = 0; i < w->materials; ++i) {
        if (strcmp(w->material_name[i], name) == 0) {
            if (out) {
                out->index = i;
                out->generation = 1;
            }
            return RBS_OK;
        }
    }
    return RBS_E_NOT_FOUND;
}

rbs_status rbs_world_material_at(const rbs_world *w, uint32_t index, rbs_material_id *out,
                                 const char **name)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    if (index >= w->materials)
        return RBS_E_NOT_FOUND;
    if (out) {
        out->index = index;
        out->generation = 1;
    }
    if (name)
        *name = w->material_name[index];
    return RBS_OK;
}

rbs_status rbs_world_pair_at(const rbs_world *w, uint32_t index, rbs_pair_def *out)
{
    rbs_pair_def d;
    const rbs__pair *r;
    uint32_t size;
    if (w == NULL || out == NULL || w->magic != WORLD_MAGIC || out->struct_size < sizeof(uint32_t))
        return RBS_E_INVALID;
    if (index >= w->pairs)
        return RBS_E_NOT_FOUND;
    r = &w->pair[index];
    rbs_pair_def_init(&d);
    d.a.index = r->a ? r->a - 1 : 0;
    d.a.generation = r->a ? 1 : 0;
    d.b.index = r->b ? r->b - 1 : 0;
    d.b.generation = r->b ? 1 : 0;
    d.static_friction = r->mu_s;
    d.kinetic_friction = r->mu_k;
    d.restitution = r->e;
    d.rolling = r->rolling;
    d.spinning = r->spinning;
    size = out->struct_size < sizeof d ? out->struct_size : (uint32_t)sizeof d;
    memcpy(out, &d, size);
    out->struct_size = size;
    return RBS_OK;
}

/* Material id -> stored code (index + 1, 0 = none/"*"); -1 if invalid. */
static int64_t material_code(const rbs_world *w, rbs_material_id m)
{
    if (m.index == 0 && m.generation == 0)
        return 0;
    if (m.generation != 1 || m.index >= w->materials)
        return -1;
    return (int64_t)m.index + 1;
}

/* Best row for every ordered pair of material codes: exact pair, then one
 * wildcard, then both.  Rebuilt when materials or pairs change. */
void rbs__rebuild_pair_table(rbs_world *w)
{
    uint32_t n = w->def.max_materials + 1, a, b, p;
    for (a = 0; a < n; ++a) {
        for (b = 0; b < n; ++b) {
            int best = -1, best_score = -1;
            for (p = 0; p < w->pairs; ++p) {
                const rbs__pair *r = &w->pair[p];
                int score = -1;
                if ((r->a == a && r->b == b) || (r->a == b && r->b == a))
                    score = (r->a != 0) + (r->b != 0);
                else if (r->a == 0 && (r->b == a || r->b == b))
                    score = r->b != 0;
                else if (r->b == 0 && (r->a == a || r->a == b))
                    score = r->a != 0;
                else if (r->a == 0 && r->b == 0)
                    score = 0; /* "*" with "*": any pair (it matched only pairs
                                  with a body of no material before session 38) */
                /* a row naming a real material matches only that material */
                if (score >= 0 && r->a != 0 && r->b != 0 &&
                    !((r->a == a && r->b == b) || (r->a == b && r->b == a)))
                    score = -1;
                if (score > best_score) {
                    best_score = score;
                    best = (int)p;
                }
            }
            w->pair_table[a * n + b] = best;
        }
    }
    w->plan_dirty = 1;
    w->rows_dirty = 1;
}

rbs_status rbs_world_set_pair(rbs_world *w, const rbs_pair_def *def)
{
    rbs_pair_def d;
    char nb[32], nb2[32]; /* (numbers for a message) */
    int64_t a, b;
    uint32_t p;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (def == NULL)
        FAIL(w, RBS_E_INVALID, "set_pair: def is NULL");
    rbs_pair_def_init(&d);
    if (!def_read(&d, sizeof d, def))
        FAIL(w, RBS_E_INVALID, "pair def not initialised (use rbs_pair_def_init)");
    a = material_code(w, d.a);
    b = material_code(w, d.b);
    if (a < 0 || b < 0)
        FAIL(w, RBS_E_STALE_ID, "pair: unknown material id");
    if (!(d.static_friction >= 0.0) || !isfinite(d.static_friction) ||
        !(d.kinetic_friction >= 0.0) || !isfinite(d.kinetic_friction))
        FAIL(w, RBS_E_INVALID, "pair: friction must be finite and >= 0 (static %s, kinetic %s)",
             rbs__shortest(nb, d.static_friction), rbs__shortest(nb2, d.kinetic_friction));
    if (d.kinetic_friction > d.static_friction)
        FAIL(w, RBS_E_INVALID, "pair: kinetic friction %s exceeds static %s", rbs__shortest(nb, d.kinetic_friction),
             rbs__shortest(nb2, d.static_friction));
    if (!(d.restitution <= 1.0) || !isfinite(d.restitution))
        FAIL(w, RBS_E_INVALID, "pair: restitution must be in [0, 1] (or negative for the world's), got %s",
             rbs__shortest(nb, d.restitution));
    if (!(d.rolling >= 0.0) || !isfinite(d.rolling) || !(d.spinning >= 0.0) || !isfinite(d.spinning))
        FAIL(w, RBS_E_INVALID, "pair: rolling and spinning resistance must be finite and >= 0");
    for (p = 0; p < w->pairs; ++p) {
        rbs__pair *r = &w->pair[p];
        if ((r->a == (uint32_t)a && r->b == (uint32_t)b) || (r->a == (uint32_t)b && r->b == (uint32_t)a))
            break;
    }
    if (p == w->pairs) {
        if (w->pairs >= w->def.max_pairs)
            FAIL(w, RBS_E_CAPACITY, "pair: world holds at most %u material pairs",
                 (unsigned)w->def.max_pairs);
        w->pairs++;
    }
    w->pair[p].a = (uint32_t)a;
    w->pair[p].b = (uint32_t)b;
    w->pair[p].mu_s = d.static_friction;
    w->pair[p].mu_k = d.kinetic_friction;
    w->pair[p].e = d.restitution;
    w->pair[p].rolling = d.rolling;
    w->pair[p].spinning = d.spinning;
    rbs__rebuild_pair_table(w);
    return RBS_OK;
}

/* ------------------------------------------------------------------------- */
/* Bodies                                                                    */
/* ------------------------------------------------------------------------- */

static int id_valid(const rbs_world *w, rbs_body_id id)
{
    return w != NULL && w->magic == WORLD_MAGIC && id.generation != 0 && id.index < w->slots &&
           w->generation[id.index] == id.generation && w->type[id.index] != RBS_BODY_NONE;
}

/* The name index: FNV-1a of the name, linear probing in a table at least
 * twice the bodies (so probes stay short and an empty entry always ends
 * one), removal by backward shift (Knuth, TAOCP vol. 3, 6.4, Algorithm R),
 * so no tombstones pile up.  It lives in the world's block: named bodies
 * are found in O(1) instead of by a walk over every slot. */
static uint32_t name_hash(const char *name)
{
    uint32_t h = 2166136261u;
    while (*name)
        h = (h ^ (unsigned char)*name++) * 16777619u;
    return h;
}

/* The index entry holding name, or the empty entry where it would go. */
static uint32_t name_probe(const rbs_world *w, const char *name)
{
    uint32_t mask = w->name_index_size - 1, k = name_hash(name) & mask;
    while (w->name_index[k] != 0 && strcmp(w->name[w->name_index[k] - 1], name) != 0)
        k = (k + 1) & mask;
    return k;
}

/* Slot of the body named name, or UINT32_MAX. */
static uint32_t name_find(const rbs_world *w, const char *name)
{
    uint32_t e = w->name_index[name_probe(w, name)];
    return e != 0 ? e - 1 : UINT32_MAX;
}

static void name_insert(rbs_world *w, uint32_t s)
{
    w->name_index[name_probe(w, w->name[s])] = s + 1;
}

static void name_remove(rbs_world *w, uint32_t s)
{
    uint32_t mask = w->name_index_size - 1, hole = name_probe(w, w->name[s]), k = hole;
    w->name_index[hole] = 0;
    for (;;) {
        uint32_t home;
        k = (k + 1) & mask;
        if (w->name_index[k] == 0)
            return;
        home = name_hash(w->name[w->name_index[k] - 1]) & mask;
        /* the entry at k may fill the hole unless its home lies
         * cyclically in (hole, k] */
        if ((k > hole) ? (home <= hole || home > k) : (home <= hole && home > k)) {
            w->name_index[hole] = w->name_index[k];
            w->name_index[k] = 0;
            hole = k;
        }
    }
}

static int name_taken(const rbs_world *w, const char *name)
{
    if (name == NULL || name[0] == '\0')
        return 0;
    return name_find(w, name) != UINT32_MAX;
}

/* Take a free slot (reusing removed ones first); UINT32_MAX if full. */
/* Store v at p unless it is zero (what a free slot already holds). */
static void store_nonzero3(double *p, v3 v)
{
    if (v.x != 0.0 || v.y != 0.0 || v.z != 0.0)
        v3_store(p, v);
}

/* Zero n doubles at p, writing only those that are not zero already (so a
 * page that was never written stays so). */
static void clear_nonzero(double *p, int n)
{
    int k;
    for (k = 0; k < n; ++k)
        if (p[k] != 0.0)
            p[k] = 0.0;
}

static uint32_t slot_take(rbs_world *w)
{
    uint32_t s;
    if (w->free_count > 0) {
        s = w->free_list[--w->free_count];
    } else {
        if (w->slots >= w->def.max_bodies)
            return UINT32_MAX;
        s = w->slots++;
    }
    w->generation[s] = w->generation[s] + 1u == 0u ? 1u : w->generation[s] + 1u;
    w->bodies++;
    return s;
}

void rbs__rebuild_lists(rbs_world *w)
{
    uint32_t i;
    w->sphere_count = 0;
    w->plane_count = 0;
    w->vl_valid = 0; /* items may be renumbered */
    for (i = 0; i < w->slots; ++i) {
        if (w->type[i] == RBS_BODY_SPHERE) {
            w->item[i] = w->sphere_count;
            w->spheres[w->sphere_count++] = i;
        } else if (w->type[i] == RBS_BODY_PLANE) {
            w->planes[w->plane_count++] = i;
        }
    }
}

/* Determinant and inverse of a symmetric 3x3 (row-major). */
static double m3_inverse(const double *m, double *inv)
{
    double c00 = m[4] * m[8] - m[5] * m[7];
    double c01 = m[5] * m[6] - m[3] * m[8];
    double c02 = m[3] * m[7] - m[4] * m[6];
    double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
    if (det == 0.0)
        return 0.0;
    inv[0] = c00 / det;
    inv[1] = (m[2] * m[7] - m[1] * m[8]) / det;
    inv[2] = (m[1] * m[5] - m[2] * m[4]) / det;
    inv[3] = c01 / det;
    inv[4] = (m[0] * m[8] - m[2] * m[6]) / det;
    inv[5] = (m[2] * m[3] - m[0] * m[5]) / det;
    inv[6] = c02 / det;
    inv[7] = (m[1] * m[6] - m[0] * m[7]) / det;
    inv[8] = (m[0] * m[4] - m[1] * m[3]) / det;
    return det;
}

/* A body was just put in slot s: append it to the sphere or plane list when
 * s is the newest slot (lists stay in slot order, O(1) per body); a reused
 * slot rebuilds them. */
static void add_to_lists(rbs_world *w, uint32_t s)
{
    if (s + 1 != w->slots) {
        rbs__rebuild_lists(w);
    } else if (w->type[s] == RBS_BODY_SPHERE) {
        w->item[s] = w->sphere_count;
        w->spheres[w->sphere_count++] = s;
    } else {
        w->planes[w->plane_count++] = s;
    }
}

/* Checks every body kind shares: its name (kind is "sphere" or "plane"). */
static rbs_status check_name(rbs_world *w, const char *kind, const char *name)
{
    rbs__name_fault fault;
    char why[96];
    /* (NULL and "": unnamed) */
    if (name != NULL && name[0] != '\0' && rbs__name_check(name, &fault) != RBS__NAME_OK) {
        /* (one message for every fault, as a material's: "got 64 bytes",
         * "got byte 0xff at byte 1, which starts no UTF-8 sequence") */
        rbs__name_fault_text(&fault, why, sizeof why);
        FAIL(w, RBS_E_INVALID, "%s name " NAME_RULE ", got %s", kind, RBS_NAME_MAX - 1, why);
    }
    if (name_taken(w, name))
        FAIL(w, RBS_E_INVALID, "%s \"%s\": name already used", kind, name);
    return RBS_OK;
}

/* ... its material (stored code into *mat) and texture, then a free slot
 * into *slot, set up as an unmoving body of that type with nothing applied
 * (the caller fills in what its kind has). */
static rbs_status take_slot(rbs_world *w, const char *kind, rbs_body_type type, rbs_material_id material,
                            rbs_texture texture, uint32_t color, const char *name, uint32_t *slot)
{
    int64_t mat = material_code(w, material);
    uint32_t s;
    if (mat < 0)
        FAIL(w, RBS_E_STALE_ID, "%s: unknown material id", kind);
    if (texture < RBS_TEXTURE_NONE || texture > RBS_TEXTURE_CHECKER)
        FAIL(w, RBS_E_INVALID, "%s texture %d is not a rbs_texture", kind, (int)texture);
    if (color > 0xffffffu)
        FAIL(w, RBS_E_INVALID, "%s color 0x%lx is not 0xRRGGBB (at most 0xffffff)", kind,
             (unsigned long)color);
    s = slot_take(w);
    if (s == UINT32_MAX)
        FAIL(w, RBS_E_CAPACITY, "%s: world holds at most %u bodies", kind, (unsigned)w->def.max_bodies);
    w->type[s] = type;
    w->fixed[s] = 1;
    w->material[s] = (uint32_t)mat;
    w->color[s] = color;
    w->texture[s] = texture;
    /* A free slot holds zeros (the block starts zeroed; remove_body clears
     * what it wrote), so only what differs from zero is written: the
     * arrays a world's bodies never use -- names, forces, 3x3 inertia of
     * isotropic spheres -- stay untouched, and calloc'd pages of them are
     * never made resident. */
    if (name && name[0] != '\0') {
        strcpy(w->name[s], name);
        name_insert(w, s);
    }
    q_store(&w->orient[4 * s], (quat){1.0, 0.0, 0.0, 0.0});
    w->isotropic[s] = 1;
    *slot = s;
    return RBS_OK;
}

/* The body in slot s is complete: list it and hand out its id. */
static rbs_status body_done(rbs_world *w, uint32_t s, rbs_body_id *out)
{
    add_to_lists(w, s);
    w->plan_dirty = 1;
    w->rows_dirty = 1;
    if (out) {
        out->index = s;
        out->generation = w->generation[s];
    }
    return RBS_OK;
}

const char *rbs__sphere_limit_unit(int k)
{
    return k < 4 ? "J" : k == 4 ? "kg m/s" : "kg m^2/s";
}

const char *rbs__sphere_limit_sum(int k)
{
    return k < 4 ? "energy" : k == 4 ? "momentum" : "angular momentum";
}

int rbs__sphere_energy(double mass, double trace, rbs_vec3 v, rbs_vec3 w, rbs_vec3 p, rbs_quat q,
                       rbs_vec3 c, rbs_vec3 g, int g_is_force, rbs_vec3 f,
                       double e[RBS__SPHERE_LIMITS])
{
    quat qq = {q.w, q.x, q.y, q.z};
    v3 vv = v3_make(v.x, v.y, v.z), ww = v3_make(w.x, w.y, w.z), gg = v3_make(g.x, g.y, g.z);
    v3 x = v3_add(v3_make(p.x, p.y, p.z), q_rotate(qq, v3_make(c.x, c.y, c.z)));
    double gx = v3_dot(gg, x);
    int k;
    e[0] = 0.5 * mass * v3_dot(vv, vv);
    e[1] = 0.5 * trace * v3_dot(ww, ww);
    e[2] = fabs(g_is_force ? gx : mass * gx);
    e[3] = fabs(v3_dot(v3_make(f.x, f.y, f.z), x));
    {
        /* (lengths by hypot: each part may be near 1e300, its square not) */
        v3 mv = v3_scale(vv, mass), l = v3_cross(x, mv);
        e[4] = hypot(hypot(mv.x, mv.y), mv.z);
        e[5] = hypot(hypot(l.x, l.y), l.z);
        e[6] = trace * hypot(hypot(ww.x, ww.y), ww.z);
    }
    for (k = 0; k < RBS__SPHERE_LIMITS; ++k)
        if (!(e[k] <= RBS__ENERGY_MAX))
            return k;
    return -1;
}

/* *q (finite) made a unit quaternion: 0 when it is zero.  A quaternion
 * whose norm overflows or underflows (1e300, 1e-200) is still a rotation:
 * scaled by its largest component first -- only then, so that ordinary
 * input rounds as before.  The one rule of add_sphere and set_orientation
 * (the setter took sqrt of the sum of squares as it came: it refused
 * (1e300, 0, 0, 0) and 5e-324, and stored |q| = 0.954 for 3e-162; a probe
 * of session 40). */
static int unit_quat(quat *q)
{
    double qn = sqrt(q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z);
    if (!(qn > 1e-150) || !isfinite(qn)) {
        double big = fmax(fmax(fabs(q->w), fabs(q->x)), fmax(fabs(q->y), fabs(q->z)));
        if (!(big > 0.0))
            return 0;
        q->w /= big; q->x /= big; q->y /= big; q->z /= big;
    }
    *q = q_normalize(*q);
    return 1;
}

/* What a sphere's limits read: its values as add_sphere takes them, or as
 * the world holds them with one setter's new value put in. */
typedef struct sphere_vals {
    double mass, trace; /* kg; trace of the inertia about the COM, kg m^2 */
    rbs_vec3 p, v, av, c, f; /* position, velocity, angular velocity, COM offset, force */
    rbs_quat q;              /* unit */
    int fixed;
} sphere_vals;

/* The limits each argument of a sphere enters: bit k for
 * rbs__sphere_energy's term k, LIM_MUTUAL for the potential of mutual
 * gravity with each other sphere.  A setter checks the limits of its
 * argument only (a state that stepping carried past a limit of another
 * argument does not make every setter fail). */
#define LIM_MUTUAL (1u << RBS__SPHERE_LIMITS)
#define LIM_VELOCITY ((1u << 0) | (1u << 4) | (1u << 5))
#define LIM_ANGULAR ((1u << 1) | (1u << 6))
#define LIM_POSITION ((1u << 2) | (1u << 3) | (1u << 5) | LIM_MUTUAL) /* and orientation: both move the COM */
#define LIM_FORCE (1u << 3)
#define LIM_ALL (LIM_VELOCITY | LIM_ANGULAR | LIM_POSITION | LIM_FORCE)

/* "velocity (1e+308, 0, 0) m/s": an argument and its value, for a
 * message (count 3, or 4 for a quaternion; unit "" for none). */
static const char *given_text(char *buf, size_t n, const char *arg, const double *v, int count,
                              const char *unit)
{
    char nb[4][32];
    int k;
    for (k = 0; k < count; ++k)
        rbs__shortest(nb[k], v[k]);
    if (count == 4)
        snprintf(buf, n, "%s (%s, %s, %s, %s)", arg, nb[0], nb[1], nb[2], nb[3]);
    else
        snprintf(buf, n, "%s (%s, %s, %s)%s%s", arg, nb[0], nb[1], nb[2], unit[0] ? " " : "", unit);
    return buf;
}

/* RBS_E_NUMERIC naming the argument and its value when a component of v
 * (count 3 or 4) is not finite: "who: velocity (nan, 0, 0) m/s: every
 * component must be finite". */
static rbs_status finite_arg(rbs_world *w, const char *who, const char *arg, const double *v, int count,
                             const char *unit)
{
    char given[192];
    int k;
    for (k = 0; k < count; ++k)
        if (!isfinite(v[k]))
            FAIL(w, RBS_E_NUMERIC, "%s: %s: every component must be finite", who,
                 given_text(given, sizeof given, arg, v, count, unit));
    return RBS_OK;
}

/* The one check of a sphere's limits (scenes/FORMAT.md, "Limits of a
 * sphere"), for rbs_world_add_sphere (who NULL, self UINT32_MAX) and the
 * setters (who the setter, given the text of the argument and its value,
 * self the sphere's slot, left out of the mutual sums): a movable sphere's
 * energies and momenta at most RBS__ENERGY_MAX, and with mutual gravity
 * its potential with each other sphere (a pair of fixed ones is left out,
 * as rbs_world_energy leaves it).  RBS_E_INVALID, the world unchanged. */
static rbs_status sphere_limits(rbs_world *w, const sphere_vals *s, unsigned lims, const char *who,
                                const char *given, uint32_t self)
{
    static const char *const what[RBS__SPHERE_LIMITS] = {
        "kinetic energy m v^2 / 2 (velocity)", "rotational energy (angular_velocity)",
        "potential energy in gravity (position, mass)", "potential energy of its force (force)",
        "momentum m v (velocity, mass)",
        "angular momentum r x m v about the origin (position, velocity)",
        "spin angular momentum, at most trace(I) |w| (angular_velocity)"};
    int k;
    if (!s->fixed) {
        double e[RBS__SPHERE_LIMITS];
        (void)rbs__sphere_energy(s->mass, s->trace, s->v, s->av, s->p, s->q, s->c, w->def.gravity,
                                 w->def.gravity_mode == RBS_GRAVITY_FORCE, s->f, e);
        for (k = 0; k < RBS__SPHERE_LIMITS; ++k) {
            if (!(lims & (1u << k)) || e[k] <= RBS__ENERGY_MAX)
                continue;
            if (who == NULL)
                FAIL(w, RBS_E_INVALID, "sphere %s at the start is %g %s, beyond 1e300 %s (the world's %s "
                     "would overflow)", what[k], e[k], rbs__sphere_limit_unit(k), rbs__sphere_limit_unit(k),
                     rbs__sphere_limit_sum(k));
            FAIL(w, RBS_E_INVALID, "%s: %s: the sphere's %s would be %g %s, beyond 1e300 %s (the world's %s "
                 "would overflow; rbs_world_add_sphere refuses it too)", who, given, what[k], e[k],
                 rbs__sphere_limit_unit(k), rbs__sphere_limit_unit(k), rbs__sphere_limit_sum(k));
        }
    }
    if (w->def.mutual_gravity && (lims & LIM_MUTUAL)) {
        /* (G = 1e308 with 1 kg spheres 1 m apart passed here and failed at
         * the first frame; softening bounds it) */
        const double G = w->def.gravity_constant, eps2 = w->def.softening * w->def.softening;
        const quat q = {s->q.w, s->q.x, s->q.y, s->q.z};
        const v3 com = v3_add(v3_make(s->p.x, s->p.y, s->p.z), q_rotate(q, v3_make(s->c.x, s->c.y, s->c.z)));
        uint32_t j;
        for (j = 0; j < w->sphere_count; ++j) {
            const uint32_t b = w->spheres[j];
            v3 dx;
            double pot;
            if (b == self || (s->fixed && w->fixed[b]))
                continue;
            dx = v3_sub(rbs__body_com(w, b), com);
            pot = G * s->mass * w->mass[b] / sqrt(v3_dot(dx, dx) + eps2);
            if (pot <= RBS__ENERGY_MAX)
                continue;
            if (who == NULL)
                FAIL(w, RBS_E_INVALID, "sphere potential energy of mutual gravity with sphere %u (\"%s\") "
                     "at the start is %g J, beyond 1e300 J (the world's energy would overflow; "
                     "softening bounds it)", (unsigned)b, w->name[b], pot);
            FAIL(w, RBS_E_INVALID, "%s: %s: the sphere's potential energy of mutual gravity with sphere %u "
                 "(\"%s\") would be %g J, beyond 1e300 J (the world's energy would overflow; softening "
                 "bounds it; rbs_world_add_sphere refuses it too)", who, given, (unsigned)b, w->name[b], pot);
        }
    }
    return RBS_OK;
}

rbs_status rbs_world_add_sphere(rbs_world *w, const rbs_sphere_def *def, rbs_body_id *out)
{
    rbs_sphere_def d;
    char nb[32], nb2[32], nb3[32]; /* (numbers for a message) */
    double mass, I[9], inv[9], c2;
    v3 c, p, v, av, f, t;
    quat q;
    uint32_t s;
    rbs_status st;
    int k;

    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (def == NULL)
        FAIL(w, RBS_E_INVALID, "add_sphere: def is NULL");
    rbs_sphere_def_init(&d);
    if (!def_read(&d, sizeof d, def))
        FAIL(w, RBS_E_INVALID, "sphere def not initialised (use rbs_sphere_def_init)");
    if ((st = check_name(w, "sphere", d.name)) != RBS_OK)
        return st;
    if (!(d.radius > 0.0) || !isfinite(d.radius))
        FAIL(w, RBS_E_INVALID, "sphere radius must be finite and > 0, got %s", rbs__shortest(nb, d.radius));
    if (d.density != 0.0) {
        if (!(d.density > 0.0) || !isfinite(d.density))
            FAIL(w, RBS_E_INVALID, "sphere density must be finite and > 0, got %s", rbs__shortest(nb, d.density));
        mass = d.density * (4.0 / 3.0) * RBS__PI * d.radius * d.radius * d.radius;
        /* (named by what was given: it read "sphere mass must be finite and
         * > 0, got inf" for a density the caller gave, no mass) */
        if (!(mass > 0.0) || !isfinite(mass))
            FAIL(w, RBS_E_INVALID, "sphere mass from density %s kg/m^3 and radius %s m (density * 4/3 pi r^3) %s a double",
                 rbs__shortest(nb, d.density), rbs__shortest(nb2, d.radius),
                 isfinite(mass) ? "underflows" : "overflows");
    } else {
        mass = d.mass;
    }
    if (!(mass > 0.0) || !isfinite(mass))
        FAIL(w, RBS_E_INVALID, "sphere mass must be finite and > 0, got %s", rbs__shortest(nb, mass));
    p = v3_make(d.position.x, d.position.y, d.position.z);
    v = v3_make(d.velocity.x, d.velocity.y, d.velocity.z);
    av = v3_make(d.angular_velocity.x, d.angular_velocity.y, d.angular_velocity.z);
    c = v3_make(d.center_of_mass.x, d.center_of_mass.y, d.center_of_mass.z);
    f = v3_make(d.force.x, d.force.y, d.force.z);
    t = v3_make(d.torque.x, d.torque.y, d.torque.z);
    {
        const rbs_vec3 vals[6] = {d.position, d.velocity, d.angular_velocity, d.center_of_mass, d.force,
                                  d.torque};
        static const char *const args[6][2] = {{"position", "m"}, {"velocity", "m/s"},
                                                {"angular_velocity", "rad/s"}, {"center_of_mass", "m"},
                                                {"force", "N"}, {"torque", "N m"}};
        int k;
        for (k = 0; k < 6; ++k) {
            const double xyz[3] = {vals[k].x, vals[k].y, vals[k].z};
            if ((st = finite_arg(w, "sphere", args[k][0], xyz, 3, args[k][1])) != RBS_OK)
                return st;
        }
    }
    if (d.fixed) {
        /* a fixed sphere never moves: a velocity, force or torque would be
         * dropped silently (the setters refuse them on it) */
        const rbs_vec3 moving[4] = {d.velocity, d.angular_velocity, d.force, d.torque};
        static const char *const args[4][2] = {
            {"velocity", "m/s"}, {"angular_velocity", "rad/s"}, {"force", "N"}, {"torque", "N m"}};
        int k;
        for (k = 0; k < 4; ++k)
            if (moving[k].x != 0.0 || moving[k].y != 0.0 || moving[k].z != 0.0)
                FAIL(w, RBS_E_INVALID, "sphere %s must be zero for a fixed sphere (it never moves), got "
                     "(%s, %s, %s) %s", args[k][0], rbs__shortest(nb, moving[k].x),
                     rbs__shortest(nb2, moving[k].y), rbs__shortest(nb3, moving[k].z), args[k][1]);
    }
    q.w = d.orientation.w; q.x = d.orientation.x; q.y = d.orientation.y; q.z = d.orientation.z;
    {
        const double wxyz[4] = {q.w, q.x, q.y, q.z};
        if ((st = finite_arg(w, "sphere", "orientation", wxyz, 4, "")) != RBS_OK)
            return st;
    }
    if (!unit_quat(&q))
        FAIL(w, RBS_E_INVALID, "sphere orientation must be a nonzero quaternion");
    if (!(v3_len(c) < d.radius))
        FAIL(w, RBS_E_INVALID, "sphere centre of mass offset %g must be < radius %g", v3_len(c), d.radius);

    /* Inertia about the geometric centre, body axes. */
    memset(I, 0, sizeof I);
    switch (d.inertia_kind) {
    case RBS_INERTIA_SOLID:
        I[0] = I[4] = I[8] = 0.4 * mass * d.radius * d.radius;
        break;
    case RBS_INERTIA_HOLLOW:
        I[0] = I[4] = I[8] = (2.0 / 3.0) * mass * d.radius * d.radius;
        break;
    case RBS_INERTIA_PRINCIPAL:
        I[0] = d.inertia.x; I[4] = d.inertia.y; I[8] = d.inertia.z;
        if (!(I[0] > 0.0 && I[4] > 0.0 && I[8] > 0.0) || !isfinite(I[0]) || !isfinite(I[4]) ||
            !isfinite(I[8]))
            FAIL(w, RBS_E_INVALID, "sphere principal moments must be finite and > 0, got (%s, %s, %s) kg m^2",
                 rbs__shortest(nb, I[0]), rbs__shortest(nb2, I[4]), rbs__shortest(nb3, I[8]));
        /* (each finite, their sum not: it read "must be finite and > 0") */
        if (!isfinite(I[0] + I[4] + I[8]))
            FAIL(w, RBS_E_INVALID,
                 "sphere principal moments must have a finite sum (the world takes the "
                 "inertia's trace), got (%s, %s, %s) kg m^2",
                 rbs__shortest(nb, I[0]), rbs__shortest(nb2, I[4]), rbs__shortest(nb3, I[8]));
        if (I[0] + I[4] < I[8] || I[4] + I[8] < I[0] || I[0] + I[8] < I[4])
            FAIL(w, RBS_E_INVALID, "sphere principal moments violate the triangle inequality");
        break;
    default:
        FAIL(w, RBS_E_INVALID, "sphere inertia_kind %d is not a rbs_inertia_kind", (int)d.inertia_kind);
    }
    if (!(I[0] >= DBL_MIN && I[4] >= DBL_MIN && I[8] >= DBL_MIN) || !isfinite(I[0] + I[4] + I[8]))
        FAIL(w, RBS_E_INVALID,
             "sphere moments of inertia (%g, %g, %g kg m^2 from radius %g m, mass %g kg) underflow or "
             "overflow a double", I[0], I[4], I[8], d.radius, mass);
    /* Parallel-axis rule: move the inertia from the centre to the COM. */
    c2 = v3_dot(c, c);
    {
        double cc[3] = {c.x, c.y, c.z};
        int i, j;
        for (i = 0; i < 3; ++i)
            for (j = 0; j < 3; ++j)
                I[3 * i + j] -= mass * ((i == j ? c2 : 0.0) - cc[i] * cc[j]);
    }
    /* Positive definite (Sylvester), checked and inverted on I / trace so
     * that tiny or huge bodies neither underflow nor overflow. */
    {
        double sc = (I[0] + I[4] + I[8]) / 3.0, In[9];
        for (k = 0; k < 9; ++k)
            In[k] = I[k] / sc;
        if (!(sc > 0.0) || !isfinite(sc) || !(In[0] > 0.0) || !(In[0] * In[4] - In[1] * In[3] > 0.0) ||
            !(m3_inverse(In, inv) > 0.0))
            sc = 0.0;
        for (k = 0; k < 9; ++k)
            inv[k] /= sc;
        if (sc == 0.0)
            inv[0] = NAN;
    }
    if (!isfinite(inv[0]) || !isfinite(inv[4]) || !isfinite(inv[8]))
        FAIL(w, RBS_E_INVALID,
             "sphere: centre of mass offset %g is too far from the centre for this inertia "
             "(inertia about the COM would not be positive definite)", sqrt(c2));
    if (!d.fixed && !isfinite(1.0 / mass))
        FAIL(w, RBS_E_INVALID, "sphere mass %s kg is too small for double precision (1 / mass "
             "overflows); a fixed sphere may have it", rbs__shortest(nb, mass));
    {
        /* a movable sphere's energies (so that the world's sums stay
         * finite: FORMAT.md, "Limits of a sphere", the scene's rule too),
         * and its potential of mutual gravity: the rule the setters apply */
        sphere_vals sv;
        sv.mass = mass;
        sv.trace = I[0] + I[4] + I[8];
        sv.p = d.position; sv.v = d.velocity; sv.av = d.angular_velocity;
        sv.c = d.center_of_mass; sv.f = d.force;
        sv.q.w = q.w; sv.q.x = q.x; sv.q.y = q.y; sv.q.z = q.z;
        sv.fixed = d.fixed != 0;
        if ((st = sphere_limits(w, &sv, LIM_ALL, NULL, NULL, UINT32_MAX)) != RBS_OK)
            return st;
    }
    st = take_slot(w, "sphere", RBS_BODY_SPHERE, d.material, d.texture, d.color, d.name, &s);
    if (st != RBS_OK)
        return st;
    w->fixed[s] = d.fixed != 0;
    store_nonzero3(&w->pos[3 * s], p);
    if (!d.fixed) {
        store_nonzero3(&w->vel[3 * s], v);
        store_nonzero3(&w->avel[3 * s], av);
    }
    q_store(&w->orient[4 * s], q);
    store_nonzero3(&w->force[3 * s], f);
    store_nonzero3(&w->torque[3 * s], t);
    store_nonzero3(&w->com_body[3 * s], c);
    w->radius[s] = d.radius;
    w->mass[s] = mass;
    w->inv_mass[s] = d.fixed ? 0.0 : 1.0 / mass;
    w->isotropic[s] = I[1] == 0.0 && I[2] == 0.0 && I[3] == 0.0 && I[5] == 0.0 && I[6] == 0.0 &&
                      I[7] == 0.0 && I[0] == I[4] && I[4] == I[8];
    if (w->isotropic[s]) {
        w->iso_inertia[s] = I[0];
        w->iso_inv_inertia[s] = d.fixed ? 0.0 : inv[0];
    } else {
        for (k = 0; k < 9; ++k) {
            w->inertia[9 * s + k] = I[k];
            w->inv_inertia[9 * s + k] = d.fixed ? 0.0 : inv[k];
        }
    }
    return body_done(w, s, out);
}

rbs_status rbs_world_add_plane(rbs_world *w, const rbs_plane_def *def, rbs_body_id *out)
{
    rbs_plane_def d;
    v3 p, n;
    double len;
    uint32_t s;
    rbs_status st;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (def == NULL)
        FAIL(w, RBS_E_INVALID, "add_plane: def is NULL");
    rbs_plane_def_init(&d);
    if (!def_read(&d, sizeof d, def))
        FAIL(w, RBS_E_INVALID, "plane def not initialised (use rbs_plane_def_init)");
    if ((st = check_name(w, "plane", d.name)) != RBS_OK)
        return st;
    p = v3_make(d.point.x, d.point.y, d.point.z);
    n = v3_make(d.normal.x, d.normal.y, d.normal.z);
    {
        const double pt[3] = {p.x, p.y, p.z}, nn[3] = {n.x, n.y, n.z};
        if ((st = finite_arg(w, "plane", "point", pt, 3, "m")) != RBS_OK ||
            (st = finite_arg(w, "plane", "normal", nn, 3, "")) != RBS_OK)
            return st;
    }
    {
        /* scaled by its largest component first: a finite normal whose
         * length would overflow or underflow (1e300, 1e-200) is still a
         * direction */
        double big = fmax(fabs(n.x), fmax(fabs(n.y), fabs(n.z)));
        if (!(big > 0.0))
            FAIL(w, RBS_E_INVALID, "plane normal must be nonzero");
        len = v3_len(n);
        if (!(len > 1e-150) || !isfinite(len)) { /* (only then: ordinary input rounds as before) */
            /* divided, not scaled by 1 / big: below 2^-1024 (5.6e-309)
             * that overflows, and 0 x inf stored a NaN normal (a probe of
             * session 40: normal (0, 0, 1e-310) was taken, and the ball fell
             * through the floor) */
            n = v3_make(n.x / big, n.y / big, n.z / big);
            len = v3_len(n);
        }
    }
    n = v3_scale(n, 1.0 / len);
    st = take_slot(w, "plane", RBS_BODY_PLANE, d.material, d.texture, d.color, d.name, &s);
    if (st != RBS_OK)
        return st;
    store_nonzero3(&w->pos[3 * s], p);
    v3_store(&w->normal[3 * s], n);
    return body_done(w, s, out);
}

rbs_status rbs_world_remove_body(rbs_world *w, rbs_body_id id)
{
    uint32_t s = id.index;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    if (!id_valid(w, id))
        FAIL(w, RBS_E_STALE_ID, "remove_body: null or stale body id {%u, %u}", (unsigned)id.index,
             (unsigned)id.generation);
    w->type[s] = RBS_BODY_NONE;
    /* back to zeros, as take_slot expects of a free slot */
    if (w->name[s][0] != '\0') {
        name_remove(w, s);
        memset(w->name[s], 0, RBS_NAME_MAX);
    }
    memset(&w->pos[3 * s], 0, 3 * sizeof(double));
    memset(&w->vel[3 * s], 0, 3 * sizeof(double));
    memset(&w->avel[3 * s], 0, 3 * sizeof(double));
    memset(&w->orient[4 * s], 0, 4 * sizeof(double));
    clear_nonzero(&w->force[3 * s], 3);
    clear_nonzero(&w->torque[3 * s], 3);
    clear_nonzero(&w->normal[3 * s], 3);
    clear_nonzero(&w->com_body[3 * s], 3);
    clear_nonzero(&w->inertia[9 * s], 9);
    clear_nonzero(&w->inv_inertia[9 * s], 9);
    w->radius[s] = w->mass[s] = w->inv_mass[s] = 0.0;
    w->iso_inertia[s] = w->iso_inv_inertia[s] = 0.0;
    w->free_list[w->free_count++] = s;
    w->bodies--;
    rbs__rebuild_lists(w);
    w->plan_dirty = 1;
    w->rows_dirty = 1;
    return RBS_OK;
}

rbs_status rbs_world_find_body(const rbs_world *w, const char *name, rbs_body_id *out)
{
    uint32_t i;
    if (w == NULL || w->magic != WORLD_MAGIC || name == NULL)
        return RBS_E_INVALID;
    /* the rule of both finds: a string that names nothing -- "" (which an
     * unnamed body has, and no body is found by) as any other no body or
     * material may have -- is not found; it said RBS_E_INVALID for "" alone
     * (and rbs_world_find_material RBS_E_NOT_FOUND) */
    if (name[0] == '\0' || (i = name_find(w, name)) == UINT32_MAX)
        return RBS_E_NOT_FOUND;
    if (out) {
        out->index = i;
        out->generation = w->generation[i];
    }
    return RBS_OK;
}

rbs_status rbs_world_body_at(const rbs_world *w, uint32_t slot, rbs_body_id *out)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    if (slot >= w->slots || w->type[slot] == RBS_BODY_NONE)
        return RBS_E_NOT_FOUND;
    if (out) {
        out->index = slot;
        out->generation = w->generation[slot];
    }
    return RBS_OK;
}

v3 rbs__body_com(const rbs_world *w, uint32_t i)
{
    v3 p = v3_load(&w->pos[3 * i]);
    if (w->type[i] == RBS_BODY_SPHERE) {
        v3 c = v3_load(&w->com_body[3 * i]);
        if (c.x != 0.0 || c.y != 0.0 || c.z != 0.0)
            p = v3_add(p, q_rotate(q_load(&w->orient[4 * i]), c));
    }
    return p;
}

rbs_status rbs_body_get_state(const rbs_world *w, rbs_body_id id, rbs_body_state *out)
{
    uint32_t s = id.index;
    if (w == NULL || out == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    if (!id_valid(w, id))
        return RBS_E_STALE_ID;
    memset(out, 0, sizeof *out);
    out->type = (rbs_body_type)w->type[s];
    out->slot = s;
    out->name = w->name[s];
    out->position.x = w->pos[3 * s]; out->position.y = w->pos[3 * s + 1]; out->position.z = w->pos[3 * s + 2];
    out->orientation.w = w->orient[4 * s]; out->orientation.x = w->orient[4 * s + 1];
    out->orientation.y = w->orient[4 * s + 2]; out->orientation.z = w->orient[4 * s + 3];
    out->velocity.x = w->vel[3 * s]; out->velocity.y = w->vel[3 * s + 1]; out->velocity.z = w->vel[3 * s + 2];
    out->angular_velocity.x = w->avel[3 * s]; out->angular_velocity.y = w->avel[3 * s + 1];
    out->angular_velocity.z = w->avel[3 * s + 2];
    out->normal.x = w->normal[3 * s]; out->normal.y = w->normal[3 * s + 1]; out->normal.z = w->normal[3 * s + 2];
    out->radius = w->radius[s];
    out->mass = w->mass[s];
    out->force.x = w->force[3 * s]; out->force.y = w->force[3 * s + 1]; out->force.z = w->force[3 * s + 2];
    out->torque.x = w->torque[3 * s]; out->torque.y = w->torque[3 * s + 1]; out->torque.z = w->torque[3 * s + 2];
    out->material.index = w->material[s] ? w->material[s] - 1 : 0;
    out->material.generation = w->material[s] ? 1 : 0;
    out->color = w->color[s];
    out->texture = (rbs_texture)w->texture[s];
    out->fixed = w->fixed[s];
    return RBS_OK;
}

rbs_status rbs_body_get_inertia(const rbs_world *w, rbs_body_id id, rbs_vec3 *center_of_mass,
                                double inertia[9])
{
    uint32_t s = id.index, k;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    if (!id_valid(w, id))
        return RBS_E_STALE_ID;
    if (center_of_mass) {
        center_of_mass->x = w->com_body[3 * s];
        center_of_mass->y = w->com_body[3 * s + 1];
        center_of_mass->z = w->com_body[3 * s + 2];
    }
    if (inertia) {
        for (k = 0; k < 9; ++k)
            inertia[k] = w->isotropic[s] ? (k % 4 == 0 ? w->iso_inertia[s] : 0.0) : w->inertia[9 * s + k];
    }
    return RBS_OK;
}

/* Common checks of the setters: valid id, finite value. */
static rbs_status setter_check(rbs_world *w, rbs_body_id id, const double *v, int n, const char *what,
                               const char *arg, const char *unit)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (!id_valid(w, id))
        FAIL(w, RBS_E_STALE_ID, "%s: null or stale body id {%u, %u}", what, (unsigned)id.index,
             (unsigned)id.generation);
    return finite_arg(w, what, arg, v, n, unit);
}

/* A sphere's values as the world holds them now (for the setters' check
 * of the limits, one value then replaced). */
static void sphere_vals_of(const rbs_world *w, uint32_t s, sphere_vals *out)
{
    out->mass = w->mass[s];
    out->trace = w->isotropic[s] ? 3.0 * w->iso_inertia[s]
                                 : w->inertia[9 * s] + w->inertia[9 * s + 4] + w->inertia[9 * s + 8];
    out->p.x = w->pos[3 * s]; out->p.y = w->pos[3 * s + 1]; out->p.z = w->pos[3 * s + 2];
    out->v.x = w->vel[3 * s]; out->v.y = w->vel[3 * s + 1]; out->v.z = w->vel[3 * s + 2];
    out->av.x = w->avel[3 * s]; out->av.y = w->avel[3 * s + 1]; out->av.z = w->avel[3 * s + 2];
    out->c.x = w->com_body[3 * s]; out->c.y = w->com_body[3 * s + 1]; out->c.z = w->com_body[3 * s + 2];
    out->f.x = w->force[3 * s]; out->f.y = w->force[3 * s + 1]; out->f.z = w->force[3 * s + 2];
    out->q.w = w->orient[4 * s]; out->q.x = w->orient[4 * s + 1];
    out->q.y = w->orient[4 * s + 2]; out->q.z = w->orient[4 * s + 3];
    out->fixed = w->fixed[s] != 0;
}

rbs_status rbs_body_set_position(rbs_world *w, rbs_body_id id, rbs_vec3 p)
{
    double v[3] = {p.x, p.y, p.z};
    rbs_status st = setter_check(w, id, v, 3, "set_position", "position", "m");
    if (st != RBS_OK)
        return st;
    if (w->type[id.index] == RBS_BODY_SPHERE) {
        sphere_vals sv;
        char given[160];
        sphere_vals_of(w, id.index, &sv);
        sv.p = p;
        st = sphere_limits(w, &sv, LIM_POSITION, "set_position", given_text(given, sizeof given, "position", v, 3, "m"),
                           id.index);
        if (st != RBS_OK)
            return st;
    }
    v3_store(&w->pos[3 * id.index], v3_load(v));
    return RBS_OK;
}

rbs_status rbs_body_set_orientation(rbs_world *w, rbs_body_id id, rbs_quat q)
{
    double v[4] = {q.w, q.x, q.y, q.z};
    quat qq = {q.w, q.x, q.y, q.z};
    rbs_status st = setter_check(w, id, v, 4, "set_orientation", "orientation", "");
    if (st != RBS_OK)
        return st;
    if (!unit_quat(&qq))
        FAIL(w, RBS_E_INVALID, "set_orientation: quaternion must be nonzero");
    if (w->type[id.index] != RBS_BODY_SPHERE)
        FAIL(w, RBS_E_INVALID, "set_orientation: planes have no orientation");
    {
        /* (it moves the centre of mass of an off-centre sphere) */
        sphere_vals sv;
        char given[192];
        sphere_vals_of(w, id.index, &sv);
        sv.q.w = qq.w; sv.q.x = qq.x; sv.q.y = qq.y; sv.q.z = qq.z;
        st = sphere_limits(w, &sv, LIM_POSITION, "set_orientation",
                           given_text(given, sizeof given, "orientation", v, 4, ""), id.index);
        if (st != RBS_OK)
            return st;
    }
    q_store(&w->orient[4 * id.index], qq);
    return RBS_OK;
}

/* The setters of velocity, angular velocity, force and torque: arg names
 * the argument, unit its unit, lims the limits it enters. */
static rbs_status set_motion(rbs_world *w, rbs_body_id id, rbs_vec3 a, double *arr, const char *what,
                             const char *arg, const char *unit, unsigned lims)
{
    double v[3] = {a.x, a.y, a.z};
    rbs_status st = setter_check(w, id, v, 3, what, arg, unit);
    if (st != RBS_OK)
        return st;
    if (!rbs__body_moves(w, id.index) && (a.x != 0.0 || a.y != 0.0 || a.z != 0.0))
        FAIL(w, RBS_E_INVALID, "%s: body does not move (plane or fixed sphere)", what);
    if (lims != 0 && w->type[id.index] == RBS_BODY_SPHERE) {
        sphere_vals sv;
        char given[160];
        sphere_vals_of(w, id.index, &sv);
        if (arr == w->vel)
            sv.v = a;
        else if (arr == w->avel)
            sv.av = a;
        else
            sv.f = a;
        st = sphere_limits(w, &sv, lims, what, given_text(given, sizeof given, arg, v, 3, unit), id.index);
        if (st != RBS_OK)
            return st;
    }
    v3_store(&arr[3 * id.index], v3_load(v));
    w->plan_dirty = 1;
    return RBS_OK;
}

rbs_status rbs_body_set_velocity(rbs_world *w, rbs_body_id id, rbs_vec3 v)
{
    if (w == NULL) return RBS_E_INVALID;
    return set_motion(w, id, v, w->vel, "set_velocity", "velocity", "m/s", LIM_VELOCITY);
}
rbs_status rbs_body_set_angular_velocity(rbs_world *w, rbs_body_id id, rbs_vec3 v)
{
    if (w == NULL) return RBS_E_INVALID;
    return set_motion(w, id, v, w->avel, "set_angular_velocity", "angular_velocity", "rad/s", LIM_ANGULAR);
}
rbs_status rbs_body_set_force(rbs_world *w, rbs_body_id id, rbs_vec3 v)
{
    if (w == NULL) return RBS_E_INVALID;
    return set_motion(w, id, v, w->force, "set_force", "force", "N", LIM_FORCE);
}
rbs_status rbs_body_set_torque(rbs_world *w, rbs_body_id id, rbs_vec3 v)
{
    /* (a sphere's torque enters no limit: finite is its whole rule) */
    if (w == NULL) return RBS_E_INVALID;
    return set_motion(w, id, v, w->torque, "set_torque", "torque", "N m", 0);
}

/* ------------------------------------------------------------------------- */
/* Settings, state, diagnostics                                              */
/* ------------------------------------------------------------------------- */

double rbs_world_time(const rbs_world *w)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return 0.0;
    return w->time_base + (double)(w->step_count - w->step_base) * w->def.dt;
}

uint64_t rbs_world_step_count(const rbs_world *w)
{
    return (w == NULL || w->magic != WORLD_MAGIC) ? 0 : w->step_count;
}

uint64_t rbs_world_rounded_steps(const rbs_world *w)
{
    return (w == NULL || w->magic != WORLD_MAGIC) ? 0 : w->rounded_steps;
}

rbs_status rbs_world_set_dt(rbs_world *w, double dt)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (!dt_ok(dt, w->error, sizeof w->error))
        return RBS_E_INVALID;
    if (dt != w->def.dt) {
        /* the time so far stays: the new step counts from here */
        w->time_base = rbs_world_time(w);
        w->step_base = w->step_count;
        w->def.dt = dt;
        w->plan_dirty = 1; /* (auto's choice reads dt: the sink it allows) */
    }
    return RBS_OK;
}

rbs_status rbs_world_set_method(rbs_world *w, rbs_method method, double tolerance)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    w->error[0] = '\0';
    if (!method_ok(method, w->error, sizeof w->error))
        return RBS_E_INVALID;
    /* (tolerance <= 0 keeps the current one) */
    if ((isnan(tolerance) || tolerance > 0.0) && !tolerance_ok(tolerance, w->error, sizeof w->error))
        return RBS_E_INVALID;
    if (method == RBS_METHOD_ADAPTIVE && rbs__adaptive_reserve(w) != RBS_OK)
        FAIL(w, RBS_E_MEMORY, "method \"adaptive\": out of memory for GSL's workspaces");
    w->def.method = method;
    w->plan_dirty = 1; /* (the plan holds the method a step takes) */
    if (tolerance > 0.0)
        w->def.tolerance = tolerance;
    return RBS_OK;
}

void rbs_workers_init_sized(rbs_workers *workers, size_t size)
{
    rbs_workers d;
    if (workers == NULL || size < sizeof(uint32_t))
        return;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof d;
    d.count = 1;
    def_give(workers, size, &d, sizeof d);
}

rbs_status rbs_world_set_workers(rbs_world *w, const rbs_workers *workers)
{
    rbs_workers d;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    rbs_workers_init(&d);
    if (workers != NULL && !def_read(&d, sizeof d, workers))
        FAIL(w, RBS_E_INVALID, "rbs_workers: struct_size %u is not one of this library's (use rbs_workers_init)",
             (unsigned)workers->struct_size);
    if (d.count < 1 || d.count > RBS_WORKERS_MAX)
        FAIL(w, RBS_E_INVALID, "workers.count must be 1 to %d, got %u", RBS_WORKERS_MAX, (unsigned)d.count);
    if (d.count > 1 && (d.start == NULL || d.finish == NULL))
        FAIL(w, RBS_E_INVALID, "workers.count is %u but workers.%s is NULL", (unsigned)d.count,
             d.start == NULL ? "start" : "finish");
#if !defined(__GNUC__)
    if (d.count > 1)
        FAIL(w, RBS_E_UNSUPPORTED, "this build of the library has no atomics: it steps on one thread");
#endif
    w->workers = d;
    rbs__team_fit(w);
    return RBS_OK;
}

uint32_t rbs_world_workers(const rbs_world *w)
{
    if (w == NULL || w->magic != WORLD_MAGIC)
        return 0;
    return w->workers.count;
}

rbs_method rbs_world_method_in_use(const rbs_world *w)
{
    rbs__plan p;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_METHOD_COUNT;
    if (!w->plan_dirty)
        return w->plan.method;
    rbs__plan_compute(w, &p);
    return p.method;
}

rbs_status rbs_world_state(const rbs_world *w, rbs_state_view *out)
{
    if (w == NULL || out == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    out->slots = w->slots;
    out->capacity = w->def.max_bodies;
    out->position = w->pos;
    out->velocity = w->vel;
    out->angular_velocity = w->avel;
    out->orientation = w->orient;
    out->type = w->type;
    return RBS_OK;
}

/* Kinetic and potential energy. */
rbs_status rbs_world_energy(const rbs_world *w, rbs_energy *out)
{
    double ke = 0.0, pe = 0.0;
    v3 g;
    uint32_t i, j;
    if (w == NULL || out == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    g = v3_make(w->def.gravity.x, w->def.gravity.y, w->def.gravity.z);
    for (i = 0; i < w->slots; ++i) {
        v3 v, om, x, Iw;
        quat q;
        if (!rbs__body_moves(w, i))
            continue;
        v = v3_load(&w->vel[3 * i]);
        om = v3_load(&w->avel[3 * i]);
        q = q_load(&w->orient[4 * i]);
        Iw = rbs__inertia_times(w, i, q, om);
        ke += 0.5 * w->mass[i] * v3_dot(v, v) + 0.5 * v3_dot(om, Iw);
        x = rbs__body_com(w, i);
        if (w->def.gravity_mode == RBS_GRAVITY_ACCELERATION)
            pe -= w->mass[i] * v3_dot(g, x);
        else
            pe -= v3_dot(g, x);
        pe -= v3_dot(v3_load(&w->force[3 * i]), x);
    }
    if (w->def.mutual_gravity) {
        double G = w->def.gravity_constant, eps2 = w->def.softening * w->def.softening;
        for (i = 0; i < w->sphere_count; ++i) {
            uint32_t a = w->spheres[i];
            v3 xa = rbs__body_com(w, a);
            for (j = i + 1; j < w->sphere_count; ++j) {
                uint32_t b = w->spheres[j];
                v3 d;
                if (w->fixed[a] && w->fixed[b])
                    continue; /* a constant (the pair never moves): left out, so
                                 two fixed spheres at one point are no infinity */
                d = v3_sub(rbs__body_com(w, b), xa);
                pe -= G * w->mass[a] * w->mass[b] / sqrt(v3_dot(d, d) + eps2);
            }
        }
    }
    out->kinetic = ke;
    out->potential = pe;
    out->total = ke + pe;
    /* huge but finite states can overflow the sums: say so, never NaN */
    if (!isfinite(out->total))
        return RBS_E_NUMERIC;
    return RBS_OK;
}

rbs_status rbs_world_momentum(const rbs_world *w, rbs_vec3 *linear, rbs_vec3 *angular)
{
    v3 P = v3_make(0, 0, 0), L = v3_make(0, 0, 0);
    uint32_t i;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    for (i = 0; i < w->slots; ++i) {
        v3 p, x, om;
        if (!rbs__body_moves(w, i))
            continue;
        p = v3_scale(v3_load(&w->vel[3 * i]), w->mass[i]);
        x = rbs__body_com(w, i);
        om = v3_load(&w->avel[3 * i]);
        P = v3_add(P, p);
        L = v3_add(L, v3_add(v3_cross(x, p), rbs__inertia_times(w, i, q_load(&w->orient[4 * i]), om)));
    }
    if (linear) { linear->x = P.x; linear->y = P.y; linear->z = P.z; }
    if (angular) { angular->x = L.x; angular->y = L.y; angular->z = L.z; }
    if (!v3_finite(P) || !v3_finite(L))
        return RBS_E_NUMERIC; /* huge but finite states overflowed the sums */
    return RBS_OK;
}

void rbs__momentum_failure(const rbs_world *w, char *buf, size_t n)
{
    v3 P = v3_make(0, 0, 0), L = v3_make(0, 0, 0);
    uint32_t i;
    buf[0] = '\0';
    for (i = 0; i < w->slots; ++i) {
        v3 p, x, l, spin;
        if (!rbs__body_moves(w, i))
            continue;
        p = v3_scale(v3_load(&w->vel[3 * i]), w->mass[i]);
        x = rbs__body_com(w, i);
        l = v3_cross(x, p);
        spin = rbs__inertia_times(w, i, q_load(&w->orient[4 * i]), v3_load(&w->avel[3 * i]));
        if (!v3_finite(p) || !v3_finite(l) || !v3_finite(spin) || !v3_finite(v3_add(l, spin))) {
            const char *what = !v3_finite(p)      ? "its momentum m v"
                               : !v3_finite(l)    ? "its angular momentum r x m v about the origin"
                               : !v3_finite(spin) ? "its spin angular momentum I w"
                                                  : "its angular momentum r x m v + I w";
            snprintf(buf, n, "sphere %u (\"%s\"): %s overflows (|r| = %g m, |m v| = %g kg m/s, "
                     "|w| = %g rad/s)", (unsigned)i, w->name[i], what,
                     hypot(hypot(x.x, x.y), x.z), hypot(hypot(p.x, p.y), p.z),
                     hypot(hypot(w->avel[3 * i], w->avel[3 * i + 1]), w->avel[3 * i + 2]));
            return;
        }
        P = v3_add(P, p);
        L = v3_add(L, v3_add(l, spin));
        if (!v3_finite(P) || !v3_finite(L)) {
            snprintf(buf, n, "the world's %s overflows when sphere %u (\"%s\") is added to it",
                     !v3_finite(P) ? "momentum" : "angular momentum", (unsigned)i, w->name[i]);
            return;
        }
    }
}

rbs_status rbs_world_usage(const rbs_world *w, rbs_usage *out)
{
    if (w == NULL || out == NULL || w->magic != WORLD_MAGIC)
        return RBS_E_INVALID;
    memset(out, 0, sizeof *out);
    out->bytes = w->bytes;
    out->bodies = w->bodies;
    out->bodies_high = w->slots;
    out->materials = w->materials;
    out->pairs = w->pairs;
    out->contacts_high = w->contacts_high;
    return RBS_OK;
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    size_t i;
    for (i = 0; i < n; ++i) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}

uint64_t rbs_world_hash(const rbs_world *w)
{
    uint64_t h = 14695981039346656037ull;
    uint32_t n;
    if (w == NULL || w->magic != WORLD_MAGIC)
        return 0;
    /* up to the last body: free slots after it (zeros, left by
     * remove_body) are no part of the state -- a body added and removed
     * changed the hash of a world whose bodies were the same as a fresh
     * one's, bit for bit (a probe of session 47) */
    n = w->slots;
    while (n > 0 && w->type[n - 1] == RBS_BODY_NONE)
        n--;
    h = fnv(h, &w->step_count, sizeof w->step_count);
    h = fnv(h, w->pos, 3 * (size_t)n * sizeof(double));
    h = fnv(h, w->vel, 3 * (size_t)n * sizeof(double));
    h = fnv(h, w->avel, 3 * (size_t)n * sizeof(double));
    h = fnv(h, w->orient, 4 * (size_t)n * sizeof(double));
    return h;
}
