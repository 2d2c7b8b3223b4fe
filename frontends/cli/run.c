/*
 * run.c - "rbsim run": load a scene (or the built-in demonstration), apply
 * the command line, check every output before any is opened, then run the
 * projector with an input thread (commands on stdin) and a signal thread
 * (Ctrl-C, SIGTERM, SIGHUP), and print a summary.
 */
#include "cli.h"
#include "shown.h"
#include "demo.h"
#include "dump.h"
#ifdef RBSF_HAVE_SDL
#include "sdl_renderer.h"
#endif

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <stdarg.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define DEMO_DIR "rbsim-demo"

typedef struct run_options {
    const char *scene;
    uint64_t steps;      /* with steps_given; else the scene's */
    int steps_given;     /* --steps N was given (N may be 0) */
    double dt;           /* <= 0: the scene's */
    const char *method;  /* NULL: the scene's */
    double slop;         /* 0: the scene's */
    const char *csv, *json, *stats, *png;
    uint32_t every;      /* 0: every frame */
    int realtime, quiet, paused;
    double speed;
    uint32_t reel;
    uint32_t threads;    /* threads that step the world, the simulation
                            thread's own included (1: no pool) */
    const char *checkpoint; /* --checkpoint FILE or NULL */
    uint64_t checkpoint_every; /* 0: only at the end */
    const char *resume;     /* --resume FILE or NULL */
} run_options;

/* The after_step hook's state: written on the simulation thread while the
 * projector runs, read by the main thread only after rbs_projector_wait. */
typedef struct checkpointer {
    const char *name; /* as given, for messages */
    const char *path; /* its links followed: the file rename() replaces */
    uint64_t every;   /* save when frame % every == 0; 0: never on the way */
    uint64_t last;    /* the run's last frame: always saved */
    int saved;        /* a checkpoint was written */
    uint64_t saved_at;/* its frame */
} checkpointer;

/* One renderer to attach, with where it came from. */
typedef struct output {
    rbs_renderer_config config;
    int from_scene;        /* 1: a scene entry (errors exit 3), 0: argv (2) */
    uint32_t scene_index;  /* a scene entry's index in "renderers" */
    char *owned_json;      /* JSON text made here, freed at the end */
    char *owned_path;
    /* A file output staged by stage_output: the renderer writes work, which
     * is target itself (made here) or a temporary renamed onto target once
     * the run has started. */
    char *target, *work;
    int created, made_dir, temporary;
} output;

/* ---- argument parsing --------------------------------------------------- */

/* (a and b repeat the command line: shown safely, shown.h) */
static int usage_error(const char *fmt, const char *a, const char *b)
{
    char sa[256], sb[256];
    rbsf__tell(stderr, "rbsim run: ");
    rbsf__tell(stderr, fmt, rbsf__shown(a, sa, sizeof sa), rbsf__shown(b, sb, sizeof sb));
    rbsf__tell(stderr, "\ntry 'rbsim help run'\n");
    return RBSF_EXIT_USAGE;
}

static int parse_u64(const char *s, uint64_t min, uint64_t max, uint64_t *out)
{
    char *end;
    unsigned long long v;
    if (s == NULL || *s < '0' || *s > '9')
        return -1;
    errno = 0;
    v = strtoull(s, &end, 10);
    if (errno != 0 || *end != '\0' || v < min || v > max)
        return -1;
    *out = (uint64_t)v;
    return 0;
}

/* A positive finite decimal number (digits, '.', an exponent: "0.001",
 * "1e-3"; not strtod's hexadecimal, "inf" or leading blanks, which a scene
 * file's JSON would not take either). */
static int parse_positive(const char *s, double *out)
{
    char *end;
    double v;
    if (s == NULL || *s == '\0' || s[strspn(s, "0123456789.eE+-")] != '\0')
        return -1;
    errno = 0;
    v = strtod(s, &end);
    /* (ERANGE with a subnormal result is a number the scene's JSON takes
     * too, 5e-324; with 0 or infinity it is not one) */
    if ((errno != 0 && !(errno == ERANGE && v > 0 && v < DBL_MIN)) || *end != '\0' || !isfinite(v) ||
        !(v > 0))
        return -1;
    *out = v;
    return 0;
}

/* What a decimal number that parse_positive refused is beyond: "" or a
 * note for a value past double precision's range either way. */
static const char *range_note(const char *s)
{
    double v;
    if (s == NULL || *s == '\0' || s[strspn(s, "0123456789.eE+-")] != '\0')
        return "";
    errno = 0;
    v = strtod(s, NULL);
    if (errno == ERANGE && v == 0.0)
        return " (below the smallest double, about 4.9e-324: it reads as 0)";
    if (errno == ERANGE && isinf(v))
        return " (beyond the largest double, about 1.8e308)";
    return "";
}

#define RUN_STR_(x) #x
#define RUN_STR(x) RUN_STR_(x)

/* Every option of "rbsim run", flags and those that take a value. */
static const char *const run_option_names[] = {
    "--steps", "--dt", "--method", "--slop", "--csv", "--json", "--stats",
    "--png", "--every", "--realtime", "--speed", "--paused", "--reel",
    "--threads", "--quiet", "--checkpoint", "--checkpoint-every", "--resume", NULL};

/* Is a (up to any '=') the name of an option of "rbsim run"? */
static int is_run_option(const char *a)
{
    size_t i, n = strcspn(a, "=");
    for (i = 0; run_option_names[i] != NULL; i++)
        if (strlen(run_option_names[i]) == n &&
            strncmp(a, run_option_names[i], n) == 0)
            return 1;
    return 0;
}

/* Options take their value as the next argument or after '='.  A next
 * argument that is itself an option ("--csv --quiet") is a missing value. */
static int parse_run_args(int argc, char **argv, run_options *o)
{
    int i, seen_reel = 0, seen_speed = 0, seen_threads = 0;
    memset(o, 0, sizeof *o);
    o->speed = 1.0;
    o->reel = 64;
    o->threads = 1;
    for (i = 0; i < argc; i++) {
        const char *a = argv[i], *value = NULL, *eq;
        char name[32];
        size_t n;
        uint64_t u;
        if (a[0] != '-' || strcmp(a, "-") == 0) {
            if (o->scene != NULL)
                return usage_error("one scene at most, got '%s' and '%s'",
                                   o->scene, a);
            o->scene = rbsf_scene_arg(a);
            continue;
        }
        if (strcmp(a, "--") == 0) {
            if (i + 1 < argc && o->scene == NULL)
                o->scene = rbsf_scene_arg(argv[++i]);
            if (i + 1 < argc)
                return usage_error("unexpected argument '%s'%s", argv[i + 1], "");
            break;
        }
        eq = strchr(a, '=');
        n = eq ? (size_t)(eq - a) : strlen(a);
        if (n >= sizeof name)
            return usage_error("unknown option '%s'%s", a, "");
        memcpy(name, a, n);
        name[n] = '\0';
        /* Flags. */
        if (strcmp(name, "--realtime") == 0 || strcmp(name, "--quiet") == 0 ||
            strcmp(name, "--paused") == 0) {
            int *flag = name[2] == 'r' ? &o->realtime
                        : name[2] == 'q' ? &o->quiet : &o->paused;
            if (eq)
                return usage_error("%s takes no value%s", name, "");
            /* Every option once, a flag as a value option ("--paused
             * --paused" was taken; "--csv a --csv b" never was). */
            if (*flag)
                return usage_error("%s given twice%s", name, "");
            *flag = 1;
            continue;
        }
        if (strcmp(name, "--steps") && strcmp(name, "--dt") &&
            strcmp(name, "--method") && strcmp(name, "--slop") && strcmp(name, "--csv") &&
            strcmp(name, "--json") && strcmp(name, "--stats") &&
            strcmp(name, "--png") && strcmp(name, "--every") &&
            strcmp(name, "--reel") && strcmp(name, "--speed") &&
            strcmp(name, "--threads") &&
            strcmp(name, "--checkpoint") && strcmp(name, "--checkpoint-every") &&
            strcmp(name, "--resume"))
            return usage_error("unknown option '%s'%s", name, "");
        if ((strcmp(name, "--steps") == 0 && o->steps_given) ||
            (strcmp(name, "--dt") == 0 && o->dt > 0) ||
            (strcmp(name, "--method") == 0 && o->method) ||
            (strcmp(name, "--slop") == 0 && o->slop > 0) ||
            (strcmp(name, "--csv") == 0 && o->csv) ||
            (strcmp(name, "--json") == 0 && o->json) ||
            (strcmp(name, "--stats") == 0 && o->stats) ||
            (strcmp(name, "--png") == 0 && o->png) ||
            (strcmp(name, "--every") == 0 && o->every) ||
            (strcmp(name, "--reel") == 0 && seen_reel) ||
            (strcmp(name, "--threads") == 0 && seen_threads) ||
            (strcmp(name, "--checkpoint") == 0 && o->checkpoint) ||
            (strcmp(name, "--checkpoint-every") == 0 && o->checkpoint_every) ||
            (strcmp(name, "--resume") == 0 && o->resume) ||
            (strcmp(name, "--speed") == 0 && seen_speed))
            return usage_error("%s given twice%s", name, "");
        seen_reel |= strcmp(name, "--reel") == 0;
        seen_speed |= strcmp(name, "--speed") == 0;
        seen_threads |= strcmp(name, "--threads") == 0;
        if (eq)
            value = eq + 1;
        else if (i + 1 < argc && !is_run_option(argv[i + 1]))
            value = argv[++i];
        else if (i + 1 < argc) {
            char shown[256];
            rbsf__shown(argv[i + 1], shown, sizeof shown);
            rbsf__tell(stderr, "rbsim run: %s needs a value, got the option '%s' "
                            "(a file of that name: write ./%s or %s=%s)\n"
                            "try 'rbsim help run'\n",
                    name, shown, shown, name, shown);
            return RBSF_EXIT_USAGE;
        }
        else
            return usage_error("%s needs a value%s", name, "");
        if (strcmp(name, "--steps") == 0) {
            if (parse_u64(value, 0, 9007199254740992ULL, &o->steps) != 0)
                return usage_error("--steps: expected a whole number from 0 to "
                                   "2^53, got '%s'%s", value, "");
            o->steps_given = 1;
        } else if (strcmp(name, "--dt") == 0) {
            if (parse_positive(value, &o->dt) != 0)
                return usage_error("--dt: expected a time step in seconds, > 0, "
                                   "got '%s'%s", value, range_note(value));
        } else if (strcmp(name, "--slop") == 0) {
            if (parse_positive(value, &o->slop) != 0 || !(o->slop < 0.1))
                return usage_error("--slop: expected a fraction of the smaller "
                                   "radius in (0, 0.1), got '%s'%s", value, range_note(value));
        } else if (strcmp(name, "--speed") == 0) {
            if (parse_positive(value, &o->speed) != 0 || o->speed > 1e6)
                return usage_error("--speed: expected a factor > 0 and <= 1e6, "
                                   "got '%s'%s", value, range_note(value));
        } else if (strcmp(name, "--method") == 0) {
            rbs_method m;
            char list[256];
            if (rbs_method_from_name(value, &m) != RBS_OK) {
                rbsf_method_list(list, sizeof list);
                return usage_error("--method: unknown method '%s'; expected %s",
                                   value, list);
            }
            o->method = value;
        } else if (strcmp(name, "--every") == 0) {
            if (parse_u64(value, 1, RBS_EVERY_MAX, &u) != 0)
                return usage_error("--every: expected a whole number from 1 to "
                                   "2147483647 (2^31 - 1), got '%s'%s", value, "");
            o->every = (uint32_t)u;
        } else if (strcmp(name, "--reel") == 0) {
            if (parse_u64(value, 2, 1u << 20, &u) != 0)
                return usage_error("--reel: expected a capacity from 2 to "
                                   "1048576 frames, got '%s'%s", value, "");
            o->reel = (uint32_t)u;
        } else if (strcmp(name, "--threads") == 0) {
            if (parse_u64(value, 1, RBS_WORKERS_MAX, &u) != 0)
                return usage_error("--threads: expected a whole number of "
                                   "threads from 1 to " RUN_STR(RBS_WORKERS_MAX)
                                   ", got '%s'%s", value, "");
            o->threads = (uint32_t)u;
        } else if (strcmp(name, "--checkpoint-every") == 0) {
            if (parse_u64(value, 1, 9007199254740992ULL, &o->checkpoint_every) != 0)
                return usage_error("--checkpoint-every: expected a whole number "
                                   "of steps from 1 to 2^53, got '%s'%s", value, "");
        } else if (value[0] == '\0') {
            return usage_error("%s: expected a path, got an empty string%s",
                               name, "");
        } else if (strcmp(name, "--csv") == 0) {
            o->csv = value;
        } else if (strcmp(name, "--json") == 0) {
            o->json = value;
        } else if (strcmp(name, "--stats") == 0) {
            o->stats = value;
        } else if (strcmp(name, "--checkpoint") == 0) {
            o->checkpoint = value;
        } else if (strcmp(name, "--resume") == 0) {
            o->resume = rbsf_scene_arg(value); /* "-": standard input too */
        } else {
            o->png = value;
        }
    }
    if (o->resume != NULL && o->scene != NULL && strcmp(o->resume, "/dev/stdin") == 0 &&
        strcmp(o->scene, "/dev/stdin") == 0)
        return usage_error("the scene and --resume cannot both be standard "
                           "input ('%s')%s", "-", "");
    if (o->checkpoint_every && !o->checkpoint)
        return usage_error("--checkpoint-every needs --checkpoint FILE%s%s", "",
                           "");
    if ((o->checkpoint || o->resume) && o->scene == NULL)
        return usage_error("--checkpoint and --resume need a SCENE (not the "
                           "demonstration)%s%s", "", "");
    /* The demonstration checks its run against exact answers made for its
     * own steps, time step, method and slop: with others they would fail
     * (too few steps never reach the impact) or check nothing meant. */
    if (o->scene == NULL && (o->steps_given || o->dt > 0 || o->method || o->slop > 0))
        return usage_error("%s changes the built-in demonstration, which "
                           "checks its run against exact answers for its own "
                           "steps, dt, method and slop: give a SCENE to run "
                           "with it%s",
                           o->steps_given ? "--steps" : o->dt > 0 ? "--dt"
                                            : o->method ? "--method" : "--slop",
                           "");
    if (seen_speed && !o->realtime)
        return usage_error("--speed sets the pace of --realtime, and a run "
                           "without it goes as fast as it can: give "
                           "--realtime too%s%s", "", "");
    /* --every thins the command line's --csv, --json and --png (the
     * demonstration's own outputs included); without one it would change
     * nothing, silently: a scene's renderer keeps its own "every", and
     * --stats keeps every frame. */
    if (o->every && o->scene != NULL && !o->csv && !o->json && !o->png)
        return usage_error("--every K keeps every K-th frame of --csv, --json "
                           "and --png, and this run has none of them (a "
                           "scene's renderer takes \"every\" in its entry; "
                           "--stats keeps every frame)%s%s", "", "");
    return 0;
}

