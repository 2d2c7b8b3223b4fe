/*
 * pool.c - a pool of threads to lend a world's steps (rbs_workers; the core
 * starts no thread, reel.h).
 *
 * start(fn, task, n) hands tasks k = 1 .. n (at most the pool's threads) to
 * the threads and returns; finish waits until they have all returned.  A
 * generation number tells the threads a new batch is there: a thread that
 * finished one spins on it for a while (about SPIN_ROUNDS plain loads, tens
 * of microseconds -- a pile's steps follow each other closely, and a
 * sleeping thread takes that long again to wake) before it sleeps on the
 * condition variable.  finish likewise spins on the count of tasks still
 * running before it sleeps: asleep at every step's end and woken by the
 * last task's broadcast, it took 4-15 us a step on this project's virtual
 * machine (the 1,000-sphere pile's steps take about 280 us on two threads),
 * spinning under 1 us.  Every wait is in a loop on its predicate under the
 * mutex; the count changes under it too (atomically, for finish's spin);
 * destroy sets quit and broadcasts.
 */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "rbsim/reel.h"

#define SPIN_ROUNDS 100000 /* a plain load a round: tens of microseconds
                              (no PAUSE: see core/team.c) */

struct rbs_pool {
    pthread_mutex_t mutex;
    pthread_cond_t wake;    /* a batch was started, or quit */
    pthread_cond_t idle;    /* the batch's last task returned */
    uint32_t threads;
    pthread_t *thread;
    uint64_t generation;    /* batches started (read without the mutex while
                               spinning: __atomic where the compiler has it) */
    rbs_task_fn *fn;
    void *task;
    uint32_t next, last;    /* the batch's next task to hand out, its last */
    uint32_t running;       /* the batch's tasks not yet returned */
    int quit;
};

static uint64_t generation_now(rbs_pool *p)
{
#if defined(__GNUC__)
    return __atomic_load_n(&p->generation, __ATOMIC_ACQUIRE);
#else
    uint64_t g;
    pthread_mutex_lock(&p->mutex);
    g = p->generation;
    pthread_mutex_unlock(&p->mutex);
    return g;
#endif
}

static void *pool_thread(void *arg)
{
    rbs_pool *p = (rbs_pool *)arg;
    uint64_t seen = 0;
    for (;;) {
        uint32_t k;
        int spins;
        /* a while spinning, then asleep */
        for (spins = 0; spins < SPIN_ROUNDS && generation_now(p) == seen; ++spins)
            continue;
        pthread_mutex_lock(&p->mutex);
        while (!p->quit && p->generation == seen)
            pthread_cond_wait(&p->wake, &p->mutex);
        if (p->quit) {
            pthread_mutex_unlock(&p->mutex);
            return NULL;
        }
        seen = p->generation;
        if (p->next > p->last) {
            /* every task of this batch is taken */
            pthread_mutex_unlock(&p->mutex);
            continue;
        }
        k = p->next++;
        pthread_mutex_unlock(&p->mutex);
        p->fn(p->task, k);
        pthread_mutex_lock(&p->mutex);
#if defined(__GNUC__)
        if (__atomic_sub_fetch(&p->running, 1u, __ATOMIC_RELEASE) == 0)
#else
        if (--p->running == 0)
#endif
            pthread_cond_broadcast(&p->idle);
        pthread_mutex_unlock(&p->mutex);
    }
}

static void pool_start(void *user, rbs_task_fn *fn, void *task, uint32_t n)
{
    rbs_pool *p = (rbs_pool *)user;
    pthread_mutex_lock(&p->mutex);
    p->fn = fn;
    p->task = task;
    p->next = 1;
    p->last = n < p->threads ? n : p->threads;
#if defined(__GNUC__)
    __atomic_store_n(&p->running, p->last, __ATOMIC_RELAXED);
    __atomic_store_n(&p->generation, p->generation + 1, __ATOMIC_RELEASE);
#else
    p->running = p->last;
    p->generation++;
#endif
    pthread_mutex_unlock(&p->mutex);
    /* (after the unlock: a spinning thread that sees the generation takes
     * the mutex at once) */
    pthread_cond_broadcast(&p->wake);
}

static void pool_finish(void *user)
{
    rbs_pool *p = (rbs_pool *)user;
#if defined(__GNUC__)
    /* a while spinning (the count is written under the mutex, read here
     * without it), then asleep */
    int spins;
    for (spins = 0; spins < SPIN_ROUNDS && __atomic_load_n(&p->running, __ATOMIC_ACQUIRE) > 0; ++spins)
        continue;
#endif
    pthread_mutex_lock(&p->mutex);
    while (p->running > 0)
        pthread_cond_wait(&p->idle, &p->mutex);
    pthread_mutex_unlock(&p->mutex);
}

void rbs_pool_destroy(rbs_pool *p)
{
    uint32_t i;
    if (p == NULL)
        return;
    pthread_mutex_lock(&p->mutex);
    p->quit = 1;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mutex);
    for (i = 0; i < p->threads; ++i)
        pthread_join(p->thread[i], NULL);
    pthread_cond_destroy(&p->idle);
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->mutex);
    free(p->thread);
    free(p);
}

rbs_status rbs_pool_create(uint32_t threads, rbs_pool **out)
{
    rbs_pool *p;
    uint32_t i;
    if (out == NULL)
        return RBS_E_INVALID;
    *out = NULL;
    if (threads < 1 || threads > RBS_WORKERS_MAX - 1)
        return RBS_E_INVALID;
    p = (rbs_pool *)calloc(1, sizeof *p);
    if (p == NULL)
        return RBS_E_MEMORY;
    /* each step of the setup undone, in reverse, by the one below it */
    p->thread = (pthread_t *)calloc(threads, sizeof *p->thread);
    if (p->thread == NULL)
        goto no_thread;
    if (pthread_mutex_init(&p->mutex, NULL) != 0)
        goto no_mutex;
    if (pthread_cond_init(&p->wake, NULL) != 0)
        goto no_wake;
    if (pthread_cond_init(&p->idle, NULL) != 0)
        goto no_idle;
    for (i = 0; i < threads; ++i) {
        if (pthread_create(&p->thread[i], NULL, pool_thread, p) != 0) {
            p->threads = i; /* (destroy joins those started) */
            rbs_pool_destroy(p);
            return RBS_E_MEMORY;
        }
        p->threads = i + 1;
    }
    *out = p;
    return RBS_OK;

no_idle:
    pthread_cond_destroy(&p->wake);
no_wake:
    pthread_mutex_destroy(&p->mutex);
no_mutex:
    free(p->thread);
no_thread:
    free(p);
    return RBS_E_MEMORY;
}

rbs_status rbs_pool_workers(rbs_pool *p, rbs_workers *out)
{
    rbs_workers w;
    if (p == NULL || out == NULL || out->struct_size < sizeof(uint32_t))
        return RBS_E_INVALID;
    rbs_workers_init(&w);
    w.count = p->threads + 1;
    w.start = pool_start;
    w.finish = pool_finish;
    w.user = p;
    memcpy(out, &w, out->struct_size < sizeof w ? out->struct_size : sizeof w);
    out->struct_size = (uint32_t)(out->struct_size < sizeof w ? out->struct_size : sizeof w);
    return RBS_OK;
}
