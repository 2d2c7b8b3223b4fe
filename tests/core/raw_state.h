/* raw_state.h - write a body's state past the setters' limits (tests only).
 *
 * Since session 50 the setters hold a sphere's value to the limits
 * rbs_world_add_sphere applies (energies and momenta at most 1e300 in SI
 * units), but a step can still carry a world past them (a huge force over a
 * frame), and the tests of how a step fails -- RBS_E_NUMERIC, the world left
 * bit for bit at its last good state -- need such states at once.  This
 * writes the value into the world's arrays as the setters wrote it before
 * (the same array, the plan marked stale).  Finite values only.  Needs
 * lib/src on the include path (core/world_internal.h, for the layout; the
 * library's internal functions are not called, so linking the shared
 * library is enough). */
#ifndef RBS_TEST_RAW_STATE_H
#define RBS_TEST_RAW_STATE_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "core/world_internal.h"

typedef enum raw_what { RAW_POSITION, RAW_VELOCITY, RAW_ANGULAR_VELOCITY, RAW_FORCE } raw_what;

static inline void raw_set(rbs_world *w, rbs_body_id id, raw_what what, rbs_vec3 v)
{
    double *arr = what == RAW_POSITION ? w->pos : what == RAW_VELOCITY ? w->vel
                  : what == RAW_ANGULAR_VELOCITY ? w->avel : w->force;
    rbs_body_state s;
    assert_int_equal(rbs_body_get_state(w, id, &s), RBS_OK); /* (a live body) */
    assert_true(isfinite(v.x) && isfinite(v.y) && isfinite(v.z));
    arr[3 * id.index] = v.x;
    arr[3 * id.index + 1] = v.y;
    arr[3 * id.index + 2] = v.z;
    w->plan_dirty = 1;
}

#endif
