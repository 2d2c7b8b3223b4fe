/*
 * scene_validate.c - check a scene tree (format version 1, see
 * scenes/FORMAT.md) and fill the scene's description.
 *
 * Every problem is reported with the file, line and column of the offending
 * value (or key), its key path and what was expected; checking goes on after
 * an error so that all errors of a file are reported at once.  Cross-checks
 * (material names, material pairs of bodies that could touch, overlap at the
 * start, camera mounts) run after the local checks.
 */
#include "scene/scene_internal.h"
#include "core/name.h"
#include "core/world_internal.h" /* RBS__SOFT_SUBSTEPS_MAX */
#include "rbsim/reel.h" /* RBS_EVERY_MAX */

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vctx {
    rbs_scene *scene;
    const rbs__posmap *map;
    const rbs__src *srcs;
    int32_t src_count;
    char path[512];
    size_t path_len;
} vctx;

/* ---- places and paths --------------------------------------------------- */

static rbs__loc loc_at(const vctx *v, const cJSON *item, int key)
{
    rbs__loc none = {0, 0, 0};
    const rbs__pos *pos = rbs__posmap_get(v->map, item);
    if (pos == NULL || pos->file < 0 || pos->file >= v->src_count) {
        return none;
    }
    return rbs__src_loc(&v->srcs[pos->file], pos->file,
                        key && pos->has_key ? pos->key_off : pos->value_off);
}

static rbs__loc loc_value(const vctx *v, const cJSON *item) { return loc_at(v, item, 0); }
static rbs__loc loc_key(const vctx *v, const cJSON *item) { return loc_at(v, item, 1); }

static size_t push_key(vctx *v, const char *key)
{
    size_t saved = v->path_len;
    /* a key the path could not tell apart -- empty, or holding '.', '[',
     * ']', '"' or a blank -- is written in quotes: simulation."" and
     * simulation."a.b", not simulation. and simulation.a.b */
    const int quote = key[0] == '\0' || strpbrk(key, ".[]\" \t\r\n") != NULL;
    int k = snprintf(v->path + v->path_len, sizeof v->path - v->path_len, quote ? "%s\"%s\"" : "%s%s",
                     v->path_len ? "." : "", key);
    if (k > 0) {
        v->path_len += (size_t)k;
        if (v->path_len >= sizeof v->path) {
            v->path_len = sizeof v->path - 1;
        }
    }
    return saved;
}

static size_t push_index(vctx *v, size_t i)
{
    size_t saved = v->path_len;
    int k = snprintf(v->path + v->path_len, sizeof v->path - v->path_len, "[%lu]",
                     (unsigned long)i);
    if (k > 0) {
        v->path_len += (size_t)k;
        if (v->path_len >= sizeof v->path) {
            v->path_len = sizeof v->path - 1;
        }
    }
    return saved;
}

static void pop(vctx *v, size_t saved)
{
    v->path_len = saved;
    v->path[saved] = '\0';
}

#ifdef __GNUC__
__attribute__((format(printf, 3, 4)))
#endif
static void err(vctx *v, rbs__loc at, const char *fmt, ...);

static void err(vctx *v, rbs__loc at, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    rbs__vsnprintf_c(msg, sizeof msg, fmt, ap);
    va_end(ap);
    rbs__scene_error(v->scene, at, v->path, "%s", msg);
}

/* The value as written, for "got ..." (raw number text, quoted string). */
static void got(const vctx *v, const cJSON *item, char *out, size_t n)
{
    const rbs__pos *pos = rbs__posmap_get(v->map, item);
    if (cJSON_IsNumber(item) && pos != NULL && pos->file >= 0 &&
        pos->file < v->src_count && pos->raw_len > 0 &&
        (size_t)pos->raw_off + pos->raw_len <= v->srcs[pos->file].len) {
        size_t len = pos->raw_len;
        if (len > 40) {
            len = 40;
        }
        snprintf(out, n, "%.*s%s", (int)len, v->srcs[pos->file].text + pos->raw_off,
                 len < pos->raw_len ? "..." : "");
    } else if (cJSON_IsNumber(item)) {
        snprintf(out, n, "%.17g", item->valuedouble);
    } else if (cJSON_IsString(item)) {
        /* (as JSON writes it: a quote or backslash escaped, so that the
         * value's end is plain -- "\"q", not ""q"; a control or invisible
         * character shows as '?' in the message, by rbs__scene_error's
         * rule, rbs_text_shown_len) */
        char clean[48];
        size_t i, k = 0;
        const char *s = item->valuestring;
        for (i = 0; s[i] != '\0' && k < 40; i++) {
            const char c = s[i];
            if (c == '"' || c == '\\')
                clean[k++] = '\\';
            clean[k++] = c;
        }
        clean[k] = '\0';
        snprintf(out, n, "\"%s\"%s", clean, s[i] != '\0' ? "..." : "");
    } else if (cJSON_IsTrue(item)) {
        snprintf(out, n, "true");
    } else if (cJSON_IsFalse(item)) {
        snprintf(out, n, "false");
    } else if (cJSON_IsNull(item)) {
        snprintf(out, n, "null");
    } else if (cJSON_IsArray(item)) {
        int count = cJSON_GetArraySize(item);
        snprintf(out, n, "an array of %d element%s", count, count == 1 ? "" : "s");
    } else if (cJSON_IsObject(item)) {
        snprintf(out, n, "an object");
    } else {
        snprintf(out, n, "an invalid value");
    }
}

/* An array as written, "[a, b, c]", each element by got(): a number's text
 * as written, so that 2.0000000001 is not shown as the 2 of %g. */
static void got_list(const vctx *v, const cJSON *arr, char *out, size_t n)
{
    const cJSON *e;
    size_t at;
    snprintf(out, n, "[");
    at = strlen(out);
    cJSON_ArrayForEach(e, arr)
    {
        char g[64];
        got(v, e, g, sizeof g);
        snprintf(out + at, n - at, "%s%s", e == arr->child ? "" : ", ", g);
        at = strlen(out);
    }
    snprintf(out + at, n - at, "]");
}

/* ---- typed values ------------------------------------------------------- */

/* Whether two values of a text scene's list are one number written with a
 * decimal comma: the digits, one comma and the digits again, no blank. */
static int glued(const vctx *v, const cJSON *first, const cJSON *second)
{
    const rbs__pos *a = rbs__posmap_get(v->map, first);
    const rbs__pos *b = rbs__posmap_get(v->map, second);
    const char *t;
    size_t i, gap;
    if (!cJSON_IsNumber(first) || a == NULL || b == NULL || a->file != b->file ||
        a->file < 0 || a->file >= v->src_count || a->raw_len == 0 || b->raw_len == 0 ||
        (size_t)b->raw_off + b->raw_len > v->srcs[a->file].len)
        return 0;
    t = v->srcs[a->file].text;
    gap = (size_t)a->raw_off + a->raw_len;
    /* "0,001": the two written side by side with one comma, not in "[...]"
     * (the part after the comma may be no number of its own: "001") */
    if (gap + 1 != b->raw_off || t[gap] != ',' ||
        (a->raw_off > 0 && t[a->raw_off - 1] == '['))
        return 0;
    for (i = a->raw_off; i < gap; i++)
        if (!(t[i] >= '0' && t[i] <= '9') && !(i == a->raw_off && t[i] == '-'))
            return 0;
    for (i = b->raw_off; i < (size_t)b->raw_off + b->raw_len; i++)
        if (!(t[i] >= '0' && t[i] <= '9'))
            return 0;
    return 1;
}

/* Whether the array item holds a text scene's number written with a
 * decimal comma ("dt = 0,001", "radius 0,1", "position 0,5 0 1"), which the
 * text format reads as two values.  (German settings write numbers so;
 * "must be a number, got an array of 2 elements" alone did not say why: a
 * probe of session 47.) */
static int decimal_comma(const vctx *v, const cJSON *item)
{
    const cJSON *e;
    if (!cJSON_IsArray(item))
        return 0;
    for (e = item->child; e != NULL && e->next != NULL; e = e->next)
        if (glued(v, e, e->next))
            return 1;
    return 0;
}

/* The hint a wrong value adds when decimal_comma finds one, else "". */
static const char *comma_hint(const vctx *v, const cJSON *item)
{
    return decimal_comma(v, item) ? " (a decimal comma? write the number with a point, e.g. "
                                    "0.5: a comma separates values)"
                                  : "";
}

/* A finite number; reports wrong types, overflow (cJSON turns 1e999 into inf)
 * and literals that underflow to zero. */
static int get_number(vctx *v, const cJSON *item, double *out)
{
    char g[64];
    const rbs__pos *pos;
    if (!cJSON_IsNumber(item)) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be a number, got %s%s", g,
            comma_hint(v, item));
        return -1;
    }
    got(v, item, g, sizeof g);
    if (!isfinite(item->valuedouble)) {
        err(v, loc_value(v, item),
            "number out of range (overflows a double), got %s", g);
        return -1;
    }
    pos = rbs__posmap_get(v->map, item);
    if (item->valuedouble == 0.0 && pos != NULL && pos->file >= 0 &&
        pos->file < v->src_count) {
        /* a literal with a nonzero digit before the exponent is not zero */
        size_t i;
        const char *t = v->srcs[pos->file].text + pos->raw_off;
        for (i = 0; i < pos->raw_len && t[i] != 'e' && t[i] != 'E'; i++) {
            if (t[i] >= '1' && t[i] <= '9') {
                err(v, loc_value(v, item),
                    "number out of range (underflows to 0), got %s", g);
                return -1;
            }
        }
    }
    *out = item->valuedouble;
    return 0;
}

enum { R_ANY, R_POS, R_NONNEG, R_UNIT };

static int get_ranged(vctx *v, const cJSON *item, int range, double *out)
{
    double x;
    char g[64];
    if (get_number(v, item, &x) != 0) {
        return -1;
    }
    got(v, item, g, sizeof g);
    if (range == R_POS && !(x > 0)) {
        err(v, loc_value(v, item), "must be > 0, got %s", g);
        return -1;
    }
    if (range == R_NONNEG && !(x >= 0)) {
        err(v, loc_value(v, item), "must be >= 0, got %s", g);
        return -1;
    }
    if (range == R_UNIT && !(x >= 0 && x <= 1)) {
        err(v, loc_value(v, item), "must be in [0, 1], got %s", g);
        return -1;
    }
    *out = x;
    return 0;
}

/* An array of exactly n numbers. */
static int get_numbers(vctx *v, const cJSON *item, double *out, int n,
                       const char *what)
{
    char g[64];
    const cJSON *e;
    int i = 0, bad = 0;
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be %s, got %s%s", what, g,
            comma_hint(v, item));
        return -1;
    }
    for (e = item->child; e != NULL; e = e->next, i++) {
        size_t saved = push_index(v, (size_t)i);
        if (get_number(v, e, &out[i]) != 0) {
            bad = 1;
        }
        pop(v, saved);
    }
    return bad ? -1 : 0;
}

static int get_vec3(vctx *v, const cJSON *item, rbs_vec3 *out)
{
    double a[3];
    if (get_numbers(v, item, a, 3, "an array of 3 numbers [x, y, z]") != 0) {
        return -1;
    }
    out->x = a[0];
    out->y = a[1];
    out->z = a[2];
    return 0;
}

static int get_bool(vctx *v, const cJSON *item, int32_t *out)
{
    char g[64];
    if (!cJSON_IsBool(item)) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be true or false, got %s", g);
        return -1;
    }
    *out = cJSON_IsTrue(item) ? 1 : 0;
    return 0;
}

static int get_string(vctx *v, const cJSON *item, const char **out)
{
    char g[64];
    if (!cJSON_IsString(item)) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be a string, got %s", g);
        return -1;
    }
    *out = item->valuestring;
    return 0;
}

/* A string naming one of n choices; *out gets its index. */
static int get_choice(vctx *v, const cJSON *item, const char *const *names, int n,
                      int *out)
{
    char g[64], list[256];
    const char *s, *hint;
    int i;
    size_t k = 0;
    if (get_string(v, item, &s) != 0) {
        return -1;
    }
    for (i = 0; i < n; i++) {
        if (strcmp(s, names[i]) == 0) {
            *out = i;
            return 0;
        }
    }
    list[0] = '\0';
    for (i = 0; i < n && k < sizeof list; i++) {
        int w = snprintf(list + k, sizeof list - k, "%s\"%s\"",
                         i == 0 ? "" : (i == n - 1 ? " or " : ", "), names[i]);
        if (w > 0) {
            k += (size_t)w;
        }
    }
    got(v, item, g, sizeof g);
    hint = rbs__suggest(s, names, (size_t)n);
    if (hint != NULL) {
        err(v, loc_value(v, item), "must be %s, got %s (did you mean \"%s\"?)", list, g,
            hint);
    } else {
        err(v, loc_value(v, item), "must be %s, got %s", list, g);
    }
    return -1;
}

/* Whether a number literal t[0..n) (JSON grammar) is exactly the integer x,
 * not a longer or fractional number that rounded to it: 9007199254740993
 * reads as the double 2^53. */
static int literal_is(const char *t, size_t n, uint64_t x)
{
    char dig[96], want[24];
    size_t i = 0, nd = 0, k;
    long point = 0, e = 0;
    int neg_e = 0, seen_point = 0;
    if (i < n && t[i] == '-') {
        i++;
    }
    for (; i < n && t[i] != 'e' && t[i] != 'E'; i++) {
        if (t[i] == '.') {
            seen_point = 1;
        } else if (nd > 0 || t[i] != '0') {
            if (nd == sizeof dig) {
                return 0;
            }
            dig[nd++] = t[i];
            point += !seen_point;
        } else {
            point -= seen_point; /* a leading zero after the point */
        }
    }
    if (i < n) { /* exponent */
        i++;
        if (i < n && (t[i] == '+' || t[i] == '-')) {
            neg_e = t[i] == '-';
            i++;
        }
        for (; i < n; i++) {
            if (e < 100000) {
                e = e * 10 + (t[i] - '0');
            }
        }
    }
    while (nd > 0 && dig[nd - 1] == '0') {
        nd--; /* the value is 0.dig * 10^point: trailing zeros change nothing */
    }
    if (nd == 0) {
        return x == 0;
    }
    point += neg_e ? -e : e; /* digits before the decimal point */
    if (point < (long)nd || point > 20) {
        return 0; /* a fraction, or more than 20 digits */
    }
    snprintf(want, sizeof want, "%llu", (unsigned long long)x);
    if (strlen(want) != (size_t)point) {
        return 0;
    }
    for (k = 0; k < (size_t)point; k++) {
        if (want[k] != (k < nd ? dig[k] : '0')) {
            return 0;
        }
    }
    return 1;
}

