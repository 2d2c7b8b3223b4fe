/*
 * dump.h - the recording renderers of rbsim: CSV for spreadsheets, JSON Lines
 * and a CSV of per-frame statistics.  A static library for the front ends;
 * register the types with rbs_renderer_register(registry, rbsf_csv_class()).
 *
 * Every output is written a whole frame at a time (formatted into a buffer
 * reserved at create, then written in full), so a file never ends in half a
 * line: on a write error the frame's partial bytes are cut off again and the
 * run stops with a message naming the file.  Numbers are printed in the
 * shortest form that reads back as the same double, in the "C" locale
 * whatever the process's (a program may call setlocale(LC_ALL, "")): the
 * renderer switches its own thread with uselocale while it formats a frame.
 *
 * Renderer entries in a scene: {"type": "csv"|"json"|"stats", "path": FILE,
 * "every": K}; "path" "-" is standard output.  No other keys.
 */
#ifndef RBSF_DUMP_H
#define RBSF_DUMP_H

#include "rbsim/reel.h"

#ifdef __cplusplus
extern "C" {
#endif

/** "csv": one row per body per frame,
 * frame,t,body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz.  Static table. */
const rbs_renderer_class *rbsf_csv_class(void);
/** "json": JSON Lines, one object per frame:
 * {"frame","t","bodies":[{"body","name","position","orientation",
 * "velocity","angular_velocity"}]}.  Static table. */
const rbs_renderer_class *rbsf_json_class(void);
/** "stats": one CSV row per frame: frame,t,kinetic,potential,total,px,py,pz,
 * lx,ly,lz,max_overlap,contacts,collisions,substeps,rollbacks.  Static
 * table. */
const rbs_renderer_class *rbsf_stats_class(void);

/** Write x in the shortest "%.Ng" (N = 1..17) that strtod reads back as the
 * same double ("nan", "inf", "-inf" for those), in the "C" locale ('.' as
 * the decimal point) whatever the thread's.  Returns the length written
 * (buf must hold at least 32 bytes).  Thread-safe. */
size_t rbsf_format_double(char *buf, size_t size, double x);

/** Check that an output file could be created at path without creating it:
 * its folder exists and is writable (or is one missing folder inside a
 * writable one, created when the file is opened), and the path is not a
 * folder.  "-" (the
 * standard output) is fine.  Returns RBS_OK or RBS_E_IO with a message. */
rbs_status rbsf_check_output_file(const char *path, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* RBSF_DUMP_H */
