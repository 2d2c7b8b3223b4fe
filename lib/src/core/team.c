/*
 * team.c - a step's stages on the threads the caller lends the world (see
 * team.h for what a stage may be and why results do not depend on the
 * threads).
 *
 * Design (after Box2D v3's solver stages): the step calls the pool's start
 * once, which runs worker() on the lent threads for the whole step; each
 * stage is published in one 64-bit ticket -- the stage's number, its share
 * count and a bit for each share claimed -- so a thread claims a share with
 * one atomic compare-and-exchange that also checks which stage the share
 * belongs to (a thread late from the last stage cannot take a share of the
 * next one for the last one's).  Thread k of T owns the k-th T-th of every
 * stage's shares and takes them in order, so each keeps the same part of
 * every stage -- the same slabs' bodies and chunks -- in its own cache
 * (taken at random, the records' cache lines moved between the cores at
 * every stage and a 8,000-sphere pile stepped 1.3x slower on two threads
 * than on one); a share nobody has claimed when a thread is done with its
 * own is taken by that thread, from the far end.  The stage's function and items sit in one of two slots,
 * by the stage number's parity: the step writes the slot before it
 * publishes the ticket (release) and rewrites it two stages later, after
 * every share of the stage between has been done, so a thread that holds an
 * unfinished share always reads its own stage's slot.  The step's thread
 * publishes a stage with its own first share claimed, takes shares too and
 * counts them itself; the workers count theirs in one counter for the whole
 * step (release), and the step's thread waits (acquire) until it has grown
 * by the shares it did not take -- the ticket's and the counter's cache
 * lines then cross between the cores once each a stage (0.992x of the time
 * with a counter reset at every stage and every share claimed by
 * compare-and-exchange, on the 1,000 pile, 2 threads, 20 pairs).  Everything a share writes is so seen by every later
 * stage, on any thread.  Atomics are GCC's and Clang's
 * __atomic built-ins; other compilers step on one thread
 * (rbs_world_set_workers refuses a pool there).
 */
#if defined(__linux__) && !defined(_GNU_SOURCE)
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT (rbs__team_fit) */
#endif
#include "core/team.h"

#include <sched.h>
#include <unistd.h> /* sysconf */

#define QUIT 0xFFFFu /* a ticket's share count that tells the workers to return */

#if defined(__GNUC__)
#define TEAM_ATOMICS 1
#endif

/* Rounds a waiting thread spins (a plain load of the word it waits on)
 * before it yields the processor at every round -- about a millisecond: a
 * wait for a stage is a few microseconds, so the yield is only for a
 * machine whose threads share a processor, where a spinning wait would
 * hold back the thread it waits for.  Measured on this 2-core virtual
 * machine: yielding after a microsecond let the scheduler put both threads
 * on one processor for seconds at a time (a pile's frame 1.2x slower on two
 * threads than on one, in most runs), and a PAUSE in the spin made the
 * hypervisor take the processor away (pause-loop exiting: the rows two to
 * three times slower in one run of two); spinning on plain loads, neither
 * (10 runs in 10 at full speed). */
#define SPINS_BEFORE_YIELD (1u << 22)
/* With more threads than processors the thread a waiter waits for may be
 * the one it keeps off a processor: a waiter yields almost at once (a probe
 * of session 38: --threads 16 on 2 cores stepped a 2,000-sphere pile 13x
 * slower than one thread, the same bits). */
#define SPINS_OVERSUBSCRIBED 64u

typedef struct stage {
    rbs__stage_fn fn;
    void *ctx;
    uint32_t n, shares;
} stage;

struct rbs__team {
    uint64_t ticket;    /* stage << 32 | shares << 16 | next share (atomic) */
    unsigned char pad0[56];
    uint32_t done;      /* shares the workers have done, all stages of the
                           step (atomic; the step's thread counts its own) */
    unsigned char pad1[60];
    stage slot[2];      /* by the stage's parity */
    uint64_t stage_no;  /* the step's thread's own: the stage published last */
    uint32_t done_seen; /* and done at the end of the last stage */
    uint32_t threads;   /* the step's threads, its own included (set at start) */
    int running;        /* the workers were started for this step */
    uint32_t spins;     /* a waiter's spins before it yields (rbs__team_fit;
                           0: SPINS_BEFORE_YIELD) -- in the struct's tail
                           padding, so the block's layout is as before */
};

size_t rbs__team_size(void) { return sizeof(rbs__team) + 64; }

static rbs__team *team_of(const rbs_world *w)
{
    uintptr_t p = (uintptr_t)w->team_mem;
    return (rbs__team *)(void *)(w->team_mem + (64u - p % 64u) % 64u);
}

uint32_t rbs__team_threads(const rbs_world *w)
{
#if defined(TEAM_ATOMICS)
    return team_of(w)->running ? w->workers.count : 1u;
#else
    (void)w;
    return 1u;
#endif
}

static void run_share(const stage *st, uint32_t k)
{
    uint32_t begin = (uint32_t)((uint64_t)k * st->n / st->shares);
    uint32_t end = (uint32_t)((uint64_t)(k + 1) * st->n / st->shares);
    st->fn(st->ctx, k, begin, end);
}

#if defined(TEAM_ATOMICS)
/* The share a thread claims next among those not yet claimed (a bit each in
 * `claimed`, all below `shares`): thread `mine` of `threads` owns the run
 * [mine * shares / threads, (mine + 1) * shares / threads) and takes its
 * first unclaimed share, so each thread keeps the same slabs -- the same
 * bodies, the same chunks -- stage after stage, in its own cache; with its
 * run done, it takes the last unclaimed share of all (the far end of
 * another thread's run, which that thread reaches last). */
