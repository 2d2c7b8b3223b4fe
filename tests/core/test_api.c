/*
 * test_api.c - the public API's contract: versions, status text, defs that
 * grow, ids, validation with messages, capacity errors that leave the world
 * unchanged, caller-owned memory.
 */
#include <stdlib.h>
#include <string.h>

#include "common.h"
#include "rbsim/scene.h"

#include <unistd.h>

static void version_matches_header(void **state)
{
    char buf[32];
    (void)state;
    snprintf(buf, sizeof buf, "%d.%d.%d", RBS_VERSION_MAJOR, RBS_VERSION_MINOR, RBS_VERSION_PATCH);
    assert_string_equal(rbs_version(), buf);
    assert_int_equal(rbs_version_number(), RBS_VERSION_NUMBER);
}

static void status_strings(void **state)
{
    (void)state;
    assert_string_equal(rbs_status_name(RBS_E_CAPACITY), "E_CAPACITY");
    assert_string_equal(rbs_status_string(RBS_OK), "success");
    assert_string_equal(rbs_status_name((rbs_status)-999), "UNKNOWN");
    assert_non_null(rbs_status_string((rbs_status)12345));
}

static void method_names_round_trip(void **state)
{
    int i;
    rbs_method m;
    (void)state;
    for (i = 0; i < RBS_METHOD_COUNT; ++i) {
        CHECK_OK(rbs_method_from_name(rbs_method_name((rbs_method)i), &m));
        assert_int_equal(m, i);
    }
    assert_int_equal(rbs_method_from_name("eulerx", &m), RBS_E_NOT_FOUND);
    assert_null(rbs_method_name(RBS_METHOD_COUNT));
}

/* A caller compiled against an older, shorter def: the library fills the
 * fields it did not know with defaults. */
typedef struct old_world_def {
    uint32_t struct_size;
    uint32_t max_bodies;
} old_world_def;

static void old_shorter_defs_get_defaults(void **state)
{
    old_world_def old;
    rbs_world *w;
    rbs_world_def got;
    (void)state;
    rbs_world_def_init_sized((rbs_world_def *)(void *)&old, sizeof old);
    assert_int_equal(old.struct_size, sizeof old);
    assert_int_equal(old.max_bodies, 64);
    old.max_bodies = 3;
    CHECK_OK(rbs_world_create((const rbs_world_def *)(const void *)&old, &w));
    rbs_world_def_init(&got);
    CHECK_OK(rbs_world_get_def(w, &got));
    assert_int_equal(got.max_bodies, 3);
    assert_true(got.dt == 0.001);
    assert_true(got.gravity.z == -9.81);
    rbs_world_destroy(w);
}

/* A struct_size that ends inside a field (no header version has it: every
 * sizeof is a multiple of the alignment of doubles and pointers) is
 * refused, never read half from the caller and half from the defaults. */
static void struct_size_inside_a_field_is_rejected(void **state)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_sphere_def s;
    (void)state;
    rbs_world_def_init(&d);
    d.dt = 0.5;
    d.struct_size = 28; /* inside dt */
    assert_int_equal(rbs_world_create(&d, &w), RBS_E_INVALID);
    assert_null(w);
    w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_sphere_def_init(&s);
    s.name = "n";
    s.struct_size = 12; /* inside the name pointer */
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    {
        rbs_body_id id;
        assert_int_equal(rbs_world_body_at(w, 0, &id), RBS_E_NOT_FOUND); /* nothing added */
    }
    rbs_world_destroy(w);
}

/* rbs_world_set_dt changes the steps after it, not the time before: a
 * ball at 1 m/s without gravity, 100 steps of 1 ms then 10 of 10 ms, is at
 * x = 0.2 m at t = 0.2 s (before, the time was recomputed as 110 * 10 ms);
 * a checkpoint keeps the time. */
static void set_dt_keeps_the_elapsed_time(void **state)
{
    rbs_world *w = make_world(4, 1e-3, 0.0, 0.5), *r = NULL;
    rbs_body_id b = ball(w, 0.1, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, (rbs_material_id){0, 0});
    size_t n;
    unsigned char *buf;
    (void)state;
    step_n(w, 100);
    assert_true(fabs(rbs_world_time(w) - 0.1) < 1e-15);
    CHECK_OK(rbs_world_set_dt(w, 0.01));
    assert_true(fabs(rbs_world_time(w) - 0.1) < 1e-15);
    step_n(w, 10);
    assert_true(fabs(rbs_world_time(w) - 0.2) < 1e-15);
    assert_true(fabs(state_of(w, b).position.x - rbs_world_time(w)) < 1e-14);
    CHECK_OK(rbs_world_set_dt(w, 0.01)); /* the same dt: nothing moves */
    assert_true(fabs(rbs_world_time(w) - 0.2) < 1e-15);
    n = rbs_world_checkpoint_size(w);
    buf = malloc(n);
    assert_non_null(buf);
    CHECK_OK(rbs_world_checkpoint_write(w, buf, n, NULL));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &r));
    assert_true(rbs_world_time(r) == rbs_world_time(w));
    free(buf);
    rbs_world_destroy(r);
    rbs_world_destroy(w);
    /* a huge time (steps of a huge dt) is still a checkpoint's time (the
     * fuzzer found it refused as corrupt); a step whose time would
     * overflow is refused (it went on to inf with status OK: a probe of
     * session 40), leaving the world as it was */
    w = make_world(4, 1e-3, 0.0, 0.5);
    (void)ball(w, 0.1, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, (rbs_material_id){0, 0});
    step_n(w, 1);
    CHECK_OK(rbs_world_set_dt(w, 1e308));
    step_n(w, 1);
    assert_int_equal(rbs_world_step(w, NULL), RBS_E_NUMERIC);
    assert_non_null(strstr(rbs_world_last_error(w), "step 3: the time after it would be beyond the largest double"));
    CHECK_OK(rbs_world_set_dt(w, 1.0));
    assert_true(rbs_world_time(w) == 1e-3 + 1e308 && rbs_world_step_count(w) == 2);
    n = rbs_world_checkpoint_size(w);
    buf = malloc(n);
    assert_non_null(buf);
    CHECK_OK(rbs_world_checkpoint_write(w, buf, n, NULL));
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &r));
    assert_true(rbs_world_time(r) == rbs_world_time(w));
    free(buf);
    rbs_world_destroy(r);
    rbs_world_destroy(w);
}

/* Values a double cannot carry are named for what they are; a NULL def
 * sets the error text too; a colour is 0xRRGGBB, not masked; a finite
 * quaternion or normal whose norm overflows is still a direction. */
static void messages_name_the_real_cause(void **state)
{
    rbs_world *w = make_world(8, 1e-3, -9.81, 0.5);
    rbs_sphere_def s;
    rbs_plane_def p;
    rbs_body_id id;
    (void)state;
    rbs_sphere_def_init(&s);
    s.radius = 1e-300;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "underflow or overflow"));
    assert_int_equal(rbs_world_add_sphere(w, NULL, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "def is NULL"));
    assert_int_equal(rbs_world_set_pair(w, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "def is NULL"));
    rbs_sphere_def_init(&s);
    s.color = 0x1000000u;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "0xRRGGBB"));
    rbs_sphere_def_init(&s);
    s.orientation.w = 1e300;
    s.orientation.x = 1e300; /* norm overflows; a 90-degree turn about x */
    s.orientation.y = s.orientation.z = 0.0;
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    assert_true(fabs(state_of(w, id).orientation.w - sqrt(0.5)) < 1e-15);
    assert_true(fabs(state_of(w, id).orientation.x - sqrt(0.5)) < 1e-15);
    rbs_plane_def_init(&p);
    p.normal.x = 1e300;
    p.normal.y = 1e300;
    p.normal.z = 0.0;
    CHECK_OK(rbs_world_add_plane(w, &p, &id));
    assert_true(fabs(state_of(w, id).normal.x - sqrt(0.5)) < 1e-15);
    rbs_world_destroy(w);
}

/* A value out of range is echoed exactly, in its shortest form, never
 * rounded by %g (restitution 1.0000001 was 'got 1'). */