/* An integer in [lo, hi] (JSON number without fraction). */
static int get_integer(vctx *v, const cJSON *item, double lo, double hi,
                       const char *what, uint64_t *out)
{
    double x;
    char g[64];
    const rbs__pos *pos;
    if (!cJSON_IsNumber(item)) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be %s, got %s", what, g);
        return -1;
    }
    if (get_number(v, item, &x) != 0) {
        return -1;
    }
    got(v, item, g, sizeof g);
    if (x != floor(x) || x < lo || x > hi) {
        err(v, loc_value(v, item), "must be %s, got %s", what, g);
        return -1;
    }
    pos = rbs__posmap_get(v->map, item);
    if (pos != NULL && pos->file >= 0 && pos->file < v->src_count && pos->raw_len > 0 &&
        (size_t)pos->raw_off + pos->raw_len <= v->srcs[pos->file].len &&
        !literal_is(v->srcs[pos->file].text + pos->raw_off, pos->raw_len,
                    (uint64_t)(x < 0 ? -x : x))) {
        /* the double is an integer in range, the number written is not */
        if (fabs(x) >= 9007199254740992.0) {
            err(v, loc_value(v, item),
                "must be %s, got %s (a double cannot hold it exactly: integers above "
                "2^53 are rounded)",
                what, g);
        } else {
            err(v, loc_value(v, item), "must be %s, got %s", what, g);
        }
        return -1;
    }
    *out = (uint64_t)x;
    return 0;
}

/* A body or material name: the rule of the world's API (core/name.h:
 * 1..RBS_NAME_MAX-1 bytes, no blanks, controls, '#', '"', '=' or ',', so
 * that it also fits the text format, nor invisible code points). */
static int get_name(vctx *v, const cJSON *item, const char **out)
{
    const char *s;
    char g[64];
    rbs__name_fault fault;
    if (get_string(v, item, &s) != 0) {
        return -1;
    }
    got(v, item, g, sizeof g);
    switch (rbs__name_check(s, &fault)) {
    case RBS__NAME_OK:
        *out = s;
        return 0;
    case RBS__NAME_LENGTH:
        err(v, loc_value(v, item), "a name must have 1 to %d bytes, got %s",
            RBS_NAME_MAX - 1, g);
        return -1;
    case RBS__NAME_UNSEEN:
        err(v, loc_value(v, item),
            "a name must not contain spaces, control characters or invisible "
            "formatting characters, got %s with U+%04lX (%s) at byte %lu",
            g, (unsigned long)fault.code, fault.what, (unsigned long)fault.byte);
        return -1;
    default:
        /* (RBS__NAME_UTF8 cannot be: a scene's strings were checked when
         * read; it is refused as the ASCII faults are all the same) */
        err(v, loc_value(v, item),
            "a name must not contain spaces, control characters, '#', '\"', '=' "
            "or ',', got %s",
            g);
        return -1;
    }
}

/* ---- objects and keys --------------------------------------------------- */

/* Check an object's keys: unknown keys (with a suggestion) and duplicates. */
static void check_keys(vctx *v, const cJSON *obj, const char *const *keys, int n,
                       const char *what)
{
    const cJSON *c, *d;
    for (c = obj->child; c != NULL; c = c->next) {
        int i, known = 0;
        size_t saved;
        for (i = 0; i < n; i++) {
            if (strcmp(c->string, keys[i]) == 0) {
                known = 1;
                break;
            }
        }
        saved = push_key(v, c->string);
        if (!known) {
            const char *hint = rbs__suggest(c->string, keys, (size_t)n);
            if (hint != NULL) {
                err(v, loc_key(v, c), "unknown key in %s (did you mean \"%s\"?)", what,
                    hint);
            } else {
                char list[512];
                size_t k = 0;
                list[0] = '\0';
                for (i = 0; i < n && k < sizeof list; i++) {
                    int w = snprintf(list + k, sizeof list - k, "%s%s", i ? ", " : "",
                                     keys[i]);
                    if (w > 0) {
                        k += (size_t)w;
                    }
                }
                err(v, loc_key(v, c), "unknown key in %s; expected one of: %s", what,
                    list);
            }
        }
        for (d = obj->child; d != c; d = d->next) {
            if (strcmp(d->string, c->string) == 0) {
                rbs__loc first = loc_key(v, d);
                err(v, loc_key(v, c), "duplicate key (first given at line %ld, column %ld)",
                    (long)first.line, (long)first.column);
                break;
            }
        }
        pop(v, saved);
    }
}

static int require_object(vctx *v, const cJSON *item, const char *what)
{
    char g[64];
    if (!cJSON_IsObject(item)) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be %s (a JSON object), got %s", what, g);
        return -1;
    }
    return 0;
}

static int require_array(vctx *v, const cJSON *item, const char *what)
{
    char g[64];
    if (!cJSON_IsArray(item)) {
        got(v, item, g, sizeof g);
        err(v, loc_value(v, item), "must be %s (a JSON array), got %s", what, g);
        return -1;
    }
    return 0;
}

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

static void missing(vctx *v, const cJSON *obj, const char *key, const char *what)
{
    err(v, loc_value(v, obj), "missing required key \"%s\" (%s)", key, what);
}

/* ---- simulation --------------------------------------------------------- */

static const char *const sim_keys[] = {
    "steps", "dt", "gravity", "gravity_mode", "method", "tolerance", "slop",
    "max_sweeps", "max_contacts", "max_substeps", "soft_substeps", "soft_tolerance", "restitution",
    "pause_on_collision", "mutual_gravity"};
static const char *const mutual_keys[] = {"G", "softening"};
static const char *const gravity_modes[] = {"acceleration", "force"};

static void check_simulation(vctx *v, const cJSON *sim)
{
    rbs_scene *s = v->scene;
    const cJSON *c;
    size_t saved;
    int steps_ok = 0, dt_ok = 1;
    if (require_object(v, sim, "the simulation settings") != 0) {
        return;
    }
    check_keys(v, sim, sim_keys, (int)(sizeof sim_keys / sizeof *sim_keys),
               "simulation");
    if ((c = member(sim, "steps")) != NULL) {
        uint64_t n;
        saved = push_key(v, "steps");
        if (get_integer(v, c, 0, RBS__SCENE_STEPS_MAX,
                        "a non-negative integer (at most 2^53)", &n) == 0) {
            s->steps = n;
            steps_ok = 1;
        }
        pop(v, saved);
    } else {
        missing(v, sim, "steps", "the number of steps to run, an integer >= 0");
    }
    if ((c = member(sim, "dt")) != NULL) {
        saved = push_key(v, "dt");
        dt_ok = get_ranged(v, c, R_POS, &s->dt) == 0;
        pop(v, saved);
    }
    if (steps_ok && dt_ok && !isfinite((double)s->steps * s->dt)) {
        saved = push_key(v, "steps");
        err(v, loc_value(v, member(sim, "steps")),
            "steps * dt overflows (%llu * %g s)", (unsigned long long)s->steps, s->dt);
        pop(v, saved);
    }
    if ((c = member(sim, "gravity")) != NULL) {
        saved = push_key(v, "gravity");
        (void)get_vec3(v, c, &s->gravity);
        pop(v, saved);
    }
    if ((c = member(sim, "gravity_mode")) != NULL) {
        int k;
        saved = push_key(v, "gravity_mode");
        if (get_choice(v, c, gravity_modes, 2, &k) == 0) {
            s->gravity_mode = k == 0 ? RBS_GRAVITY_ACCELERATION : RBS_GRAVITY_FORCE;
        }
        pop(v, saved);
    }
    if ((c = member(sim, "method")) != NULL) {
        const char *names[RBS_METHOD_COUNT];
        int k;
        for (k = 0; k < RBS_METHOD_COUNT; k++) {
            const char *nm = rbs_method_name((rbs_method)k);
            names[k] = nm != NULL ? nm : "";
        }
        saved = push_key(v, "method");
        if (cJSON_IsString(c) &&
            rbs_method_from_name(c->valuestring, &s->method) == RBS_OK) {
            /* known */
        } else if (get_choice(v, c, names, RBS_METHOD_COUNT, &k) == 0) {
            s->method = (rbs_method)k;
        }
        pop(v, saved);
    }
    if ((c = member(sim, "tolerance")) != NULL) {
        double x;
        saved = push_key(v, "tolerance");
        if (get_number(v, c, &x) == 0) {
            if (x >= RBS__SCENE_TOLERANCE_MIN) {
                s->tolerance = x;
            } else {
                char g[64];
                got(v, c, g, sizeof g);
                err(v, loc_value(v, c), "must be >= 1e-15 (double precision), got %s", g);
            }
        }
        pop(v, saved);
    }
    if ((c = member(sim, "slop")) != NULL) {
        double x;
        saved = push_key(v, "slop");
        if (get_number(v, c, &x) == 0) {
            if (x > 0.0 && x < RBS__SCENE_SLOP_MAX) {
                s->slop = x;
            } else {
                char g[64];
                got(v, c, g, sizeof g);
                err(v, loc_value(v, c), RBS__SCENE_SLOP_RANGE ", got %s", g);
            }
        }
        pop(v, saved);
    }
    if ((c = member(sim, "max_sweeps")) != NULL) {
        uint64_t n;
        saved = push_key(v, "max_sweeps");
        if (get_integer(v, c, 1, RBS__SCENE_SWEEPS_MAX, "an integer from 1 to 100000", &n) == 0) {
            s->max_sweeps = (uint32_t)n;
        }
        pop(v, saved);
    }
    if ((c = member(sim, "max_contacts")) != NULL) {
        uint64_t n;
        saved = push_key(v, "max_contacts");
        if (get_integer(v, c, 1, RBS__SCENE_CONTACTS_MAX, "an integer from 1 to 67108864 (2^26)", &n) == 0) {
            s->max_contacts = (uint32_t)n;
        }
        pop(v, saved);
    }
    if ((c = member(sim, "max_substeps")) != NULL) {
        uint64_t n;
        saved = push_key(v, "max_substeps");
        if (get_integer(v, c, 1, RBS__SCENE_SUBSTEPS_MAX, "an integer from 1 to 4294967295 (2^32 - 1)",
                        &n) == 0) {
            s->max_substeps = (uint32_t)n;
        }
        pop(v, saved);
    }
    if ((c = member(sim, "soft_substeps")) != NULL) {
        uint64_t n;
        char what[48];
        snprintf(what, sizeof what, "an integer from 1 to %u",
                 (unsigned)RBS__SOFT_SUBSTEPS_MAX);
        saved = push_key(v, "soft_substeps");
        if (get_integer(v, c, 1, RBS__SOFT_SUBSTEPS_MAX, what, &n) == 0) {
            s->soft_substeps = (uint32_t)n;
        }
        pop(v, saved);
    }
    if ((c = member(sim, "soft_tolerance")) != NULL) {
        /* (the world's range, rbs_world_def_validate: a fraction of the
         * pair's smaller radius) */
        saved = push_key(v, "soft_tolerance");
        (void)get_ranged(v, c, R_UNIT, &s->soft_tolerance);
        pop(v, saved);
    }
    if ((c = member(sim, "restitution")) != NULL) {
        saved = push_key(v, "restitution");
        (void)get_ranged(v, c, R_UNIT, &s->restitution);
        pop(v, saved);
    }
    if ((c = member(sim, "pause_on_collision")) != NULL) {
        saved = push_key(v, "pause_on_collision");
        (void)get_bool(v, c, &s->pause_on_collision);
        pop(v, saved);
    }
    if ((c = member(sim, "mutual_gravity")) != NULL) {
        saved = push_key(v, "mutual_gravity");
        if (cJSON_IsBool(c)) {
            s->mutual_gravity = cJSON_IsTrue(c) ? 1 : 0;
        } else if (cJSON_IsObject(c)) {
            const cJSON *g;
            size_t inner;
            s->mutual_gravity = 1;
            check_keys(v, c, mutual_keys, 2, "mutual_gravity");
            if ((g = member(c, "G")) != NULL) {
                inner = push_key(v, "G");
                (void)get_ranged(v, g, R_POS, &s->gravity_constant);
                pop(v, inner);
            }
            if ((g = member(c, "softening")) != NULL) {
                inner = push_key(v, "softening");
                (void)get_ranged(v, g, R_NONNEG, &s->softening);
                pop(v, inner);
            }
        } else {
            char g[64];
            got(v, c, g, sizeof g);
            err(v, loc_value(v, c),
                "must be false, true or an object {\"G\": ..., \"softening\": ...}, got %s",
                g);
        }
        pop(v, saved);
    }
}

/* ---- materials ---------------------------------------------------------- */

static int32_t material_find(const rbs_scene *s, const char *name)
{
    uint32_t i;
    for (i = 0; i < s->material_count; i++) {
        if (strcmp(s->materials[i], name) == 0) {
            return (int32_t)i;
        }
    }
    return -1;
}

static const char *const pair_keys[] = {"pair",        "static",  "kinetic",
                                        "restitution", "rolling", "spinning"};