static uint32_t next_share(uint32_t claimed, uint32_t shares, uint32_t mine, uint32_t threads)
{
    uint32_t lo = (uint32_t)((uint64_t)mine * shares / threads);
    uint32_t hi = (uint32_t)((uint64_t)(mine + 1) * shares / threads), k;
    for (k = lo; k < hi; ++k)
        if (!(claimed >> k & 1u))
            return k;
    for (k = shares; k-- > 0;)
        if (!(claimed >> k & 1u))
            return k;
    return shares; /* (not reached: the caller checked one is left) */
}

/* Claim and do shares of the stage on the ticket until none is left, the
 * thread's own run first (next_share), counting them into *did (NULL: into
 * done, a worker's); the stage number, or UINT64_MAX when the ticket says
 * to return. */
static uint64_t take_shares(rbs__team *t, uint32_t mine, uint32_t threads, uint32_t *did)
{
    uint64_t tk = __atomic_load_n(&t->ticket, __ATOMIC_ACQUIRE);
    for (;;) {
        uint32_t shares = (uint32_t)(tk >> 16) & 0xFFFFu, claimed = (uint32_t)tk & 0xFFFFu, k;
        if (shares == QUIT)
            return UINT64_MAX;
        if (claimed == (1u << shares) - 1u)
            return tk >> 32;
        k = next_share(claimed, shares, mine, threads);
        /* (a failed exchange reloads tk: another thread claimed, or the
         * stage changed) */
        if (__atomic_compare_exchange_n(&t->ticket, &tk, tk | (uint64_t)1 << k, 0, __ATOMIC_ACQ_REL,
                                        __ATOMIC_ACQUIRE)) {
            run_share(&t->slot[(tk >> 32) & 1u], k);
            if (did != NULL)
                ++*did;
            else
                __atomic_fetch_add(&t->done, 1, __ATOMIC_RELEASE);
            tk = __atomic_load_n(&t->ticket, __ATOMIC_ACQUIRE);
        }
    }
}

/* A lent thread, for the whole step: the shares of each stage as it comes. */
static void worker(void *task, uint32_t k)
{
    rbs__team *t = (rbs__team *)task;
    for (;;) {
        uint64_t s = take_shares(t, k, t->threads, NULL);
        if (s == UINT64_MAX)
            return;
        const uint32_t limit = t->spins ? t->spins : SPINS_BEFORE_YIELD;
        uint32_t spins = 0;
        while ((__atomic_load_n(&t->ticket, __ATOMIC_ACQUIRE) >> 32) == s)
            if (++spins >= limit)
                sched_yield();
    }
}
#endif

void rbs__team_fit(rbs_world *w)
{
    rbs__team *t = team_of(w);
    long cpus = 0;
#if defined(__linux__) && defined(CPU_COUNT)
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0)
        cpus = CPU_COUNT(&set); /* (taskset and cpusets included) */
#endif
#if defined(_SC_NPROCESSORS_ONLN)
    if (cpus <= 0)
        cpus = sysconf(_SC_NPROCESSORS_ONLN);
#endif
    t->spins = cpus > 0 && (long)w->workers.count > cpus ? SPINS_OVERSUBSCRIBED : 0u;
}

void rbs__team_start(rbs_world *w)
{
    rbs__team *t = team_of(w);
    t->running = 0;
#if defined(TEAM_ATOMICS)
    if (w->workers.count > 1) {
        t->stage_no++;
        t->done = 0;
        t->done_seen = 0;
        t->threads = w->workers.count;
        /* no share yet: the workers wait for the first stage */
        __atomic_store_n(&t->ticket, t->stage_no << 32, __ATOMIC_RELEASE);
        t->running = 1;
        w->workers.start(w->workers.user, worker, t, w->workers.count - 1);
    }
#endif
}

void rbs__team_stop(rbs_world *w)
{
    rbs__team *t = team_of(w);
    if (!t->running)
        return;
#if defined(TEAM_ATOMICS)
    t->stage_no++;
    __atomic_store_n(&t->ticket, t->stage_no << 32 | (uint64_t)QUIT << 16, __ATOMIC_RELEASE);
    w->workers.finish(w->workers.user);
#endif
    t->running = 0;
}

void rbs__team_run(rbs_world *w, rbs__stage_fn fn, void *ctx, uint32_t n, uint32_t shares)
{
    rbs__team *t = team_of(w);
    stage *st;
    if (n == 0)
        return;
    if (shares > n)
        shares = n;
    if (shares > RBS__TEAM_SHARES)
        shares = RBS__TEAM_SHARES;
    if (!t->running || shares <= 1) {
        fn(ctx, 0, 0, n);
        return;
    }
#if defined(TEAM_ATOMICS)
    t->stage_no++;
    st = &t->slot[t->stage_no & 1u];
    st->fn = fn;
    st->ctx = ctx;
    st->n = n;
    st->shares = shares;
    {
        /* The step's thread publishes the stage with its first share (0:
         * next_share's) already claimed and counts its shares itself, so
         * that the ticket's and the count's cache lines go to the workers
         * and come back once each a stage, not at every claim. */
        const uint32_t limit = t->spins ? t->spins : SPINS_BEFORE_YIELD;
        uint32_t mine = 1, spins = 0;
        __atomic_store_n(&t->ticket, t->stage_no << 32 | (uint64_t)shares << 16 | 1u, __ATOMIC_RELEASE);
        run_share(st, 0);
        (void)take_shares(t, 0, t->threads, &mine);
        while (__atomic_load_n(&t->done, __ATOMIC_ACQUIRE) - t->done_seen != shares - mine)
            if (++spins >= limit)
                sched_yield();
        t->done_seen += shares - mine;
    }
#else
    (void)st;
#endif
}
