/*
 * commands.c - the command map: what a user may type while a run goes on.
 * A const table of name, arguments, help and handler; the projector does the
 * work (rbs_projector_command), camera lines go on to the renderers.
 */
#include "cli.h"

#include <string.h>

typedef rbs_status (*rbsf_handler)(rbs_projector *projector, const char *line,
                                   char *reply, size_t reply_size);

typedef struct rbsf_command {
    const char *name;
    const char *args;
    const char *help;
    rbsf_handler handler;
} rbsf_command;

static rbs_status cmd_help(rbs_projector *projector, const char *line,
                           char *reply, size_t reply_size);
static rbs_status cmd_forward(rbs_projector *projector, const char *line,
                              char *reply, size_t reply_size);
static rbs_status cmd_camera(rbs_projector *projector, const char *line,
                             char *reply, size_t reply_size);

static const rbsf_command commands[] = {
    {"help", "[COMMAND]", "list these commands (or COMMAND's line)", cmd_help},
    {"quit", "", "stop the run; every output is finished up to the last frame",
     cmd_forward},
    {"pause", "", "hold the display on the frame shown (named in the reply); "
     "frames already made wait in the reel", cmd_forward},
    {"resume", "", "go on after a pause", cmd_forward},
    {"step", "[N]", "show N more frames (default 1; at most to the last), "
     "then stay paused",
     cmd_forward},
    {"speed", "FACTOR", "real-time factor (--realtime runs), e.g. 0.5",
     cmd_forward},
    {"status", "", "frame, simulated time, state and counters", cmd_forward},
    {"orbit", "DYAW DPITCH", "turn the SDL camera about its target, degrees",
     cmd_camera},
    {"pan", "DX DY", "move the SDL camera along the picture, metres",
     cmd_camera},
    {"zoom", "FACTOR", "SDL camera distance divided by FACTOR (2: closer)",
     cmd_camera},
    {"reset", "", "put the SDL camera back where it started", cmd_camera},
    {"view", "N", "SDL camera commands act on view N (digits only)", cmd_camera},
    {"camera", "", "describe the current SDL camera", cmd_camera},
};

#define COMMAND_COUNT (sizeof commands / sizeof commands[0])

void rbsf_command_help(char *out, size_t size)
{
    size_t i, used = 0;
    if (size == 0)
        return;
    out[0] = '\0';
    for (i = 0; i < COMMAND_COUNT && used < size; i++) {
        char head[48];
        int n;
        snprintf(head, sizeof head, "%s%s%s", commands[i].name,
                 commands[i].args[0] ? " " : "", commands[i].args);
        n = snprintf(out + used, size - used, "  %-20s %s\n", head,
                     commands[i].help);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

/* "help" lists every command; "help CMD" gives CMD's line (the argument
 * was ignored: "help quit" and "help nosuch" listed them all). */
static rbs_status cmd_help(rbs_projector *projector, const char *line,
                           char *reply, size_t reply_size)
{
    size_t n, i, len = 0;
    const char *arg = line;
    (void)projector;
    while (*arg == ' ' || *arg == '\t')
        arg++;
    arg += strlen("help");
    while (*arg == ' ' || *arg == '\t')
        arg++;
    while (arg[len] && arg[len] != ' ' && arg[len] != '\t' && arg[len] != '\r' &&
           arg[len] != '\n')
        len++;
    if (len > 0) {
        const char *after = arg + len;
        while (*after == ' ' || *after == '\t' || *after == '\r' || *after == '\n')
            after++;
        for (i = 0; i < COMMAND_COUNT && *after == '\0'; i++) {
            char head[48];
            if (strlen(commands[i].name) != len ||
                strncmp(commands[i].name, arg, len) != 0)
                continue;
            snprintf(head, sizeof head, "%s%s%s", commands[i].name,
                     commands[i].args[0] ? " " : "", commands[i].args);
            snprintf(reply, reply_size, "  %-20s %s\n", head, commands[i].help);
            return RBS_OK;
        }
        n = (size_t)snprintf(reply, reply_size,
                             "help: %s '%.*s'; commands:\n",
                             *after ? "expected one command, got" : "unknown command",
                             *after ? (int)strcspn(arg, "\r\n") : (int)len, arg);
        if (n < reply_size)
            rbsf_command_help(reply + n, reply_size - n);
        return RBS_E_INVALID;
    }
    n = (size_t)snprintf(reply, reply_size, "commands:\n");
    if (n < reply_size)
        rbsf_command_help(reply + n, reply_size - n);
    return RBS_OK;
}

static rbs_status cmd_forward(rbs_projector *projector, const char *line,
                              char *reply, size_t reply_size)
{
    rbs_status st = rbs_projector_command(projector, line, reply, reply_size);
    size_t n = strlen(reply);
    if (n + 1 < reply_size) {
        reply[n] = '\n';
        reply[n + 1] = '\0';
    }
    return st;
}

/* Camera commands go to the renderers; say so when none takes them. */
static rbs_status cmd_camera(rbs_projector *projector, const char *line,
                             char *reply, size_t reply_size)
{
    rbs_status st = cmd_forward(projector, line, reply, reply_size);
    if (st == RBS_E_NOT_FOUND)
        snprintf(reply, reply_size,
                 "no renderer of this run takes camera commands (they need "
                 "an sdl renderer with a free or mounted camera)\n");
    return st;
}

rbs_status rbsf_command_run(rbs_projector *projector, const char *line,
                            char *reply, size_t reply_size)
{
    char word[32];
    size_t i, n = 0;

    if (reply_size == 0)
        return RBS_E_INVALID;
    reply[0] = '\0';
    while (*line == ' ' || *line == '\t')
        line++;
    while (line[n] && line[n] != ' ' && line[n] != '\t' && line[n] != '\r' &&
           line[n] != '\n' && n + 1 < sizeof word) {
        word[n] = line[n];
        n++;
    }
    word[n] = '\0';
    if (word[0] == '\0')
        return RBS_OK; /* an empty line: nothing to do */
    for (i = 0; i < COMMAND_COUNT; i++)
        if (strcmp(word, commands[i].name) == 0)
            return commands[i].handler(projector, line, reply, reply_size);
    /* Unknown: say so and list what is known. */
    {
        size_t m = (size_t)snprintf(reply, reply_size,
                                    "unknown command '%s'; commands:\n", word);
        if (m < reply_size)
            rbsf_command_help(reply + m, reply_size - m);
    }
    return RBS_E_NOT_FOUND;
}