/* ---- scene -------------------------------------------------------------- */

void rbsf_print_scene_errors(const rbs_scene *scene, FILE *out)
{
    uint32_t i, n = rbs_scene_error_count(scene);
    for (i = 0; i < n && i < RBS_SCENE_ERRORS_MAX; i++) {
        rbs_scene_error e;
        if (rbs_scene_error_get(scene, i, &e) == RBS_OK)
            fprintf(out, "%s\n", e.text);
    }
    if (n > RBS_SCENE_ERRORS_MAX)
        fprintf(out, "... and %lu more errors\n",
                (unsigned long)(n - RBS_SCENE_ERRORS_MAX));
}

void rbsf_print_build_failure(const rbs_scene *scene, rbs_status st, const char *prefix, const char *path,
                              FILE *out)
{
    rbs_world_def def;
    size_t need;
    if (st == RBS_E_MEMORY && rbs_scene_world_def(scene, &def) == RBS_OK &&
        (need = rbs_world_memory_size(&def)) != 0) {
        /* (the one allocation of the world: say how much, and what it is
         * for, so that a user knows which capacity to lower) */
        const int gb = need >= 1000000000u;
        rbsf__tell(out,
                   "%s%s: cannot build the world: %s: its memory, %.1f %s for max_bodies %lu and "
                   "max_contacts %lu (simulation.max_contacts), could not be reserved\n",
                   prefix, path, rbs_status_string(st), (double)need / (gb ? 1e9 : 1e6), gb ? "GB" : "MB",
                   (unsigned long)def.max_bodies, (unsigned long)def.max_contacts);
        return;
    }
    rbsf__tell(out, "%s%s: cannot build the world: %s\n", prefix, path, rbs_status_string(st));
}

void rbsf_print_scene_warnings(const rbs_scene *scene, FILE *out)
{
    uint32_t i, n = rbs_scene_warning_count(scene);
    for (i = 0; i < n && i < RBS_SCENE_ERRORS_MAX; i++) {
        rbs_scene_error e;
        size_t at;
        if (rbs_scene_warning_get(scene, i, &e) != RBS_OK)
            continue;
        /* "FILE:LINE:COL: PATH: warning: MESSAGE" (text ends in message) */
        at = strlen(e.text) - strlen(e.message);
        fprintf(out, "%.*swarning: %s\n", (int)at, e.text, e.message);
    }
    if (n > RBS_SCENE_ERRORS_MAX)
        fprintf(out, "... and %lu more warnings\n",
                (unsigned long)(n - RBS_SCENE_ERRORS_MAX));
}

int rbsf_override_options(rbs_scene *scene, uint64_t steps, double dt, const char *method, const char *what)
{
    const rbs_status st = rbs_scene_override(scene, steps, dt, method);
    if (st == RBS_OK)
        return 0;
    if (rbs_scene_error_count(scene) > 0)
        rbsf_print_scene_errors(scene, stderr);
    else
        rbsf__tell(stderr, "%s: %s\n", what, rbs_status_string(st));
    return RBSF_EXIT_USAGE;
}

/* Load a scene file or the demonstration; on failure print why.  The
 * reading may block (a FIFO with no writer, a pipe whose writer stalls): it
 * is done in a slot of the signal thread's stopper, so that SIGINT, SIGTERM
 * or SIGHUP end it (they were taken and the read went on waiting: only
 * SIGKILL ended `rbsim run FIFO`).  -1 on failure, or 128 + the signal
 * when a signal stopped it (said on stderr). */
static int load_scene(const char *path, rbs_scene **out, rbsf_signals *signals)
{
    rbs_status st;
    int slot, sig;
    *out = NULL;
    slot = rbsf_stopper_enter(&signals->stopper);
    if (path != NULL)
        st = rbs_scene_load(path, RBS_SCENE_AUTO, out);
    else
        st = rbs_scene_parse_json(rbsf_demo_scene, strlen(rbsf_demo_scene),
                                  "(built-in demonstration)", out);
    rbsf_stopper_leave(&signals->stopper, slot);
    if (st == RBS_OK) {
        rbsf_print_scene_warnings(*out, stderr); /* (even with --quiet) */
        return 0;
    }
    if ((sig = rbsf_signals_caught(signals)) != 0) {
        rbsf__tell(stderr, "rbsim: stopped by %s before the run started: while "
                        "reading the scene '%s'\n",
                rbsf_signal_name(sig), path ? path : "(built-in demonstration)");
        rbs_scene_free(*out);
        *out = NULL;
        return 128 + sig;
    }
    if (*out != NULL && rbs_scene_error_count(*out) > 0)
        rbsf_print_scene_errors(*out, stderr);
    else
        rbsf__tell(stderr, "rbsim: %s: %s\n", path ? path : "demonstration",
                rbs_status_string(st));
    rbsf_scene_hint(stderr, path, st);
    rbs_scene_free(*out);
    *out = NULL;
    return -1;
}

/* ---- outputs ------------------------------------------------------------ */

/* Whether a file output's path names the file this process's standard
 * output is (/dev/stdout, /dev/fd/1, or the very file stdout is redirected
 * to): such an output is written as "-", to the stream itself.  Staged as
 * a file it was replaced by rename (what stdout held before, and what came
 * after, lost), failed on a pipe, and escaped the one-output-on-stdout
 * rule. */
/* fstat of standard output, -1 when it cannot be written: a closed one is
 * /dev/null opened for reading (main.c), which is no file an output should
 * be taken for ("--csv /dev/null" with stdout closed was written as "-" and
 * failed: a probe of session 46). */
static int stdout_stat(struct stat *b)
{
    int fl = fcntl(STDOUT_FILENO, F_GETFL);
    if (fl == -1 || (fl & O_ACCMODE) == O_RDONLY)
        return -1;
    return fstat(STDOUT_FILENO, b);
}

static int is_stdout(const char *type, const char *path)
{
    struct stat a, b;
    if (path == NULL || strcmp(path, "-") == 0 ||
        (strcmp(type, "csv") && strcmp(type, "json") && strcmp(type, "stats")))
        return 0;
    return stat(path, &a) == 0 && stdout_stat(&b) == 0 && a.st_dev == b.st_dev &&
           a.st_ino == b.st_ino;
}

/* A renderer entry made on the command line, as the JSON a scene would
 * hold. */
