/*
 * test_scene_fuzz.c - parsing never crashes and never reads past its input:
 * every truncated prefix of the demonstration scenes, byte mutations of them,
 * and random bytes (a fixed seed, so failures reproduce) are fed to
 * rbs_scene_parse_json, each in a heap buffer of exactly its length so that
 * the sanitizer build catches any read past the end.  Invalid input must give
 * RBS_E_SCENE with at least one error, each with a place.  Random text files
 * go through the text loader the same way.
 */
#include "scene_test.h"

/* xorshift64*: deterministic, seeded below. */
static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 2685821657736338717ULL;
}

static long parsed, rejected;

/* Parse len bytes; returns the status, checks the error contract. */
static rbs_status parse(const char *bytes, size_t len, int must_fail)
{
    char *copy = malloc(len ? len : 1);
    rbs_scene *scene = NULL;
    rbs_status st;
    assert_non_null(copy);
    if (len > 0) {
        memcpy(copy, bytes, len);
    }
    st = rbs_scene_parse_json(copy, len, "fuzz", &scene);
    free(copy);
    parsed++;
    assert_non_null(scene);
    if (st == RBS_E_SCENE) {
        rbs_scene_error e;
        rejected++;
        assert_true(rbs_scene_error_count(scene) >= 1);
        assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
        assert_true(e.line >= 1 && e.column >= 1);
        assert_true(strncmp(e.text, "fuzz:", 5) == 0);
    } else {
        assert_int_equal(st, RBS_OK);
        assert_int_equal(rbs_scene_error_count(scene), 0);
    }
    if (must_fail && st != RBS_E_SCENE) {
        fail_msg("a truncated scene of %lu bytes was accepted", (unsigned long)len);
    }
    rbs_scene_free(scene);
    return st;
}

static char *load_demo(size_t i, size_t *len)
{
    char path[256];
    char *text;
    snprintf(path, sizeof path, "../../scenes/%s.json", demo_names[i]);
    text = read_all(path, len);
    assert_non_null(text);
    return text;
}

/* Every prefix shorter than the closing brace is invalid; big files are cut
 * at a stride (every 7th byte) plus each of their last 256 lengths. */
static void test_prefixes(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < DEMO_COUNT; i++) {
        size_t len = 0, n, end, stride;
        char *text = load_demo(i, &len);
        end = len;
        while (end > 0 && text[end - 1] != '}') {
            end--;
        }
        assert_true(end > 0);
        stride = end > 8192 ? 7 : 1;
        for (n = 0; n < end; n += (n + 256 >= end ? 1 : stride)) {
            (void)parse(text, n, 1);
        }
        assert_int_equal(parse(text, len, 0), RBS_OK);
        free(text);
    }
}

/* Random bytes, and random bytes in JSON's alphabet (more likely to get
 * deep into the parser). */
static void test_random_bytes(void **state)
{
    static const char alphabet[] = "{}[]\":,0123456789.eE+-truefalsnl \n\\u\"abcxyz";
    uint64_t seed = 0x5eed5eed12345678ULL;
    char buf[2048];
    int round;
    (void)state;
    for (round = 0; round < 4000; round++) {
        size_t len = (size_t)(rng_next(&seed) % sizeof buf), k;
        int json_like = round % 2;
        for (k = 0; k < len; k++) {
            uint64_t r = rng_next(&seed);
            buf[k] = json_like ? alphabet[r % (sizeof alphabet - 1)] : (char)(r & 0xff);
        }
        (void)parse(buf, len, 0);
    }
}

/* A valid scene with a few bytes changed: accepted or rejected, never a
 * crash; mutated numbers and names exercise the validator. */
static void test_mutations(void **state)
{
    static const char bytes[] = "0-9e.\"{}[],:#xa \\";
    uint64_t seed = 42;
    size_t i;
    (void)state;
    for (i = 0; i < DEMO_COUNT; i++) {
        size_t len = 0;
        char *text = load_demo(i, &len);
        char *work = malloc(len);
        int round;
        assert_non_null(work);
        for (round = 0; round < (len > 8192 ? 60 : 400); round++) {
            int flips = 1 + (int)(rng_next(&seed) % 4), f;
            memcpy(work, text, len);
            for (f = 0; f < flips; f++) {
                size_t at = (size_t)(rng_next(&seed) % len);
                work[at] = bytes[rng_next(&seed) % (sizeof bytes - 1)];
            }
            (void)parse(work, len, 0);
        }
        free(work);
        free(text);
    }
}

