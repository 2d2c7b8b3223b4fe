/*
 * scene_stub.c - temporary stubs of the scene API so the library links while
 * the real implementation is written.  Every function reports
 * RBS_E_UNSUPPORTED.
 */
#include "rbsim/scene.h"

#include <stddef.h>

rbs_status rbs_scene_load(const char *path, rbs_scene_format format, rbs_scene **out)
{
    (void)path;
    (void)format;
    if (out != NULL) {
        *out = NULL;
    }
    return RBS_E_UNSUPPORTED;
}

rbs_status rbs_scene_parse_json(const char *text, size_t len, const char *name,
                                rbs_scene **out)
{
    (void)text;
    (void)len;
    (void)name;
    if (out != NULL) {
        *out = NULL;
    }
    return RBS_E_UNSUPPORTED;
}

void rbs_scene_free(rbs_scene *scene) { (void)scene; }

uint32_t rbs_scene_error_count(const rbs_scene *scene)
{
    (void)scene;
    return 0;
}

rbs_status rbs_scene_error_get(const rbs_scene *scene, uint32_t i, rbs_scene_error *out)
{
    (void)scene;
    (void)i;
    (void)out;
    return RBS_E_UNSUPPORTED;
}

rbs_status rbs_scene_world_def(const rbs_scene *scene, rbs_world_def *out)
{
    (void)scene;
    (void)out;
    return RBS_E_UNSUPPORTED;
}

rbs_status rbs_scene_populate(const rbs_scene *scene, rbs_world *world)
{
    (void)scene;
    (void)world;
    return RBS_E_UNSUPPORTED;
}

rbs_status rbs_scene_build(const rbs_scene *scene, rbs_world **out)
{
    (void)scene;
    if (out != NULL) {
        *out = NULL;
    }
    return RBS_E_UNSUPPORTED;
}

uint64_t rbs_scene_steps(const rbs_scene *scene)
{
    (void)scene;
    return 0;
}

int32_t rbs_scene_pause_on_collision(const rbs_scene *scene)
{
    (void)scene;
    return 0;
}

rbs_status rbs_scene_override(rbs_scene *scene, uint64_t steps, double dt,
                              const char *method)
{
    (void)scene;
    (void)steps;
    (void)dt;
    (void)method;
    return RBS_E_UNSUPPORTED;
}

uint32_t rbs_scene_renderer_count(const rbs_scene *scene)
{
    (void)scene;
    return 0;
}

rbs_status rbs_scene_renderer_get(const rbs_scene *scene, uint32_t i,
                                  rbs_scene_renderer *out)
{
    (void)scene;
    (void)i;
    (void)out;
    return RBS_E_UNSUPPORTED;
}

rbs_status rbs_scene_save(const rbs_scene *scene, const char *path,
                          rbs_scene_format format)
{
    (void)scene;
    (void)path;
    (void)format;
    return RBS_E_UNSUPPORTED;
}
