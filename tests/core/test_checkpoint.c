/*
 * test_checkpoint.c - a checkpoint restores the exact state: stepping on
 * from it gives bit-identical results to never having stopped; corrupt,
 * truncated and foreign data are rejected with a reason.
 */
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common.h"

static rbs_world *scene(void)
{
    rbs_world *w = make_world(16, 1e-3, -9.81, 0.7);
    rbs_material_id m = material(w, "m", 0.4, 0.3, -1.0);
    rbs_sphere_def s;
    int i;
    floor_plane(w, m);
    for (i = 0; i < 5; ++i)
        ball(w, 0.1, 1.0 + i, 0.25 * i, 0, 0.3 + 0.1 * i, 1.0 - 0.3 * i, 0.2, 0, m);
    rbs_sphere_def_init(&s);
    s.name = "spinner";
    s.position.x = -1;
    s.position.z = 0.5;
    s.angular_velocity.z = 7;
    s.center_of_mass.y = 0.01;
    s.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    return w;
}

static void resume_is_bit_identical(void **state)
{
    char path[] = "/tmp/rbsim-ckpt-XXXXXX";
    rbs_world *a = scene(), *b;
    char msg[256];
    int fd = mkstemp(path);
    rbs_body_id id;
    (void)state;
    assert_true(fd >= 0);
    close(fd);
    step_n(a, 700);
    CHECK_OK(rbs_world_save(a, path));
    CHECK_OK(rbs_world_load(path, &b, msg, sizeof msg));
    assert_true(rbs_world_hash(a) == rbs_world_hash(b));
    assert_int_equal(rbs_world_step_count(b), 700);
    CHECK_OK(rbs_world_find_body(b, "spinner", &id));
    /* Bodies added without a name (the floor and the five balls: the API
     * takes NULL, which no scene file can hold) come back unnamed, each in
     * its slot, and "" finds none of them (RBS_NAME_MAX, scenes/FORMAT.md
     * "Names"). */
    {
        uint32_t slot, unnamed = 0;
        for (slot = 0; slot < 7; slot++) {
            rbs_body_id ia, ib;
            rbs_body_state sa, sb;
            CHECK_OK(rbs_world_body_at(a, slot, &ia));
            CHECK_OK(rbs_world_body_at(b, slot, &ib));
            CHECK_OK(rbs_body_get_state(a, ia, &sa));
            CHECK_OK(rbs_body_get_state(b, ib, &sb));
            assert_string_equal(sa.name, sb.name);
            assert_int_equal(sa.type, sb.type);
            unnamed += sb.name[0] == '\0';
        }
        assert_int_equal(unnamed, 6);
        assert_int_equal(rbs_world_body_at(b, 7, &id), RBS_E_NOT_FOUND);
        assert_int_equal(rbs_world_find_body(b, "", &id), RBS_E_NOT_FOUND);
    }
    step_n(a, 800);
    step_n(b, 800);
    assert_true(rbs_world_hash(a) == rbs_world_hash(b));
    assert_true(rbs_world_time(a) == rbs_world_time(b));
    rbs_world_destroy(a);
    rbs_world_destroy(b);
    unlink(path);
}

/* Resuming in the middle of contact: the resting pass is warm-started from
 * the last step's impulses, which a checkpoint must carry (the table and
 * its extent); and the broad phase's candidate-pair list, kept between
 * steps while bodies move little, is not carried (a resumed world builds
 * its own), so results must not depend on when a list was built.  A layer
 * of balls on a floor is hit by one rolling in at 6 m/s and one dropped on
 * it: the list is reused while the layer rests and must be rebuilt when
 * the fast ones arrive.  World b goes through a checkpoint before
 * every step; its hash must equal that of world a, stepped straight
 * through, after every step.  (Format version 1 lost the table's extent:
 * 162 steps in, the two differed.) */
static rbs_world *layer_scene(double slop)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_material_id m;
    int i, j;
    rbs_world_def_init(&d);
    d.max_bodies = 32;
    d.dt = 1e-3;
    d.gravity.z = -9.81;
    d.slop = slop;
    CHECK_OK(rbs_world_create(&d, &w));
    m = material(w, "m", 0.5, 0.5, 0.5);
    floor_plane(w, m);
    for (i = 0; i < 5; ++i)
        for (j = 0; j < 5; ++j)
            ball(w, 0.05, 0.1, 0.1 * i + 0.001 * j, 0.1 * j, 0.05, 0, 0, 0, m);
    ball(w, 0.05, 0.1, -1.0, 0.2, 0.05, 6.0, 0, 0, m);
    ball(w, 0.05, 0.1, 0.2, 0.2, 0.6, 0, 0, 0, m);
    return w;
}

