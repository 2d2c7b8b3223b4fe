/*
 * reel.c - the reel: a bounded ring of preallocated frames between one
 * writer (the simulation thread) and one reader (the renderer thread).
 *
 * Design.  Every slot has a state: FREE, WRITING (held by the writer),
 * READY (published, unread) or READING (held by the reader).  Published
 * frames get increasing sequence numbers; the reader always takes the READY
 * slot with the smallest one, so frames come out in the order they went in.
 * One mutex guards the states; two condition variables (on the monotonic
 * clock) wake the writer when a slot is freed and the reader when a frame is
 * published.  Every wait sits in a loop on its predicate, and closing the
 * reel (or a kick) broadcasts both, so no thread can wait forever.
 *
 * Policies.  Lossless: the writer waits while no slot is FREE.  Latest-only:
 * the writer never waits; with no FREE slot it takes back the oldest READY
 * frame (counted as dropped).  The reader holds at most one slot and the
 * writer at most one, so with capacity >= 2 a slot is always FREE or READY
 * for the writer in that case.
 *
 * All memory (slots and their body arrays) is taken in rbs_reel_create.
 */
#include "reel_internal.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

enum slot_state { SLOT_FREE = 0, SLOT_WRITING, SLOT_READY, SLOT_READING };

struct rbs_reel {
    pthread_mutex_t mutex;
    pthread_cond_t can_write; /* a slot became FREE, or closed */
    pthread_cond_t can_read;  /* a frame became READY, closed, or kicked */
    rbs_reel_policy policy;
    uint32_t capacity;
    uint32_t max_bodies;
    int closed;
    int kicked;
    uint32_t ready;           /* READY slots */
    uint32_t writing;         /* slot index held by the writer, or capacity */
    uint32_t reading;         /* slot index held by the reader, or capacity */
    uint64_t next_seq;
    uint64_t dropped;
    rbs_frame *frames;        /* capacity frames */
    uint8_t *state;           /* capacity slot_state */
    uint64_t *seq;            /* capacity sequence numbers */
    rbs_frame_body *bodies;   /* capacity * max_bodies */
};

struct timespec rbs__deadline_after(double seconds)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    if (seconds > 1e9)
        seconds = 1e9; /* (31 years: beyond it (long) overflowed, and the
                          deadline, in the past, made a waiter spin with the
                          lock held -- a real-time frame at speed 1e-300 --
                          so that nothing, not even quit, got through; every
                          waiter looks again when it wakes) */
    if (seconds > 0) {
        double whole = (double)(long)seconds;
        long ns = (long)((seconds - whole) * 1e9);
        ts.tv_sec += (time_t)whole;
        ts.tv_nsec += ns;
        if (ts.tv_nsec >= 1000000000L) {
            ts.tv_sec += 1;
            ts.tv_nsec -= 1000000000L;
        }
    }
    return ts;
}

double rbs__now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void reel_free(rbs_reel *reel)
{
    free(reel->frames);
    free(reel->state);
    free(reel->seq);
    free(reel->bodies);
    free(reel);
}