static void bad_values_are_echoed_exactly(void **state)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_sphere_def s;
    rbs_pair_def p;
    rbs_body_id id;
    char msg[256];
    (void)state;
    rbs_world_def_init(&d);
    d.restitution = 1.0000001;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "got 1.0000001"));
    rbs_world_def_init(&d);
    d.slop = 0.1000000000000001;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "got 0.1000000000000001"));
    rbs_world_def_init(&d);
    d.max_pairs = 2;
    CHECK_OK(rbs_world_create(&d, &w));
    assert_int_equal(rbs_world_set_dt(w, -1e-7), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "got -1e-07"));
    rbs_sphere_def_init(&s);
    s.radius = -0.30000000000000004;
    assert_int_equal(rbs_world_add_sphere(w, &s, &id), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "got -0.30000000000000004"));
    rbs_pair_def_init(&p);
    p.static_friction = 0.5;
    p.kinetic_friction = 0.50000000000000011;
    assert_int_equal(rbs_world_set_pair(w, &p), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "kinetic friction 0.5000000000000001 exceeds static 0.5"));
    rbs_world_destroy(w);
}

static void uninitialised_def_is_rejected(void **state)
{
    rbs_world_def d;
    rbs_world *w = (rbs_world *)&d;
    char msg[256];
    (void)state;
    memset(&d, 0, sizeof d);
    assert_int_equal(rbs_world_create(&d, &w), RBS_E_INVALID);
    assert_null(w);
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "rbs_world_def_init"));
    rbs_world_def_init(&d);
    d.dt = -1.0;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "dt"));
    d.dt = NAN;
    assert_int_equal(rbs_world_create(&d, &w), RBS_E_INVALID);
    assert_int_equal(rbs_world_memory_size(&d), 0);
    assert_int_equal(rbs_world_create(NULL, &w), RBS_E_INVALID);
}

static void create_in_caller_memory(void **state)
{
    rbs_world_def d;
    rbs_world *w;
    size_t need;
    void *mem;
    (void)state;
    rbs_world_def_init(&d);
    d.max_bodies = 10;
    need = rbs_world_memory_size(&d);
    assert_true(need > 0);
    assert_int_equal(posix_memalign(&mem, 16, need), 0);
    assert_int_equal(rbs_world_create_in(mem, need - 1, &d, &w), RBS_E_MEMORY);
    CHECK_OK(rbs_world_create_in(mem, need, &d, &w));
    ball(w, 0.1, 1, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    step_n(w, 10);
    {
        /* _zeroed into zero bytes (not written over): the same world, bit
         * for bit; and its checks are create_in's */
        const uint64_t h = rbs_world_hash(w);
        void *zero = calloc(1, need + 16);
        void *at = (void *)((char *)zero + (16u - (uintptr_t)zero % 16u) % 16u);
        rbs_world *z;
        assert_non_null(zero);
        assert_int_equal(rbs_world_create_in_zeroed(at, need - 1, &d, &z), RBS_E_MEMORY);
        assert_int_equal(rbs_world_create_in_zeroed((char *)at + 8, need, &d, &z), RBS_E_INVALID);
        CHECK_OK(rbs_world_create_in_zeroed(at, need, &d, &z));
        ball(z, 0.1, 1, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
        step_n(z, 10);
        assert_true(rbs_world_hash(z) == h);
        rbs_world_destroy(z);
        free(zero);
    }
    rbs_world_destroy(w);
    free(mem);
    /* memory grows with capacity */
    d.max_bodies = 1000;
    assert_true(rbs_world_memory_size(&d) > need);
}

/* Everything a world can report, captured to compare before and after. */
typedef struct snapshot {
    uint64_t hash;
    rbs_usage usage;
} snapshot;

static snapshot snap(const rbs_world *w)
{
    snapshot s;
    s.hash = rbs_world_hash(w);
    CHECK_OK(rbs_world_usage(w, &s.usage));
    return s;
}

/* A scene of one sphere named name (JSON-escaped into it), with material
 * mat, whose pair row names mat: what rbs_scene_parse_json says of it. */
static rbs_status scene_with_names(const char *name, const char *mat, rbs_scene **out)
{
    char text[1024], esc[2][256];
    const char *src[2];
    size_t i, k;
    int j;
    src[0] = name;
    src[1] = mat;
    for (j = 0; j < 2; j++) {
        for (i = k = 0; src[j][i] != '\0' && k + 8 < sizeof esc[j]; i++) {
            unsigned char c = (unsigned char)src[j][i];
            if (c == '"' || c == '\\')
                k += (size_t)snprintf(esc[j] + k, sizeof esc[j] - k, "\\%c", c);
            else if (c < 0x20)
                k += (size_t)snprintf(esc[j] + k, sizeof esc[j] - k, "\\u%04x", c);
            else
                esc[j][k++] = (char)c;
        }
        esc[j][k] = '\0';
    }
    snprintf(text, sizeof text,
             "{\"simulation\": {\"steps\": 1}, \"materials\": [{\"pair\": [\"%s\", \"*\"],"
             " \"static\": 1, \"kinetic\": 0.5}], \"bodies\": [{\"name\": \"%s\", \"type\": "
             "\"sphere\", \"radius\": 1, \"mass\": 1, \"position\": [0, 0, 0], \"material\": "
             "\"%s\"}]}",
             esc[1], esc[0], esc[1]);
    return rbs_scene_parse_json(text, strlen(text), "names.json", out);
}

/* One rule for names (core/name.h): the API refuses, with RBS_E_INVALID
 * and a message naming the character and its byte, each name a scene file
 * refuses -- a blank, a control, '#', '"', '=', ',', an invisible or
 * Unicode space code point, too long; a material's "" and "*" -- and
 * accepts what a scene file accepts (a world built through the API held
 * names no scene file could, e.g. "my ball"). */
/* rbs_text_shown_len, character by character, against the rule rbsim.h
 * states (RFC 3629 for well-formed UTF-8; the code points by their Unicode
 * names). */
static void text_shown_len_follows_its_rule(void **state)
{
    static const struct {
        const char *text;
        size_t len, shown, skip;
    } cases[] = {
        {"a", 1, 1, 1},
        {" ", 1, 1, 1},              /* the ASCII space shows */
        {"~", 1, 1, 1},
        {"\x1b[2J", 4, 0, 1},        /* ESC */
        {"\t", 1, 0, 1},             /* a control, however harmless */
        {"\x7f", 1, 0, 1},           /* DEL */
        {"\xc3\xa9", 2, 2, 2},       /* U+00E9 e acute */
        {"\xe2\x82\xac", 3, 3, 3},   /* U+20AC euro sign */
        {"\xf0\x9f\x8e\xb1", 4, 4, 4}, /* U+1F3B1 billiards */
        {"\xc2\x9b", 2, 0, 2},       /* U+009B, a C1 control (CSI) */
        {"\xc2\xa0", 2, 0, 2},       /* U+00A0 no-break space */
        {"\xe3\x80\x80", 3, 0, 3},   /* U+3000 ideographic space */
        {"\xe2\x80\xa8", 3, 0, 3},   /* U+2028 line separator */
        {"\xe2\x80\x8b", 3, 0, 3},   /* U+200B zero width space */
        {"\xe2\x80\xae", 3, 0, 3},   /* U+202E right-to-left override */
        {"\xe2\x81\xa6", 3, 0, 3},   /* U+2066 left-to-right isolate */
        {"\xef\xbb\xbf", 3, 0, 3},   /* U+FEFF byte order mark */
        {"\xff", 1, 0, 1},           /* starts no sequence */
        {"\xc0\xaf", 2, 0, 1},       /* overlong '/' */
        {"\xed\xa0\x80", 3, 0, 1},   /* a surrogate, U+D800 */
        {"\xf4\x90\x80\x80", 4, 0, 1}, /* beyond U+10FFFF */
        {"\xe2\x82\xac", 2, 0, 1},   /* cut off by len */
        {"\xc3\xa9", 0, 0, 0},       /* nothing */
    };
    size_t k;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        size_t skip = 99, shown = rbs_text_shown_len(cases[k].text, cases[k].len, &skip);
        if (shown != cases[k].shown || skip != cases[k].skip)
            fail_msg("case %zu: shown %zu skip %zu, expected %zu and %zu", k, shown, skip, cases[k].shown,
                     cases[k].skip);
    }
    assert_int_equal(rbs_text_shown_len("ab", 2, NULL), 1); /* skip may be NULL */
}

/* A sphere's inertia and density refused for what they are: principal
 * moments each finite whose sum (the trace the world takes) overflows
 * read "must be finite and > 0", and a density whose mass overflows read
 * "sphere mass must be finite and > 0, got inf" though no mass was given
 * (a probe of session 50).  The limits themselves are unchanged: 5e307
 * three times sums to 1.5e308, finite, and is taken. */
static void sphere_inertia_and_density_messages_name_the_cause(void **state)
{
    rbs_world *w = make_world(4, 1e-3, 0.0, 0.5);
    rbs_sphere_def s;
    (void)state;
    rbs_sphere_def_init(&s);
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = s.inertia.y = s.inertia.z = 6e307;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere principal moments must have a finite sum (the world takes the "
                        "inertia's trace), got (6e+307, 6e+307, 6e+307) kg m^2");
    s.inertia.y = -1.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere principal moments must be finite and > 0, got (6e+307, -1, "
                        "6e+307) kg m^2");
    s.inertia.x = s.inertia.y = s.inertia.z = 5e307;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    rbs_sphere_def_init(&s);
    s.position.x = 5.0;
    s.density = 1e308;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere mass from density 1e+308 kg/m^3 and radius 0.1 m (density * 4/3 "
                        "pi r^3) overflows a double");
    s.density = 4.9406564584124654e-324; /* (the least double: its mass rounds to 0) */
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "density 5e-324 kg/m^3"));
    assert_non_null(strstr(rbs_world_last_error(w), "underflows a double"));
    rbs_world_destroy(w);
}