static char *entry_json(const char *type, const char *path, uint32_t every,
                        int no_window)
{
    cJSON *o = cJSON_CreateObject();
    char *text;
    if (o == NULL)
        return NULL;
    cJSON_AddStringToObject(o, "type", type);
    if (path)
        cJSON_AddStringToObject(o, "path", path);
    if (every > 1)
        cJSON_AddNumberToObject(o, "every", every);
    if (no_window)
        cJSON_AddFalseToObject(o, "window");
    text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

static int add_output(output *outs, uint32_t *n, const char *type,
                      const char *path, uint32_t every, int no_window)
{
    output *o;
    if (*n == RBS_RENDERERS_MAX) {
        rbsf__tell(stderr,
                "rbsim run: too many outputs: at most %d renderers can be "
                "attached (the scene's and --csv/--json/--stats/--png "
                "together)\n",
                RBS_RENDERERS_MAX);
        return RBSF_EXIT_USAGE;
    }
    o = &outs[(*n)++];
    memset(o, 0, sizeof *o);
    o->config.struct_size = sizeof o->config;
    o->config.type = type;
    if (is_stdout(type, path))
        path = "-";
    o->owned_path = path ? malloc(strlen(path) + 1) : NULL;
    if (path && o->owned_path)
        strcpy(o->owned_path, path);
    o->config.path = o->owned_path;
    o->config.every = every ? every : 1;
    o->owned_json = entry_json(type, path, every, no_window);
    o->config.json = o->owned_json;
    o->config.file = "(command line)";
    if ((path && !o->owned_path) || !o->owned_json) {
        rbsf__tell(stderr, "rbsim: out of memory\n");
        return RBSF_EXIT_RUN;
    }
    return 0;
}

/* The scene's renderer entries: "path" and "every" are read here for every
 * type; each type checks the rest. */
static int add_scene_outputs(const rbs_scene *scene, output *outs, uint32_t *n)
{
    uint32_t i, count = rbs_scene_renderer_count(scene);
    for (i = 0; i < count; i++) {
        rbs_scene_renderer r;
        output *o;
        cJSON *root;
        const cJSON *item;
        if (rbs_scene_renderer_get(scene, i, &r) != RBS_OK)
            continue;
        if (*n == RBS_RENDERERS_MAX) {
            rbsf__tell(stderr, "%s:%d:%d: too many renderers (at most %d)\n",
                    r.file, (int)r.line, (int)r.column, RBS_RENDERERS_MAX);
            return RBSF_EXIT_SCENE;
        }
        o = &outs[(*n)++];
        memset(o, 0, sizeof *o);
        o->from_scene = 1;
        o->scene_index = i;
        o->config.struct_size = sizeof o->config;
        o->config.type = r.type;
        o->config.json = r.json;
        o->config.file = r.file;
        o->config.line = r.line;
        o->config.column = r.column;
        o->config.every = 1;
        root = cJSON_Parse(r.json);
        item = cJSON_GetObjectItemCaseSensitive(root, "path");
        if (cJSON_IsString(item)) {
            const char *path = is_stdout(r.type, item->valuestring) ? "-" : item->valuestring;
            o->owned_path = malloc(strlen(path) + 1);
            if (o->owned_path)
                strcpy(o->owned_path, path);
            o->config.path = o->owned_path;
        }
        item = cJSON_GetObjectItemCaseSensitive(root, "every");
        if (cJSON_IsNumber(item) && item->valuedouble >= 1 &&
            item->valuedouble <= (double)RBS_EVERY_MAX)
            o->config.every = (uint32_t)item->valuedouble;
        cJSON_Delete(root);
    }
    return 0;
}

static void free_outputs(output *outs, uint32_t n)
{
    uint32_t i;
    for (i = 0; i < n; i++) {
        cJSON_free(outs[i].owned_json);
        free(outs[i].owned_path);
        free(outs[i].target);
        free(outs[i].work);
    }
}

/* The demonstration's output folder path, made if missing.  0, or -1 after
 * saying why (a file in its place is named as such: "File exists" did not
 * say what to do). */
static int make_demo_dir(const char *path)
{
    struct stat sb;
    if (mkdir(path, 0777) == 0)
        return 0;
    if (errno == EEXIST && stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return 0;
    if (errno == EEXIST)
        rbsf__tell(stderr, "rbsim run: the demonstration writes its outputs in "
                        "the folder '%s', and '%s' here is not a folder: move "
                        "it, or run the demonstration in another folder\n",
                path, path);
    else
        rbsf__tell(stderr, "rbsim run: the demonstration cannot create its "
                        "output folder '%s': %s (run it in a folder you can "
                        "write in)\n",
                path, strerror(errno));
    return -1;
}

/* A copy of path with its symbolic links followed to the file they name
 * (which need not exist yet), so that a file replaced by rename() is the
 * link's target, not the link.  NULL with errno on failure. */
static char *resolve_links(const char *path)
{
    char *p = malloc(strlen(path) + 1);
    int hops;
    if (p == NULL)
        return NULL;
    strcpy(p, path);
    for (hops = 0; hops < 40; hops++) {
        struct stat sb;
        char link[4096];
        const char *slash;
        size_t dir;
        ssize_t n;
        char *next;
        if (lstat(p, &sb) != 0 || !S_ISLNK(sb.st_mode))
            return p;
        n = readlink(p, link, sizeof link - 1);
        if (n < 0) {
            free(p);
            return NULL;
        }
        link[n] = '\0';
        /* A relative link is relative to the link's folder. */
        slash = strrchr(p, '/');
        dir = link[0] == '/' || slash == NULL ? 0 : (size_t)(slash - p) + 1;
        next = malloc(dir + (size_t)n + 1);
        if (next == NULL) {
            free(p);
            return NULL;
        }
        memcpy(next, p, dir);
        memcpy(next + dir, link, (size_t)n + 1);
        free(p);
        p = next;
    }
    free(p);
    errno = ELOOP;
    return NULL;
}

/* The folder of path into out (n bytes): "." for a bare name, "/" for a
 * name at the root; the name after it into *name (if not NULL).  -1 if it
 * does not fit. */
static int folder_of(const char *path, char *out, size_t n, const char **name)
{
    const char *slash = strrchr(path, '/');
    size_t len = slash ? (size_t)(slash - path) : 0;
    if (name)
        *name = slash ? slash + 1 : path;
    if (len + 2 > n)
        return -1;
    if (slash == NULL)
        strcpy(out, ".");
    else if (len == 0)
        strcpy(out, "/");
    else {
        memcpy(out, path, len);
        out[len] = '\0';
    }
    return 0;
}

/* Where a path leads: an existing file's device and inode; for a new file,
 * its folder's, plus the name.  0 if neither can be found. */
typedef struct file_key {
    dev_t dev;
    ino_t ino;
    const char *name; /* NULL for an existing file */
    char name_buf[256]; /* the name when it comes through a link */
} file_key;

static int key_of(const char *path, file_key *k)
{
    struct stat sb;
    char dir[4096];
    char *target;
    int ok;
    if (stat(path, &sb) == 0) {
        k->dev = sb.st_dev;
        k->ino = sb.st_ino;
        k->name = NULL;
        return 1;
    }
    /* a new file: where its links lead (a link to a file not yet made
     * names that file, which another output may make too) */
    target = resolve_links(path);
    if (target == NULL)
        return 0;
    ok = folder_of(target, dir, sizeof dir, &k->name) == 0 && stat(dir, &sb) == 0;
    if (ok) {
        k->dev = sb.st_dev;
        k->ino = sb.st_ino;
        /* (kept: target is freed below) */
        strncpy(k->name_buf, k->name, sizeof k->name_buf - 1);
        k->name_buf[sizeof k->name_buf - 1] = '\0';
        k->name = k->name_buf;
    }
    free(target);
    return ok;
}

/* Two names for one file (the same text, or an existing file reached twice,
 * e.g. "a.csv" and "./a.csv"). */
static int same_file(const char *a, const char *b)
{
    file_key ka, kb;
    if (strcmp(a, b) == 0)
        return 1;
    if (!key_of(a, &ka) || !key_of(b, &kb))
        return 0;
    return ka.dev == kb.dev && ka.ino == kb.ino &&
           ((ka.name == NULL && kb.name == NULL) ||
            (ka.name != NULL && kb.name != NULL &&
             strcmp(ka.name, kb.name) == 0));
}

/* The file of scene that path names, if any: one the scene was read from
 * (its own file, a text scene's materials.txt and objects.txt), which no
 * output may overwrite; k gets its index (0: the scene's own).  NULL if
 * none. */
static const char *scene_file(const rbs_scene *scene, const char *path,
                              uint32_t *k)
{
    const char *f;
    uint32_t i;
    for (i = 0; (f = rbs_scene_source(scene, i)) != NULL; i++)
        if (same_file(path, f)) {
            if (k != NULL)
                *k = i;
            return f;
        }
    return NULL;
}

/* Whether path names the file standard input is: /dev/stdin and its other
 * names, or the same device and inode as descriptor 0 (a file redirected
 * with "<"). */
static int is_stdin(const char *path)
{
    struct stat a, b;
    if (path == NULL)
        return 0;
    if (strcmp(path, "/dev/stdin") == 0 || strcmp(path, "/dev/fd/0") == 0 ||
        strcmp(path, "/proc/self/fd/0") == 0)
        return 1;
    return fstat(STDIN_FILENO, &a) == 0 && stat(path, &b) == 0 &&
           a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

/* What the run read from standard input ("scene", "checkpoint"), so that
 * its bytes are not taken for command lines too; NULL if neither. */
static const char *stdin_taken(const rbs_scene *scene, const char *resume)
{
    const char *f;
    uint32_t i;
    if (is_stdin(resume))
        return "checkpoint";
    for (i = 0; scene != NULL && (f = rbs_scene_source(scene, i)) != NULL; i++)
        if (is_stdin(f))
            return "scene";
    return NULL;
}

/* "'s file 'F'" for a scene file after the first, "" for the scene's
 * own: the end of a "would overwrite the scene" message. */
static void scene_file_note(char *buf, size_t n, const char *f, uint32_t k)
{
    if (k == 0)
        buf[0] = '\0';
    else
        snprintf(buf, n, "'s file '%s'", f);
}

/* A path without "./" parts, doubled or trailing slashes ("pd/./a//" is
 * "pd/a"), into out (n bytes); -1 if it does not fit. */
static int tidy_path(const char *path, char *out, size_t n)
{
    size_t used = 0;
    const char *p = path;
    if (n == 0)
        return -1;
    if (*p == '/')
        out[used++] = '/';
    while (*p) {
        size_t len;
        while (*p == '/')
            p++;
        len = strcspn(p, "/");
        if (len == 0)
            break;
        if (!(len == 1 && p[0] == '.')) {
            if (used > 0 && out[used - 1] != '/')
                out[used++] = '/';
            if (used + len + 1 >= n)
                return -1;
            memcpy(out + used, p, len);
            used += len;
        }
        p += len;
    }
    if (used == 0)
        out[used++] = '.';
    out[used] = '\0';
    return 0;
}

/* Are a and b one folder: the same text once tidied, or both existing with
 * one device and inode? */
static int same_dir(const char *a, const char *b)
{
    char ta[4096], tb[4096];
    struct stat sa, sb;
    if (tidy_path(a, ta, sizeof ta) == 0 && tidy_path(b, tb, sizeof tb) == 0 &&
        strcmp(ta, tb) == 0)
        return 1;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && S_ISDIR(sa.st_mode) &&
           sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* Is name one the sdl renderer gives a frame: "frame_" then the number as
 * "%06llu" prints it (six digits, or more without a leading zero), ".png"? */
static int is_frame_png(const char *name)
{
    size_t d = 0;
    if (strncmp(name, "frame_", 6) != 0)
        return 0;
    name += 6;
    while (name[d] >= '0' && name[d] <= '9')
        d++;
    return (d == 6 || (d > 6 && name[0] != '0')) && strcmp(name + d, ".png") == 0;
}

/* The sdl entry's file layout (entry JSON json): its views (1 without a
 * "views" list), "tile" and "contact_sheet". */
static void png_layout(const char *json, int *views, int *tile, int *sheet)
{
    cJSON *root = json ? cJSON_Parse(json) : NULL;
    *views = 1;
    *tile = 0;
    *sheet = 1;
    if (root != NULL) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "views");
        const cJSON *t = cJSON_GetObjectItemCaseSensitive(root, "tile");
        const cJSON *c = cJSON_GetObjectItemCaseSensitive(root, "contact_sheet");
        if (cJSON_IsArray(v) && cJSON_GetArraySize(v) > 0)
            *views = cJSON_GetArraySize(v);
        *tile = cJSON_IsTrue(t);
        *sheet = !cJSON_IsFalse(c);
        cJSON_Delete(root);
    }
}

/* Is name "viewK" (no leading zero) with K < views? */
static int is_view_folder(const char *name, int views)
{
    char *end;
    unsigned long k;
    if (strncmp(name, "view", 4) != 0 || name[4] < '0' || name[4] > '9' ||
        (name[4] == '0' && name[5] != '\0'))
        return 0;
    k = strtoul(name + 4, &end, 10);
    return *end == '\0' && k < (unsigned long)views;
}

/* Would the sdl output folder dir (entry JSON json) write the file path?
 * The renderer writes DIR/frame_NNNNNN.png (one view, or views tiled),
 * DIR/viewK/frame_NNNNNN.png for K < views (several views, not tiled) and
 * DIR/contact_sheet.png (unless "contact_sheet": false); see
 * frontends/sdl/README.md, "Files".  1 if so, 2 if path is one of the
 * DIR/viewK folders it makes (a file there fails the renderer, or the
 * folder fails a file made there later), with the pattern in what; else
 * 0. */
static int png_folder_writes(const char *dir, const char *json,
                             const char *path, const char **what)
{
    char parent[4096], grand[4096];
    const char *name, *vname;
    int views, tile, sheet;
    png_layout(json, &views, &tile, &sheet);
    if (folder_of(path, parent, sizeof parent, &name) != 0)
        return 0;
    if (same_dir(parent, dir)) {
        if (sheet && strcmp(name, "contact_sheet.png") == 0) {
            *what = "contact_sheet.png";
            return 1;
        }
        if ((views == 1 || tile) && is_frame_png(name)) {
            *what = "frame_NNNNNN.png";
            return 1;
        }
        if (views > 1 && !tile && is_view_folder(name, views)) {
            *what = "viewK, for K below its views";
            return 2;
        }
        return 0;
    }
    /* DIR/viewK/frame_NNNNNN.png */
    if (views == 1 || tile || !is_frame_png(name))
        return 0;
    if (folder_of(parent, grand, sizeof grand, &vname) != 0 ||
        !is_view_folder(vname, views))
        return 0;
    if (!same_dir(grand, dir))
        return 0;
    *what = "viewK/frame_NNNNNN.png";
    return 1;
}

/* The start of check_distinct's message about output o: a scene entry's
 * place and key ("FILE:LINE:COL: renderers[K].path: "), else who's name. */
static void distinct_prefix(const output *o, const char *who)
{
    if (o->from_scene)
        rbsf__tell(stderr, "%s:%d:%d: renderers[%lu].path: ", o->config.file,
                (int)o->config.line, (int)o->config.column,
                (unsigned long)o->scene_index);
    else
        rbsf__tell(stderr, "%s: ", who);
}

/* Does the sdl output folder dir run through file, a file output's path (or
 * the checkpoint's): is one of the folders on dir's way that file?  Its
 * folder would be made where the file is, or the file where the folder is,
 * and one of them fails once the run has begun.  Nonzero if so, with that
 * folder's part of dir (n bytes) in part. */
static int folder_runs_through(const char *dir, const char *file, char *part,
                               size_t n)
{
    size_t i, len = strlen(dir);
    for (i = 1; i < len && i < n; i++) {
        if (dir[i] != '/' || dir[i - 1] == '/')
            continue;
        memcpy(part, dir, i);
        part[i] = '\0';
        if (same_file(part, file))
            return 1;
    }
    return 0;
}

/* "the csv and json outputs", or "two sdl outputs" for two of a type. */
static const char *two_outputs(const char *a, const char *b, char *buf,
                               size_t n)
{
    if (strcmp(a, b) == 0)
        snprintf(buf, n, "two %s outputs", a);
    else
        snprintf(buf, n, "the %s and %s outputs", a, b);
    return buf;
}

/* No two outputs may write one file (standard output included), no sdl
 * folder may run through another output's file, and none may overwrite
 * the scene or the checkpoint being resumed. */
static int check_distinct(const output *outs, uint32_t n, const rbs_scene *scene,
                          const char *resume, const char *who)
{
    uint32_t i, j, k;
    const output *on_stdout = NULL;
    const char *f;
    char both[64];
    for (i = 0; i < n; i++) {
        const char *a = outs[i].config.path;
        int sdl = strcmp(outs[i].config.type, "sdl") == 0;
        if (a != NULL && sdl && strcmp(a, "-") == 0)
            continue; /* not standard output: its check() refuses it */
        if (a != NULL && strcmp(a, "-") == 0) {
            if (on_stdout != NULL) {
                distinct_prefix(&outs[i], who);
                rbsf__tell(stderr, "%s both write "
                                "to standard output ('-'): at most one "
                                "output may\n",
                        two_outputs(on_stdout->config.type,
                                    outs[i].config.type, both,
                                    sizeof both));
                return outs[i].from_scene && on_stdout->from_scene
                           ? RBSF_EXIT_SCENE
                           : RBSF_EXIT_USAGE;
            }
            on_stdout = &outs[i];
            continue;
        }
        if (a == NULL)
            continue;
        if (resume != NULL && same_file(a, resume)) {
            distinct_prefix(&outs[i], who);
            rbsf__tell(stderr, "the %s output '%s' would overwrite the "
                            "--resume checkpoint '%s'\n",
                    outs[i].config.type, a, resume);
            return outs[i].from_scene ? RBSF_EXIT_SCENE : RBSF_EXIT_USAGE;
        }
        if ((f = scene_file(scene, a, &k)) != NULL) {
            char note[4200];
            scene_file_note(note, sizeof note, f, k);
            distinct_prefix(&outs[i], who);
            rbsf__tell(stderr, "the %s output '%s' would overwrite the "
                            "scene%s\n", outs[i].config.type, a, note);
            return outs[i].from_scene ? RBSF_EXIT_SCENE : RBSF_EXIT_USAGE;
        }
        for (j = 0; j < n; j++) {
            const char *b = outs[j].config.path, *what = NULL;
            int kind;
            if (j == i || b == NULL || strcmp(b, "-") == 0 ||
                strcmp(outs[j].config.type, "sdl") != 0 ||
                strcmp(outs[i].config.type, "sdl") == 0 ||
                !(kind = png_folder_writes(b, outs[j].config.json, a, &what)))
                continue;
            distinct_prefix(&outs[i], who);
            rbsf__tell(stderr, "the %s output '%s' is a %s the sdl "
                            "output %s in its folder '%s' (%s): give it "
                            "another name\n",
                    outs[i].config.type, a, kind == 2 ? "folder" : "file",
                    kind == 2 ? "makes" : "writes", b, what);
            return outs[i].from_scene && outs[j].from_scene ? RBSF_EXIT_SCENE
                                                            : RBSF_EXIT_USAGE;
        }
        for (j = 0; j < i; j++) {
            const char *b = outs[j].config.path;
            if (b == NULL || strcmp(b, "-") == 0 || !same_file(a, b))
                continue;
            distinct_prefix(&outs[i], who);
            rbsf__tell(stderr, "%s both write '%s'\n",
                    two_outputs(outs[j].config.type, outs[i].config.type,
                                both, sizeof both),
                    a);
            return outs[i].from_scene && outs[j].from_scene ? RBSF_EXIT_SCENE
                                                            : RBSF_EXIT_USAGE;
        }
        for (j = 0; sdl && j < n; j++) {
            const char *b = outs[j].config.path;
            char part[4096];
            if (j == i || b == NULL || strcmp(b, "-") == 0 ||
                strcmp(outs[j].config.type, "sdl") == 0 ||
                !folder_runs_through(a, b, part, sizeof part))
                continue;
            distinct_prefix(&outs[i], who);
            rbsf__tell(stderr, "the sdl output's folder '%s' runs through "
                            "'%s', which the %s output '%s' writes as a file: "
                            "give one of them another name\n",
                    a, part, outs[j].config.type, b);
            return outs[i].from_scene && outs[j].from_scene ? RBSF_EXIT_SCENE
                                                            : RBSF_EXIT_USAGE;
        }
    }
    return 0;
}


int rbsf_check_scene_outputs(const rbs_scene *scene)
{
    output outs[RBS_RENDERERS_MAX];
    uint32_t n = 0, i;
    int code = add_scene_outputs(scene, outs, &n);
    if (code == 0)
        code = check_distinct(outs, n, scene, NULL, "rbsim check");
    for (i = 0; i < n; i++)
        free(outs[i].owned_path);
    return code;
}

/* ---- png folders: this run's frames only -------------------------------- */

/* The frames a run from start to last keeps for an output of every K
 * (rbs_frame_written, reel.h: the projector's rule; a resumed run does not
 * write its starting frame, and a run saving a checkpoint keeps its last
 * frame only if it is a multiple of K): does it write frame n? */
static int run_writes_frame(uint64_t n, uint64_t start, int resumed, uint64_t last,
                            uint32_t every, int checkpoint)
{
    return n <= last && rbs_frame_written(n, every, start, resumed, n == last, checkpoint);
}

#ifdef RBSF_HAVE_SDL
/* The sdl renderer's view of the signal thread's stopper
 * (rbsf_sdl_world_api: the renderer does not link the dumpers). */
static int sdl_stop_enter(void *stopper)
{
    return rbsf_stopper_enter((rbsf_stopper *)stopper);
}

static void sdl_stop_leave(void *stopper, int slot)
{
    rbsf_stopper_leave((rbsf_stopper *)stopper, slot);
}

static int sdl_stop_stopped(void *stopper)
{
    return rbsf_stopper_stopped((rbsf_stopper *)stopper);
}
#endif

/* What is in the way of a file the sdl output (config c) will write: in its
 * folder (or its viewK folders), a folder or a FIFO (after links) named as
 * a frame the run writes or as the contact sheet.  The renderer leaves such
 * names alone: its write into a folder failed mid-run (exit 4, every output
 * cut at that frame), and its open() of a FIFO no one reads waited for a
 * reader, which no signal ended then (the sdl output is in the stopper
 * now, which ends a FIFO made during the run): a probe of session 47.  Devices are written as they are (a link to
 * /dev/null), as for any output.  RBS_OK, or RBS_E_INVALID with err naming
 * the entry and the frame. */
static rbs_status png_names_free(const rbs_renderer_config *c, uint64_t start,
                                 int resumed, uint64_t last, int checkpoint,
                                 char *err, size_t errlen)
{
    char dir[4200], path[4500];
    int views, tile, sheet, v;
    struct stat sb;
    if (c->path == NULL || strlen(c->path) > 4096)
        return RBS_OK; /* (the renderer's check refuses such a path) */
    png_layout(c->json, &views, &tile, &sheet);
    snprintf(path, sizeof path, "%s/contact_sheet.png", c->path);
    if (sheet && stat(path, &sb) == 0 && (S_ISDIR(sb.st_mode) || S_ISFIFO(sb.st_mode))) {
        snprintf(err, errlen, "'%.400s' is a %s, where the run writes its "
                              "contact sheet: move it, or name another folder",
                 path, S_ISDIR(sb.st_mode) ? "folder" : "FIFO");
        return RBS_E_INVALID;
    }
    for (v = 0; v < (views == 1 || tile ? 1 : views); v++) {
        DIR *d;
        struct dirent *e;
        if (views == 1 || tile)
            snprintf(dir, sizeof dir, "%s", c->path);
        else
            snprintf(dir, sizeof dir, "%s/view%d", c->path, v);
        if ((d = opendir(dir)) == NULL)
            continue; /* (no folder yet: nothing in the way) */
        while ((e = readdir(d)) != NULL) {
            uint64_t n;
            if (!is_frame_png(e->d_name))
                continue;
            errno = 0;
            n = strtoull(e->d_name + 6, NULL, 10);
            if (errno != 0 ||
                !run_writes_frame(n, start, resumed, last, c->every, checkpoint))
                continue;
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            if (stat(path, &sb) != 0 || !(S_ISDIR(sb.st_mode) || S_ISFIFO(sb.st_mode)))
                continue; /* (a file, a device, a link to be made: written) */
            snprintf(err, errlen, "'%.400s' is a %s, where the run writes "
                                  "frame %llu: move it, or name another folder",
                     path, S_ISDIR(sb.st_mode) ? "folder" : "FIFO",
                     (unsigned long long)n);
            closedir(d);
            return RBS_E_INVALID;
        }
        closedir(d);
    }
    return RBS_OK;
}

/* What remove_stale_frames removed from one folder. */
typedef struct stale_files {
    unsigned long count;
    uint64_t lo, hi; /* the frame numbers removed, when count > sheet */
    int sheet;       /* contact_sheet.png was one of them */
} stale_files;

/* Remove from folder dir the regular files named as the sdl renderer names
 * frames (is_frame_png) with a number from first on; the scene and the
 * checkpoint resumed are never touched.  0, or -1 after saying why. */
static int remove_stale_in(const char *dir, uint64_t first, const rbs_scene *scene,
                           const char *resume, stale_files *gone)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int failed = 0;
    if (d == NULL)
        return 0; /* (no folder: no stale frame) */
    while (!failed && (e = readdir(d)) != NULL) {
        char path[4200];
        struct stat sb;
        uint64_t k;
        int n;
        if (!is_frame_png(e->d_name))
            continue;
        k = strtoull(e->d_name + 6, NULL, 10); /* (saturates: above first) */
        if (k < first)
            continue;
        n = snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (n < 0 || (size_t)n >= sizeof path || lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode) ||
            scene_file(scene, path, NULL) != NULL ||
            (resume != NULL && same_file(path, resume)))
            continue;
        if (unlink(path) != 0) {
            rbsf__tell(stderr, "rbsim: error: cannot remove '%s', a frame an "
                            "earlier run left in the png folder: %s\n",
                    path, strerror(errno));
            failed = 1;
            break;
        }
        if (gone->count == (unsigned long)gone->sheet || k < gone->lo)
            gone->lo = k;
        if (gone->count == (unsigned long)gone->sheet || k > gone->hi)
            gone->hi = k;
        gone->count++;
    }
    closedir(d);
    return failed ? -1 : 0;
}