static void resume_in_contact(void **state)
{
    const double slops[2] = {1e-6, 0.005};
    int k, step;
    (void)state;
    for (k = 0; k < 2; ++k) {
        rbs_world *a = layer_scene(slops[k]), *b = layer_scene(slops[k]);
        size_t size = rbs_world_checkpoint_size(b);
        void *buf = malloc(size);
        assert_non_null(buf);
        for (step = 1; step <= 500; ++step) {
            rbs_world *c = NULL;
            CHECK_OK(rbs_world_checkpoint_write(b, buf, size, NULL));
            CHECK_OK(rbs_world_create_from_checkpoint(buf, size, &c));
            rbs_world_destroy(b);
            b = c;
            step_n(a, 1);
            step_n(b, 1);
            if (rbs_world_hash(a) != rbs_world_hash(b))
                fail_msg("slop %g: step %d: straight through and resumed differ", slops[k], step);
        }
        free(buf);
        rbs_world_destroy(a);
        rbs_world_destroy(b);
    }
}

static void damaged_checkpoints_are_rejected(void **state)
{
    rbs_world *a = scene(), *b = NULL;
    size_t n = rbs_world_checkpoint_size(a), written;
    unsigned char *buf = malloc(n);
    char msg[256];
    (void)state;
    assert_int_equal(rbs_world_checkpoint_write(a, buf, n - 1, NULL), RBS_E_MEMORY);
    CHECK_OK(rbs_world_checkpoint_write(a, buf, n, &written));
    assert_int_equal(written, n);
    /* truncated */
    assert_int_equal(rbs_world_create_from_checkpoint(buf, n - 9, &b), RBS_E_CORRUPT);
    assert_null(b);
    assert_int_equal(rbs_world_create_from_checkpoint(buf, 10, &b), RBS_E_CORRUPT);
    /* the _v2 form says why (and "" when it succeeds) */
    assert_int_equal(rbs_world_create_from_checkpoint_v2(buf, n - 9, &b, msg, sizeof msg), RBS_E_CORRUPT);
    assert_null(b);
    assert_non_null(strstr(msg, "truncated"));
    /* one flipped bit in a double */
    buf[n / 2] ^= 0x10;
    assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_CORRUPT);
    assert_int_equal(rbs_world_create_from_checkpoint_v2(buf, n, &b, msg, sizeof msg), RBS_E_CORRUPT);
    assert_non_null(strstr(msg, "checksum mismatch"));
    buf[n / 2] ^= 0x10;
    CHECK_OK(rbs_world_create_from_checkpoint_v2(buf, n, &b, msg, sizeof msg));
    assert_string_equal(msg, "");
    rbs_world_destroy(b);
    b = NULL;
    /* another format version: a later one, and versions 2 to 10, whose
     * blocks were laid out differently (the arrays are the block verbatim:
     * 2's contacts, 3 without the name index, 4 without soft_substeps, 5's
     * contacts of 136 bytes, 6 without soft_tolerance, 7 without the soft
     * step's slabs, chunks and team, 8 without the warm table's index, 10's
     * contacts of 120 bytes, 11 without the pressed marks, 12 without the
     * resistance records' impact share, 13 without the warm table's save)
     * or, 9, stepped by the soft step's earlier model */
    {
        unsigned char current = buf[8];
        assert_int_equal(current, 14);
        buf[8] = 15;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 13;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 12;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 11;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 10;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 2;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 3;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 4;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 5;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 6;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 7;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 8;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = 9;
        assert_int_equal(rbs_world_create_from_checkpoint(buf, n, &b), RBS_E_VERSION);
        buf[8] = current;
    }
    CHECK_OK(rbs_world_create_from_checkpoint(buf, n, &b));
    rbs_world_destroy(b);
    /* a foreign file */
    assert_int_equal(rbs_world_load("/bin/sh", &b, msg, sizeof msg), RBS_E_CORRUPT);
    assert_non_null(strstr(msg, "not an rbsim checkpoint"));
    assert_int_equal(rbs_world_load("/nonexistent/x", &b, msg, sizeof msg), RBS_E_IO);
    assert_non_null(strstr(msg, "cannot open"));
    assert_int_equal(rbs_world_save(a, "/nonexistent/dir/x"), RBS_E_IO);
    free(buf);
    rbs_world_destroy(a);
}