static void names_follow_the_scene_rule(void **state)
{
    static const char long_name[] = "a123456789b123456789c123456789d123456789"
                                    "e123456789f123456789g123"; /* 64 bytes */
    static const struct {
        const char *name;
        const char *fault; /* as the message names it */
    } bad[] = {
        {"my ball", "' ' (a space) at byte 3"},
        {"tab\there", "0x09 (a control character) at byte 4"},
        {"del\x7f", "0x7F (a control character) at byte 4"},
        {"a#b", "'#' at byte 2"},
        {"q\"x", "'\"' at byte 2"},
        {"k=v", "'=' at byte 2"},
        {"a,b", "',' at byte 2"},
        {"ba\xe2\x80\x8bll", "U+200B (an invisible formatting character) at byte 3"},
        {"ball\xe2\x80\xae", "U+202E (an invisible formatting character) at byte 5"},
        {"ba\xc2\xa0ll", "U+00A0 (a space) at byte 3"},
        {"\xef\xbb\xbf" "ball", "U+FEFF (an invisible formatting character) at byte 1"},
        {"ball\xc2\x85", "U+0085 (a control character) at byte 5"},
        {long_name, "64 bytes"},
    };
    static const char *const good[] = {"kugel_\xc3\xa4", "\xe7\x90\x83", "a-b_c.d(1)/*",
                                       long_name + 1 /* 63 bytes */};
    rbs_world_def d;
    rbs_world *w;
    rbs_sphere_def s;
    rbs_plane_def p;
    rbs_body_id id;
    rbs_material_id m;
    rbs_scene *scene;
    size_t i;
    (void)state;
    rbs_world_def_init(&d);
    CHECK_OK(rbs_world_create(&d, &w));
    rbs_sphere_def_init(&s);
    rbs_plane_def_init(&p);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *msg;
        /* the scene file refuses it ... */
        scene = NULL;
        assert_int_equal(scene_with_names(bad[i].name, "m", &scene), RBS_E_SCENE);
        rbs_scene_free(scene);
        scene = NULL;
        assert_int_equal(scene_with_names("b", bad[i].name, &scene), RBS_E_SCENE);
        rbs_scene_free(scene);
        /* ... and so does the API, for a sphere, a plane and a material,
         * naming the fault */
        s.name = bad[i].name;
        assert_int_equal(rbs_world_add_sphere(w, &s, &id), RBS_E_INVALID);
        msg = rbs_world_last_error(w);
        if (strncmp(msg, "sphere name ", 12) != 0 || strstr(msg, bad[i].fault) == NULL)
            fail_msg("case %lu: '%s' does not name '%s'", (unsigned long)i, msg, bad[i].fault);
        p.name = bad[i].name;
        assert_int_equal(rbs_world_add_plane(w, &p, &id), RBS_E_INVALID);
        msg = rbs_world_last_error(w);
        if (strncmp(msg, "plane name ", 11) != 0 || strstr(msg, bad[i].fault) == NULL)
            fail_msg("case %lu: '%s' does not name '%s'", (unsigned long)i, msg, bad[i].fault);
        assert_int_equal(rbs_world_add_material(w, bad[i].name, &m), RBS_E_INVALID);
        msg = rbs_world_last_error(w);
        if (strncmp(msg, "material name ", 14) != 0 || strstr(msg, bad[i].fault) == NULL)
            fail_msg("case %lu: '%s' does not name '%s'", (unsigned long)i, msg, bad[i].fault);
    }
    /* a material's "" and "*" (a body's "" is no name: unnamed) */
    assert_int_equal(rbs_world_add_material(w, "", &m), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "got 0 bytes"));
    assert_int_equal(rbs_world_add_material(w, "*", &m), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "must not be \"*\""));
    assert_int_equal(rbs_world_add_material(w, NULL, &m), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "NULL"));
    /* nothing of it was added */
    assert_int_equal(rbs_world_body_at(w, 0, &id), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_world_material_at(w, 0, &m, NULL), RBS_E_NOT_FOUND);
    /* what scene files take, the API takes */
    for (i = 0; i < sizeof good / sizeof good[0]; i++) {
        rbs_body_id found;
        scene = NULL;
        CHECK_OK(scene_with_names(good[i], good[i], &scene));
        rbs_scene_free(scene);
        CHECK_OK(rbs_world_add_material(w, good[i], &m));
        s.name = good[i];
        s.position.x = 3.0 * (double)i;
        CHECK_OK(rbs_world_add_sphere(w, &s, &id));
        CHECK_OK(rbs_world_find_body(w, good[i], &found));
        assert_memory_equal(&found, &id, sizeof id);
    }
    rbs_world_destroy(w);
}

/* A UTF-8 name the rule accepts goes through a save and a load in both
 * formats (JSON and text) and names the same body and material after. */
static void utf8_name_round_trips_through_save_and_load(void **state)
{
    static const char body[] = "kugel_\xc3\xa4";  /* kugel_a-umlaut */
    static const char mat[] = "\xe7\x90\x83";      /* a CJK ideograph */
    char dir[] = "/tmp/rbs_names_XXXXXX", path[2][128], side[2][128];
    rbs_scene *scene = NULL, *back;
    rbs_world *w;
    rbs_body_id id;
    rbs_material_id m;
    const char *name;
    int k;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(path[0], sizeof path[0], "%s/names.json", dir);
    snprintf(path[1], sizeof path[1], "%s/config.txt", dir);
    snprintf(side[0], sizeof side[0], "%s/materials.txt", dir);
    snprintf(side[1], sizeof side[1], "%s/objects.txt", dir);
    CHECK_OK(scene_with_names(body, mat, &scene));
    for (k = 0; k < 2; k++) {
        back = NULL;
        CHECK_OK(rbs_scene_save(scene, path[k], k == 0 ? RBS_SCENE_JSON : RBS_SCENE_TEXT));
        CHECK_OK(rbs_scene_load(path[k], RBS_SCENE_AUTO, &back));
        CHECK_OK(rbs_scene_build(back, &w));
        CHECK_OK(rbs_world_find_body(w, body, &id));
        CHECK_OK(rbs_world_find_material(w, mat, &m));
        CHECK_OK(rbs_world_material_at(w, 0, NULL, &name));
        assert_string_equal(name, mat);
        rbs_world_destroy(w);
        rbs_scene_free(back);
    }
    rbs_scene_free(scene);
    assert_int_equal(unlink(path[0]), 0);
    assert_int_equal(unlink(path[1]), 0);
    assert_int_equal(unlink(side[0]), 0);
    assert_int_equal(unlink(side[1]), 0);
    assert_int_equal(rmdir(dir), 0);
}

