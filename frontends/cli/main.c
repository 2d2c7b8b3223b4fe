/*
 * main.c - the rbsim command: run, check, explain, convert, help,
 * --version.
 */
#include "c_locale.h"
#include "shown.h"
#include "cli.h"
#include "dump.h"
#ifdef RBSF_HAVE_SDL
#include "sdl_renderer.h"
#endif

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* A macro's value as a string literal (the help texts quote the library's
 * constants instead of copying them). */
#define CLI_STR_(x) #x
#define CLI_STR(x) CLI_STR_(x)

static const char usage_text[] =
    "usage: rbsim COMMAND [ARGUMENTS]\n"
    "\n"
    "commands:\n"
    "  run [SCENE] [OPTIONS]  run a scene; with no SCENE, the built-in\n"
    "                         demonstration (outputs in ./rbsim-demo/)\n"
    "  check SCENE            validate a scene and print every error\n"
    "  explain SCENE          print the pipeline a step runs for SCENE (each\n"
    "                         stage in or out, and why)\n"
    "  convert IN OUT         convert a scene between JSON (.json) and the\n"
    "                         config.txt format (OUT ending in .txt)\n"
    "  help [COMMAND]         this text, or a command's options (also\n"
    "                         COMMAND --help, or -h)\n"
    "  --version              print the version (with --help as well, in\n"
    "                         either order: this text)\n"
    "\n"
    "exit codes: 0 success, 2 usage error, 3 scene error, 4 run-time error\n"
    "(capacity, numerical failure, renderer failure such as a full disk or a\n"
    "file size limit, lost standard output), 129/130/143 stopped by\n"
    "SIGHUP/SIGINT/SIGTERM.\n";

static const char run_text[] =
    "usage: rbsim run [SCENE] [OPTIONS]\n"
    "\n"
    "Run SCENE (a .json scene, or a config.txt with its materials.txt and\n"
    "objects.txt; - reads it from standard input).  With no SCENE, run the built-in demonstration: a bouncing\n"
    "ball, a ball launched sliding that then rolls, and a small billiards\n"
    "break; it writes rbsim-demo/demo.csv, rbsim-demo/stats.csv (and PNG\n"
    "frames in rbsim-demo/png/ when built with SDL) and checks the run against\n"
    "exact answers (first impact at sqrt(2h/g), rolling at 5/7 v0), which hold\n"
    "for its own steps, dt, method and slop: those options need a SCENE.\n"
    "\n";

