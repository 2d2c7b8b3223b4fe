/*
 * dump_internal.h - shared pieces of the dumpers: an output file written a
 * whole frame at a time, and the check of a renderer entry.
 */
#ifndef RBSF_DUMP_INTERNAL_H
#define RBSF_DUMP_INTERNAL_H

#include "dump.h"

#include <sys/types.h>

/** An output written a frame at a time from a buffer reserved up front. */
typedef struct rbsf__out {
    int fd;
    int owned;     /* close fd at the end (not for stdout) */
    int failed;    /* a write failed: nothing more is written */
    char *path;
    char *buf;
    size_t len, cap;
    off_t good;    /* bytes known to be written in full */
    rbsf_stopper *stopper; /* may end a blocked open or write; NULL: none */
} rbsf__out;

/** Open (create or truncate) path, "-" for stdout, with a frame buffer of
 * cap bytes.  An open that blocks (a FIFO with no reader) can be ended by
 * the stopper (NULL: none): RBS_E_CLOSED. */
rbs_status rbsf__out_open(rbsf__out *out, const char *path, size_t cap,
                          rbsf_stopper *stopper, char *err, size_t errlen);
/** Append n bytes to the frame buffer; RBS_E_CAPACITY if they do not fit. */
rbs_status rbsf__out_put(rbsf__out *out, const char *s, size_t n);
/** rbsf_format_double in the thread's locale: for the formats, which run
 * in the "C" locale (dumper_draw switches once a frame, not per number). */
size_t rbsf__format_double(char *buf, size_t size, double x);

/** Append a number (rbsf__format_double: in the "C" locale only if the
 * thread is in it). */
rbs_status rbsf__out_num(rbsf__out *out, double x);
/** Append an unsigned integer. */
rbs_status rbsf__out_uint(rbsf__out *out, unsigned long long v);
/** Write the buffer in full; on failure cut the file back to the last whole
 * frame and explain.  RBS_E_CLOSED when the stopper ended a write that
 * blocked (a pipe's bytes cannot be taken back: it may end mid-frame). */
rbs_status rbsf__out_commit(rbsf__out *out, char *err, size_t errlen);
/** Drop the buffer (a frame that will not be written). */
void rbsf__out_discard(rbsf__out *out);
/** Close, checking the result (once). */
rbs_status rbsf__out_close(rbsf__out *out, char *err, size_t errlen);
/** Free the buffer and close without checks (after a failure). */
void rbsf__out_free(rbsf__out *out);

/** Validate a dumper's entry: keys among type, path, every; a path given
 * and writable.  name is the renderer type. */
rbs_status rbsf__dump_check(const char *name, const rbs_renderer_config *config,
                            char *err, size_t errlen);

/** The output path: config->path, else the entry's "path". */
rbs_status rbsf__dump_path(const rbs_renderer_config *config, char *buf,
                           size_t n, char *err, size_t errlen);

/** The stopper's part for outputs: enter a slot before an output call that
 * may block (the slot, or -1 when none: stopper NULL or no slot free),
 * leave it right after; whether the stopper was stopped. */
int rbsf__stopper_enter(rbsf_stopper *s);
void rbsf__stopper_leave(rbsf_stopper *s, int slot);
int rbsf__stopper_stopped(rbsf_stopper *s);

/** Bytes per frame the formats need at most for max_bodies bodies. */
size_t rbsf__frame_bytes(uint32_t max_bodies, size_t per_body);

#endif

#ifndef RBSF_DUMP_FORMATS
#define RBSF_DUMP_FORMATS
/** A dump format: its header line and how it writes one frame into the
 * output's buffer. */
typedef struct rbsf__format {
    const char *name;
    const char *header;   /* written first, or NULL */
    size_t per_body;      /* bytes a body needs at most */
    rbs_status (*frame)(rbsf__out *out, const rbs_frame *frame, void *scratch);
    /* Optional per-instance scratch (JSON: none; kept for growth). */
} rbsf__format;

extern const rbsf__format rbsf__csv_format;
extern const rbsf__format rbsf__stats_format;
extern const rbsf__format rbsf__json_format;
#endif
