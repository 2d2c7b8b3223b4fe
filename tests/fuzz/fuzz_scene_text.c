/*
 * fuzz_scene_text.c - libFuzzer harness for the text scene format.
 *
 * The input is split into config.txt, materials.txt and objects.txt at the
 * first two lines that read exactly "%%" (missing parts are empty files);
 * the three are written to a fresh temporary directory and loaded with
 * rbs_scene_load(..., RBS_SCENE_TEXT).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_scene_common.h"

static const char *const part_names[3] = {"config.txt", "materials.txt", "objects.txt"};

static int write_file(const char *dir, const char *name, const uint8_t *p, size_t n)
{
    char path[512];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "wb");
    if (f == NULL)
        return -1;
    if (n > 0 && fwrite(p, 1, n, f) != n) {
        fclose(f);
        return -1;
    }
    return fclose(f);
}

/* Next "%%" line at or after from; returns its offset or size. */
static size_t find_sep(const uint8_t *d, size_t size, size_t from)
{
    size_t i;
    for (i = from; i + 2 <= size; ++i)
        if ((i == 0 || d[i - 1] == '\n') && d[i] == '%' && d[i + 1] == '%' &&
            (i + 2 == size || d[i + 2] == '\n'))
            return i;
    return size;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char dir[] = "/tmp/rbsim-fuzz-XXXXXX", path[512];
    size_t start = 0;
    rbs_scene *scene = NULL;
    rbs_status st;
    int k;
    if (mkdtemp(dir) == NULL)
        return 0;
    for (k = 0; k < 3; ++k) {
        size_t end = k < 2 ? find_sep(data, size, start) : size;
        if (start > size)
            start = size;
        if (end < start)
            end = start;
        if (write_file(dir, part_names[k], data + start, end - start) != 0)
            goto out;
        start = end + 3; /* skip "%%\n" */
    }
    snprintf(path, sizeof path, "%s/config.txt", dir);
    st = rbs_scene_load(path, RBS_SCENE_TEXT, &scene);
    fuzz_use_scene(scene, st);
out:
    for (k = 0; k < 3; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, part_names[k]);
        unlink(path);
    }
    rmdir(dir);
    return 0;
}
