/*
 * signals.c - Ctrl-C and SIGTERM: no handler runs at all.  The signals are
 * blocked in every thread and taken by one thread with sigwait(), which then
 * asks the projector to quit like a typed "quit" (outputs are finished up to
 * the last frame).  SIGUSR1 from rbsf_signals_stop() ends the thread.
 */
#include "cli.h"

#include <signal.h>
#include <string.h>

static void signal_set(sigset_t *set)
{
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGUSR1);
}

static void *signals_main(void *arg)
{
    rbsf_signals *s = arg;
    sigset_t set;
    signal_set(&set);
    for (;;) {
        int sig = 0;
        if (sigwait(&set, &sig) != 0)
            continue;
        if (sig == SIGUSR1)
            break;
        pthread_mutex_lock(&s->lock);
        if (s->caught == 0)
            s->caught = sig;
        if (s->projector != NULL)
            rbs_projector_command(s->projector, "quit", NULL, 0);
        pthread_mutex_unlock(&s->lock);
    }
    return NULL;
}

int rbsf_signals_start(rbsf_signals *s)
{
    sigset_t set;
    memset(s, 0, sizeof *s);
    signal_set(&set);
    if (pthread_sigmask(SIG_BLOCK, &set, NULL) != 0)
        return -1;
    if (pthread_mutex_init(&s->lock, NULL) != 0)
        return -1;
    if (pthread_create(&s->thread, NULL, signals_main, s) != 0) {
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

void rbsf_signals_stop(rbsf_signals *s)
{
    if (!s->started)
        return;
    pthread_kill(s->thread, SIGUSR1);
    pthread_join(s->thread, NULL);
    pthread_mutex_destroy(&s->lock);
    s->started = 0;
}
