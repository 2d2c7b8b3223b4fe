/*
 * test_sdl_config.c - the "sdl" scene entry is validated in check() and
 * create(): every bad key gives RBS_E_INVALID (or the stated code) and a
 * message that names the key; a rejected entry creates no folder.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "sdl_test_util.h"

typedef struct bad_case {
    const char *json;
    const char *key;  /* must appear in the message */
    const char *what; /* and so must this */
} bad_case;

static const bad_case kBad[] = {
    {"[1,2]", "entry", "object"},
    {"{\"width\":640,", "entry", "JSON"},
    {"{\"colour\":1}", "colour", "unknown key"},
    {"{\"width\":640,\"width\":320}", "width", "duplicate"},
    {"{\"type\":\"csv\"}", "type", "sdl"},
    {"{\"path\":\"\"}", "path", "folder"},
    {"{\"path\":3}", "path", "string"},
    {"{\"every\":0}", "every", "integer"},
    {"{\"every\":1.5}", "every", "integer"},
    {"{\"width\":0}", "width", "[16, 8192]"},
    {"{\"width\":\"640\"}", "width", "a string"},
    {"{\"height\":100000}", "height", "8192"},
    {"{\"width\":8192,\"height\":4096}", "width", "too large"},
    {"{\"window\":\"yes\"}", "window", "\"auto\", true or false"},
    {"{\"window\":1}", "window", "a number"},
    {"{\"tile\":1}", "tile", "true or false"},
    {"{\"contact_sheet\":\"no\"}", "contact_sheet", "true or false"},
    {"{\"camera\":{},\"views\":[{}]}", "views", "not both"},
    {"{\"views\":[]}", "views", "1 to 4"},
    {"{\"views\":[{},{},{},{},{}]}", "views", "1 to 4"},
    {"{\"views\":{}}", "views", "array"},
    {"{\"camera\":[]}", "camera", "object"},
    {"{\"camera\":{\"zoom\":2}}", "camera.zoom", "unknown key"},
    {"{\"camera\":{\"mode\":\"orbit\"}}", "camera.mode", "\"fixed\""},
    {"{\"camera\":{\"position\":[1,2]}}", "camera.position", "3 numbers"},
    {"{\"camera\":{\"target\":[1,\"a\",2]}}", "camera.target[1]", "finite number"},
    {"{\"camera\":{\"up\":[0,0,0]}}", "camera.up", "nonzero"},
    {"{\"camera\":{\"fov\":180}}", "camera.fov", "[1e-6, 180)"},
    {"{\"camera\":{\"fov\":0}}", "camera.fov", "[1e-6, 180)"},
    {"{\"camera\":{\"fov\":1e-300}}", "camera.fov", "[1e-6, 180)"},
    {"{\"camera\":{\"position\":[1e300,0,0],\"target\":[0,0,0]}}", "camera.position",
     "within +-1e100 m"},
    {"{\"camera\":{\"target\":[0,-1e101,0]}}", "camera.target", "within +-1e100 m"},
    {"{\"camera\":{\"position\":[1e-300,0,0],\"target\":[0,0,0]}}", "camera.target",
     "within 1e-100 m"},
    {"{\"camera\":{\"near\":0}}", "camera.near", "> 0"},
    {"{\"camera\":{\"near\":1,\"far\":0.5}}", "camera.far", "> near"},
    {"{\"camera\":{\"position\":[1,1,1],\"target\":[1,1,1]}}", "camera.target", "equals"},
    {"{\"camera\":{\"position\":[0,0,5],\"target\":[0,0,0]}}", "camera.target", "parallel to up"},
    {"{\"camera\":{\"mode\":\"mounted\"}}", "camera.mount", "missing"},
    {"{\"camera\":{\"mode\":\"fixed\",\"mount\":\"ball\"}}", "camera.mount", "mounted"},
    {"{\"camera\":{\"mount\":\"b\",\"offset\":[1e300,0,0]}}", "camera.offset",
     "within +-1e100 m"},
    {"{\"camera\":{\"mount\":\"b\",\"offset\":[0,1e-300,0]}}", "camera.offset",
     "shorter than 1e-100 m"},
    {"{\"camera\":{\"path\":[{\"t\":0,\"position\":[1,0,3],\"target\":[0,0,-1e200]}]}}",
     "camera.path[0].target", "within +-1e100 m"},
    {"{\"camera\":{\"mode\":\"mounted\",\"mount\":\"\"}}", "camera.mount", "body name"},
    {"{\"camera\":{\"offset\":[1,0,0]}}", "camera.offset", "mounted"},
    {"{\"camera\":{\"mode\":\"mounted\",\"mount\":\"b\",\"offset\":[0,0,0]}}",
     "camera.offset", "nonzero"},
    {"{\"camera\":{\"mode\":\"mounted\",\"mount\":\"b\",\"position\":[0,0,1]}}",
     "camera.position", "mounted"},
    {"{\"camera\":{\"mode\":\"free\",\"path\":[]}}", "camera.path", "fixed"},
    {"{\"camera\":{\"path\":[]}}", "camera.path", "non-empty"},
    {"{\"camera\":{\"path\":[{\"t\":0,\"position\":[0,-1,0]}]}}", "camera.path[0].target",
     "missing"},
    {"{\"camera\":{\"path\":[{\"t\":1,\"position\":[0,-1,0],\"target\":[0,0,0]},"
     "{\"t\":1,\"position\":[0,-2,0],\"target\":[0,0,0]}]}}",
     "camera.path[1].t", "increase"},
    {"{\"camera\":{\"path\":[{\"t\":0,\"position\":[0,0,0],\"target\":[0,0,0]}]}}",
     "camera.path[0].target", "equals"},
    {"{\"camera\":{\"path\":[{\"t\":0,\"position\":[0,-1,0],\"target\":[0,0,0],\"fov\":3}]}}",
     "camera.path[0].fov", "unknown key"},
    {"{\"camera\":{\"position\":[0,-1,0],\"path\":[{\"t\":0,\"position\":[0,-1,0],"
     "\"target\":[0,0,0]}]}}",
     "camera.position", "path"},
    {"{\"views\":[{},{\"fov\":-5}]}", "views[1].fov", "[1e-6, 180)"},
    {"{\"views\":[{},{},\"cam\"]}", "views[2]", "object"},
};

