/*
 * test_scene_stream.c - scenes read through a pipe, a FIFO or /dev/fd/N:
 * the loader opens the file once, so nothing is lost to telling the format,
 * and the size limit holds for streams (stopped just past it) and for
 * regular files (refused from their size, unread).
 *
 * A writer thread feeds each pipe or FIFO while the test loads it.  SIGPIPE
 * is ignored so that a writer whose reader has gone gets EPIPE instead.
 */
#include "scene_test.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>

#include "rbsim/rbsim.h"

#define LIMIT ((size_t)256 * 1024 * 1024) /* RBS__SCENE_FILE_MAX */

typedef struct writer {
    int fd;              /* written to, then closed; -1: open fifo first */
    const char *fifo;    /* a FIFO to open for writing, or NULL */
    const char *data;    /* bytes to write; NULL: zero bytes without end */
    size_t len;
    size_t written;      /* out: bytes the reader took */
} writer;

static void *write_all(void *arg)
{
    static const char zeros[65536] = {0};
    writer *w = arg;
    if (w->fifo != NULL) {
        w->fd = open(w->fifo, O_WRONLY); /* waits for the reader */
        if (w->fd < 0) {
            return NULL;
        }
    }
    for (;;) {
        const char *p = w->data != NULL ? w->data + w->written : zeros;
        size_t want = w->data != NULL ? w->len - w->written : sizeof zeros;
        ssize_t got;
        if (want == 0) {
            break;
        }
        got = write(w->fd, p, want);
        if (got < 0 && errno == EINTR) {
            continue;
        }
        if (got <= 0) {
            break; /* EPIPE: the reader stopped */
        }
        w->written += (size_t)got;
    }
    close(w->fd);
    return NULL;
}

/* Load a scene and save it as JSON text (every field it holds), and hash
 * the world it builds; the caller frees *json. */
static void load_fingerprint(const char *path, const char *tmp, char **json,
                             uint64_t *hash)
{
    rbs_scene *scene = NULL;
    rbs_world *world = NULL;
    char out[4200];
    size_t len;
    rbs_status st = rbs_scene_load(path, RBS_SCENE_AUTO, &scene);
    if (st != RBS_OK) {
        print_errors(scene);
    }
    assert_int_equal(st, RBS_OK);
    assert_int_equal(rbs_scene_build(scene, &world), RBS_OK);
    *hash = rbs_world_hash(world);
    snprintf(out, sizeof out, "%s/saved.json", tmp);
    assert_int_equal(rbs_scene_save(scene, out, RBS_SCENE_JSON), RBS_OK);
    *json = read_all(out, &len);
    assert_non_null(*json);
    unlink(out);
    rbs_world_destroy(world);
    rbs_scene_free(scene);
}

static char *make_tmpdir(void)
{
    char tmpl[] = "/tmp/rbs_stream_XXXXXX";
    char *dir = mkdtemp(tmpl);
    assert_non_null(dir);
    dir = strdup(dir);
    assert_non_null(dir);
    return dir;
}

/* Load *scene from the read end of a pipe as /dev/fd/N (its name into
 * path, n bytes) while a thread writes w into it; the load's status. */
static rbs_status load_from_pipe(writer *w, char *path, size_t n, rbs_scene **scene)
{
    pthread_t th;
    int fds[2];
    rbs_status st;
    assert_int_equal(pipe(fds), 0);
    w->fd = fds[1];
    assert_int_equal(pthread_create(&th, NULL, write_all, w), 0);
    snprintf(path, n, "/dev/fd/%d", fds[0]);
    st = rbs_scene_load(path, RBS_SCENE_AUTO, scene);
    close(fds[0]);
    assert_int_equal(pthread_join(th, NULL), 0);
    return st;
}

/* JSON scene `file` read through a stream -- an anonymous pipe as
 * /dev/fd/N (fifo 0) or a named FIFO "scene" (fifo 1), neither with a .json
 * name -- is the same scene, and builds the same world, as from the file. */
static void json_through_stream(const char *file, int fifo)
{
    writer w;
    pthread_t th;
    int fds[2] = {-1, -1};
    char path[64], *tmp = make_tmpdir(), *want, *got;
    uint64_t want_hash, got_hash;
    memset(&w, 0, sizeof w);
    w.data = read_all(file, &w.len);
    assert_non_null(w.data);
    load_fingerprint(file, tmp, &want, &want_hash);

    if (fifo) {
        snprintf(path, sizeof path, "%s/scene", tmp);
        assert_int_equal(mkfifo(path, 0600), 0);
        w.fifo = path;
    } else {
        assert_int_equal(pipe(fds), 0);
        w.fd = fds[1];
        snprintf(path, sizeof path, "/dev/fd/%d", fds[0]);
    }
    assert_int_equal(pthread_create(&th, NULL, write_all, &w), 0);
    load_fingerprint(path, tmp, &got, &got_hash);
    if (!fifo)
        close(fds[0]);
    assert_int_equal(pthread_join(th, NULL), 0);
    assert_int_equal(w.written, w.len);
    assert_string_equal(got, want);
    assert_true(got_hash == want_hash);

    free(want);
    free(got);
    free((char *)w.data);
    if (fifo)
        unlink(path);
    rmdir(tmp);
    free(tmp);
}

/* Through an anonymous pipe: 49 KB, several reads. */
static void test_json_from_pipe(void **state)
{
    (void)state;
    json_through_stream("../../scenes/pile.json", 0);
}

/* Through a named FIFO without a .json name: read once, not opened again
 * (which waited for a second writer for ever). */
