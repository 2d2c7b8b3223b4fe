/*
 * reel_internal.h - the reel's calls used only by the projector (not
 * installed, not exported).
 */
#ifndef RBS_REEL_INTERNAL_H
#define RBS_REEL_INTERNAL_H

#include "rbsim/reel.h"

#include "core/c_locale.h" /* rbs__shortest, rbs__strtod_c */
#include "core/ieee.h"

#include <time.h>

/** Like rbs_reel_begin_read, but gives up at `deadline` (CLOCK_MONOTONIC,
 * NULL: never) or when rbs__reel_kick() is called: then RBS_E_NOT_FOUND. */
rbs_status rbs__reel_read_until(rbs_reel *reel, const struct timespec *deadline,
                                const rbs_frame **frame);

/** Wake a reader waiting in rbs__reel_read_until (it returns
 * RBS_E_NOT_FOUND once).  Thread-safe. */
void rbs__reel_kick(rbs_reel *reel);

/** Reader: frames published and not yet read (for tests and status). */
uint32_t rbs__reel_pending(rbs_reel *reel);

/** now + seconds on CLOCK_MONOTONIC. */
struct timespec rbs__deadline_after(double seconds);
/** Seconds on CLOCK_MONOTONIC. */
double rbs__now(void);

#endif