static void capacity_error_leaves_world_unchanged(void **state)
{
    rbs_world_def d;
    rbs_world *w;
    rbs_material_id m, m2;
    rbs_sphere_def s;
    rbs_plane_def p;
    rbs_pair_def pd;
    snapshot before, after;
    (void)state;
    rbs_world_def_init(&d);
    d.max_bodies = 2;
    d.max_materials = 1;
    d.max_pairs = 1;
    CHECK_OK(rbs_world_create(&d, &w));
    m = material(w, "m", 0.5, 0.3, -1.0);
    ball(w, 0.1, 1, 0, 0, 1, 0, 0, 0, m);
    floor_plane(w, m);
    before = snap(w);
    rbs_sphere_def_init(&s);
    s.position.z = 3;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_CAPACITY);
    assert_non_null(strstr(rbs_world_last_error(w), "at most 2 bodies"));
    /* On a full world a bad definition is still named, not the capacity:
     * the definition is checked before a slot is taken (a probe of session
     * 47 suspected the other order). */
    {
        static const char long_name[] = "a123456789b123456789c123456789d123456789"
                                        "e123456789f123456789g1234";
        s.name = long_name;
        assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
        assert_non_null(strstr(rbs_world_last_error(w), "sphere name must have 1 to 63 bytes"));
        assert_non_null(strstr(rbs_world_last_error(w), "got 65 bytes"));
        s.name = "\xff";
        assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
        assert_non_null(strstr(rbs_world_last_error(w), "sphere name must have 1 to 63 bytes of UTF-8"));
        assert_non_null(strstr(rbs_world_last_error(w), "got byte 0xff at byte 1, which starts no UTF-8"));
        s.name = NULL;
        s.radius = -1.0;
        assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
        assert_non_null(strstr(rbs_world_last_error(w), "radius"));
        s.radius = 0.1;
        s.color = 0x1000000u;
        assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
        assert_non_null(strstr(rbs_world_last_error(w), "color"));
        s.color = 0;
        s.position.x = NAN;
        assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_NUMERIC);
        s.position.x = 0;
    }
    rbs_plane_def_init(&p);
    p.normal.z = 0;
    assert_int_equal(rbs_world_add_plane(w, &p, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "normal"));
    rbs_plane_def_init(&p);
    assert_int_equal(rbs_world_add_plane(w, &p, NULL), RBS_E_CAPACITY);
    assert_int_equal(rbs_world_add_material(w, "other", &m2), RBS_E_CAPACITY);
    rbs_pair_def_init(&pd);
    pd.a = m; /* m with "*": a second row */
    assert_int_equal(rbs_world_set_pair(w, &pd), RBS_E_CAPACITY);
    after = snap(w);
    assert_true(before.hash == after.hash);
    assert_int_equal(before.usage.bodies, after.usage.bodies);
    assert_int_equal(before.usage.bodies_high, after.usage.bodies_high);
    assert_int_equal(before.usage.materials, after.usage.materials);
    assert_int_equal(before.usage.pairs, after.usage.pairs);
    rbs_world_destroy(w);
}

/* Contacts beyond max_contacts fail the step and keep the last good state. */
static void contact_capacity_error_keeps_state(void **state)
{
    rbs_world_def d;
    rbs_world *w;
    uint64_t h;
    int i;
    (void)state;
    rbs_world_def_init(&d);
    d.max_bodies = 8;
    d.max_contacts = 2;
    CHECK_OK(rbs_world_create(&d, &w));
    floor_plane(w, (rbs_material_id){0, 0});
    for (i = 0; i < 4; ++i)
        ball(w, 0.1, 1, 0.3 * i, 0, 0.1, 0, 0, 0, (rbs_material_id){0, 0});
    h = rbs_world_hash(w);
    assert_int_equal(rbs_world_step(w, NULL), RBS_E_CAPACITY);
    assert_non_null(strstr(rbs_world_last_error(w), "max_contacts"));
    assert_true(rbs_world_hash(w) == h);
    assert_int_equal(rbs_world_step_count(w), 0);
    rbs_world_destroy(w);
}

/* A slot freed by remove_body and taken again carries nothing of the body
 * it held (the world writes only what differs from zero into a new body, so
 * removal must leave zeros): a spinning, anisotropic, off-centre, named,
 * forced and torqued sphere is removed, and a plain sphere added in its
 * slot must step exactly like the same sphere in a fresh world -- same
 * state hash after 200 steps, free fall z = z0 - g t^2/2 to 1e-12 m with
 * the semi-implicit Euler sum g dt^2 k(k+1)/2, no spin, the fresh energy. */
static void reused_slot_starts_clean(void **state)
{
    rbs_world *w = make_world(2, 1e-3, -9.81, 0.5), *fresh = make_world(2, 1e-3, -9.81, 0.5);
    rbs_body_id a, b, c;
    rbs_sphere_def sd;
    rbs_body_state st;
    rbs_energy e1, e2;
    rbs_body_id found;
    int k;
    (void)state;
    rbs_sphere_def_init(&sd);
    sd.name = "odd";
    sd.radius = 0.2;
    sd.mass = 3.0;
    sd.inertia_kind = RBS_INERTIA_PRINCIPAL;
    sd.inertia.x = 0.02; sd.inertia.y = 0.03; sd.inertia.z = 0.04;
    sd.center_of_mass.x = 0.05;
    sd.force.x = 7.0; sd.torque.y = 2.0;
    sd.angular_velocity.z = 11.0;
    sd.velocity.y = 3.0;
    sd.position.x = 5.0;
    CHECK_OK(rbs_world_add_sphere(w, &sd, &a));
    CHECK_OK(rbs_world_remove_body(w, a));
    rbs_sphere_def_init(&sd);
    sd.position.z = 10.0;
    CHECK_OK(rbs_world_add_sphere(w, &sd, &b));
    assert_int_equal(b.index, a.index);
    CHECK_OK(rbs_world_add_sphere(fresh, &sd, &c));
    assert_int_equal(rbs_world_find_body(w, "odd", &found), RBS_E_NOT_FOUND);
    CHECK_OK(rbs_world_energy(w, &e1));
    CHECK_OK(rbs_world_energy(fresh, &e2));
    assert_true(e1.total == e2.total);
    for (k = 0; k < 200; ++k) {
        CHECK_OK(rbs_world_step(w, NULL));
        CHECK_OK(rbs_world_step(fresh, NULL));
    }
    assert_true(rbs_world_hash(w) == rbs_world_hash(fresh));
    CHECK_OK(rbs_body_get_state(w, b, &st));
    /* semi-implicit Euler: v_k = -g k dt, z_k = z0 - g dt^2 k(k+1)/2 */
    assert_true(fabs(st.position.z - (10.0 - 9.81 * 1e-6 * 200.0 * 201.0 / 2.0)) < 1e-12);
    assert_true(st.position.x == 0.0 && st.position.y == 0.0);
    assert_true(st.angular_velocity.x == 0.0 && st.angular_velocity.y == 0.0 && st.angular_velocity.z == 0.0);
    rbs_world_destroy(w);
    rbs_world_destroy(fresh);
}

static void ids_stale_after_remove(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_body_id a, b, c, found;
    rbs_body_state s;
    rbs_vec3 v = {1, 0, 0};
    rbs_sphere_def sd;
    (void)state;
    rbs_sphere_def_init(&sd);
    sd.name = "a";
    CHECK_OK(rbs_world_add_sphere(w, &sd, &a));
    sd.name = "b";
    sd.position.x = 1;
    CHECK_OK(rbs_world_add_sphere(w, &sd, &b));
    CHECK_OK(rbs_world_find_body(w, "b", &found));
    assert_int_equal(found.index, b.index);
    CHECK_OK(rbs_world_remove_body(w, a));
    assert_int_equal(rbs_body_get_state(w, a, &s), RBS_E_STALE_ID);
    assert_int_equal(rbs_body_set_velocity(w, a, v), RBS_E_STALE_ID);
    assert_int_equal(rbs_world_remove_body(w, a), RBS_E_STALE_ID);
    assert_int_equal(rbs_world_find_body(w, "a", &found), RBS_E_NOT_FOUND);
    /* the slot is reused with a new generation */
    sd.name = "c";
    sd.position.x = 2;
    CHECK_OK(rbs_world_add_sphere(w, &sd, &c));
    assert_int_equal(c.index, a.index);
    assert_int_not_equal(c.generation, a.generation);
    assert_int_equal(rbs_body_get_state(w, a, &s), RBS_E_STALE_ID);
    assert_int_equal(rbs_body_get_state(w, (rbs_body_id){0, 0}, &s), RBS_E_STALE_ID);
    assert_int_equal(rbs_body_get_state(w, (rbs_body_id){99, 1}, &s), RBS_E_STALE_ID);
    rbs_world_destroy(w);
}

