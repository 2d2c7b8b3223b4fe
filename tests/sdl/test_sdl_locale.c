/*
 * test_sdl_locale.c - the "sdl" renderer reads and writes numbers in the
 * "C" locale whatever the calling process's: under German settings
 * (setlocale(LC_ALL, "") with a decimal comma) "zoom 1.5" was refused, the
 * camera replies and entry messages read "0,5", and the legend printed
 * "T=0,250 S".  The locale is made by german_locale.h in the folder given
 * as the first argument (also the base of the outputs).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../german_locale.h"
#include "sdl_test_util.h"

/* One frame at t = 0.25 s (legend "T=0.250 S") and the contact sheet
 * (caption "0 T=0.250") into folder name. */
static void draw_one(const char *name)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    const char *json = "{\"width\":160,\"height\":120,\"window\":false,"
                       "\"contact_sheet\":true}";
    char err[512];
    void *inst = NULL;
    tu_frame f;
    assert_int_equal(tu_create(json, tu_dir(name), &inst, err, sizeof err), RBS_OK);
    tu_frame_init(&f, 0, 0.25);
    tu_add_sphere(&f, "ball", 0, 0, 0.5, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
}

/* Pixels of two PNG files equal (the legend and the caption are drawn
 * text: a ',' is another glyph than '.'). */
static void same_pixels(const char *file)
{
    char a[1400], b[1400];
    SDL_Surface *sa, *sb;
    int x, y;
    snprintf(a, sizeof a, "%s/%s", tu_dir("c"), file);
    snprintf(b, sizeof b, "%s/%s", tu_dir("de"), file);
    sa = tu_load(a);
    sb = tu_load(b);
    assert_non_null(sa);
    assert_non_null(sb);
    assert_int_equal(sa->w, sb->w);
    assert_int_equal(sa->h, sb->h);
    for (y = 0; y < sa->h; y++)
        for (x = 0; x < sa->w; x++)
            if (tu_pixel(sa, x, y) != tu_pixel(sb, x, y))
                fail_msg("%s: pixel (%d, %d) differs under " GERMAN_LOCALE, file, x, y);
    SDL_FreeSurface(sa);
    SDL_FreeSurface(sb);
}

/* The picture and the contact sheet are the same under German settings as
 * under "C". */
static void legend_writes_a_point(void **state)
{
    (void)state;
    assert_non_null(setlocale(LC_ALL, "C"));
    draw_one("c");
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    draw_one("de");
    assert_non_null(setlocale(LC_ALL, "C"));
    same_pixels("frame_000000.png");
    same_pixels("contact_sheet.png");
}

/* Camera commands take "1.5" (not "1,5") and reply with '.'. */
static void commands_read_c_numbers(void **state)
{
    const rbs_renderer_class *cls = rbsf_sdl_class();
    char err[512], out[512];
    void *inst = NULL;
    tu_frame f;
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    assert_int_equal(tu_create("{\"width\":160,\"height\":120,\"window\":false,"
                               "\"contact_sheet\":false,\"camera\":{\"mode\":\"free\","
                               "\"position\":[5,0,1],\"target\":[0,0,1]}}",
                               tu_dir("commands"), &inst, err, sizeof err),
                     RBS_OK);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 1, 0.5, 0xd03030);
    assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    assert_int_equal(cls->command(inst, "zoom 1.5", out, sizeof out), RBS_OK);
    assert_string_equal(out, "view 0: zoom: distance 5 m -> 3.33 m");
    assert_int_equal(cls->command(inst, "zoom 1,5", out, sizeof out), RBS_E_INVALID);
    assert_string_equal(out, "zoom: expected a decimal number, got '1,5'; "
                             "usage: zoom FACTOR (> 0, 2 = twice as close)");
    assert_int_equal(cls->command(inst, "pan 0.5 0.25", out, sizeof out), RBS_OK);
    assert_string_equal(out, "view 0: pan: target (0, 0.5, 1.25) m");
    cls->destroy(inst);
    assert_non_null(setlocale(LC_ALL, "C"));
}

/* An entry's message writes the value given with '.'. */
static void entry_message_writes_a_point(void **state)
{
    char err[512];
    void *inst = NULL;
    (void)state;
    assert_non_null(setlocale(LC_ALL, GERMAN_LOCALE));
    assert_int_equal(tu_create("{\"window\":false,\"camera\":{\"fov\":180.5}}",
                               tu_dir("entry"), &inst, err, sizeof err),
                     RBS_E_INVALID);
    assert_null(inst);
    assert_string_equal(err, "camera.fov: must be in [1e-6, 180) degrees, got 180.5");
    assert_non_null(setlocale(LC_ALL, "C"));
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(legend_writes_a_point),
        cmocka_unit_test(commands_read_c_numbers),
        cmocka_unit_test(entry_message_writes_a_point),
    };
    if (german_locale_make(argc > 1 ? argv[1] : NULL) != 0)
        return 1;
    tu_set_base(argv[1]);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
