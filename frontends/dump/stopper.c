/*
 * stopper.c - ending an output call that blocks (dump.h, "Stopping outputs
 * that block").
 *
 * Design.  A thread enters its open() or write() in a slot (its id and the
 * time) under the lock and leaves it under the lock right after the call,
 * and rbsf_stopper_stop signals only threads in a slot, under the lock: so
 * a signal never reaches a thread that has left its output call (nor one
 * that has ended), and can interrupt nothing but that call.  A signal that
 * comes after a thread entered its slot but before it is in the system call
 * only runs the empty handler: the call then blocks, which is why the
 * caller repeats rbsf_stopper_stop as long as outputs may be written.  The
 * grace time spares a write that a slow reader is still taking.
 */
#include "dump_internal.h"

#include <signal.h>
#include <string.h>
#include <time.h>

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int rbsf_stopper_init(rbsf_stopper *s)
{
    memset(s, 0, sizeof *s);
    return pthread_mutex_init(&s->lock, NULL) == 0 ? 0 : -1;
}

int rbsf_stopper_stop(rbsf_stopper *s, int signo, double grace)
{
    double now = now_seconds();
    int i, in_calls = 0;
    pthread_mutex_lock(&s->lock);
    s->stopped = 1;
    for (i = 0; i < RBSF_STOPPER_THREADS; i++) {
        if (!s->blocked[i].busy)
            continue;
        in_calls++;
        if (now - s->blocked[i].since >= grace)
            pthread_kill(s->blocked[i].thread, signo);
    }
    pthread_mutex_unlock(&s->lock);
    return in_calls;
}

void rbsf_stopper_destroy(rbsf_stopper *s)
{
    pthread_mutex_destroy(&s->lock);
}

int rbsf__stopper_enter(rbsf_stopper *s)
{
    int i;
    if (s == NULL)
        return -1;
    pthread_mutex_lock(&s->lock);
    for (i = 0; i < RBSF_STOPPER_THREADS && s->blocked[i].busy; i++) {
    }
    if (i < RBSF_STOPPER_THREADS) {
        s->blocked[i].busy = 1;
        s->blocked[i].thread = pthread_self();
        s->blocked[i].since = now_seconds();
    } else {
        i = -1; /* (more threads than slots: this call cannot be ended) */
    }
    pthread_mutex_unlock(&s->lock);
    return i;
}

void rbsf__stopper_leave(rbsf_stopper *s, int slot)
{
    if (s == NULL || slot < 0)
        return;
    pthread_mutex_lock(&s->lock);
    s->blocked[slot].busy = 0;
    pthread_mutex_unlock(&s->lock);
}

int rbsf__stopper_stopped(rbsf_stopper *s)
{
    int stopped;
    if (s == NULL)
        return 0;
    pthread_mutex_lock(&s->lock);
    stopped = s->stopped;
    pthread_mutex_unlock(&s->lock);
    return stopped;
}

int rbsf_stopper_enter(rbsf_stopper *s)
{
    return rbsf__stopper_enter(s);
}

void rbsf_stopper_leave(rbsf_stopper *s, int slot)
{
    rbsf__stopper_leave(s, slot);
}

int rbsf_stopper_stopped(rbsf_stopper *s)
{
    return rbsf__stopper_stopped(s);
}