static void check_materials(vctx *v, const cJSON *mats)
{
    rbs_scene *s = v->scene;
    const cJSON *row;
    size_t i = 0, n;
    const cJSON **firsts;
    if (require_array(v, mats, "a list of material pairs") != 0) {
        return;
    }
    n = (size_t)cJSON_GetArraySize(mats);
    s->pairs = calloc(n + 1, sizeof *s->pairs);
    s->materials = calloc(2 * n + 1, sizeof *s->materials);
    firsts = calloc(n + 1, sizeof *firsts);
    if (s->pairs == NULL || s->materials == NULL || firsts == NULL) {
        err(v, loc_value(v, mats), "out of memory");
        free(firsts);
        return;
    }
    for (row = mats->child; row != NULL; row = row->next, i++) {
        size_t saved = push_index(v, i), inner;
        const cJSON *c;
        rbs__scene_pair p;
        int bad = 0, static_ok = 0;
        uint32_t k;
        memset(&p, 0, sizeof p);
        p.restitution = -1.0;
        if (require_object(v, row, "a material pair") != 0) {
            pop(v, saved);
            continue;
        }
        check_keys(v, row, pair_keys, (int)(sizeof pair_keys / sizeof *pair_keys),
                   "a material pair");
        c = member(row, "pair");
        if (c == NULL) {
            missing(v, row, "pair", "two material names, \"*\" for any");
            bad = 1;
        } else {
            inner = push_key(v, "pair");
            if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != 2) {
                char g[64];
                got(v, c, g, sizeof g);
                err(v, loc_value(v, c),
                    "must be an array of 2 material names (\"*\" for any), got %s", g);
                bad = 1;
            } else {
                const cJSON *e = c->child;
                int j;
                for (j = 0; j < 2; j++, e = e->next) {
                    size_t in2 = push_index(v, (size_t)j);
                    const char *nm;
                    int32_t idx = -1;
                    if (cJSON_IsString(e) && strcmp(e->valuestring, "*") == 0) {
                        idx = -1;
                    } else if (get_name(v, e, &nm) != 0) {
                        bad = 1;
                    } else {
                        idx = material_find(s, nm);
                        if (idx < 0) {
                            idx = (int32_t)s->material_count;
                            memcpy(s->materials[s->material_count++], nm,
                                   strlen(nm) + 1);
                        }
                    }
                    if (j == 0) {
                        p.a = idx;
                    } else {
                        p.b = idx;
                    }
                    pop(v, in2);
                }
            }
            pop(v, inner);
        }
        if ((c = member(row, "static")) != NULL) {
            inner = push_key(v, "static");
            static_ok = get_ranged(v, c, R_NONNEG, &p.static_friction) == 0;
            bad |= !static_ok;
            pop(v, inner);
        } else {
            missing(v, row, "static", "the static friction coefficient, >= 0");
            bad = 1;
        }
        if ((c = member(row, "kinetic")) != NULL) {
            inner = push_key(v, "kinetic");
            if (get_ranged(v, c, R_NONNEG, &p.kinetic_friction) != 0) {
                bad = 1;
            } else if (static_ok && p.kinetic_friction > p.static_friction) {
                char g[64], st[64];
                got(v, c, g, sizeof g);
                got(v, member(row, "static"), st, sizeof st);
                err(v, loc_value(v, c), "must not exceed the static friction (%s), got %s",
                    st, g);
                bad = 1;
            }
            pop(v, inner);
        } else {
            missing(v, row, "kinetic", "the kinetic friction coefficient, 0..static");
            bad = 1;
        }
        if ((c = member(row, "restitution")) != NULL) {
            inner = push_key(v, "restitution");
            bad |= get_ranged(v, c, R_UNIT, &p.restitution) != 0;
            pop(v, inner);
        }
        if ((c = member(row, "rolling")) != NULL) {
            inner = push_key(v, "rolling");
            bad |= get_ranged(v, c, R_NONNEG, &p.rolling) != 0;
            pop(v, inner);
        }
        if ((c = member(row, "spinning")) != NULL) {
            inner = push_key(v, "spinning");
            bad |= get_ranged(v, c, R_NONNEG, &p.spinning) != 0;
            pop(v, inner);
        }
        if (!bad) {
            /* an unordered pair may be given once */
            for (k = 0; k < s->pair_count; k++) {
                const rbs__scene_pair *q = &s->pairs[k];
                if ((q->a == p.a && q->b == p.b) || (q->a == p.b && q->b == p.a)) {
                    rbs__loc first = loc_value(v, firsts[k]);
                    inner = push_key(v, "pair");
                    err(v, loc_value(v, member(row, "pair")),
                        "duplicate material pair [\"%s\", \"%s\"] (first given at line "
                        "%ld, column %ld)",
                        p.a >= 0 ? s->materials[p.a] : "*",
                        p.b >= 0 ? s->materials[p.b] : "*", (long)first.line,
                        (long)first.column);
                    pop(v, inner);
                    bad = 1;
                    break;
                }
            }
        }
        if (!bad) {
            firsts[s->pair_count] = member(row, "pair");
            s->pairs[s->pair_count++] = p;
        }
        pop(v, saved);
    }
    free(firsts);
}

/* ---- bodies ------------------------------------------------------------- */

static const char *const sphere_keys[] = {
    "name",     "type",   "radius",   "mass",     "density",          "inertia",
    "position", "orientation", "velocity", "angular_velocity", "center_of_mass",
    "force",    "torque", "material", "color",    "texture",          "fixed"};
static const char *const plane_keys[] = {"name",     "type",  "point",  "normal",
                                         "material", "color", "texture"};
static const char *const body_types[] = {"sphere", "plane"};
static const char *const textures[] = {"none", "stripes", "checker"};
static const char *const inertia_kinds[] = {"solid", "hollow"};

static int get_color(vctx *v, const cJSON *item, uint32_t *out)
{
    char g[64];
    if (cJSON_IsString(item)) {
        const char *s = item->valuestring;
        uint32_t c = 0;
        int i, ok = s[0] == '#' && strlen(s) == 7;
        for (i = 1; ok && i < 7; i++) {
            char h = s[i];
            int d = (h >= '0' && h <= '9')   ? h - '0'
                    : (h >= 'a' && h <= 'f') ? h - 'a' + 10
                    : (h >= 'A' && h <= 'F') ? h - 'A' + 10
                                             : -1;
            if (d < 0) {
                ok = 0;
            } else {
                c = c * 16 + (uint32_t)d;
            }
        }
        if (ok) {
            *out = c;
            return 0;
        }
    } else if (cJSON_IsArray(item) && cJSON_GetArraySize(item) == 3) {
        double a[3];
        int i, bad = 0;
        const cJSON *e = item->child;
        for (i = 0; i < 3; i++, e = e->next) {
            size_t saved = push_index(v, (size_t)i);
            bad |= get_ranged(v, e, R_UNIT, &a[i]) != 0;
            pop(v, saved);
        }
        if (bad) {
            return -1;
        }
        *out = ((uint32_t)lround(a[0] * 255.0) << 16) |
               ((uint32_t)lround(a[1] * 255.0) << 8) | (uint32_t)lround(a[2] * 255.0);
        return 0;
    }
    got(v, item, g, sizeof g);
    err(v, loc_value(v, item),
        "must be \"#rrggbb\" or three numbers in [0, 1] (red, green, blue), got %s", g);
    return -1;
}

/* A length this close to 1 is left alone when normalising (8 ulp). */
#define UNIT_TOL (8.0 * 2.220446049250313e-16)

static int vec_len_zero(rbs_vec3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }

/* The length of a[0..n-1], to normalise it by: the square root of the sum of
 * squares, or, where that overflows or underflows (a normal [0, 0, 1e308] or
 * [1e-200, 1e-200, 0], finite and nonzero all the same), the length of a
 * scaled by its largest component, and a[] scaled with it (as
 * rbs_world_add_plane and add_sphere do; ordinary input rounds as before).
 * 0 for a zero vector. */
static double scaled_len(double *a, int n)
{
    double sum = 0.0, big = 0.0, len;
    int k;
    for (k = 0; k < n; k++) {
        sum += a[k] * a[k];
        big = fmax(big, fabs(a[k]));
    }
    len = sqrt(sum);
    if (!(big > 0.0)) {
        return 0.0;
    }
    if (!(len > 1e-150) || !isfinite(len)) {
        sum = 0.0;
        for (k = 0; k < n; k++) {
            a[k] /= big;
            sum += a[k] * a[k];
        }
        len = sqrt(sum);
    }
    return len;
}

/* The world's own test of a sphere's inertia (rbs_world_add_sphere, world.c),
 * repeated so that the error names the key: the inertia about the centre of
 * mass (parallel-axis rule) must be positive definite and, scaled by its mean
 * moment, invertible with a finite inverse.  Returns 0 if it is, 1 if the
 * moments underflow or overflow a double, 2 if the centre of mass is too far
 * from the centre for them, 3 if principal moments are each finite but
 * their sum (the trace) overflows.  *trace gets the trace about the centre
 * of mass. */
static int sphere_inertia(const rbs__scene_body *b, double mass, double *trace)
{
    double I[9], In[9], sc, c[3], c2, det, cof[3];
    int i, j;
    memset(I, 0, sizeof I);
    if (b->inertia_kind == RBS_INERTIA_PRINCIPAL) {
        I[0] = b->inertia.x;
        I[4] = b->inertia.y;
        I[8] = b->inertia.z;
    } else {
        I[0] = I[4] = I[8] = (b->inertia_kind == RBS_INERTIA_SOLID ? 0.4 : 2.0 / 3.0) * mass *
                             b->radius * b->radius;
    }
    c[0] = b->center_of_mass.x;
    c[1] = b->center_of_mass.y;
    c[2] = b->center_of_mass.z;
    c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            I[3 * i + j] -= mass * ((i == j ? c2 : 0.0) - c[i] * c[j]);
        }
    }
    *trace = I[0] + I[4] + I[8]; /* (as rbs_world_add_sphere sums it) */
    if (b->inertia_kind == RBS_INERTIA_PRINCIPAL && !isfinite(*trace) &&
        isfinite(I[0]) && isfinite(I[4]) && isfinite(I[8])) {
        return 3; /* (each moment finite, their sum not) */
    }
    sc = *trace / 3.0;
    if (!(sc > 0.0) || !isfinite(sc)) {
        return c2 > 0.0 && isfinite(sc) ? 2 : 1;
    }
    for (i = 0; i < 9; i++) {
        In[i] = I[i] / sc;
    }
    cof[0] = In[4] * In[8] - In[5] * In[7];
    cof[1] = In[5] * In[6] - In[3] * In[8];
    cof[2] = In[3] * In[7] - In[4] * In[6];
    det = In[0] * cof[0] + In[1] * cof[1] + In[2] * cof[2];
    if (!(In[0] > 0.0) || !(In[0] * In[4] - In[1] * In[3] > 0.0) || !(det > 0.0)) {
        return c2 > 0.0 ? 2 : 1;
    }
    /* the largest inverse moments: diagonal cofactors / det / sc */
    if (!isfinite(cof[0] / det / sc) || !isfinite((In[0] * In[8] - In[2] * In[6]) / det / sc) ||
        !isfinite((In[0] * In[4] - In[1] * In[3]) / det / sc)) {
        return 1;
    }
    return 0;
}

/* A movable sphere's energies at the start, each at most RBS__ENERGY_MAX
 * in size: the world's own rule (rbs__sphere_energy, world.c), checked here
 * so that the error names the key. */
static void check_sphere_energy(vctx *v, const cJSON *obj, const rbs__scene_body *b,
                                double mass, double trace)
{
    const rbs_scene *s = v->scene;
    double e[RBS__SPHERE_LIMITS];
    static const char *const keys[RBS__SPHERE_LIMITS] = {
        "velocity", "angular_velocity", "position", "force", "velocity", "velocity",
        "angular_velocity"};
    static const char *const what[RBS__SPHERE_LIMITS] = {
        "the kinetic energy m v^2 / 2", "the rotational energy",
        "the potential energy in gravity", "the potential energy of its force",
        "the momentum m v", "the angular momentum r x m v about the origin (position and velocity)",
        "the spin angular momentum, at most trace(I) |w|"};
    int k = rbs__sphere_energy(mass, trace, b->velocity, b->angular_velocity, b->position,
                               b->orientation, b->center_of_mass, s->gravity,
                               s->gravity_mode == RBS_GRAVITY_FORCE, b->force, e);
    if (k >= 0) {
        const cJSON *at = member(obj, keys[k]) != NULL ? member(obj, keys[k]) : obj;
        size_t saved = push_key(v, keys[k]);
        err(v, loc_value(v, at),
            "%s at the start is %g %s, beyond 1e300 %s (the world's %s would overflow)",
            what[k], e[k], rbs__sphere_limit_unit(k), rbs__sphere_limit_unit(k),
            rbs__sphere_limit_sum(k));
        pop(v, saved);
    }
}

/* A sphere whose own values are valid: the limits the world adds (inertia,
 * 1 / mass) and its energy at the start. */
static void check_sphere_limits(vctx *v, const cJSON *obj, const rbs__scene_body *b)
{
    double mass = b->density > 0 ? b->density * (4.0 / 3.0) * 3.14159265358979323846 *
                                       b->radius * b->radius * b->radius
                                 : b->mass;
    const char *mkey = b->density > 0 ? "density" : "mass";
    const char *ikey = b->inertia_kind == RBS_INERTIA_PRINCIPAL ? "inertia" : mkey;
    double trace;
    size_t saved;
    int r;
    if (!(mass > 0.0) || !isfinite(mass) || (!b->fixed && !isfinite(1.0 / mass))) {
        saved = push_key(v, mkey);
        err(v, loc_value(v, member(obj, mkey)),
            "the mass %g kg is too small for double precision (1 / mass overflows)", mass);
        pop(v, saved);
        return;
    }
    r = sphere_inertia(b, mass, &trace);
    if (r == 3) {
        /* (it read "the moments of inertia (mass 1 kg, radius 0.1 m)
         * underflow or overflow a double" of [6e307, 6e307, 6e307]) */
        char g[256];
        saved = push_key(v, ikey);
        got_list(v, member(obj, ikey), g, sizeof g);
        err(v, loc_value(v, member(obj, ikey)),
            "principal moments must have a finite sum (the world takes the inertia's "
            "trace), got %s",
            g);
        pop(v, saved);
        return;
    }
    if (r == 1) {
        const cJSON *at = member(obj, ikey) != NULL ? member(obj, ikey) : obj;
        saved = push_key(v, ikey);
        err(v, loc_value(v, at),
            "the moments of inertia (mass %g kg, radius %g m) underflow or overflow a "
            "double: the inertia and its inverse must be finite and nonzero",
            mass, b->radius);
        pop(v, saved);
        return;
    }
    if (r == 2) {
        rbs_vec3 m = b->center_of_mass;
        saved = push_key(v, "center_of_mass");
        err(v, loc_value(v, member(obj, "center_of_mass")),
            "|offset| = %g m is too far from the centre for this inertia (the inertia "
            "about the centre of mass would not be positive definite)",
            sqrt(m.x * m.x + m.y * m.y + m.z * m.z));
        pop(v, saved);
        return;
    }
    if (!b->fixed) {
        check_sphere_energy(v, obj, b, mass, trace);
    }
}