static void bad_bodies_are_rejected_with_reasons(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_sphere_def s;
    rbs_plane_def p;
    rbs_vec3 nanv = {NAN, 0, 0};
    rbs_body_id id;
    (void)state;
    rbs_sphere_def_init(&s);
    s.radius = -0.1;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "radius"));
    rbs_sphere_def_init(&s);
    s.mass = 0.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "mass"));
    rbs_sphere_def_init(&s);
    s.orientation.w = 0.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    rbs_sphere_def_init(&s);
    s.velocity.y = INFINITY;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_NUMERIC);
    /* named with its value (it read "sphere: position, velocities, centre
     * of mass, force and torque must be finite", whichever it was) */
    assert_string_equal(rbs_world_last_error(w),
                        "sphere: velocity (0, inf, 0) m/s: every component must be finite");
    rbs_sphere_def_init(&s);
    s.torque.z = -INFINITY;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_NUMERIC);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere: torque (0, 0, -inf) N m: every component must be finite");
    rbs_sphere_def_init(&s);
    s.orientation.x = NAN;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_NUMERIC);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere: orientation (1, nan, 0, 0): every component must be finite");
    rbs_plane_def_init(&p);
    p.normal.x = 0.0; p.normal.y = NAN; p.normal.z = 1.0;
    assert_int_equal(rbs_world_add_plane(w, &p, NULL), RBS_E_NUMERIC);
    assert_string_equal(rbs_world_last_error(w),
                        "plane: normal (0, nan, 1): every component must be finite");
    rbs_sphere_def_init(&s);
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = 1; s.inertia.y = 1; s.inertia.z = 5;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "triangle"));
    rbs_sphere_def_init(&s);
    s.center_of_mass.x = 0.09; /* solid: 2/5 r^2 - c^2 < 0 */
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    rbs_sphere_def_init(&s);
    s.material.index = 7;
    s.material.generation = 1;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_STALE_ID);
    rbs_plane_def_init(&p);
    p.normal.z = 0.0;
    assert_int_equal(rbs_world_add_plane(w, &p, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "normal"));
    /* a duplicate name */
    rbs_sphere_def_init(&s);
    s.name = "x";
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    s.position.x = 1;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "already"));
    /* NaN through a setter: refused, state unchanged */
    assert_int_equal(rbs_body_set_force(w, id, nanv), RBS_E_NUMERIC);
    assert_int_equal(rbs_body_set_velocity(w, id, nanv), RBS_E_NUMERIC);
    assert_true(state_of(w, id).force.x == 0.0);
    /* the message names the argument and echoes it (it read "set_velocity:
     * value must be finite") */
    {
        rbs_vec3 v = {1.5, -INFINITY, 0.0};
        rbs_quat q = {1.0, 0.0, NAN, 0.0};
        assert_int_equal(rbs_body_set_angular_velocity(w, id, v), RBS_E_NUMERIC);
        assert_string_equal(rbs_world_last_error(w), "set_angular_velocity: angular_velocity (1.5, -inf, 0) "
                                                     "rad/s: every component must be finite");
        assert_int_equal(rbs_body_set_orientation(w, id, q), RBS_E_NUMERIC);
        assert_string_equal(rbs_world_last_error(w),
                            "set_orientation: orientation (1, 0, nan, 0): every component must be finite");
    }
    rbs_world_destroy(w);
}

/* A fixed sphere never moves, so a velocity, angular velocity, force or
 * torque given with it is an error, as rbs_body_set_velocity says for one added (it was
 * stored as zero, silently); zero vectors, -0 too, are fine. */
static void fixed_sphere_refuses_a_velocity(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_sphere_def s;
    rbs_body_id id;
    (void)state;
    rbs_sphere_def_init(&s);
    s.fixed = 1;
    s.velocity.x = 1.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere velocity must be zero for a fixed sphere (it never moves), got "
                        "(1, 0, 0) m/s");
    rbs_sphere_def_init(&s);
    s.fixed = 1;
    s.angular_velocity.x = 5.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere angular_velocity must be zero for a fixed sphere (it never moves), "
                        "got (5, 0, 0) rad/s");
    /* nor would a force or torque act on it (rbs_body_set_force refuses
     * one on it; add_sphere took it, silently) */
    rbs_sphere_def_init(&s);
    s.fixed = 1;
    s.force.z = -2.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere force must be zero for a fixed sphere (it never moves), got (0, 0, -2) N");
    rbs_sphere_def_init(&s);
    s.fixed = 1;
    s.torque.y = 1e-300;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere torque must be zero for a fixed sphere (it never moves), got (0, 1e-300, 0) N m");
    rbs_sphere_def_init(&s);
    s.fixed = 1;
    s.velocity.z = -0.0;
    s.force.x = -0.0;
    s.torque.y = -0.0;
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    assert_true(state_of(w, id).velocity.z == 0.0);
    /* the same sphere movable takes them */
    rbs_sphere_def_init(&s);
    s.position.x = 1.0;
    s.velocity.x = 1.0;
    s.angular_velocity.x = 5.0;
    CHECK_OK(rbs_world_add_sphere(w, &s, &id));
    assert_true(state_of(w, id).velocity.x == 1.0 && state_of(w, id).angular_velocity.x == 5.0);
    rbs_world_destroy(w);
}

/* The finds share one rule: NULL is RBS_E_INVALID; a string that names no
 * body (or material) is RBS_E_NOT_FOUND -- "" included, though an unnamed
 * body's name reads "" and any material name must have a byte, and names
 * no name can be ("a b").  find_body said RBS_E_INVALID for "" and
 * find_material RBS_E_NOT_FOUND (a probe of session 50). */
static void finds_share_one_rule(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_sphere_def s;
    rbs_body_id id = {7, 7};
    rbs_material_id m = {7, 7};
    (void)state;
    rbs_sphere_def_init(&s); /* unnamed: its name is "" */
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    CHECK_OK(rbs_world_add_material(w, "steel", NULL));
    assert_int_equal(rbs_world_find_body(w, "", &id), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_world_find_material(w, "", &m), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_world_find_body(w, "a b", &id), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_world_find_material(w, "a b", &m), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_world_find_body(w, NULL, &id), RBS_E_INVALID);
    assert_int_equal(rbs_world_find_material(w, NULL, &m), RBS_E_INVALID);
    /* nothing written when nothing is found */
    assert_true(id.index == 7 && id.generation == 7 && m.index == 7 && m.generation == 7);
    rbs_world_destroy(w);
}

/* The setters apply the limits the constructor applies to the same
 * argument (one function, world.c's sphere_limits): a value add_sphere
 * refuses is RBS_E_INVALID, named with its value, and the world is left as
 * it was (hash and state); the setter took it before, and the world failed
 * later (velocity 1e308: RBS_E_NUMERIC at the third step; a probe of
 * session 50).  Each bound is the mechanics' exact expression (m v^2 / 2,
 * m g z, I w^2 / 2, f.x, G m1 m2 / r) against 1e300, with a margin of a
 * factor of at least 1.02 either side, so rounding cannot decide it. */