static void test_json_from_fifo(void **state)
{
    (void)state;
    json_through_stream("../../scenes/collisions.json", 1);
}

/* Copy a file; 0 on success. */
static int copy_file(const char *from, const char *to)
{
    size_t len;
    char *data = read_all(from, &len);
    FILE *f;
    int ok;
    if (data == NULL) {
        return -1;
    }
    f = fopen(to, "wb");
    ok = f != NULL && fwrite(data, 1, len, f) == len;
    ok = f != NULL && fclose(f) == 0 && ok;
    free(data);
    return ok ? 0 : -1;
}

/* A text config through a FIFO in the scene's folder finds materials.txt
 * and objects.txt beside it; through /dev/fd/N it cannot, and says why. */
static void test_text_from_pipe(void **state)
{
    const char *folder = "../../scenes/pile";
    writer w;
    pthread_t th;
    char fifo[64], dev[64], path[4200], *tmp = make_tmpdir(), *want, *got;
    uint64_t want_hash, got_hash;
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    memset(&w, 0, sizeof w);
    snprintf(path, sizeof path, "%s/config.txt", folder);
    w.data = read_all(path, &w.len);
    assert_non_null(w.data);
    load_fingerprint(folder, tmp, &want, &want_hash);

    snprintf(path, sizeof path, "%s/materials.txt", tmp);
    assert_int_equal(copy_file("../../scenes/pile/materials.txt", path), 0);
    snprintf(path, sizeof path, "%s/objects.txt", tmp);
    assert_int_equal(copy_file("../../scenes/pile/objects.txt", path), 0);
    snprintf(fifo, sizeof fifo, "%s/config", tmp);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    w.fifo = fifo;
    assert_int_equal(pthread_create(&th, NULL, write_all, &w), 0);
    load_fingerprint(fifo, tmp, &got, &got_hash);
    assert_int_equal(pthread_join(th, NULL), 0);
    assert_string_equal(got, want);
    assert_true(got_hash == want_hash);

    /* /dev/fd/N: the names resolve in the current folder (they did in
     * /dev/fd: a probe of session 46), and the error says why */
    w.fifo = NULL;
    w.written = 0;
    assert_int_equal(load_from_pipe(&w, dev, sizeof dev, &scene), RBS_E_IO);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.message,
                        "cannot open 'materials.txt': No such file or directory");
    assert_int_equal(e.line, 16); /* "materials = materials.txt" */
    assert_int_equal(rbs_scene_error_get(scene, 1, &e), RBS_OK);
    snprintf(path, sizeof path,
             "'%s' is a descriptor: the file names in it are looked for in "
             "the current folder; run from the scene's folder, name the files "
             "by absolute paths, or load the config.txt file itself",
             dev);
    assert_string_equal(e.message, path);
    assert_int_equal(e.line, 16);
    rbs_scene_free(scene);

    free(want);
    free(got);
    free((char *)w.data);
    unlink(fifo);
    snprintf(path, sizeof path, "%s/materials.txt", tmp);
    unlink(path);
    snprintf(path, sizeof path, "%s/objects.txt", tmp);
    unlink(path);
    rmdir(tmp);
    free(tmp);
}

/* The load of path refused with the one size-limit message; frees scene. */
static void assert_too_large(rbs_scene *scene, const char *path)
{
    rbs_scene_error e;
    char text[8600];
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    snprintf(text, sizeof text, "%s: cannot read '%s': larger than 268435456 bytes", path, path);
    assert_string_equal(e.text, text);
    rbs_scene_free(scene);
}

/* A stream without end is stopped just past the limit (the writer gets
 * EPIPE once the reader has gone), with the same message as a file. */
static void test_stream_over_limit(void **state)
{
    writer w;
    char path[64];
    rbs_scene *scene = NULL;
    (void)state;
    memset(&w, 0, sizeof w);
    assert_int_equal(load_from_pipe(&w, path, sizeof path, &scene), RBS_E_IO);
    assert_too_large(scene, path);
    /* the limit + 1 byte, plus what the pipe (64 KiB) and stdio's buffer
     * held when the reader stopped: 1 MiB is ample */
    fprintf(stderr, "written %zu bytes for a limit of %zu\n", w.written, LIMIT);
    assert_true(w.written > LIMIT);
    assert_true(w.written <= LIMIT + 1024 * 1024);
}

/* A regular file over the limit is refused from its size: a sparse file of
 * the limit + 1 byte, and the same message as a stream. */
static void test_file_over_limit(void **state)
{
    char *tmp = make_tmpdir(), path[4200];
    rbs_scene *scene = NULL;
    int fd;
    (void)state;
    snprintf(path, sizeof path, "%s/big.json", tmp);
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)LIMIT + 1), 0);
    close(fd);
    assert_int_equal(rbs_scene_load(path, RBS_SCENE_AUTO, &scene), RBS_E_IO);
    assert_too_large(scene, path);
    unlink(path);
    rmdir(tmp);
    free(tmp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_json_from_pipe),    cmocka_unit_test(test_json_from_fifo),
        cmocka_unit_test(test_text_from_pipe),    cmocka_unit_test(test_stream_over_limit),
        cmocka_unit_test(test_file_over_limit),
    };
    struct sigaction ign;
    memset(&ign, 0, sizeof ign);
    ign.sa_handler = SIG_IGN;
    if (sigaction(SIGPIPE, &ign, NULL) != 0 || enter_test_dir() != 0) {
        return 1;
    }
    return cmocka_run_group_tests_name("scene_stream", tests, NULL, NULL);
}
