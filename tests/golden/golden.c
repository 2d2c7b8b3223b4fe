/*
 * golden.c - golden state hashes of the demonstration scenes, and the scene
 * driver the valgrind test runs.
 *
 *   golden check HASHES SCENES_DIR   compare with the committed table
 *   golden write SCENES_DIR          print a new table on stdout
 *   golden run SCENES_DIR STEPS      load, build and step every scene
 *                                    (at most STEPS steps each), no checks
 *                                    beyond statuses (for valgrind)
 *
 * A scene is every SCENES_DIR/<name>.json; it is stepped N = min(500, the
 * scene's steps) steps (300 for scenes of more than 100 bodies, whose
 * contact-rich steps are slow under sanitizers) and rbs_world_hash() of the
 * result is its golden hash; the table records N, and `check` steps that.  When SCENES_DIR/<name>/config.txt exists, the text form must give
 * the very same hash (the formats promise equal scenes).  `check` fails on a
 * changed hash, a scene without a hash, and a hash without a scene.
 *
 * Regenerate the table only when a change of results is intended, and say
 * why in the commit:
 *   build/tests/golden/golden write scenes > tests/golden/hashes.txt
 */
#include <dirent.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "rbsim/rbsim.h"
#include "rbsim/scene.h"

#define GOLDEN_STEPS 500u
#define GOLDEN_STEPS_LARGE 300u /* scenes of more than 100 bodies */
#define MAX_SCENES 256
#define NAME_LEN 128

typedef struct entry {
    char name[NAME_LEN];
    uint64_t steps;
    uint64_t hash;
    int seen;
} entry;

static int print_scene_errors(const char *path, rbs_scene *scene, rbs_status st)
{
    uint32_t i, n = scene ? rbs_scene_error_count(scene) : 0;
    fprintf(stderr, "golden: %s: %s\n", path, rbs_status_name(st));
    for (i = 0; i < n && i < RBS_SCENE_ERRORS_MAX; ++i) {
        rbs_scene_error e;
        if (rbs_scene_error_get(scene, i, &e) == RBS_OK)
            fprintf(stderr, "  %s\n", e.text);
    }
    return 1;
}

/* Load, build and step a scene (at most max_steps; 0: the golden rule
 * above); hash in *hash, steps taken in *steps. */
static int run_scene(const char *path, rbs_scene_format fmt, uint64_t max_steps, uint64_t *steps,
                     uint64_t *hash)
{
    rbs_scene *scene = NULL;
    rbs_world *w = NULL;
    rbs_status st = rbs_scene_load(path, fmt, &scene);
    uint64_t k, n;
    if (st != RBS_OK) {
        print_scene_errors(path, scene, st);
        rbs_scene_free(scene);
        return 1;
    }
    st = rbs_scene_build(scene, &w);
    if (st != RBS_OK) {
        fprintf(stderr, "golden: %s: build: %s\n", path, rbs_status_name(st));
        rbs_scene_free(scene);
        return 1;
    }
    n = rbs_scene_steps(scene);
    if (max_steps == 0) { /* the golden rule */
        rbs_usage u;
        max_steps = GOLDEN_STEPS;
        if (rbs_world_usage(w, &u) == RBS_OK && u.bodies > 100)
            max_steps = GOLDEN_STEPS_LARGE;
    }
    if (n > max_steps)
        n = max_steps;
    rbs_scene_free(scene);
    for (k = 0; k < n; ++k) {
        st = rbs_world_step(w, NULL);
        if (st != RBS_OK) {
            fprintf(stderr, "golden: %s: step %" PRIu64 ": %s: %s\n", path, k + 1, rbs_status_name(st),
                    rbs_world_last_error(w));
            rbs_world_destroy(w);
            return 1;
        }
    }
    *steps = n;
    *hash = rbs_world_hash(w);
    rbs_world_destroy(w);
    return 0;
}

static int cmp_names(const void *a, const void *b)
{
    return strcmp((const char *)a, (const char *)b);
}

/* The scene names (file names without .json) in dir, sorted. */
static int list_scenes(const char *dir, char (*names)[NAME_LEN], int *count)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    if (d == NULL) {
        fprintf(stderr, "golden: cannot open %s\n", dir);
        return 1;
    }
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len > 5 && len < NAME_LEN && strcmp(e->d_name + len - 5, ".json") == 0 && n < MAX_SCENES) {
            memcpy(names[n], e->d_name, len - 5);
            names[n][len - 5] = '\0';
            n++;
        }
    }
    closedir(d);
    qsort(names, (size_t)n, NAME_LEN, cmp_names);
    *count = n;
    return 0;
}

/* Hash of the JSON form, and of the text form when there is one (must be
 * equal). */