static void setters_apply_the_sphere_limits(void **state)
{
    rbs_world *w = make_world(8, 1e-3, -9.81, 0.5);
    rbs_world_def def;
    rbs_sphere_def s;
    rbs_body_id a, b;
    rbs_energy e;
    uint64_t h;
    rbs_vec3 v = {0, 0, 0};
    rbs_quat q = {0.70710678118654752, 0, 0.70710678118654752, 0}; /* body x to world -z */
    (void)state;
    rbs_sphere_def_init(&s); /* 1 kg, r = 0.1 m: I = 0.004 kg m^2, trace 0.012 */
    s.position.z = 1.0;
    CHECK_OK(rbs_world_add_sphere(w, &s, &a));
    h = rbs_world_hash(w);
    /* velocity: kinetic energy, 0.5 x 1e308^2 overflows */
    v.x = 1e308;
    assert_int_equal(rbs_body_set_velocity(w, a, v), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "set_velocity: velocity (1e+308, 0, 0) m/s: the sphere's kinetic energy m v^2 / 2 "
                        "(velocity) would be inf J, beyond 1e300 J (the world's energy would overflow; "
                        "rbs_world_add_sphere refuses it too)");
    assert_true(rbs_world_hash(w) == h && state_of(w, a).velocity.x == 0.0);
    v.x = 1.43e150; /* 1.022e300 J */
    assert_int_equal(rbs_body_set_velocity(w, a, v), RBS_E_INVALID);
    v.x = 1.4e150; /* 9.8e299 J: taken, as add_sphere takes it */
    CHECK_OK(rbs_body_set_velocity(w, a, v));
    CHECK_OK(rbs_world_energy(w, &e));
    v.x = 0.0;
    CHECK_OK(rbs_body_set_velocity(w, a, v));
    /* angular velocity: 0.5 x 0.012 x (1.3e151)^2 = 1.014e300 J; 1.29e151: 9.98e299 J */
    v.z = 1.3e151;
    assert_int_equal(rbs_body_set_angular_velocity(w, a, v), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "set_angular_velocity: angular_velocity (0, 0, 1.3e+151) "
                                                   "rad/s: the sphere's rotational energy"));
    v.z = 1.29e151;
    CHECK_OK(rbs_body_set_angular_velocity(w, a, v));
    v.z = 0.0;
    CHECK_OK(rbs_body_set_angular_velocity(w, a, v));
    h = rbs_world_hash(w);
    /* position: potential energy m g z, 9.81 x 1.04e299 = 1.02e300 J */
    v.z = 1.04e299;
    assert_int_equal(rbs_body_set_position(w, a, v), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "set_position: position (0, 0, 1.04e+299) m: the "
                                                   "sphere's potential energy in gravity (position, mass) "
                                                   "would be 1.02024e+300 J"));
    assert_true(rbs_world_hash(w) == h && state_of(w, a).position.z == 1.0);
    v.z = 1e299; /* 9.81e299 J */
    CHECK_OK(rbs_body_set_position(w, a, v));
    v.z = 1.0;
    CHECK_OK(rbs_body_set_position(w, a, v));
    /* force: its potential f.x, 1.02e200 N x 1e100 m */
    v.z = 1e100;
    CHECK_OK(rbs_body_set_position(w, a, v));
    v.z = 1.02e200;
    assert_int_equal(rbs_body_set_force(w, a, v), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "set_force: force (0, 0, 1.02e+200) N: the sphere's "
                                                   "potential energy of its force (force)"));
    v.z = 0.98e200;
    CHECK_OK(rbs_body_set_force(w, a, v));
    /* torque enters no limit: any finite value, as add_sphere */
    v.z = 1e308;
    CHECK_OK(rbs_body_set_torque(w, a, v));
    rbs_world_destroy(w);

    /* orientation moves an off-centre sphere's centre of mass: 1e301 kg
     * with its COM 0.05 m along body x, turned to world -z, has m g z =
     * 9.81 x 0.05 x 1e301 = 4.9e300 J */
    w = make_world(8, 1e-3, -9.81, 0.5);
    rbs_sphere_def_init(&s);
    s.mass = 1e301;
    s.center_of_mass.x = 0.05;
    CHECK_OK(rbs_world_add_sphere(w, &s, &a));
    h = rbs_world_hash(w);
    assert_int_equal(rbs_body_set_orientation(w, a, q), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "set_orientation: orientation (0.7071067811865476, 0, "
                                                   "0.7071067811865476, 0): the sphere's potential energy "
                                                   "in gravity"));
    assert_true(rbs_world_hash(w) == h);
    s.orientation = q; /* add_sphere refuses the same */
    s.name = "b";
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    rbs_world_destroy(w);

    /* mutual gravity: G m1 m2 / r with G = 1e308, 1 kg each: 1e299 J at
     * 1e9 m, 1e308 J at 1 m */
    rbs_world_def_init(&def);
    def.mutual_gravity = 1;
    def.gravity_constant = 1e308;
    def.gravity.z = 0.0;
    CHECK_OK(rbs_world_create(&def, &w));
    rbs_sphere_def_init(&s);
    CHECK_OK(rbs_world_add_sphere(w, &s, &a));
    s.position.x = 1e9;
    CHECK_OK(rbs_world_add_sphere(w, &s, &b));
    v.x = 1.0; v.y = 0.0; v.z = 0.0;
    h = rbs_world_hash(w);
    assert_int_equal(rbs_body_set_position(w, b, v), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "set_position: position (1, 0, 0) m: the sphere's potential energy of mutual "
                        "gravity with sphere 0 (\"\") would be 1e+308 J, beyond 1e300 J (the world's "
                        "energy would overflow; softening bounds it; rbs_world_add_sphere refuses it too)");
    assert_true(rbs_world_hash(w) == h);
    /* its own slot is left out: moving a alone is no pair with itself */
    v.x = 2.0;
    CHECK_OK(rbs_body_set_position(w, a, v));
    CHECK_OK(rbs_world_energy(w, &e));
    rbs_world_destroy(w);
}

/* The limits of a sphere that FORMAT.md says the world checks when it is
 * built, as the scene does (one rule, rbs__sphere_energy): a movable
 * sphere's 1 / mass finite, and each energy at the start at most 1e300 J
 * (mass 1e308 at 1 m under g was taken, and energy() then failed); a fixed
 * sphere has neither limit. */
static void sphere_energy_at_the_start_is_bounded(void **state)
{
    rbs_world *w = make_world(8, 1e-3, -9.81, 0.5);
    rbs_sphere_def s;
    rbs_energy e;
    (void)state;
    rbs_sphere_def_init(&s);
    s.mass = 1e308;
    s.position.z = 1.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere potential energy in gravity (position, mass) at the start is inf J, "
                        "beyond 1e300 J (the world's energy would overflow)");
    rbs_sphere_def_init(&s);
    s.velocity.x = 1.5e150; /* m v^2 / 2 = 1.125e300 */
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "kinetic energy m v^2 / 2 (velocity) at the start is 1.125e+300 J"));
    rbs_sphere_def_init(&s);
    s.angular_velocity.z = 1e153; /* trace 3 * 0.004 kg m^2: 6e303 J */
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "rotational energy (angular_velocity)"));
    /* and its momenta (a sphere at 1e300 m moving at 1e100 m/s failed the
     * first frame's momentum; 1e305 kg at 1 mm/s has 5e298 J) */
    rbs_sphere_def_init(&s);
    s.position.x = 1e300;
    s.position.y = 1e300;
    s.velocity.x = 1e100;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere angular momentum r x m v about the origin (position, velocity) at "
                        "the start is inf kg m^2/s, beyond 1e300 kg m^2/s (the world's angular "
                        "momentum would overflow)");
    rbs_sphere_def_init(&s);
    s.mass = 1e305;
    s.velocity.x = 1e-3;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "sphere momentum m v (velocity, mass) at the "
                                                    "start is 1e+302 kg m/s"));
    rbs_sphere_def_init(&s);
    s.force.x = 1e200;
    s.position.x = 1e101;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "potential energy of its force (force)"));
    rbs_sphere_def_init(&s);
    s.mass = 1e-310;
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = s.inertia.y = s.inertia.z = 1.0;
    assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "1 / mass overflows"));
    /* fixed: both taken; under the limit: taken, and energy() is a number */
    s.fixed = 1;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    rbs_sphere_def_init(&s);
    s.mass = 1e308;
    s.position.z = 1.0;
    s.fixed = 1;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    rbs_sphere_def_init(&s);
    s.position.x = 5.0;
    s.velocity.x = 1e150; /* 5e299 J */
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    CHECK_OK(rbs_world_energy(w, &e));
    assert_true(e.kinetic == 0.5 * 1e150 * 1e150);
    rbs_world_destroy(w);
}

/* Mutual gravity needs G > 0, as a scene's mutual_gravity.G: G = 0 was
 * taken (an attraction of nothing); off, G = 0 is fine. */
static void mutual_gravity_needs_a_positive_g(void **state)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    char msg[256];
    (void)state;
    rbs_world_def_init(&d);
    d.mutual_gravity = 1;
    d.gravity_constant = 0.0;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_string_equal(msg, "gravity_constant must be > 0 with mutual_gravity on, got 0");
    assert_int_equal(rbs_world_create(&d, &w), RBS_E_INVALID);
    assert_null(w);
    d.gravity_constant = -1.0;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_non_null(strstr(msg, "gravity_constant"));
    d.gravity_constant = 5e-324;
    CHECK_OK(rbs_world_def_validate(&d, msg, sizeof msg));
    d.mutual_gravity = 0;
    d.gravity_constant = 0.0;
    CHECK_OK(rbs_world_def_validate(&d, msg, sizeof msg));
}

/* Each field out of range has its own message, naming it and the value
 * given: max_halvings and max_sweeps shared "max_halvings must be <= 60 and
 * max_sweeps in [1, 100000]", max_materials and max_pairs another, and
 * gravity_constant and softening a third, none with the value (a C caller
 * had to guess which field was wrong; the Python binding re-checked the
 * ranges itself to say). */
