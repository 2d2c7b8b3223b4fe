/*
 * scene_test.h - helpers shared by the scene tests (header-only, static).
 *
 * The tests run from tests/scene in the source tree (found through the
 * RBS_SOURCE_ROOT environment variable that meson sets), so the paths in
 * error messages are short and stable: "bad/zero_mass.json:5:64: ...".
 */
#ifndef RBS_SCENE_TEST_H
#define RBS_SCENE_TEST_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "rbsim/scene.h"

/* The demonstration scenes (scenes/NAME.json and scenes/NAME/). */
static const char *const demo_names[] = {"bouncing_sphere", "rolling_sphere",
                                         "sliding_sphere",  "collisions",
                                         "newtons_cradle",  "incline",
                                         "pile",            "orbit"};
#define DEMO_COUNT (sizeof demo_names / sizeof *demo_names)

/* Change to <source root>/tests/scene; returns 0 on success. */
static inline int enter_test_dir(void)
{
    const char *root = getenv("RBS_SOURCE_ROOT");
    char path[4096];
    if (root == NULL) {
        fprintf(stderr, "RBS_SOURCE_ROOT is not set (meson test sets it)\n");
        return -1;
    }
    snprintf(path, sizeof path, "%s/tests/scene", root);
    if (chdir(path) != 0) {
        perror(path);
        return -1;
    }
    return 0;
}

/* Read a whole file; NULL if unreadable.  *len gets its size. */
static inline char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    size_t n = 0, cap = 0;
    if (f == NULL) {
        return NULL;
    }
    for (;;) {
        size_t got;
        if (cap - n < 4096) {
            char *b = realloc(buf, cap + 65536 + 1);
            if (b == NULL) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = b;
            cap += 65536;
        }
        got = fread(buf + n, 1, cap - n, f);
        if (got == 0) {
            break;
        }
        n += got;
    }
    fclose(f);
    buf[n] = '\0';
    *len = n;
    return buf;
}

/* Line and column (1-based, bytes) of byte offset off in text. */
static inline void line_col(const char *text, size_t off, int *line, int *col)
{
    size_t i, start = 0;
    *line = 1;
    for (i = 0; i < off; i++) {
        if (text[i] == '\n') {
            (*line)++;
            start = i + 1;
        }
    }
    *col = (int)(off - start) + 1;
}

/* Print all errors of a scene (for failing tests' logs). */
static inline void print_errors(const rbs_scene *scene)
{
    uint32_t i, n = rbs_scene_error_count(scene);
    for (i = 0; i < n; i++) {
        rbs_scene_error e;
        if (rbs_scene_error_get(scene, i, &e) == RBS_OK) {
            fprintf(stderr, "  %s\n", e.text);
        }
    }
}

#endif /* RBS_SCENE_TEST_H */
