/*
 * input.c - the input thread: reads command lines from standard input and
 * answers each through the command map.  It waits with poll() on the input
 * and on a self-pipe, so it can be stopped at any time; end of input (a pipe
 * or /dev/null) ends the thread but never the run.  A last line without a
 * newline at end of input is answered as a whole line.
 */
#include "cli.h"
#include "shown.h"

#include <errno.h>
#include <poll.h>
#include <string.h>
#include <unistd.h>

#define LINE_MAX_BYTES 1024
#define REPLY_BYTES 4096

static void say(rbsf_input *in, const char *text)
{
    pthread_mutex_lock(in->reply_lock);
    fputs(text, in->reply);
    fflush(in->reply);
    pthread_mutex_unlock(in->reply_lock);
}

/* Answer the command line of n bytes (its newline gone).  A control
 * character -- a NUL, an escape sequence, a C1 control -- a bidirectional
 * override or invalid UTF-8 refuses it whole, naming the byte: a NUL would
 * cut the command short, and a reply that echoes an escape sequence would
 * drive the terminal.  A trailing CR (a line ended
 * by CR LF) and tabs are taken as they would be typed. */
static void answer(rbsf_input *in, char *line, size_t n)
{
    char reply[REPLY_BYTES];
    size_t i, len;
    if (n > 0 && line[n - 1] == '\r')
        line[--n] = '\0';
    for (i = 0; i < n; i += len) {
        const unsigned char *b = (const unsigned char *)line + i;
        const unsigned char c = b[0];
        unsigned long u;
        size_t k;
        if (rbs_text_shown_len(line + i, n - i, &len) > 0 || c == '\t')
            continue;
        if (c < 0x80) {
            snprintf(reply, sizeof reply,
                     "a command must not hold control characters (byte 0x%02x at %lu): ignored\n", c,
                     (unsigned long)i + 1);
            say(in, reply);
            return;
        }
        if (len == 1) {
            snprintf(reply, sizeof reply, "a command must be UTF-8 (byte 0x%02x at %lu): ignored\n", c,
                     (unsigned long)i + 1);
            say(in, reply);
            return;
        }
        /* a well-formed sequence the library does not show (rbsim.h): its
         * code point, for the reply */
        u = (unsigned long)(c & (0x7F >> len));
        for (k = 1; k < len; k++)
            u = u << 6 | (unsigned long)(b[k] & 0x3F);
        snprintf(reply, sizeof reply,
                 "a command must not hold control, space or invisible formatting characters "
                 "(U+%04lX at byte %lu): ignored\n",
                 u, (unsigned long)i + 1);
        say(in, reply);
        return;
    }
    rbsf_command_run(in->projector, line, reply, sizeof reply);
    if (reply[0] == '\0')
        return;
    pthread_mutex_lock(in->reply_lock);
    if (isatty(fileno(in->reply)) && isatty(STDERR_FILENO))
        fputs("\r\033[K", stderr); /* clear a progress bar's line first */
    fputs(reply, in->reply);
    fflush(in->reply);
    pthread_mutex_unlock(in->reply_lock);
}

static void *input_main(void *arg)
{
    rbsf_input *in = arg;
    char buf[LINE_MAX_BYTES];
    size_t len = 0;
    int overlong = 0;

    for (;;) {
        struct pollfd fds[2];
        ssize_t n;
        size_t i, start;

        fds[0].fd = in->fd;
        fds[0].events = POLLIN;
        fds[1].fd = in->wake[0];
        fds[1].events = POLLIN;
        if (poll(fds, 2, -1) < 0) {
            if (errno == EINTR)
                continue;
            break;
        }
        if (fds[1].revents)
            break; /* asked to stop */
        if (fds[0].revents & POLLNVAL)
            break; /* no input at all (closed descriptor) */
        if (!(fds[0].revents & (POLLIN | POLLHUP | POLLERR)))
            continue;
        n = read(in->fd, buf + len, sizeof buf - 1 - len);
        if (n < 0 && (errno == EINTR || errno == EAGAIN))
            continue;
        if (n <= 0) {
            /* End of input: the run goes on by itself.  A run paused now
             * could never be resumed, so resume it.  A read error (standard
             * input a folder, EISDIR; EIO) ends the commands too, and says
             * so: it was taken for an end of input without a word. */
            rbs_run_info info;
            const char *why = n < 0 ? strerror(errno) : NULL;
            if (why != NULL) {
                pthread_mutex_lock(in->reply_lock);
                fprintf(in->reply, "rbsim: note: standard input: cannot read "
                                   "commands: %s; the run goes on without them\n",
                        why);
                fflush(in->reply);
                pthread_mutex_unlock(in->reply_lock);
            }
            /* A last line without its newline is still a line, as a shell
             * takes it (printf 'quit' | rbsim run ...): answer it first,
             * so a "pause" there is resumed just below like any other. */
            if (n == 0 && len > 0 && !overlong) {
                buf[len] = '\0';
                answer(in, buf, len);
            }
            if (rbs_projector_status(in->projector, &info) == RBS_OK &&
                info.state == RBS_RUN_RUNNING && info.paused && !info.quit) {
                /* (a run quitting ends by itself: nothing to resume) */
                rbs_projector_command(in->projector, "resume", NULL, 0);
                pthread_mutex_lock(in->reply_lock);
                fprintf(in->reply, "%s: resumed (no command could "
                                   "resume the run later)\n",
                        why != NULL ? "no input" : "end of input");
                fflush(in->reply);
                pthread_mutex_unlock(in->reply_lock);
            }
            break;
        }
        len += (size_t)n;

        /* Answer every whole line. */
        start = 0;
        for (i = 0; i < len; i++) {
            if (buf[i] != '\n')
                continue;
            buf[i] = '\0';
            if (!overlong)
                answer(in, buf + start, i - start);
            overlong = 0;
            start = i + 1;
        }
        memmove(buf, buf + start, len - start);
        len -= start;
        if (len == sizeof buf - 1) {
            /* A line too long for the buffer: drop it whole, and say so
             * once (the rest of it comes in more such reads). */
            if (!overlong) {
                char text[96];
                snprintf(text, sizeof text, "line too long (at most %d bytes): ignored\n",
                         LINE_MAX_BYTES - 2);
                say(in, text);
            }
            len = 0;
            overlong = 1;
        }
    }
    return NULL;
}

int rbsf_input_start(rbsf_input *in, int fd, rbs_projector *projector,
                     FILE *reply, pthread_mutex_t *reply_lock)
{
    memset(in, 0, sizeof *in);
    in->fd = fd;
    in->projector = projector;
    in->reply = reply;
    in->reply_lock = reply_lock;
    if (pipe(in->wake) != 0)
        return -1;
    if (pthread_create(&in->thread, NULL, input_main, in) != 0) {
        close(in->wake[0]);
        close(in->wake[1]);
        return -1;
    }
    in->started = 1;
    return 0;
}

void rbsf_input_stop(rbsf_input *in)
{
    ssize_t w;
    if (!in->started)
        return;
    do
        w = write(in->wake[1], "x", 1);
    while (w < 0 && errno == EINTR);
    pthread_join(in->thread, NULL);
    close(in->wake[0]);
    close(in->wake[1]);
    in->started = 0;
}
