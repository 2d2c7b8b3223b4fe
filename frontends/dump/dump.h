/*
 * dump.h - the recording renderers of rbsim: CSV for spreadsheets, JSON Lines
 * and a CSV of per-frame statistics.  A static library for the front ends;
 * register the types with rbs_renderer_register(registry, rbsf_csv_class()).
 *
 * Every output is written a whole frame at a time (formatted into a buffer
 * reserved at create, then written in full), so a file never ends in half a
 * line: on a write error the frame's partial bytes are cut off again and the
 * run stops with a message naming the file.  Numbers are printed in the
 * shortest form that reads back as the same double, in the "C" locale
 * whatever the process's (a program may call setlocale(LC_ALL, "")): the
 * renderer switches its own thread with uselocale while it formats a frame.
 *
 * Renderer entries in a scene: {"type": "csv"|"json"|"stats", "path": FILE,
 * "every": K}; "path" "-" is standard output.  No other keys.
 */
#ifndef RBSF_DUMP_H
#define RBSF_DUMP_H

#include "rbsim/reel.h"

#include <pthread.h>

#ifdef __cplusplus
extern "C" {
#endif

/** "csv": one row per body per frame,
 * frame,t,body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz.  Static table. */
const rbs_renderer_class *rbsf_csv_class(void);
/** "json": JSON Lines, one object per frame:
 * {"frame","t","bodies":[{"body","name","position","orientation",
 * "velocity","angular_velocity"}]}.  Static table. */
const rbs_renderer_class *rbsf_json_class(void);
/** "stats": one CSV row per frame: frame,t,kinetic,potential,total,px,py,pz,
 * lx,ly,lz,max_overlap,contacts,collisions,substeps,rollbacks,work_limit
 * (1 where the step hit its work cap, rbs_step_info.work_limit).  Static
 * table. */
const rbs_renderer_class *rbsf_stats_class(void);

/* ---- Stopping outputs that block ---------------------------------------
 * A FIFO that no one opens for reading blocks open() for ever, and a pipe
 * whose reader stopped reading blocks write() once it is full: nothing the
 * projector does (quit) reaches a thread blocked there.  A stopper lets
 * another thread end such calls: the outputs of a dump type bound to it
 * (rbsf_dump_bind) enter each open() and write() in it, and
 * rbsf_stopper_stop() sends a signal to every thread that has been blocked
 * there for longer than a grace time.  The caller installs that signal's
 * handler, one that does nothing, without SA_RESTART, so the call fails
 * with EINTR; once stopped, the output gives up (RBS_E_CLOSED, naming the
 * file; a regular file is cut back to its last whole frame).  Before the
 * stop an EINTR is retried.  Writes that do not block (regular files, a
 * reader that keeps up) go on after the stop: a run stopped by a signal
 * still writes the frames it has made. */

/** Most threads at once in an output call of one stopper. */
#define RBSF_STOPPER_THREADS 4

/** Fill with rbsf_stopper_init; the fields are the stopper's own. */
typedef struct rbsf_stopper {
    pthread_mutex_t lock;
    int stopped;                      /* guarded by lock */
    struct {
        pthread_t thread;
        double since;                 /* CLOCK_MONOTONIC seconds */
        int busy;
    } blocked[RBSF_STOPPER_THREADS];  /* guarded by lock */
} rbsf_stopper;

/** Make a stopper (not stopped).  0, or -1 if its mutex cannot be made. */
int rbsf_stopper_init(rbsf_stopper *s);
/** Stop: from now on an interrupted open() or write() gives up.  Sends
 * signo to every thread blocked in an output call for grace seconds or
 * more, and returns how many threads are in one (interrupted or not yet).
 * Call it again every 0.1 s or so for as long as the outputs may still be
 * written: a thread may enter a call that blocks after this one (or just
 * after its signal, which then cannot end the call).  Thread-safe. */
int rbsf_stopper_stop(rbsf_stopper *s, int signo, double grace);
/** Free a stopper no output uses any more. */
void rbsf_stopper_destroy(rbsf_stopper *s);
/** Put the calling thread in a slot of the stopper for a call of its own
 * that may block (reading a scene or a checkpoint from a FIFO or a pipe), as
 * the outputs do for their open() and write(): rbsf_stopper_stop then sends
 * it the signal, and the blocked call fails with EINTR.  Returns the slot to
 * give rbsf_stopper_leave, or -1 (no slot free, or s NULL: the call cannot
 * be ended).  Thread-safe. */
int rbsf_stopper_enter(rbsf_stopper *s);
/** Leave the slot rbsf_stopper_enter gave (-1: nothing to do). */
void rbsf_stopper_leave(rbsf_stopper *s, int slot);
/** Nonzero once rbsf_stopper_stop was called. */
int rbsf_stopper_stopped(rbsf_stopper *s);

/** A dump type whose outputs a stopper can end: register &bound->cls.  It
 * must outlive the registry and every projector using it. */
typedef struct rbsf_dump_bound {
    rbs_renderer_class cls;
    struct rbsf_dump_type {
        const void *format;     /* the type's format (internal) */
        rbsf_stopper *stopper;  /* NULL: none */
    } type;
} rbsf_dump_bound;

/** Bind a dump type (rbsf_csv_class(), rbsf_json_class() or
 * rbsf_stats_class()) to a stopper.  RBS_E_INVALID for another class. */
rbs_status rbsf_dump_bind(rbsf_dump_bound *bound, const rbs_renderer_class *dump_class,
                          rbsf_stopper *stopper);

/** Write x in the shortest "%.Ng" (N = 1..17) that strtod reads back as the
 * same double ("nan", "inf", "-inf" for those), in the "C" locale ('.' as
 * the decimal point) whatever the thread's.  Returns the length written
 * (buf must hold at least 32 bytes).  Thread-safe. */
size_t rbsf_format_double(char *buf, size_t size, double x);

/** Check that an output file could be created at path without creating it:
 * the path is not a folder; an existing file is writable; a new file's
 * folder exists and takes a file (a temporary one is made and removed
 * again), or is one missing folder inside such a folder (created when the
 * file is opened).  A path through a file ("base.json/x.csv") or more than
 * one missing folder is refused, the message naming the part.  "-" (the
 * standard output) is fine.  Returns RBS_OK or RBS_E_IO with a message. */
rbs_status rbsf_check_output_file(const char *path, char *err, size_t errlen);

/** path as a message shows it, in buf (size bytes, at least 16): whole if it
 * fits, else its start and its end around "..." -- a message cut at the end
 * of its buffer lost its reason along with the path's end -- with each
 * control character, C1 control, invisible formatting character and byte of
 * invalid UTF-8 as '?' (frontends/common/shown.h).  Returns buf. */
const char *rbsf_shown_path(const char *path, char *buf, size_t size);

#ifdef __cplusplus
}
#endif

#endif /* RBSF_DUMP_H */