/* Saving refuses to replace what is not a regular file (the rename would
 * put a file where /dev/null or a FIFO was) and writes through a link. */
static void save_keeps_devices_and_links(void **state)
{
    rbs_world *a = scene(), *b = NULL;
    char dir[] = "/tmp/rbs_ckpt_XXXXXX", fifo[64], link[64], real[64], msg[256];
    struct stat sb;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(fifo, sizeof fifo, "%s/pipe", dir);
    snprintf(link, sizeof link, "%s/link", dir);
    snprintf(real, sizeof real, "%s/real", dir);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    assert_int_equal(rbs_world_save(a, fifo), RBS_E_IO);
    assert_int_equal(lstat(fifo, &sb), 0);
    assert_true(S_ISFIFO(sb.st_mode));
    assert_int_equal(rbs_world_save_v2(a, dir, msg, sizeof msg), RBS_E_IO); /* a folder */
    assert_non_null(strstr(msg, "is a folder"));
    assert_int_equal(rbs_world_save_v2(a, fifo, msg, sizeof msg), RBS_E_IO);
    assert_non_null(strstr(msg, "not a regular file"));
    assert_int_equal(lstat(dir, &sb), 0);
    assert_true(S_ISDIR(sb.st_mode));
    assert_int_equal(symlink(real, link), 0);
    CHECK_OK(rbs_world_save(a, link));
    assert_int_equal(lstat(link, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    CHECK_OK(rbs_world_load(real, &b, msg, sizeof msg));
    assert_true(rbs_world_hash(b) == rbs_world_hash(a));
    rbs_world_destroy(b);
    assert_int_equal(unlink(link), 0);
    assert_int_equal(unlink(real), 0);
    assert_int_equal(unlink(fifo), 0);
    assert_int_equal(rmdir(dir), 0); /* nothing else was left in it */
    rbs_world_destroy(a);
}

/* A checkpoint read from a pipe (cat ck.bin | rbsim run ... --resume
 * /dev/stdin): loading seeked to find the size, and a pipe failed with
 * "cannot read" and no reason.  It is read to its end now, a child process
 * writing it (bigger than a pipe's buffer holds at once). */
static void load_from_a_pipe(void **state)
{
    rbs_world *a = make_world(2000, 1e-3, -9.81, 0.7), *b = NULL;
    rbs_material_id m = material(a, "m", 0.4, 0.3, -1.0);
    size_t n = 0;
    unsigned char *buf;
    char path[32], msg[256];
    int fds[2], i, status;
    pid_t child;
    (void)state;
    for (i = 0; i < 100; ++i)
        ball(a, 0.1, 1.0, 0.3 * (i % 10), 0.3 * (i / 10), 0.5, 0, 0, 0, m);
    step_n(a, 3);
    n = rbs_world_checkpoint_size(a);
    assert_true(n > 65536);
    buf = malloc(n);
    assert_non_null(buf);
    CHECK_OK(rbs_world_checkpoint_write(a, buf, n, &n));
    assert_int_equal(pipe(fds), 0);
    child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        size_t at = 0;
        close(fds[0]);
        while (at < n) {
            ssize_t w = write(fds[1], buf + at, n - at);
            if (w <= 0)
                _exit(1);
            at += (size_t)w;
        }
        _exit(0);
    }
    close(fds[1]);
    snprintf(path, sizeof path, "/dev/fd/%d", fds[0]);
    CHECK_OK(rbs_world_load(path, &b, msg, sizeof msg));
    close(fds[0]);
    assert_int_equal(waitpid(child, &status, 0), child);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    assert_true(rbs_world_hash(a) == rbs_world_hash(b));
    assert_int_equal(rbs_world_step_count(b), 3);
    rbs_world_destroy(b);
    /* a truncated stream is named as such, with its length */
    assert_int_equal(pipe(fds), 0);
    assert_int_equal(write(fds[1], buf, 100), 100);
    close(fds[1]);
    snprintf(path, sizeof path, "/dev/fd/%d", fds[0]);
    assert_int_equal(rbs_world_load(path, &b, msg, sizeof msg), RBS_E_CORRUPT);
    assert_non_null(strstr(msg, "truncated: 100 bytes"));
    close(fds[0]);
    free(buf);
    rbs_world_destroy(a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(resume_is_bit_identical),
        cmocka_unit_test(resume_in_contact),
        cmocka_unit_test(damaged_checkpoints_are_rejected),
        cmocka_unit_test(save_keeps_devices_and_links),
        cmocka_unit_test(load_from_a_pipe),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
