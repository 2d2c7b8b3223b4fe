/*
 * test_commands.c - the command map of the rbsim command: every command is
 * listed by help, an unknown one answers with the list, the projector's
 * commands reach the projector, camera commands reach the renderers' hook
 * (or say that no renderer takes them).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cli.h"

static const char *const names[] = {"help",  "quit", "pause", "resume",
                                    "step",  "speed", "status", "orbit",
                                    "pan",   "zoom", "reset",  "view",
                                    "camera"};

typedef struct fixture {
    rbs_world *world;
    rbs_renderer_registry *registry;
    rbs_projector *projector;
    int orbits;
} fixture;

static rbs_status t_create(void *context, const rbs_renderer_config *config,
                           const rbs_world *world, void **instance, char *err,
                           size_t errlen)
{
    (void)config; (void)world; (void)err; (void)errlen;
    *instance = context;
    return RBS_OK;
}
static rbs_status t_draw(void *instance, const rbs_frame *f, char *err,
                         size_t errlen)
{
    (void)instance; (void)f; (void)err; (void)errlen;
    return RBS_OK;
}
static void t_destroy(void *instance) { (void)instance; }
static rbs_status t_command(void *instance, const char *line, char *out,
                            size_t outlen)
{
    fixture *f = instance;
    if (strncmp(line, "orbit ", 6) != 0)
        return RBS_E_NOT_FOUND;
    f->orbits++;
    snprintf(out, outlen, "orbited by %s", line + 6);
    return RBS_OK;
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    rbs_world_def wd;
    rbs_sphere_def sd;
    rbs_body_id id;
    rbs_renderer_class c;
    rbs_renderer_config cfg;
    rbs_projector_def def;
    rbs_world_def_init(&wd);
    wd.max_bodies = 2;
    assert_int_equal(rbs_world_create(&wd, &f->world), RBS_OK);
    rbs_sphere_def_init(&sd);
    assert_int_equal(rbs_world_add_sphere(f->world, &sd, &id), RBS_OK);
    memset(&c, 0, sizeof c);
    c.struct_size = sizeof c;
    c.name = "cam";
    c.context = f;
    c.create = t_create;
    c.draw = t_draw;
    c.destroy = t_destroy;
    c.command = t_command;
    assert_int_equal(rbs_renderer_registry_create(&f->registry), RBS_OK);
    assert_int_equal(rbs_renderer_register(f->registry, &c), RBS_OK);
    memset(&cfg, 0, sizeof cfg);
    cfg.struct_size = sizeof cfg;
    cfg.type = "cam";
    rbs_projector_def_init(&def);
    def.steps = 3;
    assert_int_equal(rbs_projector_create(f->world, f->registry, &cfg, 1, &def,
                                          &f->projector),
                     RBS_OK);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rbs_projector_destroy(f->projector);
    rbs_renderer_registry_destroy(f->registry);
    rbs_world_destroy(f->world);
    free(f);
    return 0;
}

static void help_lists_every_command(void **state)
{
    fixture *f = *state;
    char reply[4096];
    size_t i;
    assert_int_equal(rbsf_command_run(f->projector, "help", reply, sizeof reply),
                     RBS_OK);
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        char key[32];
        snprintf(key, sizeof key, "\n  %s", names[i]);
        assert_non_null(strstr(reply, key));
    }
}

/* "help CMD" gives that command's line; an unknown CMD, or two, is
 * refused with the list (the argument was ignored: "help nosuch" listed
 * every command as "help" does; a probe of session 46). */