static int dir_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

static rbs_status check(const char *json, const char *path, char *err, size_t errlen)
{
    rbs_renderer_config c;
    memset(&c, 0, sizeof c);
    c.struct_size = sizeof c;
    c.type = "sdl";
    c.path = path;
    c.every = 1;
    c.json = json;
    err[0] = '\0';
    return rbsf_sdl_class()->check(NULL, &c, NULL, err, errlen);
}

static void test_bad_entries(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < sizeof kBad / sizeof kBad[0]; i++) {
        char err[512], name[32];
        void *inst = (void *)&i;
        rbs_status st;
        snprintf(name, sizeof name, "bad%02u", (unsigned)i);
        st = check(kBad[i].json, tu_dir(name), err, sizeof err);
        if (st != RBS_E_INVALID || strstr(err, kBad[i].key) == NULL ||
            strstr(err, kBad[i].what) == NULL)
            fprintf(stderr, "case %u %s: status %d, message \"%s\"\n", (unsigned)i,
                    kBad[i].json, (int)st, err);
        assert_int_equal(st, RBS_E_INVALID);
        assert_non_null(strstr(err, kBad[i].key));
        assert_non_null(strstr(err, kBad[i].what));
        /* create() says the same and leaves nothing behind. */
        assert_int_equal(tu_create(kBad[i].json, tu_dir(name), &inst, err, sizeof err),
                         RBS_E_INVALID);
        assert_null(inst);
        assert_non_null(strstr(err, kBad[i].key));
        assert_false(dir_exists(tu_dir(name)));
    }
}

/* Good entries pass check() without creating their folder. */
static void test_good_entries(void **state)
{
    static const char *const good[] = {
        NULL,
        "{}",
        "{\"type\":\"sdl\",\"path\":\"x\",\"every\":3,\"width\":64,\"height\":48,"
        "\"window\":\"auto\",\"tile\":true,\"contact_sheet\":false}",
        "{\"camera\":{\"mode\":\"fixed\",\"position\":[1,2,3],\"target\":[0,0,0],"
        "\"up\":[0,0,2],\"fov\":70,\"near\":0.1,\"far\":50}}",
        "{\"camera\":{\"mode\":\"mounted\",\"mount\":\"ball\",\"offset\":[0,-2,1]}}",
        "{\"camera\":{\"mode\":\"free\"}}",
        "{\"camera\":{\"mount\":\"ball\",\"offset\":[0,-2,1]}}",
        /* straight above its body, along up: the along-up rule draws it,
         * as check accepts it */
        "{\"camera\":{\"mount\":\"ball\",\"offset\":[0,0,3]}}",
        "{\"camera\":{\"fov\":1e-6,\"up\":[0,1e-300,1e-300]}}",
        "{\"views\":[{},{\"mode\":\"free\"},{\"position\":[0,-3,0],\"target\":[0,0,0]},"
        "{\"path\":[{\"t\":0,\"position\":[0,-1,0],\"target\":[0,0,0]}]}]}",
        "{\"window\":false}",
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof good / sizeof good[0]; i++) {
        char err[512];
        rbs_status st = check(good[i], tu_dir("good"), err, sizeof err);
        if (st != RBS_OK) fprintf(stderr, "good case %u: %s\n", (unsigned)i, err);
        assert_int_equal(st, RBS_OK);
    }
    assert_false(dir_exists(tu_dir("good")));
}

/* Messages name the key and what is wrong; the scene's place is left to
 * the caller (the projector and the command line put it in front). */
static void test_message_place(void **state)
{
    char err[512];
    void *inst = NULL;
    (void)state;
    assert_int_equal(tu_create_full("{\"camera\":{\"fov\":200}}", tu_dir("place"),
                                    "scenes/demo.json", 12, 7, NULL, NULL, &inst, err,
                                    sizeof err),
                     RBS_E_INVALID);
    assert_string_equal(err, "camera.fov: must be in [1e-6, 180) degrees, got 200");
}

