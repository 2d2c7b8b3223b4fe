/*
 * test_threads_tsan.c - the library under ThreadSanitizer: four threads each
 * parse every demonstration scene (JSON), build it, step it with every
 * available method, write and read a checkpoint and hash the result, all at
 * once.  Each hash must equal the one computed alone on the main thread, and
 * ThreadSanitizer must report no race (the library keeps no global mutable
 * state; scene parsing switches the locale per thread).  Then a pile of 600
 * spheres (two slabs: soft_detect.c; a wall added between them, so that
 * detection copies their centres in its shares) stepped by the soft step on pools of
 * one and two more threads (rbs_pool_create), which must give the hash of
 * the caller's thread alone, with no race among the step's threads.
 *
 * Usage: test_threads_tsan SCENES_DIR
 */
#include <dirent.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rbsim/rbsim.h"
#include "rbsim/reel.h"
#include "rbsim/scene.h"

#define MAX_SCENES 32
#define THREADS 4
#define STEPS 60

typedef struct job {
    char paths[MAX_SCENES][512];
    int n;
    uint64_t hash[MAX_SCENES][RBS_METHOD_COUNT];
    int failed;
} job;

/* Hash after STEPS steps of a scene with method m; 0 if m does not apply. */
static uint64_t run(const char *path, rbs_method m, int *failed)
{
    rbs_scene *s = NULL;
    rbs_world *w = NULL, *b = NULL;
    uint64_t h = 0;
    size_t n;
    void *buf;
    int k;
    if (rbs_scene_load(path, RBS_SCENE_JSON, &s) != RBS_OK || rbs_scene_build(s, &w) != RBS_OK) {
        fprintf(stderr, "%s: cannot load or build\n", path);
        *failed = 1;
        rbs_scene_free(s);
        return 0;
    }
    rbs_scene_free(s);
    if (rbs_world_set_method(w, m, 0.0) != RBS_OK) {
        rbs_world_destroy(w);
        return 0;
    }
    for (k = 0; k < STEPS; ++k)
        if (rbs_world_step(w, NULL) != RBS_OK)
            break; /* out of the method's scope: the hash still compares */
    n = rbs_world_checkpoint_size(w);
    buf = malloc(n);
    if (buf && rbs_world_checkpoint_write(w, buf, n, NULL) == RBS_OK &&
        rbs_world_create_from_checkpoint(buf, n, &b) == RBS_OK) {
        h = rbs_world_hash(b);
        rbs_world_destroy(b);
    } else {
        *failed = 1;
    }
    free(buf);
    rbs_world_destroy(w);
    return h;
}

static void *work(void *arg)
{
    job *j = (job *)arg;
    int i, m;
    for (i = 0; i < j->n; ++i)
        for (m = 0; m < RBS_METHOD_COUNT; ++m)
            j->hash[i][m] = run(j->paths[i], (rbs_method)m, &j->failed);
    return NULL;
}

/* Plane i of the pile's box: the floor (0), then four walls. */
static int add_wall(rbs_world *w, int i)
{
    rbs_plane_def p;
    rbs_plane_def_init(&p);
    if (i > 0) {
        p.normal.x = i == 1 ? 1 : i == 2 ? -1 : 0;
        p.normal.y = i == 3 ? 1 : i == 4 ? -1 : 0;
        p.normal.z = 0;
        p.point.x = -0.6 * p.normal.x;
        p.point.y = -0.6 * p.normal.y;
    }
    return rbs_world_add_plane(w, &p, NULL) == RBS_OK;
}

/* The pile's hash after 40 frames on `threads` threads (1: the caller's
 * only); 0 on failure. */
static uint64_t pile_hash(uint32_t threads)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_pool *pool = NULL;
    rbs_workers wk;
    uint64_t h = 0, seed = 7;
    int i, ok = 1;
    rbs_world_def_init(&d);
    d.max_bodies = 610;
    d.method = RBS_METHOD_SOFT;
    d.dt = 0.002;
    if (rbs_world_create(&d, &w) != RBS_OK)
        return 0;
    for (i = 0; i < 4; ++i)
        ok &= add_wall(w, i);
    for (i = 0; i < 600; ++i) {
        rbs_sphere_def s;
        /* the last wall between the spheres: their slots are then not
         * consecutive, and detection copies their centres in its shares */
        if (i == 300)
            ok &= add_wall(w, 4);
        rbs_sphere_def_init(&s);
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        s.radius = 0.05;
        s.position.x = -0.55 + 0.11 * (i % 10) + 1e-3 * (double)(seed >> 60);
        s.position.y = -0.55 + 0.11 * ((i / 10) % 10);
        s.position.z = 0.06 + 0.11 * (i / 100);
        s.velocity.z = -1.0;
        ok &= rbs_world_add_sphere(w, &s, NULL) == RBS_OK;
    }
    if (threads > 1) {
        rbs_workers_init(&wk);
        ok &= rbs_pool_create(threads - 1, &pool) == RBS_OK && rbs_pool_workers(pool, &wk) == RBS_OK &&
              rbs_world_set_workers(w, &wk) == RBS_OK;
    }
    for (i = 0; ok && i < 40; ++i)
        ok = rbs_world_step(w, NULL) == RBS_OK;
    if (ok)
        h = rbs_world_hash(w);
    rbs_world_set_workers(w, NULL);
    rbs_pool_destroy(pool);
    rbs_world_destroy(w);
    return h;
}

int main(int argc, char **argv)
{
    static job alone, par[THREADS];
    pthread_t t[THREADS];
    DIR *d;
    struct dirent *e;
    int i, k, m, rc = 0;
    if (argc != 2 || (d = opendir(argv[1])) == NULL) {
        fprintf(stderr, "usage: %s SCENES_DIR\n", argv[0]);
        return 2;
    }
    while ((e = readdir(d)) != NULL && alone.n < MAX_SCENES) {
        size_t len = strlen(e->d_name);
        if (len > 5 && strcmp(e->d_name + len - 5, ".json") == 0 && strcmp(e->d_name, "pile.json") != 0)
            snprintf(alone.paths[alone.n++], 512, "%.400s/%.100s", argv[1], e->d_name);
    }
    closedir(d);
    work(&alone);
    for (k = 0; k < THREADS; ++k) {
        par[k].n = alone.n;
        memcpy(par[k].paths, alone.paths, sizeof alone.paths);
        if (pthread_create(&t[k], NULL, work, &par[k]) != 0)
            return 1;
    }
    for (k = 0; k < THREADS; ++k)
        pthread_join(t[k], NULL);
    for (k = 0; k < THREADS; ++k)
        for (i = 0; i < alone.n; ++i)
            for (m = 0; m < RBS_METHOD_COUNT; ++m)
                if (par[k].hash[i][m] != alone.hash[i][m]) {
                    fprintf(stderr, "thread %d: %s with %s: hash %016llx, alone %016llx\n", k, alone.paths[i],
                            rbs_method_name((rbs_method)m), (unsigned long long)par[k].hash[i][m],
                            (unsigned long long)alone.hash[i][m]);
                    rc = 1;
                }
    if (alone.failed)
        rc = 1;
    printf("%d scenes x %d methods in %d threads: %s\n", alone.n, RBS_METHOD_COUNT, THREADS,
           rc ? "MISMATCH" : "identical");
    {
        uint64_t one = pile_hash(1), two = pile_hash(2), three = pile_hash(3);
        int same = one != 0 && one == two && one == three;
        printf("a pile of 600 on 1, 2 and 3 threads: %s\n", same ? "identical" : "MISMATCH");
        if (!same)
            rc = 1;
    }
    return rc;
}