static void check_sphere(vctx *v, const cJSON *obj, rbs__scene_body *b)
{
    uint32_t before = v->scene->error_count;
    const cJSON *c, *mass, *density;
    size_t saved;
    int radius_ok = 0;
    check_keys(v, obj, sphere_keys, (int)(sizeof sphere_keys / sizeof *sphere_keys),
               "a sphere");
    b->orientation.w = 1.0;
    b->color = 0xd03030;
    b->texture = RBS_TEXTURE_STRIPES;
    b->inertia_kind = RBS_INERTIA_SOLID;
    if ((c = member(obj, "radius")) != NULL) {
        saved = push_key(v, "radius");
        radius_ok = get_ranged(v, c, R_POS, &b->radius) == 0;
        pop(v, saved);
    } else {
        missing(v, obj, "radius", "m, > 0");
    }
    mass = member(obj, "mass");
    density = member(obj, "density");
    if (mass != NULL && density != NULL) {
        saved = push_key(v, "density");
        err(v, loc_key(v, density), "give either \"mass\" or \"density\", not both");
        pop(v, saved);
    } else if (mass != NULL) {
        saved = push_key(v, "mass");
        (void)get_ranged(v, mass, R_POS, &b->mass);
        pop(v, saved);
    } else if (density != NULL) {
        saved = push_key(v, "density");
        if (get_ranged(v, density, R_POS, &b->density) == 0 && radius_ok &&
            !isfinite(b->density * 4.0 / 3.0 * 3.14159265358979323846 * b->radius * b->radius * b->radius)) {
            err(v, loc_value(v, density), "the mass (density * volume) overflows");
        }
        pop(v, saved);
    } else {
        missing(v, obj, "mass", "kg, > 0; or give \"density\" in kg/m^3");
    }
    if ((c = member(obj, "inertia")) != NULL) {
        saved = push_key(v, "inertia");
        if (cJSON_IsString(c)) {
            int k;
            if (get_choice(v, c, inertia_kinds, 2, &k) == 0) {
                b->inertia_kind = k == 0 ? RBS_INERTIA_SOLID : RBS_INERTIA_HOLLOW;
            }
        } else if (cJSON_IsNumber(c)) {
            double I;
            if (get_ranged(v, c, R_POS, &I) == 0) {
                b->inertia_kind = RBS_INERTIA_PRINCIPAL;
                b->inertia.x = b->inertia.y = b->inertia.z = I;
            }
        } else if (cJSON_IsArray(c)) {
            double a[3];
            if (get_numbers(v, c, a, 3, "three principal moments [I1, I2, I3]") == 0) {
                int k, bad = 0;
                for (k = 0; k < 3; k++) {
                    if (!(a[k] > 0)) {
                        size_t in2 = push_index(v, (size_t)k);
                        char g[64];
                        const cJSON *e = cJSON_GetArrayItem(c, k);
                        got(v, e, g, sizeof g);
                        err(v, loc_value(v, e), "must be > 0, got %s", g);
                        pop(v, in2);
                        bad = 1;
                    }
                }
                if (!bad && (a[0] > a[1] + a[2] || a[1] > a[0] + a[2] ||
                             a[2] > a[0] + a[1])) {
                    char g[256];
                    got_list(v, c, g, sizeof g);
                    err(v, loc_value(v, c),
                        "principal moments must satisfy the triangle inequality "
                        "(each <= the sum of the other two), got %s",
                        g);
                    bad = 1;
                }
                if (!bad) {
                    b->inertia_kind = RBS_INERTIA_PRINCIPAL;
                    b->inertia.x = a[0];
                    b->inertia.y = a[1];
                    b->inertia.z = a[2];
                }
            }
        } else {
            char g[64];
            got(v, c, g, sizeof g);
            err(v, loc_value(v, c),
                "must be \"solid\", \"hollow\", a number or three principal moments, "
                "got %s",
                g);
        }
        pop(v, saved);
    }
    if ((c = member(obj, "position")) != NULL) {
        saved = push_key(v, "position");
        (void)get_vec3(v, c, &b->position);
        b->at_position = loc_value(v, c);
        pop(v, saved);
    } else {
        missing(v, obj, "position", "the centre, [x, y, z] in m");
    }
    if ((c = member(obj, "orientation")) != NULL) {
        double q[4];
        saved = push_key(v, "orientation");
        if (get_numbers(v, c, q, 4, "a quaternion [w, x, y, z]") == 0) {
            double n = scaled_len(q, 4);
            if (fabs(n - 1.0) <= UNIT_TOL) {
                n = 1.0; /* already unit: keep the bits, so saving and loading
                            again changes nothing */
            }
            if (!(n > 0)) {
                char g[256];
                got_list(v, c, g, sizeof g);
                err(v, loc_value(v, c), "must be a nonzero quaternion [w, x, y, z], got %s",
                    g);
            } else {
                b->orientation.w = q[0] / n;
                b->orientation.x = q[1] / n;
                b->orientation.y = q[2] / n;
                b->orientation.z = q[3] / n;
            }
        }
        pop(v, saved);
    }
    if ((c = member(obj, "velocity")) != NULL) {
        saved = push_key(v, "velocity");
        (void)get_vec3(v, c, &b->velocity);
        pop(v, saved);
    }
    if ((c = member(obj, "angular_velocity")) != NULL) {
        saved = push_key(v, "angular_velocity");
        (void)get_vec3(v, c, &b->angular_velocity);
        pop(v, saved);
    }
    if ((c = member(obj, "center_of_mass")) != NULL) {
        saved = push_key(v, "center_of_mass");
        if (get_vec3(v, c, &b->center_of_mass) == 0 && radius_ok) {
            rbs_vec3 m = b->center_of_mass;
            double len = sqrt(m.x * m.x + m.y * m.y + m.z * m.z);
            if (!(len < b->radius)) {
                err(v, loc_value(v, c),
                    "must lie inside the sphere: |offset| = %g m, radius %g m", len,
                    b->radius);
            }
        }
        pop(v, saved);
    }
    if ((c = member(obj, "force")) != NULL) {
        saved = push_key(v, "force");
        (void)get_vec3(v, c, &b->force);
        pop(v, saved);
    }
    if ((c = member(obj, "torque")) != NULL) {
        saved = push_key(v, "torque");
        (void)get_vec3(v, c, &b->torque);
        pop(v, saved);
    }
    if ((c = member(obj, "fixed")) != NULL) {
        saved = push_key(v, "fixed");
        (void)get_bool(v, c, &b->fixed);
        pop(v, saved);
    }
    if (b->fixed) {
        /* a fixed sphere never moves: a velocity, force or torque would be
         * dropped silently (rbs_world_add_sphere refuses them too) */
        static const char *const moving[4] = {"velocity", "angular_velocity", "force", "torque"};
        const rbs_vec3 *at[4] = {&b->velocity, &b->angular_velocity, &b->force, &b->torque};
        int k;
        for (k = 0; k < 4; k++) {
            if ((c = member(obj, moving[k])) != NULL && !vec_len_zero(*at[k])) {
                char g[256];
                got_list(v, c, g, sizeof g);
                saved = push_key(v, moving[k]);
                err(v, loc_value(v, c),
                    "a fixed sphere does not move: must be [0, 0, 0] or left out, got %s",
                    g);
                pop(v, saved);
            }
        }
    }
    if (v->scene->error_count == before) {
        check_sphere_limits(v, obj, b);
    }
}

static void check_plane(vctx *v, const cJSON *obj, rbs__scene_body *b)
{
    const cJSON *c;
    size_t saved;
    check_keys(v, obj, plane_keys, (int)(sizeof plane_keys / sizeof *plane_keys),
               "a plane");
    b->color = 0x808080;
    b->texture = RBS_TEXTURE_CHECKER;
    b->normal.z = 1.0;
    if ((c = member(obj, "point")) != NULL) {
        saved = push_key(v, "point");
        (void)get_vec3(v, c, &b->point);
        b->at_position = loc_value(v, c);
        pop(v, saved);
    } else {
        missing(v, obj, "point", "a point on the plane, [x, y, z] in m");
    }
    if ((c = member(obj, "normal")) != NULL) {
        rbs_vec3 n;
        saved = push_key(v, "normal");
        if (get_vec3(v, c, &n) == 0) {
            double a[3] = {n.x, n.y, n.z};
            double len = scaled_len(a, 3);
            if (fabs(len - 1.0) <= UNIT_TOL) {
                len = 1.0; /* already unit: keep the bits (see orientation) */
            }
            if (!(len > 0)) {
                char g[256];
                got_list(v, c, g, sizeof g);
                err(v, loc_value(v, c), "must be a nonzero vector, got %s", g);
            } else {
                b->normal.x = a[0] / len;
                b->normal.y = a[1] / len;
                b->normal.z = a[2] / len;
            }
        }
        pop(v, saved);
    } else {
        missing(v, obj, "normal", "the outward normal, [x, y, z], nonzero");
    }
}

int rbs__body_key_near(const char *word)
{
    const size_t ns = sizeof sphere_keys / sizeof *sphere_keys,
                 np = sizeof plane_keys / sizeof *plane_keys;
    return rbs__suggest(word, sphere_keys, ns) != NULL ||
           rbs__suggest(word, plane_keys, np) != NULL;
}

/* qsort has no context argument: sort (name, index) records instead. */
typedef struct name_rec {
    const char *name;
    size_t index;
} name_rec;

static int cmp_name_rec(const void *pa, const void *pb)
{
    const name_rec *a = pa, *b = pb;
    int c = strcmp(a->name, b->name);
    return c != 0 ? c : (a->index < b->index ? -1 : a->index > b->index);
}

static void check_bodies(vctx *v, const cJSON *bodies, const cJSON ***items_out)
{
    rbs_scene *s = v->scene;
    const cJSON *obj;
    const cJSON **items;
    name_rec *recs;
    size_t i = 0, n, nrec = 0, k;
    const char **mat_names;
    *items_out = NULL;
    if (require_array(v, bodies, "a list of bodies") != 0) {
        return;
    }
    n = (size_t)cJSON_GetArraySize(bodies);
    s->bodies = calloc(n + 1, sizeof *s->bodies);
    items = calloc(n + 1, sizeof *items);
    recs = calloc(n + 1, sizeof *recs);
    mat_names = calloc(s->material_count + 1, sizeof *mat_names);
    if (s->bodies == NULL || items == NULL || recs == NULL || mat_names == NULL) {
        err(v, loc_value(v, bodies), "out of memory");
        free(items);
        free(recs);
        free(mat_names);
        return;
    }
    for (k = 0; k < s->material_count; k++) {
        mat_names[k] = s->materials[k];
    }
    for (obj = bodies->child; obj != NULL; obj = obj->next, i++) {
        size_t saved = push_index(v, i), inner;
        rbs__scene_body *b = &s->bodies[i];
        const cJSON *c;
        int type = -1;
        uint32_t before = s->error_count;
        b->material = -1;
        b->at = loc_value(v, obj);
        b->at_position = b->at;
        b->at_material = b->at;
        items[i] = obj;
        if (require_object(v, obj, "a body") != 0) {
            pop(v, saved);
            continue;
        }
        if ((c = member(obj, "type")) != NULL) {
            inner = push_key(v, "type");
            (void)get_choice(v, c, body_types, 2, &type);
            pop(v, inner);
        } else {
            missing(v, obj, "type", "\"sphere\" or \"plane\"");
        }
        if ((c = member(obj, "name")) != NULL) {
            const char *nm;
            inner = push_key(v, "name");
            if (get_name(v, c, &nm) == 0) {
                memcpy(b->name, nm, strlen(nm) + 1);
                recs[nrec].name = b->name;
                recs[nrec].index = i;
                nrec++;
            }
            pop(v, inner);
        } else {
            missing(v, obj, "name", "a unique body name");
        }
        if (type == 0) {
            b->type = RBS_BODY_SPHERE;
            check_sphere(v, obj, b);
        } else if (type == 1) {
            b->type = RBS_BODY_PLANE;
            check_plane(v, obj, b);
        }
        if ((c = member(obj, "material")) != NULL) {
            const char *nm;
            inner = push_key(v, "material");
            b->at_material = loc_value(v, c);
            if (get_name(v, c, &nm) == 0) {
                b->material = material_find(s, nm);
                if (b->material < 0) {
                    const char *hint = rbs__suggest(nm, mat_names, s->material_count);
                    if (strcmp(nm, "*") == 0) {
                        /* (as the API refuses it: a body's material is one) */
                        err(v, loc_value(v, c),
                            "\"*\" is not a material: it stands for any material in a "
                            "\"materials\" pair; give a material named there, or leave "
                            "\"material\" out for none");
                    } else if (hint != NULL) {
                        err(v, loc_value(v, c),
                            "undefined material \"%s\" (did you mean \"%s\"?)", nm, hint);
                    } else {
                        err(v, loc_value(v, c),
                            "undefined material \"%s\"; materials are the names used "
                            "in \"materials\" pairs",
                            nm);
                    }
                }
            }
            pop(v, inner);
        }
        if ((c = member(obj, "color")) != NULL) {
            inner = push_key(v, "color");
            (void)get_color(v, c, &b->color);
            pop(v, inner);
        }
        if ((c = member(obj, "texture")) != NULL) {
            int t;
            inner = push_key(v, "texture");
            if (get_choice(v, c, textures, 3, &t) == 0) {
                b->texture = (rbs_texture)t;
            }
            pop(v, inner);
        }
        b->ok = s->error_count == before && type >= 0;
        pop(v, saved);
    }
    s->body_count = (uint32_t)n;
    /* duplicate names: sort, then compare neighbours */
    qsort(recs, nrec, sizeof *recs, cmp_name_rec);
    for (k = 1; k < nrec; k++) {
        if (strcmp(recs[k].name, recs[k - 1].name) == 0) {
            size_t j = k - 1, saved = v->path_len;
            while (j > 0 && strcmp(recs[j - 1].name, recs[k].name) == 0) {
                j--;
            }
            push_index(v, recs[k].index);
            push_key(v, "name");
            err(v, loc_value(v, member(items[recs[k].index], "name")),
                "duplicate body name \"%s\" (first used by bodies[%lu])", recs[k].name,
                (unsigned long)recs[j].index);
            s->bodies[recs[k].index].ok = 0;
            pop(v, saved);
        }
    }
    free(recs);
    free(mat_names);
    *items_out = items;
}

