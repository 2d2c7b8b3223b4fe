/*
 * frame.c - capture a world into a frame: the glue between the core and
 * the reel, through the public world API only.  Allocates nothing.
 */
#include "rbsim/reel.h"

#include <string.h>

rbs_status rbs_frame_capture(const rbs_world *world, rbs_frame *frame,
                             uint32_t bodies_capacity)
{
    rbs_state_view view;
    rbs_energy energy;
    rbs_vec3 p, l;
    rbs_status st;
    uint32_t slot, n = 0;

    if (world == NULL || frame == NULL ||
        (bodies_capacity > 0 && frame->bodies == NULL))
        return RBS_E_INVALID;
    st = rbs_world_state(world, &view);
    if (st != RBS_OK)
        return st;

    /* Bodies: every occupied slot, in slot order. */
    for (slot = 0; slot < view.slots; slot++) {
        rbs_body_id id;
        rbs_body_state bs;
        rbs_frame_body *fb;
        if (view.type[slot] == RBS_BODY_NONE)
            continue;
        if (n == bodies_capacity)
            return RBS_E_CAPACITY;
        st = rbs_world_body_at(world, slot, &id);
        if (st != RBS_OK)
            return st;
        st = rbs_body_get_state(world, id, &bs);
        if (st != RBS_OK)
            return st;
        fb = &frame->bodies[n++];
        fb->type = (int32_t)bs.type;
        fb->color = bs.color;
        fb->texture = (int32_t)bs.texture;
        fb->slot = slot;
        fb->name = bs.name ? bs.name : "";
        fb->position[0] = bs.position.x;
        fb->position[1] = bs.position.y;
        fb->position[2] = bs.position.z;
        fb->orientation[0] = bs.orientation.w;
        fb->orientation[1] = bs.orientation.x;
        fb->orientation[2] = bs.orientation.y;
        fb->orientation[3] = bs.orientation.z;
        fb->velocity[0] = bs.velocity.x;
        fb->velocity[1] = bs.velocity.y;
        fb->velocity[2] = bs.velocity.z;
        fb->angular_velocity[0] = bs.angular_velocity.x;
        fb->angular_velocity[1] = bs.angular_velocity.y;
        fb->angular_velocity[2] = bs.angular_velocity.z;
        fb->normal[0] = bs.normal.x;
        fb->normal[1] = bs.normal.y;
        fb->normal[2] = bs.normal.z;
        fb->radius = bs.radius;
    }
    frame->body_count = n;

    /* Time and statistics; the caller fills stats.step. */
    frame->number = rbs_world_step_count(world);
    frame->time = rbs_world_time(world);
    st = rbs_world_energy(world, &energy);
    if (st != RBS_OK)
        return st;
    st = rbs_world_momentum(world, &p, &l);
    if (st != RBS_OK)
        return st;
    memset(&frame->stats, 0, sizeof frame->stats);
    frame->stats.kinetic = energy.kinetic;
    frame->stats.potential = energy.potential;
    frame->stats.total = energy.total;
    frame->stats.momentum[0] = p.x;
    frame->stats.momentum[1] = p.y;
    frame->stats.momentum[2] = p.z;
    frame->stats.angular_momentum[0] = l.x;
    frame->stats.angular_momentum[1] = l.y;
    frame->stats.angular_momentum[2] = l.z;
    return RBS_OK;
}

int32_t rbs_frame_written(uint64_t frame, uint32_t every, uint64_t start, int32_t skip_first,
                          int32_t is_last, int32_t continued)
{
    /* (a resumed run's starting frame was an earlier run's last: not drawn) */
    if (frame < start || (skip_first && frame == start))
        return 0;
    return frame == start || frame % (every != 0 ? every : 1u) == 0 ||
           (is_last && !continued);
}