/* (run's help in two strings: C99 promises string literals of 4095 bytes) */
static const char run_options_text[] =
    "options (they override the scene):\n"
    "  --steps N     steps to take, 0 to 2^53: frames 0..N at t = k dt\n"
    "                (0: frame 0 only, as \"steps\": 0 in a scene)\n"
    "  --dt S        time step, seconds (> 0)\n"
    "  --method M    euler, selective, event, verlet, rk4, adaptive, soft or\n"
    "                auto (a scene's default: soft from " CLI_STR(RBS_METHOD_AUTO_SOFT_BODIES) " moving spheres\n"
    "                on without mutual gravity, their masses within a ratio\n"
    "                of " CLI_STR(RBS_METHOD_AUTO_SOFT_MASS_RATIO) ", else euler)\n"
    "  --slop X      overlap an impact may end a step with before it is\n"
    "                rolled back, of the smaller radius, in (0, 0.1)\n"
    "                (default the scene's simulation.slop, else 1e-6)\n"
    "  --csv FILE    every body's state each frame, as CSV (\"-\": stdout)\n"
    "  --json FILE   JSON Lines, one object per frame\n"
    "  --stats FILE  energy, momentum and step counters each frame, as CSV\n"
    "  --png DIR     PNG frames into DIR (builds with SDL; a folder, not\n"
    "                stdout: '-' is refused); the frames and contact sheet\n"
    "                an earlier run left in DIR are removed first (with\n"
    "                --resume at frame K: the frames above K)\n"
    "  --every K     keep frames 0, K, 2K, ... (and the last) in --csv, --json\n"
    "                and --png, K from 1 to 2147483647 (2^31 - 1, as the\n"
    "                scene's \"every\"; a resumed run keeps the same numbers,\n"
    "                and a run with --checkpoint keeps its last frame only\n"
    "                if a multiple of K: the resumed run goes on from it);\n"
    "                without --csv, --json or --png it is refused (a\n"
    "                scene's renderer keeps its own \"every\", --stats every\n"
    "                frame)\n"
    "  --realtime    show frame k at k dt of wall time (default: as fast as\n"
    "                possible)\n"
    "  --speed X     real-time factor for --realtime (default 1; only with it)\n"
    "  --paused      start paused (then \"resume\" or \"step N\")\n"
    "  --reel N      frames the reel holds between the threads (default 64)\n"
    "  --threads N   threads that step the world, the simulation thread\n"
    "                included, 1 to " CLI_STR(RBS_WORKERS_MAX) " (default 1): the soft method's\n"
    "                piles split each step among them; the results are the\n"
    "                same bits for any N\n"
    "  --quiet       no progress bar and no summary\n"
    "  --checkpoint FILE\n"
    "                save the exact world state to FILE (atomically) at the\n"
    "                end of the run, also when stopped by quit, Ctrl-C,\n"
    "                SIGTERM or SIGHUP (at the last frame made); with\n"
    "                --steps N below the scene's, the run stops at step N\n"
    "                with a checkpoint\n"
    "  --checkpoint-every N\n"
    "                also save it after every N-th step (frames N, 2N, ...)\n"
    "  --resume FILE continue from a checkpoint at step k (- is standard\n"
    "                input): frames k+1 .. the scene's steps (or --steps,\n"
    "                counted from 0), numbered as in the first run; frame k\n"
    "                itself is not written again, so the\n"
    "                first run's frames 0..k plus these equal an uninterrupted\n"
    "                run's, byte for byte (PNG pictures alike only where each\n"
    "                view gives its position and target).  The checkpoint\n"
    "                must continue SCENE (same bodies by slot, name, type\n"
    "                and definition: radius, mass, fixed, force, torque,\n"
    "                material, colour, texture, centre of mass, inertia,\n"
    "                plane normal and point;\n"
    "                capacities, dt, method, gravity, materials); a\n"
    "                corrupt, truncated, foreign or unmatched file exits 3; no\n"
    "                output may be FILE\n"
    "At most 4 outputs (the scene's renderers and these) per run, at most one\n"
    "on stdout.  Every output is checked and made before any is written: an\n"
    "existing file is written as a temporary beside it, renamed onto it when\n"
    "the run ends; a rejected run writes nothing.  A value that is an option\n"
    "name (--csv --quiet) is refused: write ./--quiet for such a file.  Each\n"
    "option is given once at most, a flag too (--paused --paused is refused).\n"
    "\n"
    "While it runs, type commands on standard input (unless it is the scene\n"
    "or the --resume checkpoint):\n";

static const char check_text[] =
    "usage: rbsim check SCENE\n"
    "\n"
    "Validate SCENE: the file, the world it builds and its renderer entries\n"
    "(including that their output folders exist); - reads it from standard\n"
    "input.  Prints every error as file:line:column: key: message.  Exit 0 if\n"
    "valid, 3 if not.  A warning (file:line:column: key: warning: message;\n"
    "a material named in a materials row that no body has) does not make a\n"
    "scene invalid: exit 0.\n";

static const char explain_text[] =
    "usage: rbsim explain SCENE [--method M]\n"
    "\n"
    "Load and validate SCENE (- is standard input; errors as in 'rbsim\n"
    "check', exit 3), build its world and print the pipeline rbs_world_step()\n"
    "runs for it: the bodies, the method and its sub-steps, and each stage in\n"
    "or out with the reason.\n"
    "--method M explains the scene with another method (euler, selective,\n"
    "event, verlet, rk4, adaptive, soft, auto; for auto it says which one it\n"
    "takes and why; one the scene cannot take is a usage error, as in run).\n"
    "Exit 0, 2 (usage) or 3 (scene error).\n";

static const char convert_text[] =
    "usage: rbsim convert IN OUT\n"
    "\n"
    "Read the scene IN (either format; - is standard input) and write it to\n"
    "OUT: JSON when OUT ends in .json (or .JSON), the config.txt format (with\n"
    "materials.txt and objects.txt beside it) when OUT ends in .txt (or .TXT); OUT - is\n"
    "refused (no file to rename into place).  Every file is written to a temporary\n"
    "and renamed into place only when all are complete: a failed convert\n"
    "leaves what was there and names the file that failed and why.  A folder,\n"
    "device or FIFO is never replaced, nor one with no write permission; a\n"
    "symbolic link's target is written.  An OUT that is a file IN is read\n"
    "from (IN itself by any path or link, its materials.txt ...) is refused\n"
    "before anything is written (exit 2).\n"
    "Exit 0, 2 (usage), 3 (IN is not a valid scene) or 4 (OUT could not be\n"
    "written).\n";