rbs_status rbs_reel_create(uint32_t capacity, uint32_t max_bodies,
                           rbs_reel_policy policy, rbs_reel **out)
{
    rbs_reel *reel;
    pthread_condattr_t attr;
    uint32_t i;

    if (out == NULL)
        return RBS_E_INVALID;
    *out = NULL;
    if (capacity < 2 || max_bodies == 0 ||
        (policy != RBS_REEL_LOSSLESS && policy != RBS_REEL_LATEST_ONLY))
        return RBS_E_INVALID;
    if ((size_t)capacity * max_bodies > SIZE_MAX / sizeof(rbs_frame_body))
        return RBS_E_CAPACITY;

    reel = calloc(1, sizeof *reel);
    if (reel == NULL)
        return RBS_E_MEMORY;
    reel->frames = calloc(capacity, sizeof *reel->frames);
    reel->state = calloc(capacity, sizeof *reel->state);
    reel->seq = calloc(capacity, sizeof *reel->seq);
    reel->bodies = calloc((size_t)capacity * max_bodies, sizeof *reel->bodies);
    if (!reel->frames || !reel->state || !reel->seq || !reel->bodies) {
        reel_free(reel);
        return RBS_E_MEMORY;
    }
    reel->policy = policy;
    reel->capacity = capacity;
    reel->max_bodies = max_bodies;
    reel->writing = capacity;
    reel->reading = capacity;
    for (i = 0; i < capacity; i++)
        reel->frames[i].bodies = reel->bodies + (size_t)i * max_bodies;

    /* The conditions time out on the monotonic clock (immune to clock
     * changes). */
    if (pthread_mutex_init(&reel->mutex, NULL) != 0) {
        reel_free(reel);
        return RBS_E_MEMORY;
    }
    if (pthread_condattr_init(&attr) != 0) {
        pthread_mutex_destroy(&reel->mutex);
        reel_free(reel);
        return RBS_E_MEMORY;
    }
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    if (pthread_cond_init(&reel->can_write, &attr) != 0) {
        pthread_condattr_destroy(&attr);
        pthread_mutex_destroy(&reel->mutex);
        reel_free(reel);
        return RBS_E_MEMORY;
    }
    if (pthread_cond_init(&reel->can_read, &attr) != 0) {
        pthread_cond_destroy(&reel->can_write);
        pthread_condattr_destroy(&attr);
        pthread_mutex_destroy(&reel->mutex);
        reel_free(reel);
        return RBS_E_MEMORY;
    }
    pthread_condattr_destroy(&attr);
    *out = reel;
    return RBS_OK;
}

void rbs_reel_destroy(rbs_reel *reel)
{
    if (reel == NULL)
        return;
    pthread_cond_destroy(&reel->can_read);
    pthread_cond_destroy(&reel->can_write);
    pthread_mutex_destroy(&reel->mutex);
    reel_free(reel);
}

/* A FREE slot, or capacity if none.  Lock held. */
static uint32_t find_free(const rbs_reel *reel)
{
    uint32_t i;
    for (i = 0; i < reel->capacity; i++)
        if (reel->state[i] == SLOT_FREE)
            return i;
    return reel->capacity;
}

/* The READY slot with the smallest sequence number, or capacity.  Lock
 * held. */
static uint32_t find_oldest_ready(const rbs_reel *reel)
{
    uint32_t i, best = reel->capacity;
    for (i = 0; i < reel->capacity; i++)
        if (reel->state[i] == SLOT_READY &&
            (best == reel->capacity || reel->seq[i] < reel->seq[best]))
            best = i;
    return best;
}

rbs_status rbs_reel_begin_write(rbs_reel *reel, rbs_frame **slot)
{
    uint32_t i;
    rbs_frame_body *bodies;

    if (reel == NULL || slot == NULL)
        return RBS_E_INVALID;
    *slot = NULL;
    pthread_mutex_lock(&reel->mutex);
    if (reel->writing != reel->capacity) {
        pthread_mutex_unlock(&reel->mutex);
        return RBS_E_INVALID; /* one slot at a time */
    }
    for (;;) {
        if (reel->closed) {
            pthread_mutex_unlock(&reel->mutex);
            return RBS_E_CLOSED;
        }
        i = find_free(reel);
        if (i != reel->capacity)
            break;
        if (reel->policy == RBS_REEL_LATEST_ONLY) {
            /* Take back the oldest unread frame. */
            i = find_oldest_ready(reel);
            if (i != reel->capacity) {
                reel->ready--;
                reel->dropped++;
                break;
            }
        }
        pthread_cond_wait(&reel->can_write, &reel->mutex);
    }
    reel->state[i] = SLOT_WRITING;
    reel->writing = i;
    pthread_mutex_unlock(&reel->mutex);

    /* The slot is ours alone now: clear it outside the lock. */
    bodies = reel->frames[i].bodies;
    memset(&reel->frames[i], 0, sizeof reel->frames[i]);
    reel->frames[i].bodies = bodies;
    *slot = &reel->frames[i];
    return RBS_OK;
}