/* Before the run starts: an sdl output's folder may hold the frames of an
 * earlier run, which this run's would only partly overwrite (a shorter run,
 * another --every), so a glob of the folder would mix two runs.  Remove the
 * files the renderer names in this entry's layout (frontends/sdl/README.md,
 * "Files": DIR/frame_N.png or DIR/viewK/frame_N.png for K < views, and
 * contact_sheet.png when it writes one): on a fresh run all of them, on a
 * resumed run (first > 0) the frames from first on, keeping the first run's
 * part of the sequence.  Files of other names, and of another layout, stay;
 * no other output can be among these (check_distinct).  A note names what
 * went (not with --quiet).  0, or -1 after saying why. */
static int remove_stale_frames(const output *o, uint64_t first, const rbs_scene *scene,
                               const char *resume, int quiet)
{
    const char *dir = o->config.path;
    stale_files gone;
    char path[4200];
    struct stat sb;
    int views, tile, sheet, v;
    memset(&gone, 0, sizeof gone);
    if (strlen(dir) > 4096)
        return 0; /* (longer than a path can be: the renderer made nothing) */
    png_layout(o->config.json, &views, &tile, &sheet);
    if (first == 0 && sheet) {
        snprintf(path, sizeof path, "%s/contact_sheet.png", dir);
        if (lstat(path, &sb) == 0 && S_ISREG(sb.st_mode) &&
            scene_file(scene, path, NULL) == NULL &&
            !(resume != NULL && same_file(path, resume))) {
            if (unlink(path) != 0) {
                rbsf__tell(stderr, "rbsim: error: cannot remove '%s', the contact "
                                "sheet of an earlier run: %s\n",
                        path, strerror(errno));
                return -1;
            }
            gone.count = 1;
            gone.sheet = 1;
        }
    }
    for (v = 0; v < (views == 1 || tile ? 1 : views); v++) {
        if (views == 1 || tile)
            snprintf(path, sizeof path, "%s", dir);
        else
            snprintf(path, sizeof path, "%s/view%d", dir, v);
        if (remove_stale_in(path, first, scene, resume, &gone) != 0)
            return -1;
    }
    if (gone.count > 0 && !quiet) {
        char frames[96] = "";
        unsigned long n = gone.count - (unsigned long)gone.sheet;
        if (n == 1)
            snprintf(frames, sizeof frames, "frame %llu", (unsigned long long)gone.lo);
        else if (n > 1)
            snprintf(frames, sizeof frames, "frames %llu to %llu",
                     (unsigned long long)gone.lo, (unsigned long long)gone.hi);
        rbsf__tell(stderr, "rbsim: note: removed %lu file%s an earlier run left in "
                        "the png folder '%s' (%s%s%s), so that it holds this "
                        "run's files only\n",
                gone.count, gone.count == 1 ? "" : "s", dir, frames,
                n > 0 && gone.sheet ? ", " : "",
                gone.sheet ? "contact_sheet.png" : "");
    }
    return 0;
}

/* ---- staging: a rejected run writes nothing ------------------------------ */

/* Make a file output safe to open: an existing regular file is opened for
 * writing without truncating it (so its permissions, its file system and the
 * like are proven) and a temporary beside it takes the run's bytes; a new
 * file is made at once (so its name, folder and file system are proven) and
 * written in place.  Devices and pipes are opened as they are.  0, or -1
 * with the reason in err. */
static int stage_output(output *o, char *err, size_t errlen)
{
    const char *path = o->config.path;
    struct stat sb;
    const char *slash;
    char shown[160]; /* (shortened: the reason must fit in err) */
    size_t dir;
    int fd;

    rbsf_shown_path(path, shown, sizeof shown);
    o->target = resolve_links(path);
    if (o->target == NULL) {
        snprintf(err, errlen, "'%s': %s", shown, strerror(errno));
        return -1;
    }
    slash = strrchr(o->target, '/');
    dir = slash ? (size_t)(slash - o->target) + 1 : 0;
    o->work = malloc(strlen(o->target) + 32);
    if (o->work == NULL) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    if (stat(o->target, &sb) == 0) {
        if (!S_ISREG(sb.st_mode)) {
            strcpy(o->work, o->target); /* a device or a pipe: nothing kept */
            return 0;
        }
        fd = open(o->target, O_WRONLY | O_NOCTTY);
        if (fd < 0) {
            snprintf(err, errlen, "cannot write '%s': %s", shown,
                     strerror(errno));
            return -1;
        }
        close(fd);
        memcpy(o->work, o->target, dir);
        strcpy(o->work + dir, ".rbsim-XXXXXX");
        fd = mkstemp(o->work);
        if (fd < 0) {
            snprintf(err, errlen, "cannot create a temporary file beside '%s': "
                                  "%s", shown, strerror(errno));
            return -1;
        }
        fchmod(fd, sb.st_mode & 07777); /* the old file's permissions */
        close(fd);
        o->temporary = 1;
        return 0;
    }
    strcpy(o->work, o->target);
    fd = open(o->target, O_WRONLY | O_CREAT | O_EXCL | O_NOCTTY, 0666);
    if (fd < 0 && errno == ENOENT && slash != NULL && slash != o->target) {
        /* the one missing folder rbsf_check_output_file allows */
        o->work[dir - 1] = '\0';
        if (mkdir(o->work, 0777) == 0)
            o->made_dir = 1;
        o->work[dir - 1] = '/';
        fd = open(o->target, O_WRONLY | O_CREAT | O_EXCL | O_NOCTTY, 0666);
    }
    if (fd < 0) {
        snprintf(err, errlen, "cannot create '%s': %s", shown, strerror(errno));
        return -1;
    }
    close(fd);
    o->created = 1;
    return 0;
}