static void each_def_field_has_its_own_message(void **state)
{
    static const struct {
        const char *field;
        const char *expect;
    } cases[] = {
        {"max_materials", "max_materials must be <= 4096, got 4097"},
        {"max_pairs", "max_pairs must be <= 65536, got 65537"},
        {"max_substeps", "max_substeps must be >= 1, got 0"},
        {"max_halvings", "max_halvings must be <= 60, got 61"},
        {"max_sweeps0", "max_sweeps must be in [1, 100000], got 0"},
        {"max_sweeps", "max_sweeps must be in [1, 100000], got 100001"},
        {"gravity_constant", "gravity_constant must be finite and >= 0, got -5e-324"},
        {"softening", "softening must be finite and >= 0, got inf"},
        {"gravity", "gravity must be finite, got (0, nan, -9.81)"},
    };
    size_t k;
    char msg[256];
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        rbs_world_def d;
        const char *f = cases[k].field;
        rbs_world_def_init(&d);
        CHECK_OK(rbs_world_def_validate(&d, msg, sizeof msg));
        if (strcmp(f, "max_materials") == 0)
            d.max_materials = 4097;
        else if (strcmp(f, "max_pairs") == 0)
            d.max_pairs = 65537;
        else if (strcmp(f, "max_substeps") == 0)
            d.max_substeps = 0;
        else if (strcmp(f, "max_halvings") == 0)
            d.max_halvings = 61;
        else if (strcmp(f, "max_sweeps0") == 0)
            d.max_sweeps = 0;
        else if (strcmp(f, "max_sweeps") == 0)
            d.max_sweeps = 100001;
        else if (strcmp(f, "gravity_constant") == 0)
            d.gravity_constant = -5e-324;
        else if (strcmp(f, "softening") == 0)
            d.softening = INFINITY;
        else
            d.gravity.y = NAN;
        assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
        assert_string_equal(msg, cases[k].expect);
    }
}