static int scene_hash(const char *dir, const char *name, uint64_t max_steps, uint64_t *steps, uint64_t *hash)
{
    char path[1024];
    struct stat sb;
    uint64_t tsteps, thash;
    snprintf(path, sizeof path, "%.800s/%.127s.json", dir, name);
    if (run_scene(path, RBS_SCENE_JSON, max_steps, steps, hash))
        return 1;
    snprintf(path, sizeof path, "%.800s/%.127s/config.txt", dir, name);
    if (stat(path, &sb) != 0)
        return 0;
    if (run_scene(path, RBS_SCENE_TEXT, max_steps, &tsteps, &thash))
        return 1;
    if (tsteps != *steps || thash != *hash) {
        fprintf(stderr,
                "golden: %s: the text form gives %" PRIu64 " steps, hash 0x%016" PRIx64
                "; the JSON form %" PRIu64 " steps, hash 0x%016" PRIx64 "\n",
                name, tsteps, thash, *steps, *hash);
        return 1;
    }
    return 0;
}

static int cmd_write(const char *dir)
{
    static char names[MAX_SCENES][NAME_LEN];
    int n, i, rc = 0;
    if (list_scenes(dir, names, &n))
        return 1;
    printf("# Golden state hashes: scene, steps taken, rbs_world_hash() after them.\n"
           "# Generated by `build/tests/golden/golden write scenes > tests/golden/hashes.txt`;\n"
           "# regenerate only for an intended change of results, explained in the commit.\n");
    for (i = 0; i < n; ++i) {
        uint64_t steps, hash;
        if (scene_hash(dir, names[i], 0, &steps, &hash)) {
            rc = 1;
            continue;
        }
        printf("%s %" PRIu64 " 0x%016" PRIx64 "\n", names[i], steps, hash);
    }
    return rc;
}

static int cmd_check(const char *table, const char *dir)
{
    static entry e[MAX_SCENES];
    static char names[MAX_SCENES][NAME_LEN];
    char line[512];
    int ne = 0, n, i, j, rc = 0;
    FILE *f = fopen(table, "r");
    if (f == NULL) {
        fprintf(stderr, "golden: cannot open %s\n", table);
        return 1;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        char name[NAME_LEN];
        unsigned long long steps, hash;
        if (line[0] == '#' || line[0] == '\n')
            continue;
        if (sscanf(line, "%127s %llu %llx", name, &steps, &hash) != 3 || ne >= MAX_SCENES) {
            fprintf(stderr, "golden: %s: bad line: %s", table, line);
            fclose(f);
            return 1;
        }
        snprintf(e[ne].name, NAME_LEN, "%s", name);
        e[ne].steps = steps;
        e[ne].hash = hash;
        ne++;
    }
    fclose(f);
    if (list_scenes(dir, names, &n))
        return 1;
    for (i = 0; i < n; ++i) {
        uint64_t steps, hash;
        for (j = 0; j < ne && strcmp(e[j].name, names[i]) != 0; ++j)
            ;
        if (j == ne) {
            fprintf(stderr, "golden: scene %s has no golden hash in %s (regenerate, see golden.c)\n", names[i],
                    table);
            rc = 1;
            continue;
        }
        e[j].seen = 1;
        if (scene_hash(dir, names[i], e[j].steps, &steps, &hash)) {
            rc = 1;
            continue;
        }
        if (steps != e[j].steps || hash != e[j].hash) {
            fprintf(stderr,
                    "golden: %s: after %" PRIu64 " steps the state hash is 0x%016" PRIx64
                    ", the golden table says 0x%016" PRIx64 " after %" PRIu64 " steps\n",
                    names[i], steps, hash, e[j].hash, e[j].steps);
            rc = 1;
        } else {
            printf("golden: %s: %" PRIu64 " steps, 0x%016" PRIx64 " ok\n", names[i], steps, hash);
        }
    }
    for (j = 0; j < ne; ++j)
        if (!e[j].seen) {
            fprintf(stderr, "golden: %s lists %s, which is not in %s\n", table, e[j].name, dir);
            rc = 1;
        }
    return rc;
}

static int cmd_run(const char *dir, uint64_t max_steps)
{
    static char names[MAX_SCENES][NAME_LEN];
    int n, i, rc = 0;
    if (list_scenes(dir, names, &n))
        return 1;
    for (i = 0; i < n; ++i) {
        char path[1024];
        uint64_t steps, hash;
        snprintf(path, sizeof path, "%.800s/%.127s.json", dir, names[i]);
        if (run_scene(path, RBS_SCENE_JSON, max_steps, &steps, &hash)) {
            rc = 1;
            continue;
        }
        printf("golden: %s: %" PRIu64 " steps\n", names[i], steps);
    }
    return rc;
}

int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "check") == 0)
        return cmd_check(argv[2], argv[3]);
    if (argc == 3 && strcmp(argv[1], "write") == 0)
        return cmd_write(argv[2]);
    if (argc == 4 && strcmp(argv[1], "run") == 0)
        return cmd_run(argv[2], strtoull(argv[3], NULL, 10));
    fprintf(stderr, "usage: %s check HASHES SCENES_DIR | write SCENES_DIR | run SCENES_DIR STEPS\n", argv[0]);
    return 2;
}
