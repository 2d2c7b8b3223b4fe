// header_cxx.cpp - the public headers are valid C++ (extern "C", no C-only
// constructs); built with the project's warnings as errors.
#include "rbsim/rbsim.h"
#include "rbsim/scene.h"
#include "rbsim/reel.h"

int main()
{
    rbs_world_def def;
    rbs_world *world = nullptr;
    rbs_world_def_init(&def);
    if (rbs_world_create(&def, &world) != RBS_OK)
        return 1;
    rbs_world_destroy(world);
    return rbs_version_number() == RBS_VERSION_NUMBER ? 0 : 1;
}