void rbsf_method_list(char *out, size_t size)
{
    size_t used = 0;
    int k;
    if (size == 0)
        return;
    out[0] = '\0';
    for (k = 0; k < RBS_METHOD_COUNT; k++) {
        const char *name = rbs_method_name((rbs_method)k);
        int w = snprintf(out + used, size - used, "%s%s",
                         k == 0 ? "" : (k == RBS_METHOD_COUNT - 1 ? " or " : ", "),
                         name != NULL ? name : "?");
        if (w < 0 || (size_t)w >= size - used)
            return; /* cut short: what fitted stays */
        used += (size_t)w;
    }
}

void rbsf_print_unknown_renderer(FILE *out, const char *file, int line, int column,
                                 unsigned long index, const char *type)
{
    /* The types this rbsim registers (main.c's check, run.c). */
    static const char *const known[] = {"csv", "json", "stats",
#ifdef RBSF_HAVE_SDL
                                        "sdl",
#endif
    };
    const char *hint = rbs_scene_suggest(type, known, sizeof known / sizeof known[0]);
    char shown[256];
#ifndef RBSF_HAVE_SDL
    if (strcmp(type, "sdl") == 0) {
        rbsf__tell(out, "%s:%d:%d: renderers[%lu].type: unknown renderer type "
                        "\"sdl\" (this rbsim was built without SDL)\n",
                   file, line, column, index);
        return;
    }
#endif
    rbsf__tell(out, "%s:%d:%d: renderers[%lu].type: unknown renderer type \"%s\" "
                    "(%s%s%sknown: csv, json, stats%s)\n",
               file, line, column, index, rbsf__shown(type, shown, sizeof shown),
               hint ? "did you mean \"" : "", hint ? hint : "", hint ? "\"?; " : "",
#ifdef RBSF_HAVE_SDL
               ", sdl (PNG frames)"
#else
               ""
#endif
    );
}

/* Whether path names a regular file whose name does not end in .json or
 * .txt (any case) and whose first non-blank byte is not '{': the file
 * RBS_SCENE_AUTO read as a config.txt by elimination.  (Read again, once,
 * after the load failed; a FIFO or device is not.) */
static int text_by_elimination(const char *path)
{
    struct stat sb;
    size_t len = strlen(path);
    FILE *f;
    int c;
    if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
        return 0;
    if ((len >= 5 && strcasecmp(path + len - 5, ".json") == 0) ||
        (len >= 4 && strcasecmp(path + len - 4, ".txt") == 0))
        return 0;
    if ((f = fopen(path, "rb")) == NULL)
        return 0;
    do
        c = getc(f);
    while (c == ' ' || c == '\t' || c == '\n' || c == '\r');
    fclose(f);
    return c != '{';
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

void rbsf_scene_hint(FILE *out, const char *path, rbs_status st)
{
    struct stat sb;
    const char *slash, *base;
    char dir[4096], shown[512];
    const char *hint;
    char **names = NULL;
    size_t n, count = 0, cap = 0, k;
    DIR *d;
    struct dirent *e;
    if (path == NULL)
        return;
    if (st == RBS_E_SCENE && text_by_elimination(path)) {
        rbsf__puts_shown(out, path);
        fputs(" was read as a text scene's config.txt: its name does not end in "
              ".json and it does not start with '{' (a scene is NAME.json or a "
              "config.txt with its materials and objects files: scenes/FORMAT.md)\n",
              out);
        return;
    }
    if (st != RBS_E_IO || stat(path, &sb) == 0 || errno != ENOENT)
        return;
    slash = strrchr(path, '/');
    base = slash ? slash + 1 : path;
    n = slash ? (size_t)(slash - path) : 0;
    if (*base == '\0' || n >= sizeof dir)
        return;
    if (slash == NULL)
        strcpy(dir, ".");
    else if (n == 0)
        strcpy(dir, "/");
    else {
        memcpy(dir, path, n);
        dir[n] = '\0';
    }
    if ((d = opendir(dir)) == NULL)
        return; /* (the folder is missing too: nothing to suggest) */
    /* the folder's names, sorted (readdir's order is the file system's: of
     * equally near names the first by name is suggested), then the
     * library's rule for "did you mean" (rbs_scene_suggest, as a scene's
     * keys and names get it); a folder too large to hold is not searched */
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' && base[0] != '.')
            continue; /* (".", "..", hidden files: only when asked for) */
        if (count == cap) {
            char **more = cap < 4096 ? realloc(names, (cap ? 2 * cap : 64) * sizeof *names) : NULL;
            if (more == NULL)
                break;
            names = more;
            cap = cap ? 2 * cap : 64;
        }
        if ((names[count] = strdup(e->d_name)) == NULL)
            break;
        count++;
    }
    closedir(d);
    if (e == NULL) {
        qsort(names, count, sizeof *names, compare_names);
        hint = rbs_scene_suggest(base, (const char *const *)names, count);
        if (hint != NULL) {
            rbsf__puts_shown(out, path);
            fputs(": did you mean '", out);
            fwrite(path, 1, (size_t)(base - path), out);
            fputs(rbsf__shown(hint, shown, sizeof shown), out);
            fputs("'?\n", out);
        }
    }
    for (k = 0; k < count; k++)
        free(names[k]);
    free(names);
}

