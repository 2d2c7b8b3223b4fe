/*
 * sdl_png.c - PNG files whose every write is checked.
 *
 * Design notes.
 *  - Why not IMG_SavePNG.  SDL_image 2.6.3 ignores what its stream's write
 *    and close return (its libpng write callback drops SDL_RWwrite's result),
 *    so a full disk or a file size limit left a truncated or empty PNG and
 *    "success".  Here SDL_image encodes into an SDL_RWops of our own whose
 *    callbacks buffer the bytes and write() them to the file, keeping the
 *    first errno; the file is closed and checked by us.  Any failure removes
 *    the partial file, so every PNG left behind is whole.
 *  - Memory.  The writer, its SDL_RWops (filled in place, never given to
 *    SDL_FreeRW) and its buffer are made by rbsf__png_create; saving
 *    allocates nothing itself (SDL_image and libpng do, inside).
 *  - Once a write has failed, later writes are dropped: libpng goes on
 *    encoding (its callback cannot stop it), but nothing more reaches the
 *    file.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <SDL.h>
#include <SDL_image.h>

#include "sdl_internal.h"
#include "sdl_renderer.h"

/* Bytes gathered before a write(): libpng writes each chunk's header, data
 * and CRC separately, a few bytes to 8 KiB at a time. */
#define RBSF_PNG_BUFFER 65536

struct rbsf__png {
    SDL_RWops rw;   /* hidden.unknown.data1 = this writer */
    const rbsf_sdl_world_api *api; /* its stopper (may be NULL) */
    int fd;         /* the file being written, -1 between files */
    int error;      /* first errno of this file, 0 while all is well */
    int given_up;   /* a call of this file was ended by the stopper */
    Sint64 written; /* bytes given to the file */
    size_t len;     /* bytes waiting in buf */
    unsigned char buf[RBSF_PNG_BUFFER];
};

/* The system's text for errno e (strerror_r: the renderer and window threads
 * may both ask). */
static void reason(int e, char *why, size_t n)
{
    if (strerror_r(e, why, n) != 0) snprintf(why, n, "errno %d", e);
}

/* The stopper of w's api, if it has one whole: enter, leave, stopped. */
static int stop_enter(const rbsf__png *w)
{
    const rbsf_sdl_world_api *a = w->api;
    if (a == NULL || a->stopper == NULL || a->enter == NULL || a->leave == NULL ||
        a->stopped == NULL)
        return -1;
    return a->enter(a->stopper);
}

static void stop_leave(const rbsf__png *w, int slot)
{
    if (slot >= 0) w->api->leave(w->api->stopper, slot);
}

/* An EINTR of w's call: 1 when the stopper ended it (give up), 0 to retry. */
static int stop_given_up(rbsf__png *w)
{
    const rbsf_sdl_world_api *a = w->api;
    if (a == NULL || a->stopper == NULL || a->stopped == NULL || !a->stopped(a->stopper))
        return 0;
    w->given_up = 1;
    return 1;
}

/* write() all of buf's bytes; on failure keep the first errno.  Each
 * write() is in the stopper's slot: a blocked one ended by it gives up. */
static void drain(rbsf__png *w)
{
    size_t done = 0;
    while (w->error == 0 && done < w->len) {
        int slot = stop_enter(w), e;
        ssize_t n = write(w->fd, w->buf + done, w->len - done);
        e = errno;
        stop_leave(w, slot);
        errno = e;
        if (n < 0 && errno == EINTR && !stop_given_up(w)) continue;
        if (n <= 0) {
            w->error = n < 0 ? errno : EIO; /* 0 bytes: no errno to give */
            break;
        }
        done += (size_t)n;
        w->written += n;
    }
    w->len = 0;
}

static size_t SDLCALL rw_write(SDL_RWops *rw, const void *ptr, size_t size, size_t num)
{
    rbsf__png *w = (rbsf__png *)rw->hidden.unknown.data1;
    const unsigned char *p = (const unsigned char *)ptr;
    size_t left;
    if (size == 0 || num == 0) return 0;
    if (num > SIZE_MAX / size) {
        SDL_SetError("PNG write of %zu x %zu bytes overflows", num, size);
        return 0;
    }
    left = size * num;
    while (left > 0 && w->error == 0) {
        size_t k = RBSF_PNG_BUFFER - w->len;
        if (k > left) k = left;
        memcpy(w->buf + w->len, p, k);
        w->len += k;
        p += k;
        left -= k;
        if (w->len == RBSF_PNG_BUFFER) drain(w);
    }
    if (w->error != 0) {
        char why[128];
        reason(w->error, why, sizeof why);
        SDL_SetError("%s", why);
        return 0;
    }
    return num;
}