/* Deep nesting, long strings and numbers, many keys: bounded and clear. */
static void test_extremes(void **state)
{
    size_t n = 1000000, k;
    char *big = malloc(n);
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_non_null(big);
    /* a million '[' */
    memset(big, '[', n);
    assert_int_equal(rbs_scene_parse_json(big, n, "deep", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.message, "nesting deeper than 64 levels");
    assert_int_equal(e.column, 65);
    rbs_scene_free(scene);
    /* a 1 MB string never closed */
    big[0] = '"';
    memset(big + 1, 'a', n - 1);
    assert_int_equal(rbs_scene_parse_json(big, n, "str", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "str:1:1: unterminated string (truncated JSON?)");
    rbs_scene_free(scene);
    /* a number of 64 digits */
    for (k = 0; k < 64; k++) {
        big[k] = '1';
    }
    assert_int_equal(rbs_scene_parse_json(big, 64, "num", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "num:1:1: number literal longer than 63 characters");
    rbs_scene_free(scene);
    /* NUL bytes inside a string */
    memcpy(big, "{\"description\": \"a\0b\"}", 22);
    assert_int_equal(rbs_scene_parse_json(big, 22, "nul", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "nul:1:19: description: control character inside a string "
                                "(write it as an escape)");
    rbs_scene_free(scene);
    /* NULL text */
    assert_int_equal(rbs_scene_parse_json(NULL, 0, NULL, &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "<json>:1:1: empty input: expected a JSON object");
    rbs_scene_free(scene);
    assert_int_equal(rbs_scene_parse_json(NULL, 5, "x", &scene), RBS_E_INVALID);
    assert_null(scene);
    free(big);
}

/* Random lines through the text loader. */
static void test_random_text(void **state)
{
    static const char *const words[] = {
        "steps", "=", "dt", "1e999", "-1", "0", "#", "\"", "renderer", "csv", "path=x",
        "every=", "a.b[0]=1", "[1]", "sphere", "plane", "radius", "x", ",", "\n", "\n",
        "materials", "objects", "mutual_gravity", "G=1", "#ff0000", "\\", "nan"};
    char dir[] = "/tmp/rbs_scene_fuzz_XXXXXX";
    char cfg[128], obj[128], mat[128];
    uint64_t seed = 7;
    int round;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(cfg, sizeof cfg, "%s/config.txt", dir);
    snprintf(mat, sizeof mat, "%s/materials.txt", dir);
    snprintf(obj, sizeof obj, "%s/objects.txt", dir);
    for (round = 0; round < 300; round++) {
        const char *files[3];
        int f;
        rbs_scene *scene = NULL;
        rbs_status st;
        files[0] = cfg;
        files[1] = mat;
        files[2] = obj;
        for (f = 0; f < 3; f++) {
            FILE *out = fopen(files[f], "w");
            int w, n = (int)(rng_next(&seed) % 60);
            assert_non_null(out);
            if (f == 0) {
                fputs("materials = materials.txt\nobjects = objects.txt\n", out);
            }
            for (w = 0; w < n; w++) {
                fputs(words[rng_next(&seed) % (sizeof words / sizeof *words)], out);
                fputc(rng_next(&seed) % 3 ? ' ' : '\n', out);
            }
            fclose(out);
        }
        st = rbs_scene_load(cfg, RBS_SCENE_TEXT, &scene);
        assert_true(st == RBS_OK || st == RBS_E_SCENE);
        if (st == RBS_E_SCENE) {
            assert_true(rbs_scene_error_count(scene) >= 1);
        }
        rbs_scene_free(scene);
    }
    (void)remove(cfg);
    (void)remove(mat);
    (void)remove(obj);
    assert_int_equal(rmdir(dir), 0);
}

static int report(void **state)
{
    (void)state;
    fprintf(stderr, "fuzz: %ld inputs parsed, %ld rejected\n", parsed, rejected);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_prefixes),   cmocka_unit_test(test_random_bytes),
        cmocka_unit_test(test_mutations),  cmocka_unit_test(test_extremes),
        cmocka_unit_test(test_random_text),
    };
    if (enter_test_dir() != 0) {
        return 1;
    }
    return cmocka_run_group_tests_name("scene_fuzz", tests, NULL, report);
}