int rbsf_help(FILE *out, const char *command)
{
    if (command == NULL) {
        fputs(usage_text, out);
        return 0;
    }
    if (strcmp(command, "run") == 0) {
        char list[2048];
        fputs(run_text, out);
        fputs(run_options_text, out);
        rbsf_command_help(list, sizeof list);
        fputs(list, out);
        fputs("End of input (a pipe, /dev/null) does not stop the run (a "
              "paused run is resumed:\nnothing could resume it later); "
              "simulation.pause_on_collision needs a terminal.\nCtrl-C, "
              "SIGTERM or SIGHUP (unless ignored, as by nohup) stops the run "
              "cleanly\n(outputs complete up to the last frame; exit 130, 143 "
              "or 129), after saving\n--checkpoint FILE at that frame.  "
              "SIGUSR1 is ignored.\n",
              out);
        return 0;
    }
    if (strcmp(command, "check") == 0) {
        fputs(check_text, out);
        return 0;
    }
    if (strcmp(command, "explain") == 0) {
        fputs(explain_text, out);
        return 0;
    }
    if (strcmp(command, "convert") == 0) {
        fputs(convert_text, out);
        return 0;
    }
    if (strcmp(command, "help") == 0) {
        fputs("usage: rbsim help [COMMAND]\n", out);
        return 0;
    }
    return -1;
}

/* Print a scene's load errors on stdout (check and explain). */
static void print_load_errors(const rbs_scene *scene, const char *path,
                              rbs_status st)
{
    if (scene != NULL && rbs_scene_error_count(scene) > 0)
        rbsf_print_scene_errors(scene, stdout);
    else
        rbsf__tell(stdout, "%s: %s\n", path, rbs_status_string(st));
    rbsf_scene_hint(stdout, path, st);
}

/* A command's file arguments (check: SCENE; convert: IN OUT) into files:
 * exactly want of them.  These commands take no option, so one ("--steps"
 * after check) is named as unknown, and so is an argument too many, an
 * empty one, or a missing one; "--" ends the options.  0, or an exit code
 * after the message and the command's help. */
static int file_args(const char *cmd, const char *help, int argc, char **argv,
                     const char **files, int want)
{
    int i, got = 0, options = 1;
    for (i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (options && strcmp(a, "--") == 0) {
            options = 0;
            continue;
        }
        if (options && a[0] == '-' && a[1] != '\0') {
            char shown[256];
            rbsf__tell(stderr, "rbsim %s: unknown option '%s'\n%s", cmd,
                    rbsf__shown(a, shown, sizeof shown), help);
            return RBSF_EXIT_USAGE;
        }
        if (a[0] == '\0') {
            rbsf__tell(stderr, "rbsim %s: argument %d is an empty string, not a "
                            "file name\n%s", cmd, i + 1, help);
            return RBSF_EXIT_USAGE;
        }
        if (got == want) {
            char shown[256];
            rbsf__tell(stderr, "rbsim %s: unexpected argument '%s' (expected %s)\n%s",
                    cmd, rbsf__shown(a, shown, sizeof shown),
                    want == 1 ? "one scene file" : "IN and OUT", help);
            return RBSF_EXIT_USAGE;
        }
        files[got] = got == 0 ? rbsf_scene_arg(a) : a;
        got++;
    }
    if (got < want) {
        rbsf__tell(stderr, "rbsim %s: expected %s\n%s", cmd,
                want == 1 ? "one scene file"
                          : got == 0 ? "IN and OUT" : "OUT after IN",
                help);
        return RBSF_EXIT_USAGE;
    }
    return 0;
}