static void pair_rules(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_material_id a, b;
    rbs_pair_def p;
    (void)state;
    CHECK_OK(rbs_world_add_material(w, "a", &a));
    CHECK_OK(rbs_world_add_material(w, "b", &b));
    assert_int_equal(rbs_world_add_material(w, "a", NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_add_material(w, "*", NULL), RBS_E_INVALID);
    rbs_pair_def_init(&p);
    p.a = a;
    p.b = b;
    p.kinetic_friction = 0.9;
    p.static_friction = 0.5;
    assert_int_equal(rbs_world_set_pair(w, &p), RBS_E_INVALID);
    assert_non_null(strstr(rbs_world_last_error(w), "exceeds static"));
    p.kinetic_friction = 0.1;
    p.restitution = 1.5;
    assert_int_equal(rbs_world_set_pair(w, &p), RBS_E_INVALID);
    p.restitution = 0.2;
    CHECK_OK(rbs_world_set_pair(w, &p));
    {
        /* read back: materials by index, rows as set; a replaced row keeps
         * its place; past the end RBS_E_NOT_FOUND */
        rbs_pair_def r, star;
        rbs_material_id m;
        const char *name = NULL;
        CHECK_OK(rbs_world_material_at(w, 1, &m, &name));
        assert_int_equal(m.index, b.index);
        assert_int_equal(m.generation, b.generation);
        assert_string_equal(name, "b");
        assert_int_equal(rbs_world_material_at(w, 2, &m, &name), RBS_E_NOT_FOUND);
        rbs_pair_def_init(&star);
        star.restitution = -1.0;
        CHECK_OK(rbs_world_set_pair(w, &star));
        p.rolling = 0.01;
        CHECK_OK(rbs_world_set_pair(w, &p)); /* replaces row 0 */
        rbs_pair_def_init(&r);
        CHECK_OK(rbs_world_pair_at(w, 0, &r));
        assert_int_equal(r.struct_size, sizeof r);
        assert_int_equal(r.a.index, a.index);
        assert_int_equal(r.b.index, b.index);
        assert_true(r.static_friction == 0.5 && r.kinetic_friction == 0.1);
        assert_true(r.restitution == 0.2 && r.rolling == 0.01 && r.spinning == 0.0);
        CHECK_OK(rbs_world_pair_at(w, 1, &r));
        assert_true(r.a.index == 0 && r.a.generation == 0 && r.b.generation == 0);
        assert_true(r.restitution == -1.0);
        assert_int_equal(rbs_world_pair_at(w, 2, &r), RBS_E_NOT_FOUND);
        assert_int_equal(rbs_world_pair_at(w, 0, NULL), RBS_E_INVALID);
    }
    rbs_world_destroy(w);
}

/* The most specific pair row wins: a ball of "rubber" on "ice" with an exact
 * row (e = 1) must bounce elastically even though "*"/"*" says e = 0. */
static void most_specific_pair_wins(void **state)
{
    rbs_world *w = make_world(4, 1e-3, 0.0, 0.5);
    rbs_material_id rubber, ice;
    rbs_pair_def p;
    rbs_plane_def pl;
    rbs_body_id b;
    (void)state;
    CHECK_OK(rbs_world_add_material(w, "rubber", &rubber));
    CHECK_OK(rbs_world_add_material(w, "ice", &ice));
    rbs_pair_def_init(&p);
    p.restitution = 0.0;
    CHECK_OK(rbs_world_set_pair(w, &p)); /* "*" / "*" */
    p.a = ice;
    p.b = rubber; /* unordered */
    p.restitution = 1.0;
    CHECK_OK(rbs_world_set_pair(w, &p));
    rbs_plane_def_init(&pl);
    pl.material = ice;
    CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
    b = ball(w, 0.1, 1, 0, 0, 0.2, 0, 0, -1, rubber);
    step_n(w, 200);
    ASSERT_NEAR(state_of(w, b).velocity.z, 1.0, 1e-12);
    rbs_world_destroy(w);
}

/* The "*"/"*" row covers every pair no other row does, two named materials
 * included (before session 38 it matched only pairs with a body of no
 * material: rubber on ice took the frictionless default row and the world's
 * restitution, silently).  With rows "*"/"*" (e = 0.9, mu = 0.2) and
 * rubber/rubber (e = 0.1): rubber on ice and rubber on rubber-plane, each
 * dropped at 1 m/s with 0.5 m/s sideways in no gravity -- the rebound is e
 * times 1 m/s, and the sideways speed after the impact is that of Coulomb
 * friction's impulse mu (1 + e) m v_n taken until rolling sets in: for a
 * solid sphere rolling at 5/7 of 0.5 m/s (0.357) when mu (1 + e) = 0.38 is
 * enough, 0.5 with no friction. */
static void star_star_row_covers_named_materials(void **state)
{
    const double want_e[2] = {0.9, 0.1}, want_vx[2] = {5.0 / 7.0 * 0.5, 5.0 / 7.0 * 0.5};
    int k;
    (void)state;
    for (k = 0; k < 2; ++k) {
        rbs_world *w = make_world(4, 1e-3, 0.0, 0.5);
        rbs_material_id rubber, ice;
        rbs_pair_def p;
        rbs_plane_def pl;
        rbs_sphere_def s;
        rbs_body_id b;
        CHECK_OK(rbs_world_set_method(w, RBS_METHOD_EVENT, 0.0));
        CHECK_OK(rbs_world_add_material(w, "rubber", &rubber));
        CHECK_OK(rbs_world_add_material(w, "ice", &ice));
        rbs_pair_def_init(&p);
        p.static_friction = p.kinetic_friction = 0.2;
        p.restitution = 0.9;
        CHECK_OK(rbs_world_set_pair(w, &p)); /* "*" / "*" */
        p.a = p.b = rubber;
        p.static_friction = p.kinetic_friction = 0.5;
        p.restitution = 0.1;
        CHECK_OK(rbs_world_set_pair(w, &p));
        rbs_plane_def_init(&pl);
        pl.material = k == 0 ? ice : rubber;
        CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
        rbs_sphere_def_init(&s);
        s.radius = 0.1;
        s.position.z = 0.2;
        s.velocity.x = 0.5;
        s.velocity.z = -1.0;
        s.material = rubber;
        CHECK_OK(rbs_world_add_sphere(w, &s, &b));
        step_n(w, 300);
        ASSERT_NEAR(state_of(w, b).velocity.z, want_e[k], 1e-12);
        ASSERT_NEAR(state_of(w, b).velocity.x, want_vx[k], 1e-12);
        rbs_world_destroy(w);
    }
}

/* Two one-wildcard rows that both match (rubber with "*", e = 0.3, set
 * first; "*" with ice, e = 0.8): the one set first wins, as rbsim.h and
 * scenes/FORMAT.md say; setting them the other way round gives the other. */
static void first_of_two_wildcard_rows_wins(void **state)
{
    int order;
    (void)state;
    for (order = 0; order < 2; ++order) {
        rbs_world *w = make_world(4, 1e-3, 0.0, 0.5);
        rbs_material_id rubber, ice;
        rbs_pair_def p[2];
        rbs_plane_def pl;
        rbs_body_id b;
        CHECK_OK(rbs_world_add_material(w, "rubber", &rubber));
        CHECK_OK(rbs_world_add_material(w, "ice", &ice));
        rbs_pair_def_init(&p[0]);
        p[0].a = rubber;
        p[0].restitution = 0.3;
        rbs_pair_def_init(&p[1]);
        p[1].b = ice;
        p[1].restitution = 0.8;
        CHECK_OK(rbs_world_set_pair(w, &p[order]));
        CHECK_OK(rbs_world_set_pair(w, &p[1 - order]));
        rbs_plane_def_init(&pl);
        pl.material = ice;
        CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
        b = ball(w, 0.1, 1, 0, 0, 0.2, 0, 0, -1, rubber);
        step_n(w, 200);
        ASSERT_NEAR(state_of(w, b).velocity.z, order == 0 ? 0.3 : 0.8, 1e-12);
        rbs_world_destroy(w);
    }
}

static void state_view_is_zero_copy(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_state_view v;
    const double *p;
    (void)state;
    ball(w, 0.1, 1, 0, 0, 5, 0, 0, 0, (rbs_material_id){0, 0});
    CHECK_OK(rbs_world_state(w, &v));
    assert_int_equal(v.slots, 1);
    p = v.position;
    assert_true(p[2] == 5.0);
    step_n(w, 1);
    CHECK_OK(rbs_world_state(w, &v));
    assert_ptr_equal(p, v.position);
    assert_true(p[2] < 5.0);
    rbs_world_destroy(w);
}

static void null_arguments_never_crash(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    (void)state;
    assert_int_equal(rbs_world_step(NULL, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_add_sphere(w, NULL, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_add_sphere(NULL, NULL, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_energy(w, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_find_body(w, NULL, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_find_material(w, NULL, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_world_set_dt(w, 0.0), RBS_E_INVALID);
    assert_int_equal(rbs_world_set_dt(w, INFINITY), RBS_E_INVALID);
    assert_non_null(rbs_world_last_error(NULL));
    rbs_world_destroy(NULL);
    rbs_world_destroy(w);
}

/* An overflow during a step (a huge force) is an error and the world stays
 * at its last good state. */
static void overflow_in_step_keeps_last_good_state(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    rbs_body_id b = ball(w, 0.1, 1e-5, 0, 0, 5, 0, 0, 0, (rbs_material_id){0, 0});
    (void)state;
    step_n(w, 3);
    overflow_keeps_state(w, b, "NaN or infinite", 3); /* a = 1e313 overflows */
    rbs_world_destroy(w);
}

/* The name index against a walk over every slot: random adds and removes
 * of names from a small pool, in a world whose index is small enough that
 * names collide and removals shift entries back; after every operation
 * each pool name is found exactly where the walk finds it, and a
 * checkpoint of the world finds the same. */
static uint32_t walk_find(const rbs_world *w, const char *name)
{
    uint32_t slot;
    for (slot = 0; slot < 64; ++slot) {
        rbs_body_id id;
        rbs_body_state st;
        if (rbs_world_body_at(w, slot, &id) == RBS_OK && rbs_body_get_state(w, id, &st) == RBS_OK &&
            strcmp(st.name, name) == 0)
            return slot;
    }
    return UINT32_MAX;
}

static void names_are_indexed(void **state)
{
    rbs_world *w = make_world(64, 1e-3, 0.0, 0.5), *r = NULL;
    rbs_body_id ids[48];
    int live[48] = {0}, op, k;
    uint32_t rng = 12345u;
    char name[16];
    (void)state;
    for (op = 0; op < 3000; ++op) {
        rng = rng * 1664525u + 1013904223u;
        k = (int)((rng >> 8) % 48u);
        snprintf(name, sizeof name, "b%d", k * 7919);
        if (!live[k]) {
            rbs_sphere_def s;
            rbs_sphere_def_init(&s);
            s.name = name;
            s.position.x = 3.0 * k;
            CHECK_OK(rbs_world_add_sphere(w, &s, &ids[k]));
            live[k] = 1;
            /* a second body of that name is refused */
            s.position.x += 1000.0;
            assert_int_equal(rbs_world_add_sphere(w, &s, NULL), RBS_E_INVALID);
        } else if ((rng >> 4) & 1u) {
            CHECK_OK(rbs_world_remove_body(w, ids[k]));
            live[k] = 0;
        }
        for (k = 0; k < 48; ++k) {
            rbs_body_id id;
            uint32_t at;
            snprintf(name, sizeof name, "b%d", k * 7919);
            at = walk_find(w, name);
            assert_true((at != UINT32_MAX) == live[k]);
            if (live[k]) {
                CHECK_OK(rbs_world_find_body(w, name, &id));
                assert_int_equal(id.index, at);
                assert_int_equal(id.index, ids[k].index);
                assert_int_equal(id.generation, ids[k].generation);
            } else {
                assert_int_equal(rbs_world_find_body(w, name, &id), RBS_E_NOT_FOUND);
            }
        }
    }
    {
        size_t n = rbs_world_checkpoint_size(w);
        unsigned char *buf = malloc(n);
        assert_non_null(buf);
        CHECK_OK(rbs_world_checkpoint_write(w, buf, n, NULL));
        CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &r));
        free(buf);
        for (k = 0; k < 48; ++k) {
            rbs_body_id id;
            snprintf(name, sizeof name, "b%d", k * 7919);
            assert_int_equal(rbs_world_find_body(r, name, &id), live[k] ? RBS_OK : RBS_E_NOT_FOUND);
        }
        rbs_world_destroy(r);
    }
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(version_matches_header),
        cmocka_unit_test(status_strings),
        cmocka_unit_test(bad_values_are_echoed_exactly),
        cmocka_unit_test(method_names_round_trip),
        cmocka_unit_test(text_shown_len_follows_its_rule),
        cmocka_unit_test(names_follow_the_scene_rule),
        cmocka_unit_test(utf8_name_round_trips_through_save_and_load),
        cmocka_unit_test(old_shorter_defs_get_defaults),
        cmocka_unit_test(uninitialised_def_is_rejected),
        cmocka_unit_test(struct_size_inside_a_field_is_rejected),
        cmocka_unit_test(set_dt_keeps_the_elapsed_time),
        cmocka_unit_test(messages_name_the_real_cause),
        cmocka_unit_test(create_in_caller_memory),
        cmocka_unit_test(capacity_error_leaves_world_unchanged),
        cmocka_unit_test(contact_capacity_error_keeps_state),
        cmocka_unit_test(ids_stale_after_remove),
        cmocka_unit_test(names_are_indexed),
        cmocka_unit_test(reused_slot_starts_clean),
        cmocka_unit_test(bad_bodies_are_rejected_with_reasons),
        cmocka_unit_test(fixed_sphere_refuses_a_velocity),
        cmocka_unit_test(sphere_energy_at_the_start_is_bounded),
        cmocka_unit_test(setters_apply_the_sphere_limits),
        cmocka_unit_test(finds_share_one_rule),
        cmocka_unit_test(mutual_gravity_needs_a_positive_g),
        cmocka_unit_test(each_def_field_has_its_own_message),
        cmocka_unit_test(pair_rules),
        cmocka_unit_test(most_specific_pair_wins),
        cmocka_unit_test(star_star_row_covers_named_materials),
        cmocka_unit_test(first_of_two_wildcard_rows_wins),
        cmocka_unit_test(state_view_is_zero_copy),
        cmocka_unit_test(null_arguments_never_crash),
        cmocka_unit_test(overflow_in_step_keeps_last_good_state),
        cmocka_unit_test(sphere_inertia_and_density_messages_name_the_cause),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
