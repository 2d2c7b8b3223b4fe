/*
 * registry.c - the renderer registry: a fixed table of renderer classes,
 * looked up by name.  No globals: the caller owns the registry.
 */
#include "rbsim/reel.h"

#include <stdlib.h>
#include <string.h>

struct rbs_renderer_registry {
    uint32_t count;
    rbs_renderer_class classes[RBS_RENDERER_TYPES_MAX];
};

rbs_status rbs_renderer_registry_create(rbs_renderer_registry **out)
{
    if (out == NULL)
        return RBS_E_INVALID;
    *out = calloc(1, sizeof **out);
    return *out ? RBS_OK : RBS_E_MEMORY;
}

void rbs_renderer_registry_destroy(rbs_renderer_registry *registry)
{
    free(registry);
}

rbs_status rbs_renderer_register(rbs_renderer_registry *registry,
                                 const rbs_renderer_class *cls)
{
    rbs_renderer_class copy;
    size_t size;
    uint32_t i;

    if (registry == NULL || cls == NULL || cls->struct_size < offsetof(rbs_renderer_class, flags))
        return RBS_E_INVALID;
    /* A class compiled against an older header is shorter: copy what it
     * has, the rest stays zero (no flags, no check). */
    memset(&copy, 0, sizeof copy);
    size = cls->struct_size < sizeof copy ? cls->struct_size : sizeof copy;
    memcpy(&copy, cls, size);
    copy.struct_size = (uint32_t)sizeof copy;
    if (copy.name == NULL || copy.name[0] == '\0' || copy.create == NULL ||
        copy.draw == NULL)
        return RBS_E_INVALID;
    for (i = 0; i < registry->count; i++)
        if (strcmp(registry->classes[i].name, copy.name) == 0)
            return RBS_E_INVALID;
    if (registry->count == RBS_RENDERER_TYPES_MAX)
        return RBS_E_CAPACITY;
    registry->classes[registry->count++] = copy;
    return RBS_OK;
}

rbs_status rbs_renderer_find(const rbs_renderer_registry *registry,
                             const char *name, const rbs_renderer_class **out)
{
    uint32_t i;
    if (out != NULL)
        *out = NULL;
    if (registry == NULL || name == NULL || out == NULL)
        return RBS_E_INVALID;
    for (i = 0; i < registry->count; i++)
        if (strcmp(registry->classes[i].name, name) == 0) {
            *out = &registry->classes[i];
            return RBS_OK;
        }
    return RBS_E_NOT_FOUND;
}
