/*
 * test_scene_alloc.c - fault injection (as SQLite does it): the k-th
 * allocation made by the scene code fails, for every k, while loading and
 * saving scenes in both formats.  Each run must end in a clean status
 * (RBS_OK, RBS_E_MEMORY, or RBS_E_SCENE/RBS_E_IO whose errors say what
 * happened), leak nothing, and never return RBS_OK with a scene that lost
 * anything: an RBS_OK scene must save to exactly the reference JSON.
 *
 * malloc, calloc, realloc and free are wrapped at link time (-Wl,--wrap) and
 * the library's objects are linked in, so the wrap sees the library's calls.
 * cJSON's own allocations happen inside libcjson and are not injected.
 */
#include "scene_test.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t m);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);

static long fail_at;  /* 1-based index of the allocation to fail; 0: none */
static long count;    /* allocations seen since the last reset */
static long live;     /* blocks allocated and not yet freed */

static int should_fail(void)
{
    count++;
    return fail_at > 0 && count == fail_at;
}

void *__wrap_malloc(size_t n)
{
    void *p;
    if (should_fail()) {
        return NULL;
    }
    p = __real_malloc(n);
    live += p != NULL;
    return p;
}

void *__wrap_calloc(size_t n, size_t m)
{
    void *p;
    if (should_fail()) {
        return NULL;
    }
    p = __real_calloc(n, m);
    live += p != NULL;
    return p;
}

void *__wrap_realloc(void *p, size_t n)
{
    void *q;
    if (should_fail()) {
        return NULL;
    }
    q = __real_realloc(p, n);
    live += (p == NULL && q != NULL);
    return q;
}

void __wrap_free(void *p)
{
    live -= p != NULL;
    __real_free(p);
}

static char tmpdir[] = "/tmp/rbs_scene_alloc_XXXXXX";

/* Load (and save) with the k-th allocation failing; returns the number of
 * allocations the whole operation makes when none fails. */
static long run(const char *path, long k, const char *reference)
{
    rbs_scene *scene = NULL;
    rbs_status st;
    char out[256], cfg[256];
    long made;
    snprintf(out, sizeof out, "%s/out.json", tmpdir);
    snprintf(cfg, sizeof cfg, "%s/config.txt", tmpdir);
    live = 0;
    count = 0;
    fail_at = k;
    st = rbs_scene_load(path, RBS_SCENE_AUTO, &scene);
    if (st == RBS_OK) {
        rbs_status s1 = rbs_scene_save(scene, cfg, RBS_SCENE_TEXT);
        rbs_status s2;
        assert_true(s1 == RBS_OK || s1 == RBS_E_MEMORY || s1 == RBS_E_IO);
        s2 = rbs_scene_save(scene, out, RBS_SCENE_JSON);
        assert_true(s2 == RBS_OK || s2 == RBS_E_MEMORY || s2 == RBS_E_IO);
        fail_at = 0;
        if (s2 == RBS_OK) {
            size_t len = 0;
            char *text = read_all(out, &len);
            assert_non_null(text);
            if (strcmp(text, reference) != 0) {
                fail_msg("%s: allocation %ld failed, the load said RBS_OK, but the scene "
                         "differs",
                         path, k);
            }
            free(text);
        }
    } else if (st == RBS_E_SCENE || st == RBS_E_IO) {
        rbs_scene_error e;
        assert_non_null(scene);
        assert_true(rbs_scene_error_count(scene) >= 1);
        /* the first message may itself have failed to be kept */
        if (rbs_scene_error_get(scene, 0, &e) == RBS_OK) {
            assert_non_null(strstr(e.text, "out of memory"));
        }
    } else {
        assert_int_equal(st, RBS_E_MEMORY);
        assert_null(scene);
    }
    made = count;
    fail_at = 0;
    rbs_scene_free(scene);
    if (live != 0) {
        fail_msg("%s: allocation %ld failed: %ld blocks leaked", path, k, live);
    }
    return made;
}

static void fault_sweep(const char *path)
{
    rbs_scene *scene = NULL;
    char out[256];
    char *reference;
    size_t len = 0;
    long total, k;
    snprintf(out, sizeof out, "%s/reference.json", tmpdir);
    assert_int_equal(rbs_scene_load(path, RBS_SCENE_AUTO, &scene), RBS_OK);
    assert_int_equal(rbs_scene_save(scene, out, RBS_SCENE_JSON), RBS_OK);
    rbs_scene_free(scene);
    reference = read_all(out, &len);
    assert_non_null(reference);
    total = run(path, 0, reference);
    assert_true(total > 10);
    for (k = 1; k <= total; k++) {
        (void)run(path, k, reference);
    }
    free(reference);
}

static void test_json(void **state)
{
    (void)state;
    fault_sweep("roundtrip_features.json");
    fault_sweep("issue_example.json");
}

static void test_text(void **state)
{
    (void)state;
    fault_sweep("../../scenes/incline/config.txt");
}

static void test_bad(void **state)
{
    long k;
    (void)state;
    /* a scene with errors: every failure point still ends cleanly */
    for (k = 1; k <= 200; k++) {
        rbs_scene *scene = NULL;
        rbs_status st;
        live = 0;
        count = 0;
        fail_at = k;
        st = rbs_scene_load("bad/many_errors.json", RBS_SCENE_AUTO, &scene);
        fail_at = 0;
        assert_true(st == RBS_E_SCENE || st == RBS_E_MEMORY);
        rbs_scene_free(scene);
        assert_int_equal(live, 0);
    }
}

static int setup(void **state)
{
    (void)state;
    return mkdtemp(tmpdir) == NULL ? -1 : 0;
}

static int teardown(void **state)
{
    static const char *const names[] = {"out.json", "reference.json", "config.txt",
                                        "materials.txt", "objects.txt"};
    char path[256];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof names / sizeof *names; i++) {
        snprintf(path, sizeof path, "%s/%s", tmpdir, names[i]);
        (void)remove(path);
    }
    return rmdir(tmpdir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_json),
        cmocka_unit_test(test_text),
        cmocka_unit_test(test_bad),
    };
    if (enter_test_dir() != 0) {
        return 1;
    }
    return cmocka_run_group_tests_name("scene_alloc", tests, setup, teardown);
}