/* Only "where are we" is answered: the stream is written front to back. */
static Sint64 SDLCALL rw_seek(SDL_RWops *rw, Sint64 offset, int whence)
{
    rbsf__png *w = (rbsf__png *)rw->hidden.unknown.data1;
    if (offset == 0 && whence == RW_SEEK_CUR) return w->written + (Sint64)w->len;
    return SDL_SetError("PNG output cannot seek");
}

static Sint64 SDLCALL rw_size(SDL_RWops *rw)
{
    (void)rw;
    return SDL_SetError("PNG output has no size yet");
}

static size_t SDLCALL rw_read(SDL_RWops *rw, void *ptr, size_t size, size_t maxnum)
{
    (void)rw;
    (void)ptr;
    (void)size;
    (void)maxnum;
    SDL_SetError("PNG output cannot be read");
    return 0;
}

/* The file is closed by rbsf__png_save itself (never through SDL). */
static int SDLCALL rw_close(SDL_RWops *rw)
{
    (void)rw;
    return 0;
}

rbsf__png *rbsf__png_create(const rbsf_sdl_world_api *api)
{
    rbsf__png *w = (rbsf__png *)calloc(1, sizeof *w);
    if (w == NULL) return NULL;
    w->api = api;
    w->fd = -1;
    w->rw.size = rw_size;
    w->rw.seek = rw_seek;
    w->rw.read = rw_read;
    w->rw.write = rw_write;
    w->rw.close = rw_close;
    w->rw.type = SDL_RWOPS_UNKNOWN;
    w->rw.hidden.unknown.data1 = w;
    return w;
}

void rbsf__png_destroy(rbsf__png *w)
{
    if (w == NULL) return;
    if (w->fd >= 0) close(w->fd);
    free(w);
}

rbs_status rbsf__png_save(rbsf__png *w, struct SDL_Surface *surface, const char *path,
                          char *err, size_t errlen)
{
    int encoded;
    char why[160];
    w->error = 0;
    w->given_up = 0;
    w->written = 0;
    w->len = 0;
    /* The open in the stopper's slot: a FIFO made at the frame's name
     * during the run waits for a reader (the check before the run refuses
     * one there then). */
    for (;;) {
        int slot = stop_enter(w), e;
        w->fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        e = errno;
        stop_leave(w, slot);
        if (w->fd >= 0 || e != EINTR) {
            errno = e;
            break;
        }
        if (stop_given_up(w)) {
            if (err != NULL && errlen > 0)
                snprintf(err, errlen, "opening \"%s\" given up: the run was stopped "
                         "while it blocked (a FIFO no one reads?)", path);
            return RBS_E_CLOSED;
        }
    }
    if (w->fd < 0) {
        reason(errno, why, sizeof why);
        if (err != NULL && errlen > 0)
            snprintf(err, errlen, "cannot write \"%s\": %s", path, why);
        return RBS_E_IO;
    }

    /* Encode, write what is left in the buffer, close: each checked.  SDL's
     * error text is read only when the encoder failed: the first SDL error
     * call on a thread makes that thread's SDL storage, which SDL frees
     * only on SDL_TLSCleanup (the sanitizer pass found it leaked by every
     * renderer thread that had cleared the error before each frame). */
    encoded = IMG_SavePNG_RW(surface, &w->rw, 0) == 0;
    why[0] = '\0';
    if (!encoded) snprintf(why, sizeof why, "%s", SDL_GetError());
    if (w->error == 0) drain(w);
    if (close(w->fd) != 0 && w->error == 0) w->error = errno;
    w->fd = -1;
    if (encoded && w->error == 0) return RBS_OK;

    /* A partial file is not a picture: remove it -- a regular file only:
     * a link the user put there (to /dev/full, say) is theirs, and stays
     * (a review of session 40).  The system's reason wins over SDL's,
     * which is then only an echo of it. */
    {
        struct stat st;
        if (lstat(path, &st) == 0 && S_ISREG(st.st_mode))
            (void)unlink(path);
    }
    if (w->given_up) {
        if (err != NULL && errlen > 0)
            snprintf(err, errlen, "write to \"%s\" given up: the run was stopped "
                     "while it blocked (%lld bytes of the PNG written)", path,
                     (long long)w->written);
        SDL_TLSCleanup();
        return RBS_E_CLOSED;
    }
    if (w->error != 0)
        reason(w->error, why, sizeof why);
    else if (why[0] == '\0')
        snprintf(why, sizeof why, "the PNG encoder failed");
    if (err != NULL && errlen > 0)
        snprintf(err, errlen, "cannot write \"%s\": %s", path, why);
    SDL_TLSCleanup(); /* (the error calls above made this thread's SDL storage) */
    return RBS_E_IO;
}