static int check_main(int argc, char **argv)
{
    rbs_scene *scene = NULL;
    rbs_world *world = NULL;
    rbs_renderer_registry *registry = NULL;
    rbs_status st;
    const char *path;
    int code = file_args("check", check_text, argc, argv, &path, 1);
    uint32_t i, n;
#ifdef RBSF_HAVE_SDL
    /* (the sdl check places its cameras at the world's start) */
    rbsf_sdl_world_api sdl_api = {rbs_world_state, rbs_frame_capture, NULL, NULL, NULL, NULL};
    rbs_renderer_class sdl_cls;
#endif

    if (code != 0)
        return code;
    st = rbs_scene_load(path, RBS_SCENE_AUTO, &scene);
    if (st != RBS_OK) {
        print_load_errors(scene, path, st);
        rbs_scene_free(scene);
        return RBSF_EXIT_SCENE;
    }
    rbsf_print_scene_warnings(scene, stdout); /* (a valid scene: exit 0 still) */
    st = rbs_scene_build(scene, &world);
    if (st != RBS_OK) {
        rbsf_print_build_failure(scene, st, "", path, stdout);
        code = RBSF_EXIT_SCENE;
        goto out;
    }
    /* Renderer entries: each known type checks its own keys and path. */
    if (rbs_renderer_registry_create(&registry) != RBS_OK) {
        code = RBSF_EXIT_RUN;
        goto out;
    }
    rbs_renderer_register(registry, rbsf_csv_class());
    rbs_renderer_register(registry, rbsf_json_class());
    rbs_renderer_register(registry, rbsf_stats_class());
#ifdef RBSF_HAVE_SDL
    sdl_cls = rbsf_sdl_class_with(&sdl_api);
    rbs_renderer_register(registry, &sdl_cls);
#endif
    n = rbs_scene_renderer_count(scene);
    for (i = 0; i < n; i++) {
        rbs_scene_renderer r;
        rbs_renderer_config c;
        const rbs_renderer_class *cls;
        char err[512] = "";
        if (rbs_scene_renderer_get(scene, i, &r) != RBS_OK)
            continue;
        if (rbs_renderer_find(registry, r.type, &cls) != RBS_OK) {
            rbsf_print_unknown_renderer(stdout, r.file, (int)r.line, (int)r.column,
                                        (unsigned long)i, r.type);
            code = RBSF_EXIT_SCENE;
            continue;
        }
        if (cls->check == NULL)
            continue;
        memset(&c, 0, sizeof c);
        c.struct_size = sizeof c;
        c.type = r.type;
        c.json = r.json;
        c.file = r.file;
        c.line = r.line;
        c.column = r.column;
        st = cls->check(cls->context, &c, world, err, sizeof err);
        if (st != RBS_OK) {
            /* (the message repeats the entry's path: shown safely) */
            rbsf__puts_shown(stdout, r.file);
            printf(":%d:%d: renderers[%lu] (%s): ", (int)r.line, (int)r.column,
                   (unsigned long)i, r.type);
            rbsf__puts_shown(stdout, err[0] ? err : rbs_status_string(st));
            putchar('\n');
            code = RBSF_EXIT_SCENE;
        }
    }
    if (code == RBSF_EXIT_OK)
        code = rbsf_check_scene_outputs(scene); /* (as run checks them) */
    if (code == RBSF_EXIT_OK)
        rbsf__tell(stdout, "%s: ok (%llu steps, %lu renderer%s)\n", path,
               (unsigned long long)rbs_scene_steps(scene), (unsigned long)n,
               n == 1 ? "" : "s");
out:
    rbs_renderer_registry_destroy(registry);
    rbs_world_destroy(world);
    rbs_scene_free(scene);
    return code;
}