/* No folder given anywhere. */
static void test_missing_path(void **state)
{
    char err[512];
    void *inst = NULL;
    (void)state;
    assert_int_equal(tu_create("{\"window\":false}", NULL, &inst, err, sizeof err),
                     RBS_E_INVALID);
    assert_non_null(strstr(err, "path: missing"));
    /* The entry's own path is used when the config has none. */
    {
        char json[1400];
        snprintf(json, sizeof json, "{\"window\":false,\"path\":\"%s\"}",
                 tu_dir("entry_path"));
        assert_int_equal(tu_create(json, NULL, &inst, err, sizeof err), RBS_OK);
        assert_true(dir_exists(tu_dir("entry_path")));
        rbsf_sdl_class()->destroy(inst);
    }
}

/* window: true needs a display; the tests run with DISPLAY and
 * WAYLAND_DISPLAY cleared (meson.build), so it is refused in create(), and
 * "auto" quietly means no window. */
static void test_window_needs_display(void **state)
{
    char err[512];
    void *inst = NULL;
    (void)state;
    assert_int_equal(tu_create("{\"window\":true}", tu_dir("win"), &inst, err, sizeof err),
                     RBS_E_RENDERER);
    assert_null(inst);
    assert_non_null(strstr(err, "window: true"));
    assert_non_null(strstr(err, "DISPLAY"));
    assert_int_equal(tu_create("{\"window\":\"auto\"}", tu_dir("win"), &inst, err, sizeof err),
                     RBS_OK);
    rbsf_sdl_class()->destroy(inst);
}

/* A mounted camera whose body is not in the frame: draw() fails and says
 * which body; so does a camera whose path makes it look along up. */
static void test_draw_errors(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512];
    void *inst = NULL;
    tu_frame f;
    (void)state;
    assert_int_equal(tu_create("{\"window\":false,\"camera\":{\"mode\":\"mounted\","
                               "\"mount\":\"rover\"}}",
                               tu_dir("mount"), &inst, err, sizeof err),
                     RBS_OK);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 0, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_E_INVALID);
    assert_non_null(strstr(err, "camera.mount"));
    assert_non_null(strstr(err, "rover"));
    /* Once the body is there, the camera works. */
    f.bodies[0].name = "rover";
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    cls->destroy(inst);

    /* "mount" without "mode": a mounted camera (FORMAT.md's default). */
    assert_int_equal(tu_create("{\"window\":false,\"camera\":{\"mount\":\"rover\"}}",
                               tu_dir("mountdefault"), &inst, err, sizeof err),
                     RBS_OK);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "camera", err, sizeof err), RBS_OK);
    assert_non_null(strstr(err, "mounted on \"rover\""));
    cls->destroy(inst);

    /* Frames that are not frames. */
    assert_int_equal(tu_create("{\"window\":false}", tu_dir("nullframe"), &inst, err,
                               sizeof err),
                     RBS_OK);
    f.frame.bodies = NULL;
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_E_INVALID);
    assert_non_null(strstr(err, "bodies"));
    assert_int_equal(cls->draw(inst, NULL, err, sizeof err), RBS_E_INVALID);
    cls->destroy(inst);
}

/* Values that are legal but extreme: a tiny image, a huge far plane, a
 * frame with no bodies, a sphere enclosing the camera, a NaN position. */
static void test_extremes(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512];
    void *inst = NULL;
    tu_frame f;
    SDL_Surface *s;
    (void)state;
    assert_int_equal(tu_create("{\"window\":false,\"width\":16,\"height\":16,"
                               "\"camera\":{\"position\":[0,-5,0],\"target\":[0,0,0],"
                               "\"far\":1e12}}",
                               tu_dir("extreme"), &inst, err, sizeof err),
                     RBS_OK);
    tu_frame_init(&f, 0, 0.0);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    tu_frame_init(&f, 1, 1e9);
    tu_add_sphere(&f, "around", 0, -5, 0, 50.0, 0xd03030);
    tu_add_sphere(&f, "nan", NAN, 0, 0, 1.0, 0x30c030);
    tu_add_plane(&f, 0, 0, -1, 0, 0, 0, 0x808080); /* zero normal: not drawn */
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    s = tu_load(tu_dir("extreme/frame_000001.png"));
    assert_non_null(s);
    assert_int_equal(s->w, 16);
    /* Inside the big sphere: its inside fills the view. */
    assert_int_equal(tu_pixel(s, 8, 15) >> 16 > 0x40, 1);
    SDL_FreeSurface(s);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_entries),
        cmocka_unit_test(test_good_entries),
        cmocka_unit_test(test_message_place),
        cmocka_unit_test(test_missing_path),
        cmocka_unit_test(test_window_needs_display),
        cmocka_unit_test(test_draw_errors),
        cmocka_unit_test(test_extremes),
    };
    tu_set_base(argc > 1 ? argv[1] : ".");
    return cmocka_run_group_tests(tests, NULL, NULL);
}