/* A rejected run: remove what stage_output made. */
static void discard_staged(output *outs, uint32_t n)
{
    uint32_t i;
    for (i = 0; i < n; i++) {
        output *o = &outs[i];
        if (o->temporary || o->created)
            unlink(o->work);
        if (o->made_dir) {
            char *slash = strrchr(o->work, '/');
            *slash = '\0';
            rmdir(o->work);
            *slash = '/';
        }
        o->temporary = o->created = o->made_dir = 0;
    }
}

/* A run that started: its temporaries replace the old files.  0, or -1
 * after saying which could not. */
static int commit_staged(output *outs, uint32_t n)
{
    uint32_t i;
    int failed = 0;
    for (i = 0; i < n; i++) {
        output *o = &outs[i];
        if (o->temporary && rename(o->work, o->target) != 0) {
            rbsf__tell(stderr, "rbsim: error: cannot replace '%s' (the run's %s "
                            "output is in '%s'): %s\n",
                    o->config.path, o->config.type, o->work, strerror(errno));
            failed = 1;
        }
        o->temporary = o->created = o->made_dir = 0;
    }
    return failed ? -1 : 0;
}

/* ---- checkpoints -------------------------------------------------------- */

/* Save the world to the checkpoint file; on failure say why in err. */
static rbs_status save_checkpoint(checkpointer *c, const rbs_world *world,
                                  char *err, size_t errlen)
{
    rbs_status st;
    errno = 0;
    st = rbs_world_save(world, c->path);
    if (st != RBS_OK) {
        int e = errno;
        snprintf(err, errlen, "cannot save the checkpoint '%s' at frame %llu: "
                              "%s%s%s",
                 c->name, (unsigned long long)rbs_world_step_count(world),
                 rbs_status_string(st), e ? ": " : "", e ? strerror(e) : "");
        return st;
    }
    c->saved = 1;
    c->saved_at = rbs_world_step_count(world);
    return RBS_OK;
}

/* The projector's after_step hook (simulation thread): every N-th frame and
 * the run's last one. */
static rbs_status checkpoint_hook(void *context, const rbs_world *world,
                                  uint64_t frame, char *err, size_t errlen)
{
    checkpointer *c = context;
    if ((c->every != 0 && frame % c->every == 0) || frame == c->last)
        return save_checkpoint(c, world, err, errlen);
    return RBS_OK;
}

/* Before anything runs: the checkpoint (path, its links followed: target)
 * must be a file we can make in an existing, writable folder, and not the
 * scene, an output or the file standard output is redirected to (which
 * counts as '-': the rename would cut off what the run prints there, a '-'
 * output or the summary, quiet or not, for one rule).  rbs_world_save writes "<target>.tmp<pid>" and renames
 * it onto target, so that file is made and removed here: it proves the
 * folder, the name's length and the file system (e.g. /proc) at once. */
static int check_checkpoint_path(const char *path, const char *target,
                                 const rbs_scene *scene, const output *outs,
                                 uint32_t n, int quiet)
{
    struct stat sb, so;
    const char *slash = strrchr(target, '/');
    char dir[4096], tmp[4200];
    size_t len = slash ? (size_t)(slash - target) : 0;
    uint32_t i, k;
    const char *f;
    int fd;
    if (stat(target, &sb) == 0 && !S_ISREG(sb.st_mode)) {
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': not a regular file\n",
                path);
        return RBSF_EXIT_USAGE;
    }
    if (len >= sizeof dir || strlen(target) + 32 >= sizeof tmp) {
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': path too long\n", path);
        return RBSF_EXIT_USAGE;
    }
    if (slash == NULL)
        strcpy(dir, ".");
    else if (len == 0)
        strcpy(dir, "/");
    else {
        memcpy(dir, target, len);
        dir[len] = '\0';
    }
    if (slash != NULL && slash[1] == '\0') {
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': a file name is needed, "
                        "not a folder\n", path);
        return RBSF_EXIT_USAGE;
    }
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
        /* (unlike an output's one missing folder, made only once the run
         * has started: a checkpoint is also saved when it is stopped) */
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': folder '%s' does not "
                        "exist%s\n", path, dir,
                stat(dir, &sb) == 0 ? " (it is not a folder)"
                                    : " (a checkpoint's folder is not made: "
                                      "make it first)");
        return RBSF_EXIT_USAGE;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': cannot write in folder "
                        "'%s': %s\n", path, dir, strerror(errno));
        return RBSF_EXIT_USAGE;
    }
    /* An existing checkpoint: may it be written (not immutable, say)?
     * Opened without truncating it. */
    fd = open(target, O_WRONLY | O_NOCTTY);
    if (fd < 0 && errno != ENOENT) {
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': cannot write it: %s\n",
                path, strerror(errno));
        return RBSF_EXIT_USAGE;
    }
    if (fd >= 0)
        close(fd);
    snprintf(tmp, sizeof tmp, "%s.tmp%ld", target, (long)getpid());
    fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) {
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s': cannot create a file "
                        "in folder '%s': %s\n", path, dir, strerror(errno));
        return RBSF_EXIT_USAGE;
    }
    close(fd);
    unlink(tmp);
    if ((f = scene_file(scene, target, &k)) != NULL) {
        char note[4200];
        scene_file_note(note, sizeof note, f, k);
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s' would overwrite the "
                        "scene%s\n", path, note);
        return RBSF_EXIT_USAGE;
    }
    if (stat(target, &sb) == 0 && stdout_stat(&so) == 0 &&
        sb.st_dev == so.st_dev && sb.st_ino == so.st_ino) {
        char use[64];
        snprintf(use, sizeof use, "%s", quiet ? "" : " (the summary goes there)");
        for (i = 0; i < n; i++)
            if (outs[i].config.path != NULL && strcmp(outs[i].config.path, "-") == 0 &&
                strcmp(outs[i].config.type, "sdl") != 0)
                snprintf(use, sizeof use, " (the %s output '-' goes there)",
                         outs[i].config.type);
        rbsf__tell(stderr, "rbsim run: --checkpoint '%s' is the file standard "
                        "output is redirected to%s: give it another name\n",
                path, use);
        return RBSF_EXIT_USAGE;
    }
    for (i = 0; i < n; i++) {
        const char *a = outs[i].config.path;
        const char *what = NULL;
        int kind;
        if (a != NULL && strcmp(a, "-") != 0 && same_file(a, target)) {
            rbsf__tell(stderr, "rbsim run: --checkpoint '%s' is also the %s "
                            "output\n", path, outs[i].config.type);
            return RBSF_EXIT_USAGE;
        }
        if (a != NULL && strcmp(outs[i].config.type, "sdl") == 0 &&
            (kind = png_folder_writes(a, outs[i].config.json, target, &what))) {
            rbsf__tell(stderr, "rbsim run: --checkpoint '%s' is a %s the sdl "
                            "output %s in its folder '%s' (%s): give it "
                            "another name\n", path,
                    kind == 2 ? "folder" : "file",
                    kind == 2 ? "makes" : "writes", a, what);
            return RBSF_EXIT_USAGE;
        }
        if (a != NULL && strcmp(outs[i].config.type, "sdl") == 0 &&
            strcmp(a, "-") != 0) {
            char part[4096];
            if (folder_runs_through(a, path, part, sizeof part) ||
                folder_runs_through(a, target, part, sizeof part)) {
                rbsf__tell(stderr, "rbsim run: --checkpoint '%s': the sdl "
                                "output's folder '%s' runs through '%s', "
                                "which the checkpoint is: give one of them "
                                "another name\n", path, a, part);
                return RBSF_EXIT_USAGE;
            }
        }
    }
    return 0;
}

static const char *type_name(rbs_body_type t)
{
    return t == RBS_BODY_SPHERE ? "sphere" : t == RBS_BODY_PLANE ? "plane"
                                                                 : "body";
}

/* Name of material id m of world w ("*" for the null id). */
static const char *material_label(const rbs_world *w, rbs_material_id m)
{
    const char *name = "?";
    if (m.index == 0 && m.generation == 0)
        return "*";
    rbs_world_material_at(w, m.index, NULL, &name);
    return name;
}

/* A message into buf (n bytes), cut to fit. */
static void say_into(char *buf, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, n, fmt, ap);
    va_end(ap);
}

/* x in its shortest exact form, in buf (40 bytes), for a message. */
static const char *short_num(char *buf, double x)
{
    rbsf_format_double(buf, 40, x);
    return buf;
}

/* A pair row's restitution for a message: a negative one is the row's
 * "use the simulation's restitution" (as a scene leaves it out). */
static const char *pair_e(char *buf, double e)
{
    if (e < 0.0) {
        snprintf(buf, 40, "(the simulation's)");
        return buf;
    }
    return short_num(buf, e);
}

/* The same materials (by index and name) and the same pair rows (in order,
 * every coefficient bit for bit)?  0 if so; otherwise the difference. */
static int materials_match(const rbs_world *a, const rbs_world *b, char *why,
                           size_t n)
{
    uint32_t i;
    for (i = 0;; i++) {
        const char *na = NULL, *nb = NULL;
        int ha = rbs_world_material_at(a, i, NULL, &na) == RBS_OK;
        int hb = rbs_world_material_at(b, i, NULL, &nb) == RBS_OK;
        if (!ha && !hb)
            break;
        if (ha != hb || strcmp(na, nb) != 0) {
            snprintf(why, n, "material %lu: the scene has %s%s%s, the "
                             "checkpoint %s%s%s",
                     (unsigned long)i, ha ? "'" : "", ha ? na : "none",
                     ha ? "'" : "", hb ? "'" : "", hb ? nb : "none",
                     hb ? "'" : "");
            return -1;
        }
    }
    for (i = 0;; i++) {
        rbs_pair_def pa, pb;
        int ha, hb;
        rbs_pair_def_init(&pa);
        rbs_pair_def_init(&pb);
        ha = rbs_world_pair_at(a, i, &pa) == RBS_OK;
        hb = rbs_world_pair_at(b, i, &pb) == RBS_OK;
        if (!ha && !hb)
            return 0;
        if (ha != hb) {
            snprintf(why, n, "material pairs: %s has a row %lu ('%s' / '%s') "
                             "that %s has not",
                     ha ? "the scene" : "the checkpoint", (unsigned long)i,
                     ha ? material_label(a, pa.a) : material_label(b, pb.a),
                     ha ? material_label(a, pa.b) : material_label(b, pb.b),
                     ha ? "the checkpoint" : "the scene");
            return -1;
        }
        if (pa.a.index != pb.a.index || pa.a.generation != pb.a.generation ||
            pa.b.index != pb.b.index || pa.b.generation != pb.b.generation ||
            !(pa.static_friction == pb.static_friction) ||
            !(pa.kinetic_friction == pb.kinetic_friction) ||
            !(pa.restitution == pb.restitution) || !(pa.rolling == pb.rolling) ||
            !(pa.spinning == pb.spinning)) {
            char x[10][40];
            say_into(why, n, "material pair '%s' / '%s': the scene has "
                             "mu_s %s mu_k %s e %s rolling %s "
                             "spinning %s, the checkpoint has '%s' / '%s' "
                             "mu_s %s mu_k %s e %s rolling %s "
                             "spinning %s",
                     material_label(a, pa.a), material_label(a, pa.b),
                     short_num(x[0], pa.static_friction), short_num(x[1], pa.kinetic_friction),
                     pair_e(x[2], pa.restitution), short_num(x[3], pa.rolling),
                     short_num(x[4], pa.spinning), material_label(b, pb.a),
                     material_label(b, pb.b), short_num(x[5], pb.static_friction),
                     short_num(x[6], pb.kinetic_friction), pair_e(x[7], pb.restitution),
                     short_num(x[8], pb.rolling), short_num(x[9], pb.spinning));
            return -1;
        }
    }
}

/* A texture as a scene names it. */
static const char *texture_name(rbs_texture t)
{
    return t == RBS_TEXTURE_NONE      ? "none"
           : t == RBS_TEXTURE_STRIPES ? "stripes"
           : t == RBS_TEXTURE_CHECKER ? "checker"
                                      : "(unknown)";
}

/* x in its shortest exact form, then unit. */
static void show_num(char *buf, size_t n, double x, const char *unit)
{
    char num[40];
    rbsf_format_double(num, sizeof num, x);
    snprintf(buf, n, "%s%s", num, unit);
}

static void show3(char *buf, size_t n, rbs_vec3 u)
{
    char x[40], y[40], z[40];
    rbsf_format_double(x, sizeof x, u.x);
    rbsf_format_double(y, sizeof y, u.y);
    rbsf_format_double(z, sizeof z, u.z);
    snprintf(buf, n, "[%s, %s, %s]", x, y, z);
}

