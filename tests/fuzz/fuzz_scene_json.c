/*
 * fuzz_scene_json.c - libFuzzer harness for the JSON scene parser
 * (rbs_scene_parse_json), then building and stepping what it accepts.
 */
#include "fuzz_scene_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rbs_scene *scene = NULL;
    rbs_status st = rbs_scene_parse_json((const char *)data, size, "fuzz.json", &scene);
    fuzz_use_scene(scene, st);
    return 0;
}
