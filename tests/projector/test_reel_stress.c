/*
 * test_reel_stress.c - the reel under two threads, built with the reel's
 * source and ThreadSanitizer (see meson.build).
 *
 *  - Lossless: 200000 frames through a reel of 4; the reader must see every
 *    frame exactly once, in order, with its contents intact (each body's
 *    numbers are a function of the frame number; a checksum of all frames
 *    read equals the writer's).
 *  - Latest-only: 200000 frames; the reader's frame numbers strictly
 *    increase (never a duplicate, never out of order), contents intact, and
 *    read + dropped = written.
 *  - Close wakes a writer blocked on a full ring and a reader blocked on an
 *    empty one (the test would hang otherwise; meson's timeout catches it).
 */
#include "rbsim/reel.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FRAMES 200000u
#define BODIES 3u

static int failures;

#define CHECK(cond, ...)                                                       \
    do {                                                                       \
        if (!(cond)) {                                                         \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__,   \
                    #cond);                                                    \
            fprintf(stderr, __VA_ARGS__);                                      \
            fputc('\n', stderr);                                               \
            failures++;                                                        \
        }                                                                      \
    } while (0)

typedef struct shared {
    rbs_reel *reel;
    uint64_t written;
    uint64_t writer_sum;
    rbs_status writer_status;
} shared;

static double value(uint64_t k, uint32_t b, int i)
{
    return (double)k * 1.5 + (double)b * 0.25 + (double)i;
}

static uint64_t mix(uint64_t h, uint64_t k)
{
    h ^= k + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    return h;
}

static void *writer(void *arg)
{
    shared *s = arg;
    uint64_t k;
    for (k = 0; k < FRAMES; k++) {
        rbs_frame *f;
        uint32_t b;
        rbs_status st = rbs_reel_begin_write(s->reel, &f);
        if (st != RBS_OK) {
            s->writer_status = st;
            return NULL;
        }
        f->number = k;
        f->time = (double)k * 0.001;
        f->body_count = BODIES;
        f->last = k + 1 == FRAMES;
        for (b = 0; b < BODIES; b++) {
            f->bodies[b].slot = b;
            f->bodies[b].position[0] = value(k, b, 0);
            f->bodies[b].position[1] = value(k, b, 1);
            f->bodies[b].position[2] = value(k, b, 2);
        }
        st = rbs_reel_end_write(s->reel);
        if (st != RBS_OK) {
            s->writer_status = st;
            return NULL;
        }
        s->writer_sum = mix(s->writer_sum, k);
        s->written++;
    }
    rbs_reel_close(s->reel);
    return NULL;
}

/* Contents of a frame match its number. */
static int intact(const rbs_frame *f)
{
    uint32_t b;
    if (f->body_count != BODIES || f->time != (double)f->number * 0.001)
        return 0;
    for (b = 0; b < BODIES; b++)
        if (f->bodies[b].slot != b ||
            f->bodies[b].position[0] != value(f->number, b, 0) ||
            f->bodies[b].position[1] != value(f->number, b, 1) ||
            f->bodies[b].position[2] != value(f->number, b, 2))
            return 0;
    return 1;
}

