/* status.c - status codes, version and method names. */
#include <string.h>

#include "rbsim/rbsim.h"

const char *rbs_status_string(rbs_status status)
{
    switch (status) {
#define RBS_STATUS_TEXT(name, value, text) case RBS_##name: return text;
        RBS_STATUS_LIST(RBS_STATUS_TEXT)
#undef RBS_STATUS_TEXT
    default:
        return "unknown status";
    }
}

const char *rbs_status_name(rbs_status status)
{
    switch (status) {
#define RBS_STATUS_NAME(name, value, text) case RBS_##name: return #name;
        RBS_STATUS_LIST(RBS_STATUS_NAME)
#undef RBS_STATUS_NAME
    default:
        return "UNKNOWN";
    }
}

const char *rbs_version(void) { return RBS_VERSION_STRING; }

uint32_t rbs_version_number(void) { return (uint32_t)RBS_VERSION_NUMBER; }

static const char *const method_names[RBS_METHOD_COUNT] = {
    "euler", "selective", "event", "verlet", "rk4", "adaptive", "soft", "auto",
};

const char *rbs_method_name(rbs_method method)
{
    if ((int)method < 0 || (int)method >= RBS_METHOD_COUNT)
        return NULL;
    return method_names[method];
}

rbs_status rbs_method_from_name(const char *name, rbs_method *out)
{
    int i;
    if (name == NULL || out == NULL)
        return RBS_E_INVALID;
    for (i = 0; i < RBS_METHOD_COUNT; ++i) {
        if (strcmp(name, method_names[i]) == 0) {
            *out = (rbs_method)i;
            return RBS_OK;
        }
    }
    return RBS_E_NOT_FOUND;
}
