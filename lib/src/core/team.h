/*
 * team.h - a step's stages on the threads the caller lends the world
 * (internal; team.c).
 *
 * A stage is a function over items [0, n) whose items are independent:
 * any split of them among threads, in any order, gives the same result
 * (bodies each on their own; the contact groups of one level, which share
 * no body).  team_run splits a stage into shares, which the step's own thread
 * and the lent workers claim one at a time until none is left, and returns
 * when every share is done, so the stages of a frame follow one another as
 * they would on one thread: results do not depend on how many threads
 * there are, nor on which took what.  The step's thread never waits for a
 * worker to arrive -- it takes every share nobody has claimed -- so a pool
 * that starts its threads late, or not at all, only slows the step.
 */
#ifndef RBS_CORE_TEAM_H
#define RBS_CORE_TEAM_H

#include "core/world_internal.h"

#define RBS__TEAM_SHARES 16 /* the most shares of a stage: a ticket's claimed bits */

/* A stage's work: items [begin, end) of share `share` (0 .. shares - 1). */
typedef void (*rbs__stage_fn)(void *ctx, uint32_t share, uint32_t begin, uint32_t end);

/* The synchronisation of one step's threads, in the world (team.c). */
typedef struct rbs__team rbs__team;

/* Fit the waits to the processors this process may run on, for the
 * world's workers as set now (rbs_world_set_workers): more threads than
 * processors and a waiter yields almost at once; else it spins about a
 * millisecond first.  Timing only: results do not depend on it. */
void rbs__team_fit(rbs_world *w);
/* Start the lent workers for one step (nothing with one thread). */
void rbs__team_start(rbs_world *w);
/* Stop them: they return, and the pool's finish waits for them. */
void rbs__team_stop(rbs_world *w);
/* Run fn over items [0, n) in `shares` shares (at most n and 16, at least
 * 1; share k: items [k n / shares, (k + 1) n / shares)), on every thread of
 * the step, thread t of T taking the t-th T-th of the shares first; returns
 * when all are done. */
void rbs__team_run(rbs_world *w, rbs__stage_fn fn, void *ctx, uint32_t n, uint32_t shares);
/* The threads the step's stages run on: the lent workers' count while
 * they are started for it (rbs__team_start), else 1 -- a stage split into
 * more shares than its threads would only do more work. */
uint32_t rbs__team_threads(const rbs_world *w);

/* *p + 1 into *p, returning *p before: atomic (relaxed: the count, not
 * the order of the additions, is read after the stage) when the stage may
 * run on several threads (shared), a plain addition otherwise. */
static inline uint32_t rbs__team_add(uint32_t *p, int shared)
{
#if defined(__GNUC__)
    if (shared)
        return __atomic_fetch_add(p, 1u, __ATOMIC_RELAXED);
#else
    (void)shared;
#endif
    return (*p)++;
}

#endif
