/*
 * cli.h - the pieces of the rbsim command (not a library API).
 */
#ifndef RBSF_CLI_H
#define RBSF_CLI_H

#include <pthread.h>
#include <signal.h>
#include <stdio.h>

#include "dump.h"
#include "rbsim/reel.h"
#include "rbsim/scene.h"

/* Exit codes of the rbsim command. */
enum {
    RBSF_EXIT_OK = 0,
    RBSF_EXIT_USAGE = 2,
    RBSF_EXIT_SCENE = 3,
    RBSF_EXIT_RUN = 4
};

/* ---- commands.c: the command map of the input thread ---- */

/** Answer one command line typed during a run (reply: one or more lines,
 * each ending in a newline).  Returns RBS_OK, or an error when the command
 * is unknown or its arguments are bad (the reply explains). */
rbs_status rbsf_command_run(rbs_projector *projector, const char *line,
                            char *reply, size_t reply_size);
/** Write the list of commands ("help"). */
void rbsf_command_help(char *out, size_t size);

/* ---- input.c: the input thread ---- */

typedef struct rbsf_input {
    pthread_t thread;
    int wake[2];          /* self-pipe: a byte here ends the thread */
    int fd;               /* the input, normally 0 */
    FILE *reply;          /* where answers go */
    pthread_mutex_t *reply_lock;
    rbs_projector *projector;
    int started;
} rbsf_input;

/** Start reading command lines from fd.  End of input ends the thread,
 * not the run. */
int rbsf_input_start(rbsf_input *in, int fd, rbs_projector *projector,
                     FILE *reply, pthread_mutex_t *reply_lock);
/** Stop and join the thread. */
void rbsf_input_stop(rbsf_input *in);

/* ---- signals.c: the signal thread ---- */

/* The signal that ends an output call blocked after a stop (its handler does
 * nothing; see rbsf_stopper in dump.h), and how long such a call may block
 * first (s): a reader that is slow, not stalled, still gets the frames. */
#define RBSF_WAKE_SIGNAL SIGUSR2
#define RBSF_STOP_GRACE 0.5

typedef struct rbsf_signals {
    pthread_t thread;
    sigset_t set;             /* the signals the thread takes */
    pthread_mutex_t lock;
    rbs_projector *projector; /* guarded by lock; NULL until attached */
    int caught;               /* guarded; the first SIGINT/TERM/HUP, 0 if none */
    int stopping;             /* guarded; set by rbsf_signals_stop */
    int started;
    rbsf_stopper stopper;     /* the dump outputs' (rbsf_dump_bind) */
} rbsf_signals;

/** Block SIGINT, SIGTERM, SIGHUP (unless the caller ignores it, as nohup
 * does) and SIGUSR1 in this thread (and the threads it starts) and start a
 * thread that takes them with sigwait.  A SIGUSR1 from outside is ignored.
 * On the first of them the thread also stops s->stopper, so dump outputs
 * blocked on a pipe or FIFO give up (RBSF_WAKE_SIGNAL gets its empty handler
 * then, before it is first sent).  Call before any other thread starts. */
int rbsf_signals_start(rbsf_signals *s);
/** From now on a signal sends "quit" to this projector (at once if one was
 * caught already). */
void rbsf_signals_attach(rbsf_signals *s, rbs_projector *projector);
/** The signal caught (SIGINT, SIGTERM, SIGHUP) or 0. */
int rbsf_signals_caught(rbsf_signals *s);
/** "SIGINT", "SIGTERM" or "SIGHUP" (a static string). */
const char *rbsf_signal_name(int sig);
/** Stop and join the signal thread. */
void rbsf_signals_stop(rbsf_signals *s);

/* ---- run.c ---- */
/** "rbsim run ARGS": the exit code. */
int rbsf_run_main(int argc, char **argv);
/* The checks `run` makes of a scene's renderer entries before it opens any
 * (no two write one file, none overwrites a file the scene was read from),
 * as `check` makes them: 0, or an exit code with the reason on stderr. */
int rbsf_check_scene_outputs(const rbs_scene *scene);
/** Print a scene's load errors, one per line, at most RBS_SCENE_ERRORS_MAX
 * then how many more (nothing when it has none). */
void rbsf_print_scene_errors(const rbs_scene *scene, FILE *out);
/** "PREFIXPATH: cannot build the world: STATUS" (rbs_scene_build's failure
 * st; the world it would have made is gone), with the memory the world
 * asked for and its capacities when st is RBS_E_MEMORY. */
void rbsf_print_build_failure(const rbs_scene *scene, rbs_status st, const char *prefix, const char *path,
                              FILE *out);
/** Print a scene's warnings (rbs_scene_warning_get), one per line as
 * "FILE:LINE:COL: PATH: warning: MESSAGE", at most RBS_SCENE_ERRORS_MAX
 * then how many more (nothing when it has none). */
void rbsf_print_scene_warnings(const rbs_scene *scene, FILE *out);
/** Apply the command line's steps, dt and method to a scene
 * (rbs_scene_override); 0, or RBSF_EXIT_USAGE with the reason on stderr
 * (`what`: how the message names the options, e.g. "rbsim run: cannot
 * apply the options") -- the options' fault, as a bad option is. */
int rbsf_override_options(rbs_scene *scene, uint64_t steps, double dt, const char *method, const char *what);
/** Print that a scene's renderer entry `index` (at file:line:column) names
 * a type this rbsim does not register, as "FILE:LINE:COL:
 * renderers[K].type: unknown renderer type "T" (did you mean "csv"?; known:
 * ...)", the suggestion when a known type is at most 2 edits away; one form
 * for check and run. */
void rbsf_print_unknown_renderer(FILE *out, const char *file, int line, int column,
                                 unsigned long index, const char *type);
/** After a scene that failed to load with status st, print a hint, or
 * nothing (path NULL: nothing).  RBS_E_IO: when `path` does not exist
 * (ENOENT) and its folder holds a name at most 2 edits from its last
 * component, "PATH: did you mean 'FOLDER/NAME'?".  RBS_E_SCENE: when path
 * is a regular file read as a config.txt by elimination (a name not ending
 * in .json or .txt, a first non-blank byte not '{'), "PATH was read as a
 * text scene's config.txt: ...".  Paths shown safely. */
void rbsf_scene_hint(FILE *out, const char *path, rbs_status st);
/** Print help for a command (NULL: the general usage). 0 if known. */
int rbsf_help(FILE *out, const char *command);

/* ---- main.c ---- */
/** Flush standard output once a command has printed all it prints there:
 * RBSF_EXIT_OK, or, when that was lost (a full disk, a closed pipe), a
 * message with the reason and RBSF_EXIT_RUN.  Only the first flush that
 * fails knows the reason (errno), so a command that flushes calls this and
 * not fflush. */
int rbsf_flush_stdout(void);
/** The path to read a scene argument from: "/dev/stdin" for "-" (standard
 * input, as most tools take it), else the argument itself. */
const char *rbsf_scene_arg(const char *arg);
/** The stepping methods the library knows, as "euler, selective, ... or
 * soft" (from rbs_method_name, so a new method is named in every message);
 * cut short if it does not fit in size bytes. */
void rbsf_method_list(char *out, size_t size);

#endif
