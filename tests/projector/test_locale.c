/*
 * test_locale.c - the dumpers and the projector's commands write and read
 * numbers in the "C" locale whatever the calling process's: a program that
 * called setlocale(LC_ALL, "") under German settings (decimal comma) got
 * CSV rows with a field per comma ("-0,5" split in two), invalid JSON
 * ("position":[-0,5,...]) and "speed 0.5" refused while "speed 0,5" was
 * taken.  The locale is made by german_locale.h in the folder given as the
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
#include "dump.h"
#include "rbsim/reel.h"

static const char *out_dir;

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

/* Read a whole file (NUL-terminated); *n gets its length. */
static char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    long len;
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    len = ftell(f);
    assert_true(len >= 0);
    rewind(f);
    buf = malloc((size_t)len + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)len, f), (size_t)len);
    buf[len] = '\0';
    fclose(f);
    *n = (size_t)len;
    return buf;
}

static const char *const kinds[] = {"csv", "json", "stats"};

/* Run 200 steps with the three dumpers writing OUT_DIR/TAG.KIND; the
 * renderer thread is the projector's own, which a thread's uselocale does
 * not reach: it runs in the process's locale. */
static void run_dumpers(const char *tag)
{
    rbs_world *w = make_world();
    rbs_renderer_registry *reg;
    rbs_renderer_config cfg[3];
    rbs_projector_def def;
    rbs_projector *p = NULL;
    char paths[3][4200];
    rbs_status st;
    int i;
    assert_int_equal(rbs_renderer_registry_create(&reg), RBS_OK);
    assert_int_equal(rbs_renderer_register(reg, rbsf_csv_class()), RBS_OK);
    assert_int_equal(rbs_renderer_register(reg, rbsf_json_class()), RBS_OK);
    assert_int_equal(rbs_renderer_register(reg, rbsf_stats_class()), RBS_OK);
    memset(cfg, 0, sizeof cfg);
    for (i = 0; i < 3; i++) {
        snprintf(paths[i], sizeof paths[i], "%s/%s.%s", out_dir, tag, kinds[i]);
        cfg[i].struct_size = sizeof cfg[i];
        cfg[i].type = kinds[i];
        cfg[i].path = paths[i];
    }
    rbs_projector_def_init(&def);
    def.steps = 200;
    st = rbs_projector_create(w, reg, cfg, 3, &def, &p);
    if (st == RBS_OK)
        st = rbs_projector_run(p);
    if (st != RBS_OK)
        fail_msg("run (%s): %s", tag, rbs_projector_last_error(p));
    rbs_projector_destroy(p);
    rbs_renderer_registry_destroy(reg);
    rbs_world_destroy(w);
}

/* The three outputs made under German settings are the bytes made under
 * "C": a decimal comma would add CSV fields and break JSON. */
static void dumpers_write_c_numbers(void **state)
{
    int i;
    (void)state;
    assert_non_null(setlocale(LC_ALL, "C"));
    run_dumpers("c");
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    run_dumpers("de");
    assert_non_null(setlocale(LC_ALL, "C"));
    for (i = 0; i < 3; i++) {
        char a[4200], b[4200];
        size_t na, nb;
        char *ca, *cb;
        snprintf(a, sizeof a, "%s/c.%s", out_dir, kinds[i]);
        snprintf(b, sizeof b, "%s/de.%s", out_dir, kinds[i]);
        ca = slurp(a, &na);
        cb = slurp(b, &nb);
        /* the control: "C" output has fractions to get wrong */
        assert_non_null(strstr(ca, "0.5"));
        if (na != nb || memcmp(ca, cb, na) != 0) {
            size_t k = 0;
            while (k < na && k < nb && ca[k] == cb[k])
                k++;
            fail_msg("%s output differs under " GERMAN_LOCALE " from byte %lu: "
                     "\"%.40s\" (C) vs \"%.40s\"", kinds[i], (unsigned long)k,
                     ca + k, cb + k);
        }
        free(ca);
        free(cb);
    }
}

/* rbsf_format_double, which the rbsim command uses for its messages too,
 * writes '.' whatever the thread's locale. */
static void format_double_writes_a_point(void **state)
{
    char b[40];
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    assert_int_equal(rbsf_format_double(b, sizeof b, -0.5), 4);
    assert_string_equal(b, "-0.5");
    /* 0.1 takes the search for the shortest form, which reads each try
     * back: read with a comma, "0.1" would fail and all 17 digits show */
    assert_int_equal(rbsf_format_double(b, sizeof b, 0.1), 3);
    assert_string_equal(b, "0.1");
    assert_int_equal(rbsf_format_double(b, sizeof b, 1.0 / 3.0), 18);
    assert_string_equal(b, "0.3333333333333333");
    assert_int_equal(rbsf_format_double(b, sizeof b, 2.5e-7), 7);
    assert_string_equal(b, "2.5e-07");
    assert_non_null(setlocale(LC_ALL, "C"));
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
        cmocka_unit_test(dumpers_write_c_numbers),
        cmocka_unit_test(format_double_writes_a_point),
        cmocka_unit_test(speed_command_reads_c_numbers),
        cmocka_unit_test(projector_message_writes_a_point),
    };
    out_dir = argc > 1 ? argv[1] : NULL;
    if (german_locale_make(out_dir) != 0)
        return 1;
    return cmocka_run_group_tests(tests, NULL, NULL);
}