/* ---- cross-checks ------------------------------------------------------- */

static int pair_matches(const rbs__scene_pair *p, int32_t m1, int32_t m2)
{
    int a1 = p->a < 0 || p->a == m1, b2 = p->b < 0 || p->b == m2;
    int a2 = p->a < 0 || p->a == m2, b1 = p->b < 0 || p->b == m1;
    return (a1 && b2) || (a2 && b1);
}

static int pair_exists(const rbs_scene *s, int32_t m1, int32_t m2)
{
    uint32_t k;
    for (k = 0; k < s->pair_count; k++) {
        if (pair_matches(&s->pairs[k], m1, m2)) {
            return 1;
        }
    }
    return 0;
}

/* Bodies that could touch need a material pair row (after "*" fallbacks).
 * Could touch: at least one is a movable sphere. */
static void check_pairs(vctx *v)
{
    rbs_scene *s = v->scene;
    uint32_t m = s->material_count + 1, i, a, b;
    /* per material (index m-1 = none): first movable sphere, first other body */
    int64_t *dyn = malloc(m * sizeof *dyn), *other = malloc(m * sizeof *other);
    if (dyn == NULL || other == NULL) {
        rbs__loc none = {0, 0, 0};
        free(dyn);
        free(other);
        rbs__scene_error(s, none, "", "out of memory (checking material pairs)");
        return;
    }
    for (i = 0; i < m; i++) {
        dyn[i] = -1;
        other[i] = -1;
    }
    for (i = 0; i < s->body_count; i++) {
        const rbs__scene_body *bd = &s->bodies[i];
        uint32_t mi = bd->material >= 0 ? (uint32_t)bd->material : m - 1;
        if (!bd->ok) {
            continue;
        }
        if (bd->type == RBS_BODY_SPHERE && !bd->fixed) {
            if (dyn[mi] < 0) {
                dyn[mi] = i;
            }
        } else if (bd->type != RBS_BODY_NONE && other[mi] < 0) {
            other[mi] = i;
        }
    }
    for (a = 0; a < m; a++) {
        if (dyn[a] < 0) {
            continue;
        }
        for (b = 0; b < m; b++) {
            int64_t j = -1;
            int32_t ma = a == m - 1 ? -1 : (int32_t)a, mb = b == m - 1 ? -1 : (int32_t)b;
            if (b < a && dyn[b] >= 0) {
                continue; /* (b, a) is checked when a and b swap */
            }
            if (b == a) {
                /* another movable sphere or other body of the same material */
                for (i = 0; i < s->body_count && j < 0; i++) {
                    const rbs__scene_body *bd = &s->bodies[i];
                    uint32_t mi = bd->material >= 0 ? (uint32_t)bd->material : m - 1;
                    if (mi == a && (int64_t)i != dyn[a] && bd->ok) {
                        j = i;
                    }
                }
            } else {
                j = dyn[b] >= 0 ? dyn[b] : other[b];
            }
            if (j < 0 || pair_exists(s, ma, mb)) {
                continue;
            }
            {
                const rbs__scene_body *bj = &s->bodies[j];
                size_t saved = v->path_len;
                push_key(v, "bodies");
                push_index(v, (size_t)j);
                push_key(v, bj->material >= 0 ? "material" : "name");
                err(v, bj->material >= 0 ? bj->at_material : bj->at,
                    "no material pair for [\"%s\", \"%s\"]: bodies \"%s\" and \"%s\" "
                    "could touch; add the pair or a \"*\" row to \"materials\"",
                    ma >= 0 ? s->materials[ma] : "(no material)",
                    mb >= 0 ? s->materials[mb] : "(no material)",
                    s->bodies[dyn[a]].name, bj->name);
                pop(v, saved);
            }
        }
    }
    free(dyn);
    free(other);
}

/* A material named in a "materials" row that no body has: the row applies
 * to no contact.  Allowed (scenes/FORMAT.md: a material exists by being
 * named in a row), but a typo ("stel" beside "steel") leaves the bodies'
 * contacts to a "*" row without a word: a warning at the material's first
 * row, suggesting the closest material a body has. */
static void warn_unused_materials(vctx *v, const cJSON *mats)
{
    rbs_scene *s = v->scene;
    uint32_t m = s->material_count, i, k, nused = 0;
    unsigned char *used;
    const char **names;
    const cJSON *row;
    size_t r = 0;
    if (m == 0 || !cJSON_IsArray(mats)) {
        return;
    }
    used = calloc(m, 1);
    names = calloc(m, sizeof *names);
    if (used == NULL || names == NULL) {
        rbs__loc none = {0, 0, 0};
        free(used);
        free(names);
        /* (not an error: the scene is valid; but not silence either) */
        rbs__scene_warning(s, none, "materials",
                           "out of memory: not checked for materials on no body");
        return;
    }
    for (i = 0; i < s->body_count; i++) {
        if (s->bodies[i].material >= 0 && (uint32_t)s->bodies[i].material < m) {
            used[s->bodies[i].material] = 1;
        }
    }
    for (k = 0; k < m; k++) {
        if (used[k]) {
            names[nused++] = s->materials[k];
        }
    }
    for (row = mats->child; row != NULL; row = row->next, r++) {
        const cJSON *pair = cJSON_IsObject(row) ? member(row, "pair") : NULL;
        const cJSON *e;
        size_t j = 0;
        if (!cJSON_IsArray(pair) || cJSON_GetArraySize(pair) != 2) {
            continue;
        }
        for (e = pair->child; e != NULL; e = e->next, j++) {
            int32_t idx;
            if (!cJSON_IsString(e) || (idx = material_find(s, e->valuestring)) < 0 ||
                used[idx]) {
                continue;
            }
            {
                const char *hint = rbs__suggest(e->valuestring, names, nused);
                size_t saved = v->path_len;
                push_key(v, "materials");
                push_index(v, r);
                push_key(v, "pair");
                push_index(v, j);
                rbs__scene_warning(s, loc_value(v, e), v->path,
                                   "material \"%s\" is on no body, so this row applies to no "
                                   "contact%s%s%s",
                                   e->valuestring, hint ? " (did you mean \"" : "",
                                   hint ? hint : "", hint ? "\"?)" : "");
                pop(v, saved);
            }
            used[idx] = 1; /* (once a material) */
        }
    }
    free(used);
    free(names);
}

/* ---- the "event" method's scope ------------------------------------------ */

/* The row the world takes for materials a and b (-1 = none; a material
 * code as rbs__rebuild_pair_table scores it: exact pair, then one "*", then
 * "*" with "*", the first of equals). */
static int32_t event_best_row(const rbs_scene *s, int32_t a, int32_t b)
{
    int32_t best = -1, best_score = -1;
    uint32_t p;
    for (p = 0; p < s->pair_count; p++) {
        const rbs__scene_pair *r = &s->pairs[p];
        int score = -1;
        int exact = (r->a == a && r->b == b) || (r->a == b && r->b == a);
        if (exact) {
            score = (r->a >= 0) + (r->b >= 0);
        } else if (r->a < 0 && (r->b == a || r->b == b)) {
            score = r->b >= 0;
        } else if (r->b < 0 && (r->a == a || r->a == b)) {
            score = r->a >= 0;
        } else if (r->a < 0 && r->b < 0) {
            score = 0;
        }
        if (score >= 0 && r->a >= 0 && r->b >= 0 && !exact) {
            score = -1;
        }
        if (score > best_score) {
            best_score = score;
            best = (int32_t)p;
        }
    }
    return best;
}

int rbs__event_rows(const rbs_scene *s, unsigned char *refused)
{
    /* step.c's rbs__row_in_use: the rows with rolling or spinning
     * resistance that the materials of a moving sphere and of any body
     * (itself included) take */
    uint32_t m = s->material_count + 1, i, a, b;
    unsigned char *moving, *any;
    int count = 0;
    for (i = 0; i < s->pair_count; i++) {
        refused[i] = 0;
        if (s->pairs[i].rolling > 0.0 || s->pairs[i].spinning > 0.0) {
            count = 1;
        }
    }
    if (count == 0) {
        return 0; /* (the common case: no row has it) */
    }
    moving = calloc(2 * (size_t)m, 1);
    if (moving == NULL) {
        return -1;
    }
    any = moving + m;
    for (i = 0; i < s->body_count; i++) {
        const rbs__scene_body *bd = &s->bodies[i];
        uint32_t mi = bd->material >= 0 ? (uint32_t)bd->material + 1 : 0;
        any[mi] = 1;
        if (bd->type == RBS_BODY_SPHERE && !bd->fixed) {
            moving[mi] = 1;
        }
    }
    count = 0;
    for (a = 0; a < m; a++) {
        for (b = 0; b < m && moving[a]; b++) {
            int32_t row;
            if (!any[b]) {
                continue;
            }
            row = event_best_row(s, (int32_t)a - 1, (int32_t)b - 1);
            if (row >= 0 && !refused[row] &&
                (s->pairs[row].rolling > 0.0 || s->pairs[row].spinning > 0.0)) {
                refused[row] = 1;
                count++;
            }
        }
    }
    free(moving);
    return count;
}

int rbs__event_sphere_refused(const rbs_scene *s, uint32_t i)
{
    /* step_event.c's check_scope on the world rbs_world_add_sphere makes:
     * a moving sphere with anisotropic inertia or an off-centre mass */
    const rbs__scene_body *b = &s->bodies[i];
    if (b->type != RBS_BODY_SPHERE || b->fixed) {
        return 0;
    }
    if (!vec_len_zero(b->center_of_mass)) {
        return 2;
    }
    return b->inertia_kind == RBS_INERTIA_PRINCIPAL &&
           !(b->inertia.x == b->inertia.y && b->inertia.y == b->inertia.z);
}

int rbs__scene_mutual_acts(const rbs_scene *s)
{
    uint32_t i, spheres = 0, moving = 0;
    for (i = 0; i < s->body_count; ++i) {
        if (s->bodies[i].type == RBS_BODY_SPHERE) {
            spheres++;
            moving += !s->bodies[i].fixed;
        }
    }
    return spheres >= 2 && moving >= 1;
}

/* The scene with method "event" must be within its scope, which the step
 * checks too (rbs__step_event): reported here at the keys that leave it. */
static void check_event_scope(vctx *v, const cJSON *tree, const cJSON **body_items,
                               int materials_ok)
{
    rbs_scene *s = v->scene;
    const cJSON *sim = member(tree, "simulation"), *c;
    size_t saved;
    uint32_t i;
    if (s->method != RBS_METHOD_EVENT) {
        return;
    }
    /* (mutual gravity that cannot act passes, as the step takes it: the
     * check refused it whatever the bodies until session 46) */
    if (s->mutual_gravity && rbs__scene_mutual_acts(s) && (c = member(sim, "mutual_gravity")) != NULL) {
        saved = push_key(v, "simulation");
        push_key(v, "mutual_gravity");
        err(v, loc_value(v, c),
            "method \"event\" does not support mutual gravity (not a constant force); use "
            "\"adaptive\"");
        pop(v, saved);
    }
    if (materials_ok && s->pair_count > 0) {
        const cJSON *mats = member(tree, "materials"), *row;
        unsigned char *refused = malloc(s->pair_count);
        int n = refused != NULL ? rbs__event_rows(s, refused) : -1;
        if (n < 0) {
            err(v, loc_value(v, mats), "out of memory");
        }
        for (row = mats->child, i = 0; n > 0 && row != NULL && i < s->pair_count;
             row = row->next, i++) {
            const rbs__scene_pair *p = &s->pairs[i];
            const char *key = p->rolling > 0.0 ? "rolling" : "spinning";
            if (!refused[i] || (c = member(row, key)) == NULL) {
                continue;
            }
            saved = push_key(v, "materials");
            push_index(v, i);
            push_key(v, key);
            err(v, loc_value(v, c),
                "method \"event\" does not support rolling and spinning resistance (pair "
                "\"%s\"/\"%s\", which bodies of this scene take); use \"euler\"",
                p->a >= 0 ? s->materials[p->a] : "*", p->b >= 0 ? s->materials[p->b] : "*");
            pop(v, saved);
        }
        free(refused);
    }
    for (i = 0; body_items != NULL && i < s->body_count; i++) {
        int why;
        if (!s->bodies[i].ok || (why = rbs__event_sphere_refused(s, i)) == 0) {
            continue;
        }
        c = member(body_items[i], why == 2 ? "center_of_mass" : "inertia");
        if (c == NULL) {
            continue;
        }
        saved = push_key(v, "bodies");
        push_index(v, i);
        push_key(v, why == 2 ? "center_of_mass" : "inertia");
        err(v, loc_value(v, c),
            "method \"event\" does not support a moving sphere with %s (\"%s\"); use \"euler\"",
            why == 2 ? "an off-centre mass" : "anisotropic inertia", s->bodies[i].name);
        pop(v, saved);
    }
}

/* A sphere in the overlap grid: its level (cells of 2^level m, at least its
 * diameter) and the cell holding its centre. */
typedef struct grid_rec {
    int32_t level;
    uint32_t index;
    int64_t cell[3];
} grid_rec;

static int cmp_grid_key(const grid_rec *a, int32_t level, const int64_t *cell)
{
    int k;
    if (a->level != level) {
        return a->level < level ? -1 : 1;
    }
    for (k = 0; k < 3; k++) {
        if (a->cell[k] != cell[k]) {
            return a->cell[k] < cell[k] ? -1 : 1;
        }
    }
    return 0;
}

