/*
 * test_locale.c - the projector's commands and messages write and read
 * numbers in the "C" locale whatever the calling process's: a program that
 * called setlocale(LC_ALL, "") under German settings (decimal comma) had
 * "speed 0.5" refused while "speed 0,5" was taken.  The locale is made by german_locale.h in the folder given as the
 * first argument.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../german_locale.h"
#include "rbsim/reel.h"

/* A world whose numbers are not short decimals (0.1, 1/3 of a step, a
 * negative coordinate) and whose spheres collide (the stats' counters). */
static rbs_world *make_world(void)
{
    rbs_world_def wd;
    rbs_world *w;
    rbs_plane_def pd;
    rbs_sphere_def sd;
    rbs_body_id id;
    int i;
    rbs_world_def_init(&wd);
    wd.max_bodies = 4;
    wd.dt = 1.0 / 3.0 * 0.01;
    assert_int_equal(rbs_world_create(&wd, &w), RBS_OK);
    rbs_plane_def_init(&pd);
    pd.name = "floor";
    assert_int_equal(rbs_world_add_plane(w, &pd, &id), RBS_OK);
    for (i = 0; i < 2; i++) {
        rbs_sphere_def_init(&sd);
        sd.name = i == 0 ? "a" : "b";
        sd.radius = 0.1;
        sd.position.x = -0.5 + 0.25 * i;
        sd.position.z = 0.105 + 0.3 * i;
        sd.velocity.x = 0.5 - i;
        sd.angular_velocity.y = 1.5;
        assert_int_equal(rbs_world_add_sphere(w, &sd, &id), RBS_OK);
    }
    return w;
}

/* A projector (not started: commands are taken before start) for the
 * command tests. */
static rbs_projector *idle_projector(rbs_world **w, rbs_renderer_registry **reg,
                                     double speed)
{
    rbs_projector_def def;
    rbs_projector *p = NULL;
    *w = make_world();
    assert_int_equal(rbs_renderer_registry_create(reg), RBS_OK);
    rbs_projector_def_init(&def);
    def.steps = 10;
    def.speed = speed;
    rbs_projector_create(*w, *reg, NULL, 0, &def, &p);
    assert_non_null(p);
    return p;
}

/* "speed 0.5" is a factor of one half and "speed 0,5" is refused, as under
 * "C"; the replies and the status line write the factor with '.'. */
static void speed_command_reads_c_numbers(void **state)
{
    rbs_world *w;
    rbs_renderer_registry *reg;
    rbs_projector *p;
    rbs_run_info info;
    char reply[256];
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    p = idle_projector(&w, &reg, 1.0);
    assert_int_equal(rbs_projector_command(p, "speed 0.5", reply, sizeof reply), RBS_OK);
    assert_string_equal(reply, "speed 0.5 (used in real-time runs)");
    assert_int_equal(rbs_projector_status(p, &info), RBS_OK);
    assert_true(info.speed == 0.5);
    assert_int_equal(rbs_projector_command(p, "speed 0,5", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_string_equal(reply, "speed: expected a factor > 0 and <= 1e6, got '0,5'");
    assert_int_equal(rbs_projector_command(p, "speed 1.25", reply, sizeof reply), RBS_OK);
    assert_int_equal(rbs_projector_command(p, "status", reply, sizeof reply), RBS_OK);
    assert_string_equal(reply, "frame 0 of 10, t = 0 s, not started, speed 1.25, "
                               "0 collisions, 0 sub-steps, 0 rollbacks");
    rbs_projector_destroy(p);
    rbs_renderer_registry_destroy(reg);
    rbs_world_destroy(w);
    assert_non_null(setlocale(LC_ALL, "C"));
}

/* The projector's own messages: a bad speed in the definition. */
static void projector_message_writes_a_point(void **state)
{
    rbs_world *w;
    rbs_renderer_registry *reg;
    rbs_projector *p;
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    p = idle_projector(&w, &reg, -0.5);
    assert_string_equal(rbs_projector_last_error(p), "speed must be > 0 and finite, got -0.5");
    rbs_projector_destroy(p);
    rbs_renderer_registry_destroy(reg);
    rbs_world_destroy(w);
    assert_non_null(setlocale(LC_ALL, "C"));
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(speed_command_reads_c_numbers),
        cmocka_unit_test(projector_message_writes_a_point),
    };
    if (german_locale_make(argc > 1 ? argv[1] : NULL) != 0)
        return 1;
    return cmocka_run_group_tests(tests, NULL, NULL);
}
