/*
 * test_locale.c - the library's messages and rbs_world_explain write
 * numbers in the "C" locale whatever the calling process's: under German
 * settings (setlocale(LC_ALL, "") with a decimal comma) they read "got
 * (0,5, 1,5, 0) m/s" and "dt = 0,001 s", which no reader of the text
 * expects and which a vector's commas make ambiguous.  The locale is made
 * by german_locale.h in the folder given as the first argument.
 */
#include <stdlib.h>

#include "common.h"
#include "../german_locale.h"
#include "rbsim/scene.h"

/* rbs_world_def_validate's message: the value by rbs__shortest, which also
 * reads each candidate back (in the German locale "0.5" read back as 0, so
 * every value came out with 17 digits and a comma). */
static void def_message_writes_a_point(void **state)
{
    rbs_world_def d;
    char msg[256];
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    rbs_world_def_init(&d);
    d.dt = -0.5;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_string_equal(msg, "dt must be finite and > 0, got -0.5");
    rbs_world_def_init(&d);
    d.restitution = 1.1;
    assert_int_equal(rbs_world_def_validate(&d, msg, sizeof msg), RBS_E_INVALID);
    assert_string_equal(msg, "restitution must be in [0, 1], got 1.1");
    assert_non_null(setlocale(LC_ALL, "C"));
}

/* The world's last error: a vector by rbs__shortest, and a message whose
 * numbers are the format's own %g. */
static void world_error_writes_a_point(void **state)
{
    rbs_world *w = make_world(4, 0.001, -9.81, 0.5);
    rbs_sphere_def sd;
    rbs_body_id id;
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    rbs_sphere_def_init(&sd);
    sd.fixed = 1;
    sd.velocity.x = 0.5;
    sd.velocity.y = 1.5;
    assert_int_equal(rbs_world_add_sphere(w, &sd, &id), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere velocity must be zero for a fixed sphere (it never moves), "
                        "got (0.5, 1.5, 0) m/s");
    rbs_sphere_def_init(&sd);
    sd.radius = 0.1;
    sd.center_of_mass.x = 0.25;
    assert_int_equal(rbs_world_add_sphere(w, &sd, &id), RBS_E_INVALID);
    assert_string_equal(rbs_world_last_error(w),
                        "sphere centre of mass offset 0.25 must be < radius 0.1");
    rbs_world_destroy(w);
    assert_non_null(setlocale(LC_ALL, "C"));
}

/* rbs_world_explain: the same text as under "C" (dt, slop, tolerance and
 * gravity are fractions). */
static void explain_writes_a_point(void **state)
{
    rbs_world *w = make_world(4, 0.001, -9.81, 0.5);
    rbs_sphere_def sd;
    rbs_body_id id;
    char c_text[8192], de_text[8192];
    (void)state;
    rbs_sphere_def_init(&sd);
    sd.radius = 0.25;
    sd.position.z = 1.5;
    CHECK_OK(rbs_world_add_sphere(w, &sd, &id));
    assert_non_null(setlocale(LC_ALL, "C"));
    CHECK_OK(rbs_world_explain(w, c_text, sizeof c_text, NULL));
    assert_non_null(strstr(c_text, "dt = 0.001 s"));
    assert_non_null(strstr(c_text, "g = (0, 0, -9.81)"));
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    CHECK_OK(rbs_world_explain(w, de_text, sizeof de_text, NULL));
    assert_non_null(setlocale(LC_ALL, "C"));
    assert_string_equal(de_text, c_text);
    rbs_world_destroy(w);
}

/* The scene module, which switched to "C" before this change: its
 * messages (a guard that they stay so). */
static void scene_stays_c(void **state)
{
    static const char text[] =
        "{\"simulation\": {\"steps\": 10, \"dt\": 0.0025},"
        " \"bodies\": [{\"type\": \"sphere\", \"name\": \"s\", \"mass\": 1,"
        " \"position\": [0, 0, 0.5], \"radius\": -0.5}]}";
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    assert_int_equal(rbs_scene_parse_json(text, sizeof text - 1, "t.json", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.message, "must be > 0, got -0.5");
    rbs_scene_free(scene);
    assert_non_null(setlocale(LC_ALL, "C"));
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(def_message_writes_a_point),
        cmocka_unit_test(world_error_writes_a_point),
        cmocka_unit_test(explain_writes_a_point),
        cmocka_unit_test(scene_stays_c),
    };
    if (german_locale_make(argc > 1 ? argv[1] : NULL) != 0)
        return 1;
    return cmocka_run_group_tests(tests, NULL, NULL);
}
