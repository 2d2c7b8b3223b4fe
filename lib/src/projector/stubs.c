/* Temporary stubs so the library links while the projector is written. */
#include "rbsim/reel.h"

#include <string.h>

rbs_status rbs_frame_capture(const rbs_world *world, rbs_frame *frame,
                             uint32_t bodies_capacity)
{
    (void)world; (void)frame; (void)bodies_capacity;
    return RBS_E_UNSUPPORTED;
}
rbs_status rbs_reel_create(uint32_t capacity, uint32_t max_bodies,
                           rbs_reel_policy policy, rbs_reel **out)
{
    (void)capacity; (void)max_bodies; (void)policy;
    if (out) *out = NULL;
    return RBS_E_UNSUPPORTED;
}
void rbs_reel_destroy(rbs_reel *reel) { (void)reel; }
rbs_status rbs_reel_begin_write(rbs_reel *reel, rbs_frame **slot)
{ (void)reel; (void)slot; return RBS_E_UNSUPPORTED; }
rbs_status rbs_reel_end_write(rbs_reel *reel)
{ (void)reel; return RBS_E_UNSUPPORTED; }
rbs_status rbs_reel_begin_read(rbs_reel *reel, const rbs_frame **frame)
{ (void)reel; (void)frame; return RBS_E_UNSUPPORTED; }
rbs_status rbs_reel_end_read(rbs_reel *reel)
{ (void)reel; return RBS_E_UNSUPPORTED; }
void rbs_reel_close(rbs_reel *reel) { (void)reel; }
uint64_t rbs_reel_dropped(rbs_reel *reel) { (void)reel; return 0; }
rbs_status rbs_renderer_registry_create(rbs_renderer_registry **out)
{ if (out) *out = NULL; return RBS_E_UNSUPPORTED; }
void rbs_renderer_registry_destroy(rbs_renderer_registry *registry)
{ (void)registry; }
rbs_status rbs_renderer_register(rbs_renderer_registry *registry,
                                 const rbs_renderer_class *cls)
{ (void)registry; (void)cls; return RBS_E_UNSUPPORTED; }
rbs_status rbs_renderer_find(const rbs_renderer_registry *registry,
                             const char *name, const rbs_renderer_class **out)
{ (void)registry; (void)name; (void)out; return RBS_E_UNSUPPORTED; }
void rbs_projector_def_init_sized(rbs_projector_def *def, size_t def_size)
{ if (def) memset(def, 0, def_size); }
rbs_status rbs_projector_create(rbs_world *world,
                                const rbs_renderer_registry *registry,
                                const rbs_renderer_config *configs,
                                uint32_t count, const rbs_projector_def *def,
                                rbs_projector **out)
{
    (void)world; (void)registry; (void)configs; (void)count; (void)def;
    if (out) *out = NULL;
    return RBS_E_UNSUPPORTED;
}
rbs_status rbs_projector_start(rbs_projector *projector)
{ (void)projector; return RBS_E_UNSUPPORTED; }
rbs_status rbs_projector_command(rbs_projector *projector, const char *line,
                                 char *reply, size_t reply_size)
{ (void)projector; (void)line; (void)reply; (void)reply_size; return RBS_E_UNSUPPORTED; }
int32_t rbs_projector_finished(rbs_projector *projector, double timeout)
{ (void)projector; (void)timeout; return 1; }
rbs_status rbs_projector_wait(rbs_projector *projector)
{ (void)projector; return RBS_E_UNSUPPORTED; }
rbs_status rbs_projector_run(rbs_projector *projector)
{ (void)projector; return RBS_E_UNSUPPORTED; }
rbs_status rbs_projector_status_sized(rbs_projector *projector,
                                      rbs_run_info *out, size_t out_size)
{ (void)projector; (void)out; (void)out_size; return RBS_E_UNSUPPORTED; }
const char *rbs_projector_last_error(const rbs_projector *projector)
{ (void)projector; return "not implemented yet"; }
void rbs_projector_destroy(rbs_projector *projector) { (void)projector; }