static int cmp_grid(const void *pa, const void *pb)
{
    const grid_rec *a = pa, *b = pb;
    int c = cmp_grid_key(a, b->level, b->cell);
    return c != 0 ? c : (a->index < b->index ? -1 : a->index > b->index);
}

/* The cell of coordinate x in cells of size h: floor(x / h), clamped to
 * +-2^62 (monotone, so neighbouring cells stay neighbours). */
static int64_t grid_cell(double x, double h)
{
    double c = floor(x / h);
    if (!(c > -4.611686018427387904e18)) {
        return -((int64_t)1 << 62);
    }
    if (!(c < 4.611686018427387904e18)) {
        return (int64_t)1 << 62;
    }
    return (int64_t)c;
}

/* First record at or after (level, cell) in the sorted array. */
static size_t grid_lower(const grid_rec *rec, size_t n, int32_t level, const int64_t *cell)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cmp_grid_key(&rec[mid], level, cell) < 0) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

static void overlap_error(vctx *v, uint32_t i, const char *fmt_other, double depth,
                          uint32_t j)
{
    rbs_scene *s = v->scene;
    size_t saved = v->path_len;
    push_key(v, "bodies");
    push_index(v, i);
    push_key(v, s->bodies[i].type == RBS_BODY_SPHERE ? "position" : "point");
    err(v, s->bodies[i].at_position, "\"%s\" %s \"%s\" (bodies[%lu]) by %.6g m at the start",
        s->bodies[i].name, fmt_other, s->bodies[j].name, (unsigned long)j, depth);
    pop(v, saved);
}

/* A sphere's mass (given, or from its density). */
static double scene_mass(const rbs__scene_body *b)
{
    return b->density > 0 ? b->density * (4.0 / 3.0) * 3.14159265358979323846 * b->radius * b->radius *
                                b->radius
                          : b->mass;
}

/* A sphere's centre of mass in the world at the start. */
static rbs_vec3 scene_com(const rbs__scene_body *b)
{
    const rbs_quat q = b->orientation;
    const rbs_vec3 c = b->center_of_mass;
    /* t = 2 u x c; c' = c + w t + u x t (u = the quaternion's vector part) */
    double tx = 2.0 * (q.y * c.z - q.z * c.y), ty = 2.0 * (q.z * c.x - q.x * c.z),
           tz = 2.0 * (q.x * c.y - q.y * c.x);
    rbs_vec3 r;
    r.x = b->position.x + c.x + q.w * tx + (q.y * tz - q.z * ty);
    r.y = b->position.y + c.y + q.w * ty + (q.z * tx - q.x * tz);
    r.z = b->position.z + c.z + q.w * tz + (q.x * ty - q.y * tx);
    return r;
}

/* With mutual gravity: each pair's potential energy at the start at most
 * 1e300 J in size, the world's rule (rbs_world_add_sphere), checked here so
 * that the error names the key: at the later sphere's position, once a
 * sphere.  (G = 1e308 with 1 kg spheres 1 m apart passed `rbsim check` and
 * failed at the first frame.)  O(spheres^2), as a step of mutual gravity. */
static void check_mutual_potential(vctx *v)
{
    rbs_scene *s = v->scene;
    const double eps2 = s->softening * s->softening;
    uint32_t i, j;
    if (!s->mutual_gravity) {
        return;
    }
    for (j = 0; j < s->body_count; j++) {
        const rbs__scene_body *b = &s->bodies[j];
        rbs_vec3 xb;
        if (!b->ok || b->type != RBS_BODY_SPHERE) {
            continue;
        }
        xb = scene_com(b);
        for (i = 0; i < j; i++) {
            const rbs__scene_body *a = &s->bodies[i];
            rbs_vec3 xa;
            double dx, dy, dz, pot;
            if (!a->ok || a->type != RBS_BODY_SPHERE || (a->fixed && b->fixed)) {
                continue;
            }
            xa = scene_com(a);
            dx = xb.x - xa.x;
            dy = xb.y - xa.y;
            dz = xb.z - xa.z;
            pot = s->gravity_constant * scene_mass(a) * scene_mass(b) / sqrt(dx * dx + dy * dy + dz * dz + eps2);
            if (!(pot <= 1e300)) {
                size_t saved = v->path_len;
                push_key(v, "bodies");
                push_index(v, j);
                push_key(v, "position");
                err(v, b->at_position,
                    "the potential energy of mutual gravity of \"%s\" and \"%s\" (bodies[%lu]) at the "
                    "start is %g J, beyond 1e300 J (the world's energy would overflow; softening "
                    "bounds it)", b->name, a->name, (unsigned long)i, pot);
                pop(v, saved);
                break;
            }
        }
    }
}

/* Two spheres at the start: an error if they overlap beyond the slop
 * (fixed pairs may overlap). */
static void overlap_pair(vctx *v, uint32_t ia, uint32_t ib)
{
    rbs_scene *s = v->scene;
    const rbs__scene_body *a = &s->bodies[ia], *b = &s->bodies[ib];
    double dx = a->position.x - b->position.x, dy = a->position.y - b->position.y,
           dz = a->position.z - b->position.z;
    double dist = sqrt(dx * dx + dy * dy + dz * dz);
    double rmin = a->radius < b->radius ? a->radius : b->radius;
    if (a->fixed && b->fixed) {
        return;
    }
    if (dist < a->radius + b->radius - s->slop * rmin) {
        uint32_t first = ia < ib ? ia : ib, second = ia ^ ib ^ first;
        overlap_error(v, second, "overlaps", a->radius + b->radius - dist, first);
    }
}

/* Bodies may not overlap at the start (beyond the scene's slop).
 *
 * Spheres against planes: the planes are collected once, O(spheres x planes).
 * Spheres against spheres: a hierarchical grid, O(N log N).  A sphere of
 * radius r goes to level L, the least with 2^L >= 2r, in the cell of its
 * centre at that level.  Two overlapping spheres a, b with level(a) <=
 * level(b) = L are less than r_a + r_b <= 2^L apart, so b lies in one of the
 * 27 cells around a's cell at level L: each sphere looks only at its own
 * level and the larger ones (never at smaller spheres), 9 binary searches per
 * level.  Spheres that do not overlap fill a cell with a bounded number of
 * spheres of its level; only fixed spheres, which may overlap each other,
 * can crowd a cell. */
static void check_overlap(vctx *v)
{
    rbs_scene *s = v->scene;
    uint32_t i, j, n = 0, np = 0, nlev = 0;
    grid_rec *rec = malloc((s->body_count + 1) * sizeof *rec);
    uint32_t *planes = malloc((s->body_count + 1) * sizeof *planes);
    int32_t *levels = malloc((s->body_count + 1) * sizeof *levels);
    if (rec == NULL || planes == NULL || levels == NULL) {
        rbs__loc none = {0, 0, 0};
        free(rec);
        free(planes);
        free(levels);
        rbs__scene_error(s, none, "", "out of memory (checking overlaps)");
        return;
    }
    for (i = 0; i < s->body_count; i++) {
        const rbs__scene_body *b = &s->bodies[i];
        if (b->ok && b->type == RBS_BODY_PLANE) {
            planes[np++] = i;
        } else if (b->ok && b->type == RBS_BODY_SPHERE) {
            int e;
            double m = frexp(b->radius, &e), h; /* r = m 2^e, m in [0.5, 1) */
            rec[n].level = m == 0.5 ? e : e + 1;  /* 2^level >= 2r */
            rec[n].index = i;
            h = ldexp(1.0, rec[n].level);
            rec[n].cell[0] = grid_cell(b->position.x, h);
            rec[n].cell[1] = grid_cell(b->position.y, h);
            rec[n].cell[2] = grid_cell(b->position.z, h);
            n++;
        }
    }
    /* spheres against planes */
    for (i = 0; i < s->body_count && s->error_kept < RBS_SCENE_ERRORS_MAX; i++) {
        const rbs__scene_body *sp = &s->bodies[i];
        if (!sp->ok || sp->type != RBS_BODY_SPHERE || sp->fixed) {
            continue;
        }
        for (j = 0; j < np; j++) {
            const rbs__scene_body *pl = &s->bodies[planes[j]];
            double d = (sp->position.x - pl->point.x) * pl->normal.x +
                       (sp->position.y - pl->point.y) * pl->normal.y +
                       (sp->position.z - pl->point.z) * pl->normal.z;
            if (d < sp->radius - s->slop * sp->radius) {
                overlap_error(v, i, "starts behind (inside) plane", sp->radius - d,
                              planes[j]);
            }
        }
    }
    /* spheres against spheres: sort by (level, cell); list the levels */
    qsort(rec, n, sizeof *rec, cmp_grid);
    for (i = 0; i < n; i++) {
        if (nlev == 0 || levels[nlev - 1] != rec[i].level) {
            levels[nlev++] = rec[i].level;
        }
    }
    for (i = 0; i < n && s->error_kept < RBS_SCENE_ERRORS_MAX; i++) {
        const rbs__scene_body *a = &s->bodies[rec[i].index];
        uint32_t l;
        for (l = 0; l < nlev; l++) {
            int32_t level = levels[l];
            double h = ldexp(1.0, level);
            int64_t c[3];
            int dx, dy;
            if (level < rec[i].level) {
                continue; /* smaller spheres look at this one */
            }
            c[0] = grid_cell(a->position.x, h);
            c[1] = grid_cell(a->position.y, h);
            c[2] = grid_cell(a->position.z, h);
            for (dx = -1; dx <= 1; dx++) {
                for (dy = -1; dy <= 1; dy++) {
                    int64_t from[3], to[3];
                    size_t k;
                    from[0] = to[0] = c[0] + dx;
                    from[1] = to[1] = c[1] + dy;
                    from[2] = c[2] - 1;
                    to[2] = c[2] + 1;
                    /* cells (x, y, z-1 .. z+1) are adjacent in the sort order */
                    for (k = grid_lower(rec, n, level, from);
                         k < n && cmp_grid_key(&rec[k], level, to) <= 0; k++) {
                        if (level == rec[i].level && k <= i) {
                            continue; /* a pair of one level is seen from both */
                        }
                        overlap_pair(v, rec[i].index, rec[k].index);
                    }
                }
            }
        }
    }
    free(rec);
    free(planes);
    free(levels);
}

/* ---- renderers ---------------------------------------------------------- */

static const char *const renderer_common_keys[] = {"type", "path", "every"};
static const char *const sdl_keys[] = {"type",  "path", "every",         "width",
                                       "height", "window", "tile", "contact_sheet",
                                       "camera", "views"};
static const char *const camera_keys[] = {"mode", "position", "target", "up",    "fov",
                                          "near", "far",      "mount",  "offset", "path"};
static const char *const camera_modes[] = {"fixed", "mounted", "free"};
static const char *const path_keys[] = {"t", "position", "target"};

/* Camera limits that keep the SDL ray caster's squares finite and nonzero
 * (the same as frontends/sdl; see scenes/FORMAT.md). */
static const double kCamCoordMax = 1e100; /* m, |each coordinate| */
static const double kCamDistMin = 1e-100; /* m, eye to target, |offset| */
static const double kCamFovMin = 1e-6;    /* degrees */
static const double kSdlPixelsMax = 16.0 * 1024 * 1024; /* per view */

/* A camera position, target or offset: a 3-vector within +-kCamCoordMax m. */
static int get_cam_vec3(vctx *v, const cJSON *item, rbs_vec3 *out)
{
    if (get_vec3(v, item, out) != 0) {
        return -1;
    }
    if (!(fabs(out->x) <= kCamCoordMax && fabs(out->y) <= kCamCoordMax &&
          fabs(out->z) <= kCamCoordMax)) {
        char g[256];
        got_list(v, item, g, sizeof g);
        err(v, loc_value(v, item), "coordinates must be within +-1e100 m, got %s", g);
        return -1;
    }
    return 0;
}

static int find_sphere(const rbs_scene *s, const char *name)
{
    uint32_t i;
    for (i = 0; i < s->body_count; i++) {
        if (s->bodies[i].type == RBS_BODY_SPHERE && strcmp(s->bodies[i].name, name) == 0) {
            return (int)i;
        }
    }
    return -1;
}

/* The sine of the angle between the view direction and up below which the
 * sdl renderer refuses a camera (frontends/sdl/sdl_config.c: up_sine), so
 * that the error comes from the key here, not from the renderer's entry. */
static const double kCamUpSine = 1e-6;

/* Whether a camera at pos looking at target can take up: 0 yes, 1 target
 * is pos, 2 target within kCamDistMin of pos, 3 the view is along up (its
 * sine below kCamUpSine, or up zero). */
static int aim_kind(rbs_vec3 pos, rbs_vec3 target, rbs_vec3 up)
{
    rbs_vec3 d = {target.x - pos.x, target.y - pos.y, target.z - pos.z}, x;
    double ld = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    double um = fmax(fabs(up.x), fmax(fabs(up.y), fabs(up.z))), lu, lx;
    rbs_vec3 un;
    if (d.x == 0 && d.y == 0 && d.z == 0)
        return 1;
    if (!(ld >= kCamDistMin))
        return 2;
    if (!(um > 0))
        return 3;
    un.x = up.x / um;
    un.y = up.y / um;
    un.z = up.z / um;
    lu = sqrt(un.x * un.x + un.y * un.y + un.z * un.z);
    x.x = d.y * un.z - d.z * un.y;
    x.y = d.z * un.x - d.x * un.z;
    x.z = d.x * un.y - d.y * un.x;
    lx = sqrt(x.x * x.x + x.y * x.y + x.z * x.z);
    return lx > kCamUpSine * ld * lu ? 0 : 3;
}

/* Whether target - position, linear from d0 to d1 as s goes from 0 to 1 (a
 * path between two keyframes), comes within rounding of zero: the position
 * passes through the target.  *at: that s.  (The closest s is where the
 * derivative of |d0 + s (d1 - d0)|^2 vanishes; "within rounding" is 1e-12
 * of the longer end, far above the interpolation's rounding, so every frame
 * time that lands on the meeting is caught.)  The vectors are scaled by
 * their largest coordinate first: squares of 1e100 m overflow. */