static int explain_main(int argc, char **argv)
{
    const char *path = NULL, *method = NULL;
    rbs_scene *scene = NULL;
    rbs_world *world = NULL;
    char *text = NULL;
    size_t needed = 0;
    rbs_status st;
    int i, code = RBSF_EXIT_OK;

    for (i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--method") == 0 || strncmp(a, "--method=", 9) == 0) {
            rbs_method m;
            const char *v =
                a[8] == '=' ? a + 9 : (i + 1 < argc ? argv[++i] : NULL);
            if (method != NULL || v == NULL) {
                rbsf__tell(stderr, "rbsim explain: --method %s\n%s",
                        method ? "given twice" : "needs a value", explain_text);
                return RBSF_EXIT_USAGE;
            }
            if (rbs_method_from_name(v, &m) != RBS_OK) {
                char list[256], shown[256];
                rbsf_method_list(list, sizeof list);
                rbsf__tell(stderr, "rbsim explain: --method: unknown method '%s'; "
                                "expected %s\n", rbsf__shown(v, shown, sizeof shown), list);
                return RBSF_EXIT_USAGE;
            }
            method = v;
        } else if (a[0] == '-' && a[1] != '\0') {
            char shown[256];
            rbsf__tell(stderr, "rbsim explain: unknown option '%s'\n%s",
                    rbsf__shown(a, shown, sizeof shown), explain_text);
            return RBSF_EXIT_USAGE;
        } else if (a[0] == '\0') {
            rbsf__tell(stderr, "rbsim explain: argument %d is an empty string, "
                            "not a file name\n%s", i + 1, explain_text);
            return RBSF_EXIT_USAGE;
        } else if (path != NULL) {
            char shown[256];
            rbsf__tell(stderr, "rbsim explain: unexpected argument '%s' (expected "
                            "one scene file)\n%s", rbsf__shown(a, shown, sizeof shown),
                    explain_text);
            return RBSF_EXIT_USAGE;
        } else {
            path = rbsf_scene_arg(a);
        }
    }
    if (path == NULL) {
        rbsf__tell(stderr, "rbsim explain: expected one scene file\n%s",
                explain_text);
        return RBSF_EXIT_USAGE;
    }
    st = rbs_scene_load(path, RBS_SCENE_AUTO, &scene);
    if (st != RBS_OK) {
        print_load_errors(scene, path, st);
        code = RBSF_EXIT_SCENE;
        goto out;
    }
    rbsf_print_scene_warnings(scene, stderr); /* (stdout is the pipeline) */
    /* A --method the scene cannot take ("event" with rolling resistance) is
     * the option's fault, as in run: on stderr, exit 2 (it was exit 3 on
     * stdout, as a scene error: a probe of session 46). */
    if (method != NULL &&
        (code = rbsf_override_options(scene, 0, 0.0, method, "rbsim explain: cannot apply --method")) != 0)
        goto out;
    st = rbs_scene_build(scene, &world);
    if (st != RBS_OK) {
        rbsf_print_build_failure(scene, st, "", path, stdout);
        code = RBSF_EXIT_SCENE;
        goto out;
    }
    /* Ask for the length, then write the whole text. */
    rbs_world_explain(world, NULL, 0, &needed);
    text = needed > 0 ? malloc(needed) : NULL;
    if (text == NULL ||
        (st = rbs_world_explain(world, text, needed, NULL)) != RBS_OK) {
        rbsf__tell(stderr, "rbsim explain: %s: cannot describe the pipeline: %s\n",
                path, text == NULL ? "out of memory" : rbs_status_string(st));
        code = RBSF_EXIT_RUN;
        goto out;
    }
    rbsf__tell(stdout, "scene: %s\n", path);
    fputs(text, stdout); /* (whole, however long; the names in it are checked) */
    code = rbsf_flush_stdout();
out:
    free(text);
    rbs_world_destroy(world);
    rbs_scene_free(scene);
    return code;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