/* Do a scene body and its checkpointed self have the same definition: the
 * properties a scene gives and the run never changes (not the state, which
 * moves on)?  0 if so; otherwise the field and both values in why. */
static int body_matches(const rbs_world *scene_world, const rbs_world *ck,
                        const rbs_body_state *a, const rbs_body_state *b,
                        char *why, size_t n)
{
    const char *what = NULL;
    char va[160] = "", vb[160] = "";
#define SAME3(u, v) ((u).x == (v).x && (u).y == (v).y && (u).z == (v).z)
#define SHOW3(buf, u) show3(buf, sizeof buf, (u))
    if (a->fixed != b->fixed) {
        what = "fixed";
        snprintf(va, sizeof va, "%s", a->fixed ? "true" : "false");
        snprintf(vb, sizeof vb, "%s", b->fixed ? "true" : "false");
    } else if (a->type == RBS_BODY_SPHERE && !(a->radius == b->radius)) {
        what = "radius";
        show_num(va, sizeof va, a->radius, " m");
        show_num(vb, sizeof vb, b->radius, " m");
    } else if (!(a->mass == b->mass)) {
        what = "mass";
        show_num(va, sizeof va, a->mass, " kg");
        show_num(vb, sizeof vb, b->mass, " kg");
    } else if (!SAME3(a->force, b->force)) {
        what = "force";
        SHOW3(va, a->force);
        SHOW3(vb, b->force);
    } else if (!SAME3(a->torque, b->torque)) {
        what = "torque";
        SHOW3(va, a->torque);
        SHOW3(vb, b->torque);
    } else if (a->type == RBS_BODY_PLANE && !SAME3(a->normal, b->normal)) {
        what = "normal";
        SHOW3(va, a->normal);
        SHOW3(vb, b->normal);
    } else if (a->type == RBS_BODY_PLANE && !SAME3(a->position, b->position)) {
        what = "point"; /* a plane never moves */
        SHOW3(va, a->position);
        SHOW3(vb, b->position);
    } else if (a->material.index != b->material.index ||
               a->material.generation != b->material.generation) {
        what = "material";
        snprintf(va, sizeof va, "'%s'", material_label(scene_world, a->material));
        snprintf(vb, sizeof vb, "'%s'", material_label(ck, b->material));
    } else if (a->color != b->color) {
        what = "color";
        snprintf(va, sizeof va, "#%06lx", (unsigned long)a->color);
        snprintf(vb, sizeof vb, "#%06lx", (unsigned long)b->color);
    } else if (a->texture != b->texture) {
        what = "texture";
        snprintf(va, sizeof va, "%s", texture_name(a->texture));
        snprintf(vb, sizeof vb, "%s", texture_name(b->texture));
    } else if (a->type == RBS_BODY_SPHERE) {
        /* the mass distribution: centre of mass and inertia about it (from
         * the scene's inertia and center_of_mass) */
        rbs_body_id ia, ib;
        rbs_vec3 ca, cb;
        double Ia[9], Ib[9];
        int k, same = 1;
        if (rbs_world_body_at(scene_world, a->slot, &ia) != RBS_OK ||
            rbs_world_body_at(ck, b->slot, &ib) != RBS_OK ||
            rbs_body_get_inertia(scene_world, ia, &ca, Ia) != RBS_OK ||
            rbs_body_get_inertia(ck, ib, &cb, Ib) != RBS_OK) {
            what = "inertia";
            snprintf(va, sizeof va, "(unreadable)");
            snprintf(vb, sizeof vb, "(unreadable)");
        } else if (!SAME3(ca, cb)) {
            what = "center_of_mass";
            SHOW3(va, ca);
            SHOW3(vb, cb);
        } else {
            for (k = 0; k < 9; ++k)
                same = same && Ia[k] == Ib[k];
            if (!same) {
                what = "inertia (about the centre of mass, kg m^2, diagonal)";
                SHOW3(va, ((rbs_vec3){Ia[0], Ia[4], Ia[8]}));
                SHOW3(vb, ((rbs_vec3){Ib[0], Ib[4], Ib[8]}));
            }
        }
    }
#undef SAME3
#undef SHOW3
    if (what == NULL)
        return 0;
    snprintf(why, n, "body '%s' (slot %lu): %s: the scene has %s, the "
                     "checkpoint %s",
             a->name, (unsigned long)a->slot, what, va, vb);
    return -1;
}

/* Does the checkpoint continue this scene?  Same capacities, step size,
 * method, gravity and every other world setting, the same materials and
 * material-pair rows, and the same bodies (by slot, name and type, with the
 * same definition: body_matches).  0 if
 * so; otherwise the difference in why. */
static int checkpoint_matches(const rbs_world *scene_world,
                              const rbs_world *ck, char *why, size_t n)
{
    rbs_world_def a, b;
    uint32_t slot;
    rbs_world_def_init(&a);
    rbs_world_def_init(&b);
    if (rbs_world_get_def(scene_world, &a) != RBS_OK ||
        rbs_world_get_def(ck, &b) != RBS_OK) {
        snprintf(why, n, "cannot read the world settings");
        return -1;
    }
#define DIFF_U(field, what)                                                    \
    if (a.field != b.field) {                                                  \
        snprintf(why, n, "%s: the scene has %lu, the checkpoint %lu", what,    \
                 (unsigned long)a.field, (unsigned long)b.field);              \
        return -1;                                                             \
    }
    DIFF_U(max_bodies, "capacity max_bodies")
    DIFF_U(max_materials, "capacity max_materials")
    DIFF_U(max_pairs, "capacity max_pairs")
    DIFF_U(max_contacts, "capacity max_contacts")
#undef DIFF_U
    if (a.dt != b.dt) {
        char x[2][40];
        snprintf(why, n, "time step: the scene has %s s, the checkpoint "
                         "%s s", short_num(x[0], a.dt), short_num(x[1], b.dt));
        return -1;
    }
    if (a.method != b.method) {
        snprintf(why, n, "method: the scene has %s, the checkpoint %s",
                 rbs_method_name(a.method), rbs_method_name(b.method));
        return -1;
    }
    if (a.gravity.x != b.gravity.x || a.gravity.y != b.gravity.y ||
        a.gravity.z != b.gravity.z) {
        char ga[128], gb[128];
        show3(ga, sizeof ga, a.gravity);
        show3(gb, sizeof gb, b.gravity);
        say_into(why, n, "gravity differs (the scene has %s, the checkpoint %s)", ga, gb);
        return -1;
    }
    if (a.gravity_mode != b.gravity_mode) {
        snprintf(why, n, "gravity_mode: the scene has %s, the checkpoint %s",
                 a.gravity_mode == RBS_GRAVITY_FORCE ? "force" : "acceleration",
                 b.gravity_mode == RBS_GRAVITY_FORCE ? "force" : "acceleration");
        return -1;
    }
#define DIFF_D(field, what)                                                    \
    if (!(a.field == b.field)) {                                               \
        char x_[2][40];                                                        \
        snprintf(why, n, "%s: the scene has %s, the checkpoint %s", what,      \
                 short_num(x_[0], (double)a.field), short_num(x_[1], (double)b.field)); \
        return -1;                                                             \
    }
    DIFF_D(restitution, "restitution")
    DIFF_D(tolerance, "tolerance")
    DIFF_D(slop, "slop")
    DIFF_D(max_halvings, "max_halvings")
    DIFF_D(max_sweeps, "max_sweeps")
    DIFF_D(soft_substeps, "soft_substeps")
    DIFF_D(soft_tolerance, "soft_tolerance")
    DIFF_D(max_substeps, "max_substeps")
    DIFF_D(gravity_constant, "gravity_constant")
    DIFF_D(softening, "softening")
#undef DIFF_D
#define DIFF_B(field, what)                                                    \
    if (!a.field != !b.field) {                                                \
        snprintf(why, n, "%s: the scene has %s, the checkpoint %s", what,      \
                 a.field ? "true" : "false", b.field ? "true" : "false");      \
        return -1;                                                             \
    }
    DIFF_B(mutual_gravity, "mutual_gravity")
    DIFF_B(prune, "prune")
#undef DIFF_B
    if (materials_match(scene_world, ck, why, n) != 0)
        return -1;
    for (slot = 0; slot < a.max_bodies; slot++) {
        rbs_body_id ia, ib;
        rbs_body_state sa, sb;
        int ha, hb;
        memset(&sa, 0, sizeof sa);
        memset(&sb, 0, sizeof sb);
        ha = rbs_world_body_at(scene_world, slot, &ia) == RBS_OK &&
                 rbs_body_get_state(scene_world, ia, &sa) == RBS_OK;
        hb = rbs_world_body_at(ck, slot, &ib) == RBS_OK &&
                 rbs_body_get_state(ck, ib, &sb) == RBS_OK;
        if (!ha && !hb)
            continue;
        if (ha != hb || sa.type != sb.type || strcmp(sa.name, sb.name) != 0) {
            /* (a body the API added without a name, which no scene can
             * hold, is "an unnamed sphere": it read "sphere ''") */
            int ua = ha && sa.name[0] == '\0', ub = hb && sb.name[0] == '\0';
            snprintf(why, n, "body slot %lu: the scene has %s%s%s%s%s, the "
                             "checkpoint %s%s%s%s%s",
                     (unsigned long)slot, ua ? "an unnamed " : "",
                     ha ? type_name(sa.type) : "none", ha && !ua ? " '" : "",
                     ha ? sa.name : "", ha && !ua ? "'" : "", ub ? "an unnamed " : "",
                     hb ? type_name(sb.type) : "none", hb && !ub ? " '" : "",
                     hb ? sb.name : "", hb && !ub ? "'" : "");
            return -1;
        }
        if (body_matches(scene_world, ck, &sa, &sb, why, n) != 0)
            return -1;
    }
    return 0;
}

/* ---- progress and summary ----------------------------------------------- */