static int path_meets_target(rbs_vec3 d0, rbs_vec3 d1, double *at)
{
    double m = fmax(fmax(fmax(fabs(d0.x), fabs(d0.y)), fmax(fabs(d0.z), fabs(d1.x))),
                    fmax(fabs(d1.y), fabs(d1.z)));
    rbs_vec3 a, e, c;
    double ee, s, lc, la, lb;
    if (!(m > 0) || !isfinite(m))
        return 0;
    a.x = d0.x / m; a.y = d0.y / m; a.z = d0.z / m;
    e.x = d1.x / m - a.x; e.y = d1.y / m - a.y; e.z = d1.z / m - a.z;
    ee = e.x * e.x + e.y * e.y + e.z * e.z;
    if (!(ee > 0))
        return 0;
    s = -(a.x * e.x + a.y * e.y + a.z * e.z) / ee;
    if (!(s > 0 && s < 1))
        return 0; /* (closest at a keyframe: checked there) */
    c.x = a.x + s * e.x; c.y = a.y + s * e.y; c.z = a.z + s * e.z;
    lc = sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
    la = sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    lb = sqrt((a.x + e.x) * (a.x + e.x) + (a.y + e.y) * (a.y + e.y) +
              (a.z + e.z) * (a.z + e.z));
    *at = s;
    return lc <= 1e-12 * fmax(la, lb);
}

static void check_camera(vctx *v, const cJSON *cam)
{
    const cJSON *c;
    size_t saved;
    rbs_vec3 pos = {3, -3, 2}, target = {0, 0, 0.5}, up = {0, 0, 1};
    int pos_ok = 1, target_ok = 1, up_ok = 1, mode = 0;
    double nearv = 0.05, farv = 100.0;
    int near_ok = 1;
    if (require_object(v, cam, "a camera") != 0) {
        return;
    }
    check_keys(v, cam, camera_keys, (int)(sizeof camera_keys / sizeof *camera_keys),
               "a camera");
    if (member(cam, "mount") != NULL) {
        mode = 1;
    }
    if ((c = member(cam, "mode")) != NULL) {
        saved = push_key(v, "mode");
        if (get_choice(v, c, camera_modes, 3, &mode) == 0) {
            if (mode == 1 && member(cam, "mount") == NULL) {
                err(v, loc_value(v, c), "mode \"mounted\" needs \"mount\" (a sphere's name)");
            }
            if (mode != 1 && member(cam, "mount") != NULL) {
                err(v, loc_value(v, c),
                    "\"mount\" is given, so the mode must be \"mounted\", got \"%s\"",
                    c->valuestring);
            }
            if (mode != 1 && member(cam, "offset") != NULL) {
                err(v, loc_value(v, c),
                    "\"offset\" is given, so the mode must be \"mounted\", got \"%s\"",
                    c->valuestring);
            }
        }
        pop(v, saved);
    } else if (member(cam, "offset") != NULL && member(cam, "mount") == NULL) {
        saved = push_key(v, "offset");
        err(v, loc_key(v, member(cam, "offset")),
            "\"offset\" needs \"mount\" (a sphere's name)");
        pop(v, saved);
    }
    if (mode == 1) {
        /* (passed here and was refused by the sdl renderer's own check, at
         * the renderer entry: "renderers[0] (sdl): views[0].position") */
        static const char *const unused[] = {"position", "target"};
        size_t i;
        for (i = 0; i < 2; i++) {
            if ((c = member(cam, unused[i])) != NULL) {
                saved = push_key(v, unused[i]);
                err(v, loc_key(v, c), "not used by a mounted camera (it looks at the body "
                    "from \"offset\")");
                pop(v, saved);
            }
        }
    }
    if ((c = member(cam, "position")) != NULL) {
        saved = push_key(v, "position");
        pos_ok = get_cam_vec3(v, c, &pos) == 0;
        pop(v, saved);
    }
    if ((c = member(cam, "target")) != NULL) {
        saved = push_key(v, "target");
        target_ok = get_cam_vec3(v, c, &target) == 0;
        pop(v, saved);
    }
    if ((c = member(cam, "up")) != NULL) {
        saved = push_key(v, "up");
        up_ok = get_vec3(v, c, &up) == 0;
        pop(v, saved);
    }
    if (pos_ok && target_ok && up_ok) {
        const rbs_vec3 d = {target.x - pos.x, target.y - pos.y, target.z - pos.z};
        const int kind = aim_kind(pos, target, up);
        if (kind == 2) {
            c = member(cam, "target") != NULL ? member(cam, "target") : cam;
            saved = push_key(v, "target");
            err(v, loc_value(v, c), "must be at least 1e-100 m from the position (too close "
                "to aim), got [%g, %g, %g] m apart", d.x, d.y, d.z);
            pop(v, saved);
        } else if (kind == 1) {
            c = member(cam, "target") != NULL ? member(cam, "target") : cam;
            saved = push_key(v, "target");
            err(v, loc_value(v, c), "must differ from the position, got [%g, %g, %g] for both",
                target.x, target.y, target.z);
            pop(v, saved);
        } else if (kind == 3) {
            char g[256];
            c = member(cam, "up") != NULL ? member(cam, "up") : cam;
            if (c != cam) {
                got_list(v, c, g, sizeof g);
            } else {
                snprintf(g, sizeof g, "[%.17g, %.17g, %.17g]", up.x, up.y, up.z);
            }
            saved = push_key(v, "up");
            err(v, loc_value(v, c),
                "must be nonzero and not parallel to the view direction (target - "
                "position = [%g, %g, %g]), got %s",
                d.x, d.y, d.z, g);
            pop(v, saved);
        }
    }
    if ((c = member(cam, "fov")) != NULL) {
        double f;
        saved = push_key(v, "fov");
        if (get_number(v, c, &f) == 0 && !(f >= kCamFovMin && f < 180)) {
            char g[64];
            got(v, c, g, sizeof g);
            err(v, loc_value(v, c), "must be in [1e-6, 180) degrees, got %s", g);
        }
        pop(v, saved);
    }
    if ((c = member(cam, "near")) != NULL) {
        saved = push_key(v, "near");
        near_ok = get_ranged(v, c, R_POS, &nearv) == 0;
        pop(v, saved);
    }
    if ((c = member(cam, "far")) != NULL) {
        saved = push_key(v, "far");
        if (get_number(v, c, &farv) == 0 && near_ok && !(farv > nearv)) {
            char g[64];
            got(v, c, g, sizeof g);
            err(v, loc_value(v, c), "must be > near (%g), got %s", nearv, g);
        }
        pop(v, saved);
    }
    if ((c = member(cam, "mount")) != NULL) {
        const char *nm;
        saved = push_key(v, "mount");
        if (get_string(v, c, &nm) == 0 && find_sphere(v->scene, nm) < 0) {
            const char **names = malloc((v->scene->body_count + 1) * sizeof *names);
            const char *hint = NULL;
            if (names != NULL) {
                uint32_t i, k = 0;
                for (i = 0; i < v->scene->body_count; i++) {
                    if (v->scene->bodies[i].type == RBS_BODY_SPHERE) {
                        names[k++] = v->scene->bodies[i].name;
                    }
                }
                hint = rbs__suggest(nm, names, k);
            }
            if (hint != NULL) {
                err(v, loc_value(v, c), "no sphere named \"%s\" (did you mean \"%s\"?)",
                    nm, hint);
            } else {
                err(v, loc_value(v, c), "no sphere named \"%s\" to mount the camera on",
                    nm);
            }
            free(names);
        }
        pop(v, saved);
    }
    if ((c = member(cam, "offset")) != NULL) {
        rbs_vec3 o;
        saved = push_key(v, "offset");
        if (get_cam_vec3(v, c, &o) == 0) {
            double lo = sqrt(o.x * o.x + o.y * o.y + o.z * o.z);
            if (o.x == 0 && o.y == 0 && o.z == 0) {
                err(v, loc_value(v, c), "must be nonzero (the camera would sit inside the body)");
            } else if (!(lo >= kCamDistMin)) {
                err(v, loc_value(v, c), "must be at least 1e-100 m long (too close to the body "
                    "to aim), got [%g, %g, %g]", o.x, o.y, o.z);
            }
        }
        pop(v, saved);
    }
    if ((c = member(cam, "path")) != NULL) {
        saved = push_key(v, "path");
        if (mode == 1) {
            err(v, loc_key(v, c), "a mounted camera follows its body; \"path\" is for "
                                  "fixed cameras");
        } else if (mode == 2) {
            err(v, loc_key(v, c), "a free camera is steered from the keyboard; \"path\" is for "
                                  "fixed cameras");
        } else if (member(cam, "position") != NULL || member(cam, "target") != NULL) {
            err(v, loc_key(v, c), "a camera with a path takes its position and target from "
                                  "the path: leave out \"%s\"",
                member(cam, "position") != NULL ? "position" : "target");
        } else if (require_array(v, c, "a list of {\"t\", \"position\", \"target\"} "
                                       "keyframes") == 0) {
            const cJSON *kf;
            size_t i = 0;
            double last_t = -INFINITY;
            /* the previous keyframe's target - position and time, when all
             * were read: the segment to this one must not pass through its
             * target (the sdl renderer stopped the run there, at the frame
             * where position met target: "closer than 1e-100 m") */
            rbs_vec3 prev_d = {0, 0, 0};
            double prev_t = 0.0, this_t = 0.0;
            int prev_ok = 0, t_ok;
            if (cJSON_GetArraySize(c) == 0) {
                err(v, loc_value(v, c), "must have at least one keyframe");
            } else if (cJSON_GetArraySize(c) > RBS__SCENE_CAMERA_KEYS_MAX) {
                /* (the sdl renderer's limit: the scene passed and the renderer
                 * refused it, at the entry's column) */
                err(v, loc_value(v, c), "at most %d keyframes, got %d",
                    RBS__SCENE_CAMERA_KEYS_MAX, cJSON_GetArraySize(c));
            }
            for (kf = c->child; kf != NULL; kf = kf->next, i++) {
                size_t s2 = push_index(v, i), s3;
                const cJSON *e;
                int seg_ok = prev_ok; /* (cleared unless this keyframe is whole) */
                t_ok = 0;
                prev_ok = 0;
                if (require_object(v, kf, "a camera keyframe") == 0) {
                    check_keys(v, kf, path_keys, 3, "a camera keyframe");
                    if ((e = member(kf, "t")) != NULL) {
                        double t;
                        s3 = push_key(v, "t");
                        if (get_ranged(v, e, R_NONNEG, &t) == 0) {
                            t_ok = t > last_t;
                            this_t = t;
                            if (!(t > last_t)) {
                                char g[64];
                                got(v, e, g, sizeof g);
                                err(v, loc_value(v, e),
                                    "times must increase, got %s after %g", g, last_t);
                            }
                            last_t = t;
                        }
                        pop(v, s3);
                    } else {
                        missing(v, kf, "t", "the keyframe's time, s");
                    }
                    {
                        rbs_vec3 kpos = {0, 0, 0}, ktarget = {0, 0, 0};
                        int kpos_ok = 0, ktarget_ok = 0, kind;
                        if ((e = member(kf, "position")) != NULL) {
                            s3 = push_key(v, "position");
                            kpos_ok = get_cam_vec3(v, e, &kpos) == 0;
                            pop(v, s3);
                        } else {
                            missing(v, kf, "position", "the camera position, m");
                        }
                        if ((e = member(kf, "target")) != NULL) {
                            s3 = push_key(v, "target");
                            ktarget_ok = get_cam_vec3(v, e, &ktarget) == 0;
                            if (kpos_ok && ktarget_ok && up_ok &&
                                (kind = aim_kind(kpos, ktarget, up)) != 0) {
                                char g[256];
                                got_list(v, e, g, sizeof g);
                                if (kind == 1)
                                    err(v, loc_value(v, e), "must differ from the keyframe's position, "
                                        "got %s for both", g);
                                else if (kind == 2)
                                    err(v, loc_value(v, e), "must be at least 1e-100 m from the "
                                        "keyframe's position (too close to aim), got %s", g);
                                else
                                    err(v, loc_value(v, e), "the view from the keyframe's position "
                                        "to %s is along the camera's up; choose another target, "
                                        "position or up", g);
                            }
                            if (kpos_ok && ktarget_ok && t_ok) {
                                const rbs_vec3 d = {ktarget.x - kpos.x, ktarget.y - kpos.y,
                                                    ktarget.z - kpos.z};
                                double at;
                                if (seg_ok && path_meets_target(prev_d, d, &at))
                                    err(v, loc_value(v, e),
                                        "between keyframes %lu and %lu the position passes "
                                        "through the target (at t = %.9g s, where the camera "
                                        "would have no view); add a keyframe that goes around it",
                                        (unsigned long)(i - 1), (unsigned long)i,
                                        prev_t + at * (this_t - prev_t));
                                prev_d = d;
                                prev_t = this_t;
                                prev_ok = 1;
                            }
                            pop(v, s3);
                        } else {
                            missing(v, kf, "target", "the point looked at, m");
                        }
                    }
                }
                pop(v, s2);
            }
        }
        pop(v, saved);
    }
}

/* Each finite number of the tree made a raw item in its shortest form that
 * reads back as the same double (cJSON prints %.15g when that reads back
 * within a relative DBL_EPSILON, which made a camera's fov of
 * 179.99999999999997 the 180 its check refuses).  0 when out of memory. */
static int numbers_exact(cJSON *item)
{
    for (; item != NULL; item = item->next) {
        if (cJSON_IsNumber(item) && isfinite(item->valuedouble)) {
            char b[40];
            double x = item->valuedouble;
            char *raw;
            if (x == 0.0 && signbit(x)) {
                /* (not "-0", which JSON readers that keep integers take for
                 * the integer 0: Python's json) */
                snprintf(b, sizeof b, "-0.0");
            } else if (x == floor(x) && fabs(x) < 1e17) {
                /* a whole number as one (3000000000, not 3e+09) */
                snprintf(b, sizeof b, "%.0f", x);
            } else {
                (void)rbs__shortest(b, x);
            }
            /* (cJSON's allocator: cJSON_Delete frees it) */
            raw = (char *)cJSON_malloc(strlen(b) + 1);
            if (raw == NULL)
                return 0;
            memcpy(raw, b, strlen(b) + 1);
            item->type = cJSON_Raw;
            item->valuestring = raw;
        } else if (item->child != NULL && !numbers_exact(item->child)) {
            return 0;
        }
    }
    return 1;
}