static int convert_main(int argc, char **argv)
{
    char why[600];
    rbs_scene *scene = NULL;
    rbs_scene_format format;
    rbs_status st;
    uint32_t k, count;
    const char *files[2];
    int code = file_args("convert", convert_text, argc, argv, files, 2);

    if (code != 0)
        return code;
    if (strcmp(files[1], "-") == 0) {
        /* (the save writes a temporary file beside OUT, then renames it, and
         * a config.txt may be several files: none of it can be a stream) */
        rbsf__tell(stderr,
                "rbsim convert: OUT '-': the converted scene cannot go to "
                "standard output; name a file (*.json or a config.txt path)\n");
        return RBSF_EXIT_USAGE;
    }
    /* (".JSON" and ".TXT" too, as the loader reads them; a folder is named as such, and
     * its config.txt offered: a probe of session 46 got "cannot tell the
     * format of 'out'" for an existing folder and of 'x.JSON') */
    if (ends_with(files[1], ".json") || ends_with(files[1], ".JSON"))
        format = RBS_SCENE_JSON;
    else if (ends_with(files[1], ".txt") || ends_with(files[1], ".TXT"))
        format = RBS_SCENE_TEXT;
    else {
        struct stat sb;
        if (stat(files[1], &sb) == 0 && S_ISDIR(sb.st_mode))
            rbsf__tell(stderr,
                    "rbsim convert: OUT '%s' is a folder: name '%s%sconfig.txt' "
                    "for the config.txt format, or a *.json file\n",
                    files[1], files[1],
                    ends_with(files[1], "/") ? "" : "/");
        else
            rbsf__tell(stderr,
                    "rbsim convert: cannot tell the format of '%s': name it "
                    "*.json or a config.txt path\n",
                    files[1]);
        return RBSF_EXIT_USAGE;
    }
    st = rbs_scene_load(files[0], RBS_SCENE_AUTO, &scene);
    if (st != RBS_OK) {
        count = scene ? rbs_scene_error_count(scene) : 0;
        for (k = 0; k < count && k < RBS_SCENE_ERRORS_MAX; k++) {
            rbs_scene_error e;
            if (rbs_scene_error_get(scene, k, &e) == RBS_OK)
                rbsf__tell(stderr, "%s\n", e.text);
        }
        if (count == 0)
            rbsf__tell(stderr, "%s: %s\n", files[0], rbs_status_string(st));
        rbsf_scene_hint(stderr, files[0], st);
        rbs_scene_free(scene);
        return RBSF_EXIT_SCENE;
    }
    rbsf_print_scene_warnings(scene, stderr); /* (written as read) */
    st = rbs_scene_save_v2(scene, files[1], format, why, sizeof why);
    if (st == RBS_E_OWN_INPUT) {
        /* OUT (or a text OUT's table beside it) is a file IN is read from,
         * through any spelling or link, or standard input redirected from
         * it: the save refuses before writing anything (the library's
         * check, scene.h), a usage error naming both files */
        rbsf__tell(stderr, "rbsim convert: OUT '%s' would write over its input: %s%s\n", files[1],
                why, strcmp(files[0], "/dev/stdin") == 0 ? " (IN '-' is standard input)" : "");
        rbs_scene_free(scene);
        return RBSF_EXIT_USAGE;
    }
    if (st != RBS_OK) {
        /* nothing was written: the save replaces files only when all are complete */
        if (why[0] != '\0')
            rbsf__tell(stderr, "rbsim convert: %s\n", why);
        else
            rbsf__tell(stderr, "rbsim convert: cannot write '%s': %s\n", files[1],
                    rbs_status_string(st));
        rbs_scene_free(scene);
        return RBSF_EXIT_RUN;
    }
    rbs_scene_free(scene);
    return RBSF_EXIT_OK;
}

/* A closed standard descriptor would be reused by the next open(): an
 * output file would become "standard input".  Put /dev/null at a closed
 * standard input or error, and at a closed standard output /dev/null opened
 * for reading only, so that what the command prints there fails with EBADF
 * ("Bad file descriptor": the descriptor was closed) and is reported as
 * lost, as on a full disk, rather than vanishing into /dev/null.  (It was
 * the write end of a pipe with no reader, and the message said "Broken
 * pipe" for a descriptor the user had closed: a probe of session 46.) */
static void guard_standard_fds(void)
{
    int fd;
    for (fd = 0; fd <= 2; fd++) {
        if (fcntl(fd, F_GETFD) != -1)
            continue;
        if (open("/dev/null", fd == 2 ? O_WRONLY : O_RDONLY) != fd)
            break;
    }
}

/* The message when what a command printed on the standard output was lost,
 * with the reason (errno e; 0 if unknown). */
static void say_stdout_lost(int e)
{
    rbsf__tell(stderr, "rbsim: what it printed on the standard output was lost%s%s\n",
            e ? ": " : "", e ? strerror(e) : "");
}

/* ("rbsim run -" said "cannot open '-'": a probe of session 46.  Taking it
 * as /dev/stdin keeps what that path already does: the scene's format told
 * from its bytes, a stalled pipe given up at a signal, and standard input
 * then read for no commands.) */
const char *rbsf_scene_arg(const char *arg)
{
    return strcmp(arg, "-") == 0 ? "/dev/stdin" : arg;
}

int rbsf_flush_stdout(void)
{
    int e;
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout))
        return RBSF_EXIT_OK;
    e = errno;
    say_stdout_lost(e);
    clearerr(stdout); /* said once: finish_stdout need not say it again */
    return RBSF_EXIT_RUN;
}

/* The command's exit code rc, unless what it printed on the standard output
 * was lost (a full disk, a closed pipe or descriptor): then a message and
 * RBSF_EXIT_RUN (a command that failed keeps its code, and is told too:
 * check's errors go to the standard output). */
static int finish_stdout(int rc)
{
    int code = rbsf_flush_stdout();
    errno = 0;
    if (fclose(stdout) != 0 && code == RBSF_EXIT_OK) {
        say_stdout_lost(errno);
        code = RBSF_EXIT_RUN;
    }
    return rc != RBSF_EXIT_OK ? rc : code;
}

static int dispatch(int argc, char **argv);

