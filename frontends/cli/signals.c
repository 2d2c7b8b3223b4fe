/*
 * signals.c - SIGINT, SIGTERM and SIGHUP: no handler runs at all.  The
 * signals are blocked in every thread and taken by one thread with
 * sigwait(), which then asks the projector to quit like a typed "quit"
 * (outputs are finished up to the last frame).  No state is global: it all
 * lives in the caller's rbsf_signals.
 *
 * Ending the thread: sigwait() returns only for a signal in its set, so
 * rbsf_signals_stop() sets s->stopping and then sends SIGUSR1 to the thread.
 * SIGUSR1 is in the set (blocked everywhere) only for that; one from outside
 * finds stopping clear and is ignored, so the thread keeps taking INT, TERM
 * and HUP.  (A self-pipe cannot be waited on together with sigwait();
 * signalfd could, but is Linux-only.)
 *
 * Outputs that block: a FIFO no one reads blocks open(), a pipe whose
 * reader stopped reading blocks write(), and "quit" reaches neither (the
 * renderer thread even drains the reel into them).  So the first signal
 * also stops s->stopper, which the dump outputs enter for each open() and
 * write(): it sends RBSF_WAKE_SIGNAL to a thread blocked there for
 * RBSF_STOP_GRACE, whose handler does nothing and is installed without
 * SA_RESTART, so the call fails with EINTR and the output gives up.  A
 * thread may enter its call after a signal came (the reel is still drained),
 * so from the first signal until rbsf_signals_stop the thread repeats this
 * every 0.1 s.  The handler is
 * installed only then: until a stop, SIGUSR2 keeps its default action.
 *
 * SIGHUP or SIGINT ignored by the caller stays ignored (nohup ignores HUP;
 * a shell ignores INT for a job it starts in the background, so that
 * Ctrl-C at the terminal leaves it alone): a blocked signal is queued even
 * when ignored, so it is left out of the set instead.  SIGTERM is always
 * taken: it is how a run is asked to stop.
 */
#include "cli.h"

#include <errno.h>
#include <string.h>

static void wake_handler(int sig)
{
    (void)sig; /* only to make a blocked open() or write() return EINTR */
}

static void *signals_main(void *arg)
{
    rbsf_signals *s = arg;
    int waking = 0; /* a signal came: stop the stopper every 0.1 s */
    for (;;) {
        int sig = 0, stopping;
        if (waking) {
            /* Wait 0.1 s at most, then signal the blocked threads again. */
            struct timespec t = {0, 100000000L};
            sig = sigtimedwait(&s->set, NULL, &t);
            if (sig < 0) {
                if (errno == EAGAIN)
                    rbsf_stopper_stop(&s->stopper, RBSF_WAKE_SIGNAL, RBSF_STOP_GRACE);
                continue;
            }
        } else if (sigwait(&s->set, &sig) != 0) {
            continue;
        }
        pthread_mutex_lock(&s->lock);
        stopping = s->stopping;
        if (sig != SIGUSR1) {
            if (s->caught == 0) {
                struct sigaction sa;
                memset(&sa, 0, sizeof sa);
                sa.sa_handler = wake_handler;
                sigemptyset(&sa.sa_mask);
                sa.sa_flags = 0; /* no SA_RESTART: the call is to fail */
                sigaction(RBSF_WAKE_SIGNAL, &sa, NULL);
                s->caught = sig;
            }
            if (s->projector != NULL)
                rbs_projector_command(s->projector, "quit", NULL, 0);
        }
        pthread_mutex_unlock(&s->lock);
        if (stopping)
            break; /* else a SIGUSR1 from outside: keep waiting */
        if (sig != SIGUSR1) {
            rbsf_stopper_stop(&s->stopper, RBSF_WAKE_SIGNAL, RBSF_STOP_GRACE);
            waking = 1;
        }
    }
    return NULL;
}

int rbsf_signals_start(rbsf_signals *s)
{
    static const int unless_ignored[2] = {SIGHUP, SIGINT};
    int k;
    memset(s, 0, sizeof *s);
    sigemptyset(&s->set);
    sigaddset(&s->set, SIGTERM);
    sigaddset(&s->set, SIGUSR1);
    for (k = 0; k < 2; ++k) {
        struct sigaction was;
        if (sigaction(unless_ignored[k], NULL, &was) == 0 && was.sa_handler != SIG_IGN)
            sigaddset(&s->set, unless_ignored[k]);
    }
    if (pthread_sigmask(SIG_BLOCK, &s->set, NULL) != 0)
        return -1;
    if (pthread_mutex_init(&s->lock, NULL) != 0)
        return -1;
    if (rbsf_stopper_init(&s->stopper) != 0) {
        pthread_mutex_destroy(&s->lock);
        return -1;
    }
    if (pthread_create(&s->thread, NULL, signals_main, s) != 0) {
        rbsf_stopper_destroy(&s->stopper);
        pthread_mutex_destroy(&s->lock);
        return -1;
    }
    s->started = 1;
    return 0;
}

void rbsf_signals_attach(rbsf_signals *s, rbs_projector *projector)
{
    pthread_mutex_lock(&s->lock);
    s->projector = projector;
    if (projector != NULL && s->caught != 0)
        rbs_projector_command(projector, "quit", NULL, 0);
    pthread_mutex_unlock(&s->lock);
}

int rbsf_signals_caught(rbsf_signals *s)
{
    int sig;
    pthread_mutex_lock(&s->lock);
    sig = s->caught;
    pthread_mutex_unlock(&s->lock);
    return sig;
}

const char *rbsf_signal_name(int sig)
{
    switch (sig) {
    case SIGINT:
        return "SIGINT";
    case SIGTERM:
        return "SIGTERM";
    case SIGHUP:
        return "SIGHUP";
    default:
        return "a signal";
    }
}

void rbsf_signals_stop(rbsf_signals *s)
{
    if (!s->started)
        return;
    /* The flag first: the thread may wake for any signal once it is set. */
    pthread_mutex_lock(&s->lock);
    s->stopping = 1;
    pthread_mutex_unlock(&s->lock);
    pthread_kill(s->thread, SIGUSR1);
    pthread_join(s->thread, NULL);
    rbsf_stopper_destroy(&s->stopper);
    pthread_mutex_destroy(&s->lock);
    s->started = 0;
}