static void progress(const rbs_run_info *info, uint64_t start)
{
    char bar[31];
    int i, filled;
    if (info->endless || info->steps == 0) {
        fprintf(stderr, "\r  frame %llu, t = %.4g s%s   ",
                (unsigned long long)info->frame, info->time,
                info->paused ? " (paused)" : "");
        return;
    }
    /* info->steps counts from the starting frame (a resumed run's k). */
    filled = (int)(30.0 * (double)(info->frame - start) / (double)info->steps);
    for (i = 0; i < 30; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[30] = '\0';
    fprintf(stderr, "\r  [%s] %3d%%  frame %llu/%llu  t = %.4g s%s   ", bar,
            (int)(100.0 * (double)(info->frame - start) / (double)info->steps),
            (unsigned long long)info->frame,
            (unsigned long long)(start + info->steps),
            info->time, info->paused ? " (paused)" : "");
}

/* start: the frame the run started from (a resumed run's k), start_time
 * its time: the steps and time counted are this run's own.  max_substeps:
 * the world's work cap, named when steps hit it. */
static void summary(FILE *out, const char *scene_name, const rbs_run_info *info,
                    const output *outs, uint32_t n, uint64_t start, double start_time,
                    uint32_t max_substeps, const rbs_world *world, uint64_t first_captured)
{
    uint32_t i;
    double drift = info->energy_last - info->energy_initial;
    const uint64_t drawn = info->frame > start ? info->frame - start : 0;
    /* The steps made (the counters and the energy at the end are theirs):
     * the simulation runs ahead of the renderers, and a run stopped by an
     * error may have made steps no output has ("simulated 0 s: 0 steps
     * (10 sub-steps ...)" after a failed first write). */
    /* (captured holds the starting frame too, unless a resumed run skipped
     * it: first_captured) */
    const uint64_t made_c = info->captured > first_captured ? info->captured - first_captured : 0;
    const uint64_t made = made_c > drawn ? made_c : drawn;
    rbs_world_def wd;
    double made_time = drawn > 0 ? info->time - start_time : 0.0;
    const uint64_t steps = made;
    rbs_world_def_init(&wd);
    if (made > drawn && world != NULL && rbs_world_get_def(world, &wd) == RBS_OK)
        made_time = (double)made * wd.dt; /* (the captured frames': a step the stop
                                             cut short is in the world, not here) */
    rbsf__tell(out, "scene: %s\n", scene_name);
    fprintf(out, "simulated %.6g s: %llu steps (%llu sub-steps, %llu rollbacks), "
                 "%llu collisions\n",
            made_time, (unsigned long long)steps,
            (unsigned long long)info->substeps,
            (unsigned long long)info->rollbacks,
            (unsigned long long)info->collisions);
    if (made > drawn)
        fprintf(out, "frames: up to frame %llu (t = %.6g s) reached the outputs; the "
                     "simulation had made %llu more when the run stopped\n",
                (unsigned long long)(start + drawn), drawn > 0 ? info->time : start_time,
                (unsigned long long)(made - drawn));
    if (info->work_limited > 0) {
        char cap[32] = "";
        if (max_substeps > 0)
            snprintf(cap, sizeof cap, " = %u", (unsigned)max_substeps);
        fprintf(out, "work cap: %llu of %llu steps hit max_substeps%s (sub-steps + "
                     "rollbacks, adaptive's events, in one step) and took the rest of their "
                     "frame without rollback, overlap pushed apart: impacts there may be missed "
                     "or wrong, a ball may pass through another (raise simulation.max_substeps "
                     "or shorten dt)\n",
                (unsigned long long)info->work_limited, (unsigned long long)steps, cap);
    }
    if (info->floor_hit_steps > 0)
        fprintf(out, "overlap: %llu of %llu steps pushed overlap apart instead of resolving "
                     "it (a sub-step at the rollback floor, dt / 2^max_halvings; a rollback "
                     "the work cap refused, simulation.max_substeps; or a body jammed in a "
                     "selective step, simulation.max_sweeps): the impacts there are not "
                     "exact (--stats' max_overlap shows the overlap; shorten dt, or raise "
                     "max_substeps or max_sweeps)\n",
                (unsigned long long)info->floor_hit_steps, (unsigned long long)steps);
    if (info->sweep_limited > 0)
        fprintf(out, "sweeps: %llu of %llu steps had a contact pass stop at max_sweeps with "
                     "its impulses not converged (raise simulation.max_sweeps)\n",
                (unsigned long long)info->sweep_limited, (unsigned long long)steps);
    if (world != NULL && info->max_overlap > 0.0) {
        /* (1 % of the smallest sphere's radius: the soft step sinks a
         * load by load / (m_eff omega^2), which a huge load makes deep --
         * a ball under g = 1e8 m/s^2 ended 25 radii under the floor with
         * no word of it; a probe of session 45) */
        double rmin = 0.0;
        uint32_t slot;
        rbs_world_def d;
        rbs_world_def_init(&d);
        if (rbs_world_get_def(world, &d) == RBS_OK)
            for (slot = 0; slot < d.max_bodies; slot++) {
                rbs_body_id id;
                rbs_body_state bs;
                if (rbs_world_body_at(world, slot, &id) == RBS_OK &&
                    rbs_body_get_state(world, id, &bs) == RBS_OK && bs.type == RBS_BODY_SPHERE &&
                    (rmin == 0.0 || bs.radius < rmin))
                    rmin = bs.radius;
            }
        if (rmin > 0.0 && info->max_overlap > 0.01 * rmin)
            fprintf(out, "overlap: the deepest at a step's end was %.3g m, %.3g %% of the "
                         "smallest radius (%.3g m): bodies sank into each other or into a "
                         "plane (the soft method sinks a load by load / (m_eff omega^2), "
                         "which falls with dt^2; --stats' max_overlap shows when; shorten "
                         "dt)\n",
                    info->max_overlap, 100.0 * info->max_overlap / rmin, rmin);
    }
    if (info->rounded_steps > 0)
        fprintf(out, "rounding: %llu of %llu steps moved a sphere by less than a thousandth "
                     "of its radius where its coordinates round by more than 1 %% of that move: "
                     "its slow motion there is partly lost (far from the origin, or dt very "
                     "small; move the scene nearer the origin or lengthen dt)\n",
                (unsigned long long)info->rounded_steps, (unsigned long long)steps);
    fprintf(out, "wall time %.3f s, %.0f steps/s\n", info->wall_time,
            info->wall_time > 0 ? (double)steps / info->wall_time : 0.0);
    fprintf(out, "energy: %.9g J at the start, %.9g J at the end (drift %+.3g J",
            info->energy_initial, info->energy_last, drift);
    if (info->energy_initial != 0)
        fprintf(out, ", %+.3g %%", 100.0 * drift / fabs(info->energy_initial));
    fprintf(out, ")\n");
    for (i = 0; i < n; i++)
        if (outs[i].config.path != NULL) {
            fprintf(out, "output: %s ", outs[i].config.type);
            rbsf__puts_shown(out, outs[i].config.path);
            fputc('\n', out);
        }
}

/* Print "rbsim: PREFIXmsg".  The projector's messages name the files the
 * renderers wrote: for an existing output that is a temporary beside it,
 * gone once renamed or removed, so each is named by its output instead.
 * Paths are shown safely (shown.h). */
static void print_run_error(const char *prefix, const char *msg,
                            const output *outs, uint32_t n)
{
    rbsf__tell(stderr, "rbsim: %s", prefix);
    while (*msg != '\0') {
        uint32_t i;
        size_t len = 0;
        for (i = 0; i < n && len == 0; i++) {
            const output *o = &outs[i];
            if (o->work != NULL && o->target != NULL &&
                strcmp(o->work, o->target) != 0 &&
                strncmp(msg, o->work, strlen(o->work)) == 0) {
                rbsf__puts_shown(stderr, o->config.path);
                len = strlen(o->work);
            }
        }
        if (len == 0) {
            /* one character (a UTF-8 sequence whole) */
            (void)rbs_text_shown_len(msg, strlen(msg), &len);
            rbsf__put_shown(stderr, msg, len);
        }
        msg += len;
    }
    fputc('\n', stderr);
}

/* ---- run ---------------------------------------------------------------- */

int rbsf_run_main(int argc, char **argv)
{
    run_options o;
    rbs_scene *scene = NULL;
    rbs_world *world = NULL;
    rbs_renderer_registry *registry = NULL;
    rbs_projector *projector = NULL;
    rbs_pool *pool = NULL;
    rbs_renderer_class demo_class;
#ifdef RBSF_HAVE_SDL
    /* (the sdl check places its cameras at the world's start) */
    rbsf_sdl_world_api sdl_api = {rbs_world_state, rbs_frame_capture, NULL, NULL, NULL, NULL};
    rbs_renderer_class sdl_cls;
#endif
    rbsf_demo_results demo_results;
    rbs_renderer_config configs[RBS_RENDERERS_MAX];
    output outs[RBS_RENDERERS_MAX];
    uint32_t n_out = 0, i;
    rbs_projector_def def;
    rbsf_signals signals;
    rbsf_dump_bound dumps[3]; /* csv, json, stats: signals.stopper ends them */
    rbsf_input input;
    const char *taken;
    pthread_mutex_t reply_lock = PTHREAD_MUTEX_INITIALIZER;
    FILE *talk = stdout;
    rbs_run_info info;
    rbs_status st;
    int code, demo, show_progress, sig;
    checkpointer ckpt;
    char *ckpt_target = NULL;
    uint64_t start_frame = 0, target;
    double start_time = 0.0; /* the resumed world's time */
    double started;
    struct timespec ts;

    code = parse_run_args(argc, argv, &o);
    if (code != 0)
        return code;
    memset(&ckpt, 0, sizeof ckpt);
    demo = o.scene == NULL;

    /* Signals are taken by their own thread; block them before any thread
     * starts so every thread inherits the mask. */
    if (rbsf_signals_start(&signals) != 0) {
        rbsf__tell(stderr, "rbsim: cannot start the signal thread\n");
        return RBSF_EXIT_RUN;
    }

    /* 1. The scene and the command line's overrides. */
    if ((code = load_scene(o.scene, &scene, &signals)) != 0) {
        if (code < 0)
            code = RBSF_EXIT_SCENE;
        goto out;
    }
    if ((o.steps || o.dt > 0 || o.method) && /* steps 0: no override */
        (code = rbsf_override_options(scene, o.steps, o.dt, o.method, "rbsim run: cannot apply the options")) != 0)
        goto out;
    if (o.slop > 0 && rbs_scene_override_slop(scene, o.slop) != RBS_OK) {
        rbsf_print_scene_errors(scene, stderr);
        code = RBSF_EXIT_USAGE;
        goto out;
    }
    st = rbs_scene_build(scene, &world);
    if (st != RBS_OK) {
        if (rbs_scene_error_count(scene) > 0)
            rbsf_print_scene_errors(scene, stderr);
        rbsf_print_build_failure(scene, st, "rbsim: ", o.scene ? o.scene : "demonstration", stderr);
        code = RBSF_EXIT_SCENE;
        goto out;
    }

    /* 1b. --resume: the checkpoint replaces the scene's world, if it
     * continues this scene. */
    if (o.resume) {
        rbs_world *ck = NULL;
        char msg[512] = "";
        int slot = rbsf_stopper_enter(&signals.stopper); /* (as load_scene) */
        st = rbs_world_load(o.resume, &ck, msg, sizeof msg);
        rbsf_stopper_leave(&signals.stopper, slot);
        if (st != RBS_OK && (sig = rbsf_signals_caught(&signals)) != 0) {
            rbsf__tell(stderr, "rbsim: stopped by %s before the run started: while "
                            "reading the checkpoint '%s'\n",
                    rbsf_signal_name(sig), o.resume);
            code = 128 + sig;
            goto out;
        }
        if (st != RBS_OK) {
            rbsf__tell(stderr, "rbsim run: --resume '");
            rbsf__puts_shown(stderr, o.resume);
            rbsf__tell(stderr, "': cannot load the checkpoint: %s%s", rbs_status_string(st),
                    msg[0] ? ": " : "");
            rbsf__puts_shown(stderr, msg);
            fputc('\n', stderr);
            code = RBSF_EXIT_SCENE;
            goto out;
        }
        if (checkpoint_matches(world, ck, msg, sizeof msg) != 0) {
            rbsf__tell(stderr, "rbsim run: --resume '%s': the checkpoint does not "
                            "continue the scene '%s': %s\n",
                    o.resume, o.scene, msg);
            rbs_world_destroy(ck);
            code = RBSF_EXIT_SCENE;
            goto out;
        }
        rbs_world_destroy(world);
        world = ck;
        start_frame = rbs_world_step_count(world);
        start_time = rbs_world_time(world);
    }
    /* 1c. --threads N: a pool of N - 1 threads lends the world's steps its
     * threads (the results are the same bits for any N). */
    if (o.threads > 1) {
        rbs_workers workers;
        rbs_workers_init(&workers);
        st = rbs_pool_create(o.threads - 1, &pool);
        if (st == RBS_OK)
            st = rbs_pool_workers(pool, &workers);
        if (st == RBS_OK)
            st = rbs_world_set_workers(world, &workers);
        if (st != RBS_OK) {
            rbsf__tell(stderr, "rbsim run: --threads %lu: cannot lend the world "
                            "threads: %s\n",
                    (unsigned long)o.threads, rbs_status_string(st));
            code = RBSF_EXIT_RUN;
            goto out;
        }
    }
    /* --steps 0 (frame 0 only) needs no override: 0 steps always fit. */
    target = o.steps_given && o.steps == 0 ? 0 : rbs_scene_steps(scene);
    if (o.resume && start_frame >= target) {
        rbsf__tell(stderr, "rbsim run: --resume '%s': the checkpoint is at step "
                        "%llu and the run ends at step %llu: nothing to run "
                        "(give --steps N with N > %llu)\n",
                o.resume, (unsigned long long)start_frame,
                (unsigned long long)target, (unsigned long long)start_frame);
        code = RBSF_EXIT_USAGE;
        goto out;
    }

    /* 2. The renderer types. */
    if (rbs_renderer_registry_create(&registry) != RBS_OK ||
        rbsf_dump_bind(&dumps[0], rbsf_csv_class(), &signals.stopper) != RBS_OK ||
        rbsf_dump_bind(&dumps[1], rbsf_json_class(), &signals.stopper) != RBS_OK ||
        rbsf_dump_bind(&dumps[2], rbsf_stats_class(), &signals.stopper) != RBS_OK ||
        rbs_renderer_register(registry, &dumps[0].cls) != RBS_OK ||
        rbs_renderer_register(registry, &dumps[1].cls) != RBS_OK ||
        rbs_renderer_register(registry, &dumps[2].cls) != RBS_OK) {
        rbsf__tell(stderr, "rbsim: cannot set up the renderer types\n");
        code = RBSF_EXIT_RUN;
        goto out;
    }
#ifdef RBSF_HAVE_SDL
    /* (its PNG files' open and writes in the stopper too: a FIFO made at a
     * frame's name during the run is given up at a signal) */
    sdl_api.stopper = &signals.stopper;
    sdl_api.enter = sdl_stop_enter;
    sdl_api.leave = sdl_stop_leave;
    sdl_api.stopped = sdl_stop_stopped;
    sdl_cls = rbsf_sdl_class_with(&sdl_api);
    if (rbs_renderer_register(registry, &sdl_cls) != RBS_OK) {
        rbsf__tell(stderr, "rbsim: cannot register the sdl renderer\n");
        code = RBSF_EXIT_RUN;
        goto out;
    }
#endif
    if (demo) {
        rbsf_demo_check_class(&demo_class, &demo_results);
        if (rbs_renderer_register(registry, &demo_class) != RBS_OK) {
            rbsf__tell(stderr, "rbsim: cannot register the demonstration check\n");
            code = RBSF_EXIT_RUN;
            goto out;
        }
    }

    /* 3. The outputs: the scene's, then the command line's (the
     * demonstration's defaults unless replaced). */
    code = add_scene_outputs(scene, outs, &n_out);
    if (code != 0)
        goto out;
    if (demo) {
        if (!o.csv)
            o.csv = DEMO_DIR "/demo.csv";
        if (!o.stats)
            o.stats = DEMO_DIR "/stats.csv";
#ifdef RBSF_HAVE_SDL
        if (!o.png)
            o.png = DEMO_DIR "/png";
#endif
    }
    if ((o.csv && (code = add_output(outs, &n_out, "csv", o.csv, o.every, 0))) ||
        (o.json &&
         (code = add_output(outs, &n_out, "json", o.json, o.every, 0))) ||
        (o.stats &&
         (code = add_output(outs, &n_out, "stats", o.stats, 1, 0))) ||
        (o.png &&
         (code = add_output(outs, &n_out, "sdl", o.png,
                            o.every ? o.every : (demo ? 50 : 1), 1))) ||
        (demo &&
         (code = add_output(outs, &n_out, demo_class.name, NULL, 1, 0))))
        goto out;
#ifndef RBSF_HAVE_SDL
    if (o.png) {
        rbsf__tell(stderr, "rbsim run: --png: this rbsim was built without SDL\n");
        code = RBSF_EXIT_USAGE;
        goto out;
    }
#endif
    for (i = 0; i < n_out; i++) {
        if (outs[i].config.path && strcmp(outs[i].config.path, "-") == 0)
            talk = stderr; /* stdout carries data */
        configs[i] = outs[i].config;
    }

    /* 4. Check every output before any is opened: a rejected run writes
     * nothing.  (The demonstration's folder is made first: it is ours.) */
    code = check_distinct(outs, n_out, scene, o.resume, "rbsim run");
    if (code != 0)
        goto out;
    if (o.checkpoint) {
        ckpt_target = resolve_links(o.checkpoint);
        if (ckpt_target == NULL) {
            rbsf__tell(stderr, "rbsim run: --checkpoint '%s': %s\n", o.checkpoint,
                    strerror(errno));
            code = RBSF_EXIT_USAGE;
            goto out;
        }
        code = check_checkpoint_path(o.checkpoint, ckpt_target, scene, outs,
                                     n_out, o.quiet);
        if (code != 0)
            goto out;
    }
    if (demo && (make_demo_dir(DEMO_DIR) != 0 ||
                 (o.png && strcmp(o.png, DEMO_DIR "/png") == 0 &&
                  make_demo_dir(DEMO_DIR "/png") != 0))) {
        code = RBSF_EXIT_USAGE; /* before the run, nothing written */
        goto out;
    }
    for (i = 0; i < n_out; i++) {
        const rbs_renderer_class *cls;
        char err[512] = "";
        if (rbs_renderer_find(registry, configs[i].type, &cls) != RBS_OK) {
            if (outs[i].from_scene)
                rbsf_print_unknown_renderer(stderr, configs[i].file,
                                            (int)configs[i].line,
                                            (int)configs[i].column,
                                            (unsigned long)i, configs[i].type);
            code = outs[i].from_scene ? RBSF_EXIT_SCENE : RBSF_EXIT_USAGE;
            goto out;
        }
        if (cls->check == NULL)
            continue;
        st = cls->check(cls->context, &configs[i], world, err, sizeof err);
        if (st == RBS_OK && strcmp(configs[i].type, "sdl") == 0)
            st = png_names_free(&configs[i], start_frame, o.resume != NULL,
                                target, o.checkpoint != NULL, err, sizeof err);
        if (st != RBS_OK) {
            /* (err repeats the path: shown safely) */
            if (outs[i].from_scene) {
                rbsf__puts_shown(stderr, configs[i].file);
                rbsf__tell(stderr, ":%d:%d: renderers[%lu] (%s): ", (int)configs[i].line,
                        (int)configs[i].column, (unsigned long)i, configs[i].type);
            } else {
                rbsf__tell(stderr, "rbsim run: --%s: ",
                        strcmp(configs[i].type, "sdl") == 0 ? "png" : configs[i].type);
            }
            rbsf__puts_shown(stderr, err[0] ? err : rbs_status_string(st));
            fputc('\n', stderr);
            code = outs[i].from_scene ? RBSF_EXIT_SCENE : RBSF_EXIT_USAGE;
            goto out;
        }
    }
    /* Every file output is made (or a temporary beside it) before any is
     * written; from here until the run starts, out: removes them again. */
    for (i = 0; i < n_out; i++) {
        char err[600] = "";
        const char *type = outs[i].config.type;
        if (outs[i].config.path == NULL ||
            strcmp(outs[i].config.path, "-") == 0 ||
            (strcmp(type, "csv") && strcmp(type, "json") && strcmp(type, "stats")))
            continue;
        if (stage_output(&outs[i], err, sizeof err) != 0) {
            /* (err repeats the path: shown safely) */
            if (outs[i].from_scene) {
                rbsf__puts_shown(stderr, configs[i].file);
                rbsf__tell(stderr, ":%d:%d: renderers[%lu] (%s): ", (int)configs[i].line,
                        (int)configs[i].column, (unsigned long)i, type);
            } else {
                rbsf__tell(stderr, "rbsim run: --%s: ", type);
            }
            rbsf__puts_shown(stderr, err);
            fputc('\n', stderr);
            code = outs[i].from_scene ? RBSF_EXIT_SCENE : RBSF_EXIT_USAGE;
            goto out;
        }
        configs[i].path = outs[i].work;
    }
    if ((sig = rbsf_signals_caught(&signals)) != 0) {
        code = 128 + sig; /* interrupted before anything was written */
        goto out;
    }

    /* 5. The projector. */
    rbs_projector_def_init(&def);
    def.steps = target - start_frame;
    def.skip_first_frame = o.resume != NULL; /* the earlier run wrote it */
    def.continued = o.checkpoint != NULL; /* --every: the next part keeps K */
    if (o.checkpoint) {
        ckpt.name = o.checkpoint;
        ckpt.path = ckpt_target;
        ckpt.every = o.checkpoint_every;
        ckpt.last = target;
        def.after_step = checkpoint_hook;
        def.after_step_context = &ckpt;
    }
    def.reel_capacity = o.reel;
    def.realtime = o.realtime;
    def.policy = o.realtime ? RBS_REEL_LATEST_ONLY : RBS_REEL_LOSSLESS;
    def.speed = o.speed;
    def.start_paused = o.paused;
    taken = stdin_taken(scene, o.resume);
    if (taken != NULL && o.paused) {
        /* No command could resume it. */
        def.start_paused = 0;
        if (!o.quiet)
            rbsf__tell(stderr, "rbsim: note: --paused is ignored: standard "
                            "input is the %s, not commands\n", taken);
    }
    def.pause_on_collision = rbs_scene_pause_on_collision(scene);
    if (def.pause_on_collision && !isatty(STDIN_FILENO)) {
        /* Only a person at a terminal can resume such pauses. */
        def.pause_on_collision = 0;
        if (!o.quiet)
            rbsf__tell(stderr, "rbsim: note: simulation.pause_on_collision is "
                            "ignored: standard input is not a terminal\n");
    }
    st = rbs_projector_create(world, registry, configs, n_out, &def, &projector);
    if (st == RBS_E_CLOSED && (sig = rbsf_signals_caught(&signals)) != 0) {
        /* A signal ended an output's open (a FIFO waiting for a reader):
         * stopped before the run started, so nothing is written. */
        char prefix[96];
        snprintf(prefix, sizeof prefix, "stopped by %s before the run started: ",
                 rbsf_signal_name(sig));
        print_run_error(prefix, rbs_projector_last_error(projector), outs, n_out);
        code = 128 + sig;
        goto out;
    }
    if (st != RBS_OK) {
        print_run_error("error: ",
                        projector ? rbs_projector_last_error(projector)
                                  : rbs_status_string(st),
                        outs, n_out);
        code = RBSF_EXIT_RUN;
        goto out;
    }
    /* Every output is made and every renderer created: the run will start.
     * A png folder is to hold this run's frames only. */
    for (i = 0; i < n_out; i++) {
        if (strcmp(outs[i].config.type, "sdl") != 0 || outs[i].config.path == NULL)
            continue;
        if (remove_stale_frames(&outs[i], o.resume ? start_frame + 1 : 0, scene,
                                o.resume, o.quiet) != 0) {
            code = RBSF_EXIT_RUN;
            goto out;
        }
    }
    rbsf_signals_attach(&signals, projector);
    if (rbs_projector_start(projector) != RBS_OK) {
        /* The run began (frame 0 failed): its outputs stand, as after a
         * failure at any later frame. */
        print_run_error("error: ", rbs_projector_last_error(projector), outs, n_out);
        commit_staged(outs, n_out);
        code = RBSF_EXIT_RUN;
        goto out;
    }
    if (taken != NULL) {
        /* (its bytes would be read again as commands: "unknown command" a
         * line, or a binary checkpoint) */
        memset(&input, 0, sizeof input);
        if (!o.quiet)
            rbsf__tell(stderr, "rbsim: note: standard input is the %s: no "
                            "commands are read from it\n", taken);
    } else if (rbsf_input_start(&input, STDIN_FILENO, projector, talk,
                                &reply_lock) != 0)
        memset(&input, 0, sizeof input); /* no commands, the run goes on */

    /* 6. Wait, with a progress bar on a terminal for long runs. */
    show_progress = !o.quiet && isatty(STDERR_FILENO) && talk == stdout;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    started = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
    {
        int shown = 0;
        while (!rbs_projector_finished(projector, 0.1)) {
            double now;
            clock_gettime(CLOCK_MONOTONIC, &ts);
            now = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
            if (show_progress && now - started > 0.5) {
                rbs_projector_status(projector, &info);
                pthread_mutex_lock(&reply_lock);
                progress(&info, start_frame);
                pthread_mutex_unlock(&reply_lock);
                shown = 1;
            }
        }
        if (shown)
            fprintf(stderr, "\r\033[K");
    }
    st = rbs_projector_wait(projector);
    rbsf_input_stop(&input);
    rbsf_signals_attach(&signals, NULL);
    rbs_projector_status(projector, &info);
    sig = rbsf_signals_caught(&signals);
    /* The run started: its outputs (complete up to the last frame) replace
     * the old files. */
    if (commit_staged(outs, n_out) != 0)
        code = RBSF_EXIT_RUN;

    /* 6b. The final checkpoint: the world is ours again and stands at the
     * last frame made (quit and signals stop after a whole frame).  Not
     * after an error: a failed step or output leaves nothing to continue. */
    if (o.checkpoint && (st == RBS_OK || st == RBS_E_CLOSED) &&
        (!ckpt.saved || ckpt.saved_at != rbs_world_step_count(world))) {
        char err[600];
        if (save_checkpoint(&ckpt, world, err, sizeof err) != RBS_OK) {
            rbsf__tell(stderr, "rbsim: error: ");
            rbsf__puts_shown(stderr, err);
            fputc('\n', stderr);
            code = RBSF_EXIT_RUN;
        }
    }

    /* 7. Report.  Stopped with a message: a signal ended an output's write
     * that blocked (a pipe whose reader stopped reading), said even with
     * --quiet, since that output is cut short. */
    if (st == RBS_E_CLOSED && rbs_projector_last_error(projector)[0] != '\0')
        print_run_error("note: ", rbs_projector_last_error(projector), outs,
                        n_out);
    if (st != RBS_OK && st != RBS_E_CLOSED) {
        print_run_error("error: ", rbs_projector_last_error(projector), outs,
                        n_out);
        code = RBSF_EXIT_RUN;
    } else if (code == RBSF_EXIT_RUN) {
        /* the final checkpoint failed (said above) */
    } else if ((st == RBS_E_CLOSED || st == RBS_OK) && sig != 0) {
        /* (also when the simulation had made every frame: a signal drops
         * realtime pacing and a slow output's wait, the reel is written
         * out, the run "completes" -- but it was stopped) */
        code = 128 + sig;
    } else {
        code = RBSF_EXIT_OK;
    }
    if (!o.quiet) {
        rbs_world_def wd;
        if (st == RBS_E_CLOSED || (st == RBS_OK && sig != 0))
            fprintf(talk, "stopped at frame %llu by %s\n",
                    (unsigned long long)info.frame,
                    sig != 0 ? rbsf_signal_name(sig) : "quit");
        rbs_world_def_init(&wd);
        if (world == NULL || rbs_world_get_def(world, &wd) != RBS_OK)
            wd.max_substeps = 0; /* (not named) */
        summary(talk, o.scene ? o.scene : "built-in demonstration", &info,
                outs, n_out, start_frame, start_time, wd.max_substeps, world,
                o.resume != NULL ? 0 : 1);
        if (o.resume) {
            fprintf(talk, "resumed: ");
            rbsf__puts_shown(talk, o.resume);
            fprintf(talk, " at frame %llu\n", (unsigned long long)start_frame);
        }
        if (ckpt.saved) {
            fprintf(talk, "checkpoint: ");
            rbsf__puts_shown(talk, ckpt.name);
            fprintf(talk, " at frame %llu\n", (unsigned long long)ckpt.saved_at);
        }

    }
    if (demo && st == RBS_OK) {
        int failed = rbsf_demo_report(&demo_results, talk);
        if (failed > 0 && code == RBSF_EXIT_OK)
            code = RBSF_EXIT_RUN;
    }
    if (talk == stdout && rbsf_flush_stdout() != RBSF_EXIT_OK && code == RBSF_EXIT_OK)
        code = RBSF_EXIT_RUN;
    else if (talk != stdout)
        fflush(talk);

out:
    rbsf_signals_stop(&signals);
    rbs_projector_destroy(projector);
    discard_staged(outs, n_out); /* a rejected run: nothing is left */
    free(ckpt_target);
    rbs_renderer_registry_destroy(registry);
    rbs_world_destroy(world); /* before the pool it may use */
    rbs_pool_destroy(pool);
    rbs_scene_free(scene);
    free_outputs(outs, n_out);
    return code;
}