int main(int argc, char **argv)
{
    rbsf__locale l;
    int code;
    /* rbsim never calls setlocale, so it runs in the "C" locale, as its
     * outputs need ('.' in every number it prints or reads); but libraries
     * it links may (libSDL2 and libX11 import setlocale), and a thread with
     * a locale of its own is not affected by that. */
    rbsf__c_locale_push(&l);
    guard_standard_fds();
    /* A file size limit (ulimit -f) fails the write with EFBIG, reported and
     * cleaned up like any write error (run, convert), instead of a SIGXFSZ
     * death that leaves temporary files behind. */
    signal(SIGXFSZ, SIG_IGN);
    signal(SIGPIPE, SIG_IGN); /* a closed pipe is a write error, reported */
    code = finish_stdout(dispatch(argc, argv));
    rbsf__c_locale_pop(&l);
    return code;
}

/* Does an argument of a command ask for its help ("--help" or "-h", before
 * a "--" that ends the options)?  It wins over the other arguments, as in
 * most commands: "rbsim run scene.json --csv a.csv --help" shows run's help
 * and runs nothing. */
static int asks_help(int argc, char **argv)
{
    int i;
    for (i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0)
            return 0;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    }
    return 0;
}

/* Is a an option of rbsim itself, before any command? */
static int is_top_flag(const char *a)
{
    return strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0 ||
           strcmp(a, "--version") == 0;
}

static int dispatch(int argc, char **argv)
{
    const char *cmd;
    if (argc < 2) {
        fputs(usage_text, stderr);
        return RBSF_EXIT_USAGE;
    }
    cmd = argv[1];
    /* The top-level flags (--help, -h, --version) at the start: --help wins
     * wherever it is among them, as in GNU tools ("rbsim --version --help"
     * and "rbsim --help --version" print the usage); what follows them is
     * help's COMMAND. */
    if (is_top_flag(cmd)) {
        int k = 1, help = 0;
        while (k < argc && is_top_flag(argv[k])) {
            if (strcmp(argv[k], "--version") != 0)
                help = 1;
            k++;
        }
        if (help && k > 2) {
            argc -= k - 2;
            argv += k - 2;
            cmd = "--help";
        }
    }
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        if (argc != 2) {
            rbsf__tell(stderr, "rbsim --version: takes no arguments\n");
            return RBSF_EXIT_USAGE;
        }
        printf("rbsim %s (library %s)\n", RBS_VERSION_STRING, rbs_version());
        if (rbs_version_number() / 10000 != RBS_VERSION_NUMBER / 10000) {
            rbsf__tell(stderr, "rbsim: library version %s does not match this "
                            "program's %s\n",
                    rbs_version(), RBS_VERSION_STRING);
            return RBSF_EXIT_RUN;
        }
        return RBSF_EXIT_OK;
    }
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 ||
        strcmp(cmd, "help") == 0) {
        if (argc == 3 && asks_help(1, argv + 2)) /* help --help */
            return rbsf_help(stdout, "help") == 0 ? RBSF_EXIT_OK : RBSF_EXIT_USAGE;
        if (argc > 3) {
            rbsf__tell(stderr, "rbsim help: one command at most\n");
            return RBSF_EXIT_USAGE;
        }
        if (rbsf_help(stdout, argc == 3 ? argv[2] : NULL) != 0) {
            char shown[256];
            rbsf__tell(stderr, "rbsim help: unknown command '%s'\n%s",
                    rbsf__shown(argv[2], shown, sizeof shown), usage_text);
            return RBSF_EXIT_USAGE;
        }
        return RBSF_EXIT_OK;
    }
    if ((strcmp(cmd, "run") == 0 || strcmp(cmd, "check") == 0 ||
         strcmp(cmd, "convert") == 0 || strcmp(cmd, "explain") == 0) &&
        asks_help(argc - 2, argv + 2))
        return rbsf_help(stdout, cmd) == 0 ? RBSF_EXIT_OK : RBSF_EXIT_USAGE;
    if (strcmp(cmd, "run") == 0)
        return rbsf_run_main(argc - 2, argv + 2);
    if (strcmp(cmd, "check") == 0)
        return check_main(argc - 2, argv + 2);
    if (strcmp(cmd, "convert") == 0)
        return convert_main(argc - 2, argv + 2);
    if (strcmp(cmd, "explain") == 0)
        return explain_main(argc - 2, argv + 2);
    {
        char shown[256];
        rbsf__tell(stderr, "rbsim: unknown command '%s'\n%s",
                rbsf__shown(cmd, shown, sizeof shown), usage_text);
    }
    return RBSF_EXIT_USAGE;
}
