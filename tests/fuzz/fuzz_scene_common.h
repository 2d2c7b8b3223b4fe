/*
 * fuzz_scene_common.h - what both scene harnesses do with a parsed scene:
 * read every error (each must carry text), and when the scene is valid,
 * build the world and take a few steps; every status must be a known code
 * and the world must never hold a non-finite state after a good step.
 */
#ifndef RBS_FUZZ_SCENE_COMMON_H
#define RBS_FUZZ_SCENE_COMMON_H

#include <math.h>
#include <string.h>

#include "fuzz_common.h"
#include "rbsim/scene.h"

static void fuzz_use_scene(rbs_scene *scene, rbs_status st)
{
    uint32_t i, n;
    rbs_world *w = NULL;
    FUZZ_CHECK(fuzz_status_valid(st), "status %d", (int)st);
    if (scene == NULL) {
        FUZZ_CHECK(st != RBS_OK, "RBS_OK without a scene");
        return;
    }
    n = rbs_scene_error_count(scene);
    FUZZ_CHECK((st == RBS_OK) == (n == 0), "status %s with %u errors", rbs_status_name(st), (unsigned)n);
    for (i = 0; i < n && i < RBS_SCENE_ERRORS_MAX; ++i) {
        rbs_scene_error e;
        FUZZ_CHECK(rbs_scene_error_get(scene, i, &e) == RBS_OK, "error %u", (unsigned)i);
        FUZZ_CHECK(e.text != NULL && e.text[0] != '\0', "error %u has no text", (unsigned)i);
        FUZZ_CHECK(e.message != NULL && e.file != NULL && e.path != NULL, "error %u has NULL fields", (unsigned)i);
    }
    if (st != RBS_OK) {
        rbs_scene_free(scene);
        return;
    }
    (void)rbs_scene_description(scene);
    for (i = 0; i < rbs_scene_renderer_count(scene); ++i) {
        rbs_scene_renderer r;
        FUZZ_CHECK(rbs_scene_renderer_get(scene, i, &r) == RBS_OK, "renderer %u", (unsigned)i);
    }
    st = rbs_scene_build(scene, &w);
    FUZZ_CHECK(fuzz_status_valid(st), "build status %d", (int)st);
    if (st == RBS_OK) {
        int k;
        for (k = 0; k < FUZZ_STEPS; ++k) {
            uint64_t h = rbs_world_hash(w);
            st = rbs_world_step(w, NULL);
            FUZZ_CHECK(fuzz_status_valid(st), "step status %d", (int)st);
            if (st != RBS_OK) {
                FUZZ_CHECK(rbs_world_hash(w) == h, "failed step changed the world");
                FUZZ_CHECK(rbs_world_last_error(w)[0] != '\0', "failed step without a message");
                break;
            }
        }
        {
            rbs_state_view v;
            FUZZ_CHECK(rbs_world_state(w, &v) == RBS_OK, "state view");
            for (i = 0; i < 3 * v.slots; ++i)
                FUZZ_CHECK(isfinite(v.position[i]) && isfinite(v.velocity[i]), "non-finite state");
        }
        rbs_world_destroy(w);
    } else {
        FUZZ_CHECK(w == NULL, "failed build left a world");
    }
    rbs_scene_free(scene);
}

#endif