static void run(rbs_reel_policy policy, uint32_t capacity)
{
    shared s;
    pthread_t t;
    uint64_t read = 0, next = 0, sum = 0, bad = 0, out_of_order = 0;
    int64_t last_seen = -1;
    int saw_last = 0;
    const rbs_frame *f;
    rbs_status st;

    memset(&s, 0, sizeof s);
    CHECK(rbs_reel_create(capacity, BODIES, policy, &s.reel) == RBS_OK, "create");
    pthread_create(&t, NULL, writer, &s);
    while ((st = rbs_reel_begin_read(s.reel, &f)) == RBS_OK) {
        if (!intact(f))
            bad++;
        if (policy == RBS_REEL_LOSSLESS) {
            if (f->number != next)
                out_of_order++;
            next = f->number + 1;
        } else if ((int64_t)f->number <= last_seen) {
            out_of_order++;
        }
        last_seen = (int64_t)f->number;
        saw_last |= f->last;
        sum = mix(sum, f->number);
        read++;
        rbs_reel_end_read(s.reel);
    }
    pthread_join(t, NULL);
    CHECK(st == RBS_E_CLOSED, "reader ends with %d", (int)st);
    CHECK(s.writer_status == RBS_OK, "writer status %d", (int)s.writer_status);
    CHECK(s.written == FRAMES, "written %llu", (unsigned long long)s.written);
    CHECK(bad == 0, "%llu frames with wrong contents", (unsigned long long)bad);
    CHECK(out_of_order == 0, "%llu frames out of order or repeated",
          (unsigned long long)out_of_order);
    CHECK(saw_last, "the last frame was not read");
    if (policy == RBS_REEL_LOSSLESS) {
        CHECK(read == FRAMES, "read %llu of %u", (unsigned long long)read, FRAMES);
        CHECK(sum == s.writer_sum, "checksum differs");
        CHECK(rbs_reel_dropped(s.reel) == 0, "dropped %llu",
              (unsigned long long)rbs_reel_dropped(s.reel));
    } else {
        CHECK(read + rbs_reel_dropped(s.reel) == FRAMES,
              "read %llu + dropped %llu != %u", (unsigned long long)read,
              (unsigned long long)rbs_reel_dropped(s.reel), FRAMES);
        CHECK(last_seen == (int64_t)FRAMES - 1, "last frame read %lld",
              (long long)last_seen);
    }
    printf("%s capacity %u: read %llu, dropped %llu\n",
           policy == RBS_REEL_LOSSLESS ? "lossless" : "latest-only", capacity,
           (unsigned long long)read,
           (unsigned long long)rbs_reel_dropped(s.reel));
    rbs_reel_destroy(s.reel);
}

/* ---- close wakes blocked threads ---- */

static void *blocked_writer(void *arg)
{
    rbs_reel *reel = arg;
    rbs_frame *f;
    rbs_status st;
    /* Fill the ring, then block on the next slot until closed. */
    while ((st = rbs_reel_begin_write(reel, &f)) == RBS_OK)
        if ((st = rbs_reel_end_write(reel)) != RBS_OK)
            break;
    return (void *)(size_t)(st == RBS_E_CLOSED);
}

static void *blocked_reader(void *arg)
{
    rbs_reel *reel = arg;
    const rbs_frame *f;
    return (void *)(size_t)(rbs_reel_begin_read(reel, &f) == RBS_E_CLOSED);
}

static void close_wakes(void)
{
    rbs_reel *full, *empty;
    pthread_t w, r;
    void *ok_w, *ok_r;
    struct timespec pause = {0, 20 * 1000 * 1000};
    rbs_reel_create(2, 1, RBS_REEL_LOSSLESS, &full);
    rbs_reel_create(2, 1, RBS_REEL_LOSSLESS, &empty);
    pthread_create(&w, NULL, blocked_writer, full);
    pthread_create(&r, NULL, blocked_reader, empty);
    nanosleep(&pause, NULL); /* let both block (the result holds either way) */
    rbs_reel_close(full);
    rbs_reel_close(empty);
    pthread_join(w, &ok_w);
    pthread_join(r, &ok_r);
    CHECK(ok_w != NULL, "blocked writer did not get RBS_E_CLOSED");
    CHECK(ok_r != NULL, "blocked reader did not get RBS_E_CLOSED");
    rbs_reel_destroy(full);
    rbs_reel_destroy(empty);
}

int main(void)
{
    run(RBS_REEL_LOSSLESS, 4);
    run(RBS_REEL_LOSSLESS, 2);
    run(RBS_REEL_LATEST_ONLY, 4);
    run(RBS_REEL_LATEST_ONLY, 2);
    close_wakes();
    if (failures)
        fprintf(stderr, "%d checks failed\n", failures);
    return failures ? 1 : 0;
}
