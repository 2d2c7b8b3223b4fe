/*
 * peers_io.h - what the C benchmark drivers share: reading a scene file,
 * writing the final state, a monotonic clock and the result line.
 *
 * Scene file (written by scenes.py; little-endian doubles after the magic):
 *   "RBSPEER1"                         8 bytes
 *   header[8]  n_spheres, n_planes, dt (s), steps, gravity z (m/s^2),
 *              restitution, friction, track_apex (1: record sphere 0's apexes)
 *   planes     n_planes x {point x y z, outward normal x y z}
 *   spheres    n_spheres x {radius, mass, position x y z, velocity x y z}
 * State file (read by peers_quality):
 *   "RBSSTAT1", then n as one double, then n x {position, velocity,
 *   angular velocity} (9 doubles per sphere).
 *
 * Driver protocol (all four engines): stdout carries "# progress STEPS WALL"
 * lines while stepping (so a killed run still tells how far it got) and one
 * final line "RESULT {json}".
 */
#ifndef PEERS_IO_H
#define PEERS_IO_H

#include <stddef.h>
#include <stdio.h>

typedef struct peers_scene {
    size_t n;          /* spheres */
    size_t n_planes;
    double dt, gravity_z, restitution, friction;
    long steps;
    int track_apex;
    double *planes;    /* n_planes x 6 */
    double *spheres;   /* n x 8 */
} peers_scene;

/* Command-line options every driver takes. */
typedef struct peers_options {
    const char *scene_path;   /* --scene FILE (required) */
    const char *state_path;   /* --state-out FILE (optional) */
    long steps;               /* --steps K (default: the scene's) */
    double max_wall;          /* --max-wall S: stop stepping after S s (0: none) */
    const char *extra;        /* --method NAME etc. (driver-specific) */
    double slop;              /* --slop X: rbsim's slop (0: the library's default) */
} peers_options;

/* Parse argv; on error prints the reason to stderr and returns nonzero. */
int peers_parse_args(int argc, char **argv, peers_options *opt, const char *usage);

/* Read a scene; on error prints "scene FILE: reason" and returns nonzero. */
int peers_scene_read(const char *path, peers_scene *s);
void peers_scene_free(peers_scene *s);

/* Write n x 9 doubles (pos, vel, avel); returns nonzero on failure. */
int peers_state_write(const char *path, size_t n, const double *state9);

/* Monotonic clock, s. */
double peers_now(void);

/* Apex tracker for sphere 0 (the bouncing-ball scene): feed z and vz after
 * every step; an apex is recorded where vz turns from > 0 to <= 0, as the
 * ballistic peak z + vz^2 / (2 |g|) from the step before. */
typedef struct peers_apex {
    double prev_z, prev_vz, g;
    int count;
    double z[32];
} peers_apex;
void peers_apex_init(peers_apex *a, double gravity_z);
void peers_apex_feed(peers_apex *a, double z, double vz);

/* Print "# progress steps wall" at most once per second of wall time. */
void peers_progress(long steps, double wall, double *last_print);

/* Print the apex list as a JSON array. */
void peers_print_apex(FILE *f, const peers_apex *a);

#endif