/* The renderer entry r as compact JSON text, its numbers exact (cJSON_free
 * it); NULL when out of memory. */
static char *print_exact(const cJSON *r)
{
    cJSON *copy = cJSON_Duplicate(r, 1);
    char *text = NULL;
    if (copy != NULL && numbers_exact(copy->child))
        text = cJSON_PrintUnformatted(copy);
    cJSON_Delete(copy);
    return text;
}

/* Whether a number item is held exactly: a literal of digits alone
 * ("9007199254740993") must be the integer its double is (as for steps);
 * one with a fraction or an exponent is read as a double is. */
static int number_exact(const vctx *v, const cJSON *item)
{
    const rbs__pos *pos = rbs__posmap_get(v->map, item);
    double x = fabs(item->valuedouble);
    const char *t;
    size_t k, n;
    if (pos == NULL || pos->file < 0 || pos->file >= v->src_count || pos->raw_len == 0 ||
        (size_t)pos->raw_off + pos->raw_len > v->srcs[pos->file].len ||
        !(x >= 9007199254740992.0)) {
        return 1;
    }
    t = v->srcs[pos->file].text + pos->raw_off;
    n = pos->raw_len;
    for (k = t[0] == '-'; k < n; k++) {
        if (t[k] < '0' || t[k] > '9') {
            return 1;
        }
    }
    return x < 18446744073709551616.0 && literal_is(t, n, (uint64_t)x);
}

/* A key given twice in an object of item, at any depth (the entries of
 * renderer types the library does not know, whose keys it does not check;
 * the JSON and text readers keep both), and an integer a double would
 * round (number_exact). */
static void check_duplicates(vctx *v, const cJSON *item)
{
    const cJSON *a, *b;
    size_t i = 0;
    for (a = item->child; a != NULL; a = a->next, i++) {
        size_t saved;
        if (cJSON_IsObject(item)) {
            for (b = item->child; b != a; b = b->next) {
                if (strcmp(a->string, b->string) == 0) {
                    rbs__loc first = loc_key(v, b);
                    saved = push_key(v, a->string);
                    err(v, loc_key(v, a), "duplicate key (first given at line %ld, column %ld)",
                        (long)first.line, (long)first.column);
                    pop(v, saved);
                    break;
                }
            }
        }
        if (a->child != NULL) {
            saved = cJSON_IsObject(item) ? push_key(v, a->string) : push_index(v, i);
            check_duplicates(v, a);
            pop(v, saved);
        } else if (cJSON_IsNumber(a) && !number_exact(v, a)) {
            char g[64], d[40];
            saved = cJSON_IsObject(item) ? push_key(v, a->string) : push_index(v, i);
            got(v, a, g, sizeof g);
            snprintf(d, sizeof d, "%.0f", a->valuedouble);
            err(v, loc_value(v, a),
                "the integer %s is beyond 2^53, which a double cannot hold exactly (it "
                "would be read as %s); give it as a string",
                g, d);
            pop(v, saved);
        }
    }
}

static void check_renderer(vctx *v, const cJSON *r, size_t index)
{
    rbs_scene *s = v->scene;
    const cJSON *c, *type_item;
    const char *type = NULL;
    size_t saved;
    int ok;
    uint32_t before = s->error_count;
    if (require_object(v, r, "a renderer entry") != 0) {
        return;
    }
    type_item = member(r, "type");
    if (type_item == NULL) {
        missing(v, r, "type", "the renderer type, e.g. \"csv\", \"json\" or \"sdl\"");
    } else {
        /* (a name: the text format's first word, and echoed by front ends
         * in their messages, so no blanks, controls or invisible characters) */
        saved = push_key(v, "type");
        if (get_string(v, type_item, &type) == 0 && type[0] == '\0') {
            err(v, loc_value(v, type_item), "must not be empty");
            type = NULL;
        } else if (type != NULL && get_name(v, type_item, &type) != 0) {
            type = NULL;
        }
        pop(v, saved);
    }
    if (type != NULL && (strcmp(type, "csv") == 0 || strcmp(type, "json") == 0 ||
                         strcmp(type, "stats") == 0)) {
        check_keys(v, r, renderer_common_keys, 3, type);
    } else if (type != NULL && strcmp(type, "sdl") == 0) {
        check_keys(v, r, sdl_keys, (int)(sizeof sdl_keys / sizeof *sdl_keys), "sdl");
    } else {
        /* other types validate their own keys; duplicates are still wrong,
         * at any depth */
        check_duplicates(v, r);
    }
    if ((c = member(r, "path")) != NULL) {
        const char *p;
        saved = push_key(v, "path");
        if (get_string(v, c, &p) == 0 && p[0] == '\0') {
            err(v, loc_value(v, c), "must not be empty");
        }
        pop(v, saved);
    }
    if ((c = member(r, "every")) != NULL) {
        uint64_t k;
        saved = push_key(v, "every");
        (void)get_integer(v, c, 1, (double)RBS_EVERY_MAX,
                          "an integer from 1 to 2147483647 (2^31 - 1)", &k);
        pop(v, saved);
    }
    if (type != NULL && strcmp(type, "sdl") == 0) {
        const char *const dims[] = {"width", "height"};
        double side[2] = {640, 480};
        int d;
        const cJSON *cam = member(r, "camera"), *views = member(r, "views");
        for (d = 0; d < 2; d++) {
            if ((c = member(r, dims[d])) != NULL) {
                uint64_t k;
                saved = push_key(v, dims[d]);
                if (get_integer(v, c, 16, 8192, "an integer in 16..8192 (pixels)", &k) == 0) {
                    side[d] = (double)k;
                }
                pop(v, saved);
            }
        }
        if (side[0] * side[1] > kSdlPixelsMax) {
            const char *key = member(r, "height") != NULL ? "height" : "width";
            c = member(r, key);
            saved = push_key(v, key);
            err(v, loc_value(v, c),
                "%g x %g pixels is too large (at most 16 Mpixel = 16777216 per view)",
                side[0], side[1]);
            pop(v, saved);
        }
        if ((c = member(r, "window")) != NULL) {
            saved = push_key(v, "window");
            if (!cJSON_IsBool(c) && !(cJSON_IsString(c) && strcmp(c->valuestring, "auto") == 0)) {
                char g[64];
                got(v, c, g, sizeof g);
                err(v, loc_value(v, c), "must be \"auto\", true or false, got %s", g);
            }
            pop(v, saved);
        }
        if ((c = member(r, "tile")) != NULL) {
            int32_t b;
            saved = push_key(v, "tile");
            (void)get_bool(v, c, &b);
            pop(v, saved);
        }
        if ((c = member(r, "contact_sheet")) != NULL) {
            int32_t b;
            saved = push_key(v, "contact_sheet");
            (void)get_bool(v, c, &b);
            pop(v, saved);
        }
        if (cam != NULL && views != NULL) {
            saved = push_key(v, "views");
            err(v, loc_key(v, views), "give either \"camera\" or \"views\", not both");
            pop(v, saved);
        }
        if (cam != NULL) {
            saved = push_key(v, "camera");
            check_camera(v, cam);
            pop(v, saved);
        }
        if (views != NULL) {
            saved = push_key(v, "views");
            if (require_array(v, views, "a list of 1 to 4 cameras") == 0) {
                int count = cJSON_GetArraySize(views);
                const cJSON *e;
                size_t i = 0;
                if (count < 1 || count > 4) {
                    err(v, loc_value(v, views), "must have 1 to 4 cameras, got %d", count);
                }
                for (e = views->child; e != NULL; e = e->next, i++) {
                    size_t s2 = push_index(v, i);
                    check_camera(v, e);
                    pop(v, s2);
                }
            }
            pop(v, saved);
        }
    }
    ok = s->error_count == before && type != NULL;
    if (index >= RBS_RENDERERS_MAX) {
        err(v, loc_value(v, r), "at most %d renderers may be attached, this is number %lu",
            RBS_RENDERERS_MAX, (unsigned long)index + 1);
        ok = 0;
    }
    if (ok) {
        char *text = print_exact(r);
        rbs__scene_renderer *out = &s->renderers[s->renderer_count];
        if (text == NULL) {
            err(v, loc_value(v, r), "out of memory");
            return;
        }
        out->json = rbs__strdup(text);
        cJSON_free(text);
        out->type = rbs__strdup(type);
        out->at = loc_value(v, r);
        if (out->json == NULL || out->type == NULL) {
            free(out->json);
            free(out->type);
            out->json = out->type = NULL;
            err(v, loc_value(v, r), "out of memory");
            return;
        }
        s->renderer_count++;
    }
}

/* The next component of path p ('.' components and repeated '/' skipped);
 * its length in *n, NULL at the end. */
static const char *path_part(const char *p, size_t *n)
{
    for (;;) {
        while (*p == '/') {
            p++;
        }
        *n = strcspn(p, "/");
        if (*n == 0) {
            return NULL;
        }
        if (!(*n == 1 && p[0] == '.')) {
            return p;
        }
        p += 1;
    }
}

/* Two renderer paths that name one file as written: equal once '.'
 * components and repeated or trailing '/' are dropped ("a.csv" and
 * "./a.csv", "out//a.csv" and "out/a.csv"), absolute or both relative.
 * ("..", links and other names of one file are for the front ends to find,
 * which know the file system.) */
static int same_path(const char *a, const char *b)
{
    size_t na, nb;
    if ((a[0] == '/') != (b[0] == '/')) {
        return 0;
    }
    for (;;) {
        a = path_part(a, &na);
        b = path_part(b, &nb);
        if (a == NULL || b == NULL) {
            return a == b;
        }
        if (na != nb || memcmp(a, b, na) != 0) {
            return 0;
        }
        a += na;
        b += nb;
    }
}

/* ---- the whole scene ---------------------------------------------------- */

static const char *const top_keys[] = {"description", "format",    "simulation",
                                       "materials",   "bodies",    "renderers"};

void rbs__scene_validate(rbs_scene *scene, const cJSON *tree, const rbs__posmap *map,
                         const rbs__src *srcs, int32_t src_count)
{
    vctx v;
    const cJSON *c;
    const cJSON **body_items = NULL;
    size_t saved;
    int materials_ok = 1;
    memset(&v, 0, sizeof v);
    v.scene = scene;
    v.map = map;
    v.srcs = srcs;
    v.src_count = src_count;
    if (!cJSON_IsObject(tree)) {
        char g[64];
        got(&v, tree, g, sizeof g);
        err(&v, loc_value(&v, tree), "a scene must be a JSON object, got %s", g);
        return;
    }
    check_keys(&v, tree, top_keys, (int)(sizeof top_keys / sizeof *top_keys), "a scene");
    if ((c = member(tree, "format")) != NULL) {
        uint64_t f;
        saved = push_key(&v, "format");
        if (get_integer(&v, c, 1, 1, "1 (this library reads format version 1)", &f) != 0) {
            pop(&v, saved);
            return; /* another version: the rest would only mislead */
        }
        pop(&v, saved);
    }
    if ((c = member(tree, "description")) != NULL) {
        const char *d;
        saved = push_key(&v, "description");
        if (get_string(&v, c, &d) == 0) {
            scene->description = rbs__strdup(d);
            if (scene->description == NULL) {
                err(&v, loc_value(&v, c), "out of memory");
            }
        }
        pop(&v, saved);
    }
    if ((c = member(tree, "simulation")) != NULL) {
        saved = push_key(&v, "simulation");
        check_simulation(&v, c);
        pop(&v, saved);
    } else {
        missing(&v, tree, "simulation", "an object with at least \"steps\"");
    }
    if ((c = member(tree, "materials")) != NULL) {
        uint32_t before = scene->error_count;
        saved = push_key(&v, "materials");
        check_materials(&v, c);
        pop(&v, saved);
        materials_ok = scene->error_count == before;
    }
    if ((c = member(tree, "bodies")) != NULL) {
        saved = push_key(&v, "bodies");
        check_bodies(&v, c, &body_items);
        pop(&v, saved);
    } else {
        missing(&v, tree, "bodies", "a list of spheres and planes");
    }
    if ((c = member(tree, "renderers")) != NULL) {
        saved = push_key(&v, "renderers");
        if (require_array(&v, c, "a list of renderer entries") == 0) {
            const cJSON *r;
            size_t i = 0;
            for (r = c->child; r != NULL; r = r->next, i++) {
                size_t s2 = push_index(&v, i);
                const cJSON *q, *p = cJSON_IsObject(r) ? member(r, "path") : NULL;
                size_t j = 0;
                check_renderer(&v, r, i);
                /* two renderers may not write one file (the front ends refuse it) */
                for (q = c->child; q != r && cJSON_IsString(p); q = q->next, j++) {
                    const cJSON *qp = cJSON_IsObject(q) ? member(q, "path") : NULL;
                    if (cJSON_IsString(qp) && p->valuestring[0] != '\0' &&
                        same_path(qp->valuestring, p->valuestring)) {
                        size_t s3 = push_key(&v, "path");
                        if (strcmp(qp->valuestring, p->valuestring) == 0) {
                            err(&v, loc_value(&v, p),
                                "renderers[%lu] already writes \"%s\"; give each renderer "
                                "its own path",
                                (unsigned long)j, p->valuestring);
                        } else {
                            err(&v, loc_value(&v, p),
                                "renderers[%lu] already writes \"%s\", the file \"%s\" "
                                "names; give each renderer its own path",
                                (unsigned long)j, qp->valuestring, p->valuestring);
                        }
                        pop(&v, s3);
                        break;
                    }
                }
                pop(&v, s2);
            }
        }
        pop(&v, saved);
    }
    /* cross-checks use the bodies whose own values were valid; missing pairs
     * are only judged when every material row was valid */
    check_overlap(&v);
    check_mutual_potential(&v);
    if (materials_ok) {
        check_pairs(&v);
    }
    if ((c = member(tree, "materials")) != NULL && member(tree, "bodies") != NULL) {
        warn_unused_materials(&v, c);
    }
    check_event_scope(&v, tree, body_items, materials_ok);
    free(body_items);
}