static void help_with_a_command_gives_its_line(void **state)
{
    fixture *f = *state;
    char reply[4096];
    assert_int_equal(rbsf_command_run(f->projector, " help  step ", reply, sizeof reply),
                     RBS_OK);
    assert_string_equal(reply, "  step [N]             show N more frames (default 1; at most "
                               "to the last), then stay paused\n");
    assert_int_equal(rbsf_command_run(f->projector, "help nosuch", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_true(strncmp(reply, "help: unknown command 'nosuch'; commands:\n", 42) == 0);
    assert_non_null(strstr(reply, "\n  quit"));
    assert_int_equal(rbsf_command_run(f->projector, "help quit pause", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_true(strncmp(reply, "help: expected one command, got 'quit pause'; commands:\n",
                        56) == 0);
}

static void unknown_command_answers_with_the_list(void **state)
{
    fixture *f = *state;
    char reply[4096];
    assert_int_equal(rbsf_command_run(f->projector, "  fly me", reply,
                                      sizeof reply),
                     RBS_E_NOT_FOUND);
    assert_true(strncmp(reply, "unknown command 'fly'; commands:\n", 33) == 0);
    assert_non_null(strstr(reply, "  quit"));
    assert_non_null(strstr(reply, "  step [N]"));
    /* A prefix of a command is not the command. */
    assert_int_equal(rbsf_command_run(f->projector, "pau", reply, sizeof reply),
                     RBS_E_NOT_FOUND);
    /* Empty and blank lines do nothing. */
    assert_int_equal(rbsf_command_run(f->projector, "", reply, sizeof reply),
                     RBS_OK);
    assert_string_equal(reply, "");
    assert_int_equal(rbsf_command_run(f->projector, " \t", reply, sizeof reply),
                     RBS_OK);
    assert_string_equal(reply, "");
}

static void projector_commands_reach_the_projector(void **state)
{
    fixture *f = *state;
    char reply[1024];
    rbs_run_info info;
    assert_int_equal(rbsf_command_run(f->projector, "speed 0.25", reply,
                                      sizeof reply),
                     RBS_OK);
    assert_non_null(strstr(reply, "speed 0.25"));
    assert_int_equal(reply[strlen(reply) - 1], '\n');
    assert_int_equal(rbs_projector_status(f->projector, &info), RBS_OK);
    assert_true(info.speed == 0.25);
    assert_int_equal(rbsf_command_run(f->projector, "speed", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_non_null(strstr(reply, "speed: expected"));
    /* decimal only: strtod read "0x10" as 16 (a probe of session 40) */
    assert_int_equal(rbsf_command_run(f->projector, "speed 0x10", reply, sizeof reply),
                     RBS_E_INVALID);
    assert_non_null(strstr(reply, "got '0x10'"));
    assert_int_equal(rbs_projector_status(f->projector, &info), RBS_OK);
    assert_true(info.speed == 0.25);
    assert_int_equal(rbsf_command_run(f->projector, "step -1", reply,
                                      sizeof reply),
                     RBS_E_INVALID);
    assert_int_equal(rbsf_command_run(f->projector, "pause", reply, sizeof reply),
                     RBS_OK);
    assert_int_equal(rbs_projector_status(f->projector, &info), RBS_OK);
    assert_true(info.paused);
    assert_int_equal(rbsf_command_run(f->projector, "status", reply,
                                      sizeof reply),
                     RBS_OK);
    assert_non_null(strstr(reply, "not started"));
    assert_int_equal(rbsf_command_run(f->projector, "quit", reply, sizeof reply),
                     RBS_OK);
    assert_int_equal(rbs_projector_status(f->projector, &info), RBS_OK);
    assert_true(info.quit);
}

static void camera_commands_reach_the_renderers(void **state)
{
    fixture *f = *state;
    char reply[1024];
    assert_int_equal(rbsf_command_run(f->projector, "orbit 10 -5", reply,
                                      sizeof reply),
                     RBS_OK);
    assert_string_equal(reply, "orbited by 10 -5\n");
    assert_int_equal(f->orbits, 1);
    assert_int_equal(rbsf_command_run(f->projector, "zoom 2", reply,
                                      sizeof reply),
                     RBS_E_NOT_FOUND);
    assert_non_null(strstr(reply, "no renderer of this run takes camera"));
}

/* Any line at all gets an answer and a status, never a crash: random
 * words from the command names and junk, with random arguments. */
static void any_line_is_answered(void **state)
{
    fixture *f = *state;
    char line[300], reply[4096];
    unsigned long seed = 12345;
    int i, j;
    for (i = 0; i < 20000; i++) {
        size_t n = 0;
        int words;
        seed = seed * 6364136223846793005UL + 1442695040888963407UL;
        words = (int)(seed >> 60) % 4;
        if ((seed >> 40) % 2)
            n += (size_t)snprintf(line, sizeof line, "%s",
                                  names[(seed >> 33) % 13]);
        for (j = 0; j < words && n < sizeof line - 40; j++) {
            seed = seed * 6364136223846793005UL + 1442695040888963407UL;
            switch ((seed >> 50) % 5) {
            case 0: n += (size_t)snprintf(line + n, sizeof line - n, " %lu",
                                          seed >> 20); break;
            case 1: n += (size_t)snprintf(line + n, sizeof line - n, " -%g",
                                          (double)(seed >> 30) / 7.0); break;
            case 2: n += (size_t)snprintf(line + n, sizeof line - n, " 1e999");
                    break;
            case 3: n += (size_t)snprintf(line + n, sizeof line - n, " %c%c",
                                          (char)(33 + (seed >> 8) % 90),
                                          (char)(1 + (seed >> 16) % 126));
                    break;
            default: n += (size_t)snprintf(line + n, sizeof line - n, "\t");
            }
        }
        if (strncmp(line, "quit", 4) == 0 || strncmp(line, "pause", 5) == 0)
            continue; /* keep the projector as it is */
        rbsf_command_run(f->projector, line, reply, sizeof reply);
        assert_true(strlen(reply) < sizeof reply);
    }
    /* A line longer than a command may be. */
    memset(line, 'x', sizeof line - 1);
    line[sizeof line - 1] = '\0';
    memcpy(line, "speed ", 6);
    assert_int_equal(rbs_projector_command(f->projector, line, reply,
                                           sizeof reply),
                     RBS_E_INVALID);
    assert_non_null(strstr(reply, "too long"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(help_lists_every_command, setup, teardown),
        cmocka_unit_test_setup_teardown(help_with_a_command_gives_its_line, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(unknown_command_answers_with_the_list,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(projector_commands_reach_the_projector,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(camera_commands_reach_the_renderers,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(any_line_is_answered, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