rbs_status rbs_reel_end_write(rbs_reel *reel)
{
    uint32_t i;
    if (reel == NULL)
        return RBS_E_INVALID;
    pthread_mutex_lock(&reel->mutex);
    i = reel->writing;
    if (i == reel->capacity) {
        pthread_mutex_unlock(&reel->mutex);
        return RBS_E_INVALID;
    }
    reel->writing = reel->capacity;
    if (reel->closed) {
        /* Nobody will read it: the frame is discarded. */
        reel->state[i] = SLOT_FREE;
        pthread_mutex_unlock(&reel->mutex);
        return RBS_E_CLOSED;
    }
    reel->state[i] = SLOT_READY;
    reel->seq[i] = reel->next_seq++;
    reel->ready++;
    pthread_cond_signal(&reel->can_read);
    pthread_mutex_unlock(&reel->mutex);
    return RBS_OK;
}

rbs_status rbs__reel_read_until(rbs_reel *reel, const struct timespec *deadline,
                                const rbs_frame **frame)
{
    uint32_t i;
    if (reel == NULL || frame == NULL)
        return RBS_E_INVALID;
    *frame = NULL;
    pthread_mutex_lock(&reel->mutex);
    if (reel->reading != reel->capacity) {
        pthread_mutex_unlock(&reel->mutex);
        return RBS_E_INVALID; /* one frame at a time */
    }
    /* Frames published before a close are still delivered (drained). */
    while (reel->ready == 0) {
        if (reel->closed) {
            pthread_mutex_unlock(&reel->mutex);
            return RBS_E_CLOSED;
        }
        if (reel->kicked) {
            reel->kicked = 0;
            pthread_mutex_unlock(&reel->mutex);
            return RBS_E_NOT_FOUND;
        }
        if (deadline == NULL) {
            pthread_cond_wait(&reel->can_read, &reel->mutex);
        } else if (pthread_cond_timedwait(&reel->can_read, &reel->mutex,
                                          deadline) == ETIMEDOUT &&
                   reel->ready == 0) {
            pthread_mutex_unlock(&reel->mutex);
            return RBS_E_NOT_FOUND;
        }
    }
    i = find_oldest_ready(reel);
    reel->state[i] = SLOT_READING;
    reel->reading = i;
    reel->ready--;
    pthread_mutex_unlock(&reel->mutex);
    *frame = &reel->frames[i];
    return RBS_OK;
}

rbs_status rbs_reel_begin_read(rbs_reel *reel, const rbs_frame **frame)
{
    rbs_status st;
    /* Kicks are for the projector's timed reads; a plain read ignores
     * them. */
    do {
        st = rbs__reel_read_until(reel, NULL, frame);
    } while (st == RBS_E_NOT_FOUND);
    return st;
}

rbs_status rbs_reel_end_read(rbs_reel *reel)
{
    uint32_t i;
    if (reel == NULL)
        return RBS_E_INVALID;
    pthread_mutex_lock(&reel->mutex);
    i = reel->reading;
    if (i == reel->capacity) {
        pthread_mutex_unlock(&reel->mutex);
        return RBS_E_INVALID;
    }
    reel->reading = reel->capacity;
    reel->state[i] = SLOT_FREE;
    pthread_cond_signal(&reel->can_write);
    pthread_mutex_unlock(&reel->mutex);
    return RBS_OK;
}

void rbs_reel_close(rbs_reel *reel)
{
    if (reel == NULL)
        return;
    pthread_mutex_lock(&reel->mutex);
    reel->closed = 1;
    pthread_cond_broadcast(&reel->can_write);
    pthread_cond_broadcast(&reel->can_read);
    pthread_mutex_unlock(&reel->mutex);
}

void rbs__reel_kick(rbs_reel *reel)
{
    pthread_mutex_lock(&reel->mutex);
    reel->kicked = 1;
    pthread_cond_broadcast(&reel->can_read);
    pthread_mutex_unlock(&reel->mutex);
}

uint64_t rbs_reel_dropped(rbs_reel *reel)
{
    uint64_t n;
    if (reel == NULL)
        return 0;
    pthread_mutex_lock(&reel->mutex);
    n = reel->dropped;
    pthread_mutex_unlock(&reel->mutex);
    return n;
}

uint32_t rbs__reel_pending(rbs_reel *reel)
{
    uint32_t n;
    pthread_mutex_lock(&reel->mutex);
    n = reel->ready;
    pthread_mutex_unlock(&reel->mutex);
    return n;
}
