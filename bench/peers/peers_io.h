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
 * final line "RESULT {json}", which carries "rss_anon_kb" (peers_rss_anon_kb,
 * read after the run, before the engine's world is destroyed).
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
    double *spheres;   /* n x 8 (peers_scene_read; NULL after peers_scene_open) */
    FILE *file;        /* peers_scene_open: positioned at the next sphere */
    const char *path;
    size_t next;       /* spheres peers_scene_sphere has read */
} peers_scene;

/* Command-line options every driver takes. */
typedef struct peers_options {
    const char *scene_path;   /* --scene FILE (required) */
    const char *state_path;   /* --state-out FILE (optional) */
    long steps;               /* --steps K (default: the scene's) */
    double max_wall;          /* --max-wall S: stop stepping after S s (0: none) */
    const char *extra;        /* --method NAME etc. (driver-specific) */
    double slop;              /* --slop X: rbsim's slop (0: the library's default) */
    double soft_tolerance;    /* --soft-tolerance X: rbsim's (< 0: the library's default) */
    long substeps;            /* --substeps K: rbsim's soft_substeps (0: the library's default) */
    long threads;             /* --threads K: rbsim's threads, its own included (0: 1) */
} peers_options;

/* Parse argv; on error prints the reason to stderr and returns nonzero. */
int peers_parse_args(int argc, char **argv, peers_options *opt, const char *usage);

/* Read a scene, spheres and all; on error prints "scene FILE: reason" and
 * returns nonzero. */
int peers_scene_read(const char *path, peers_scene *s);
/* Read a scene's header and planes and leave its spheres in the file, for
 * peers_scene_sphere to read one at a time: the drivers make their bodies
 * so, and the benchmark's peak memory then holds no copy of the scene (a
 * freed 64 KB buffer stays resident in the C library's heap). */
int peers_scene_open(const char *path, peers_scene *s);
/* The next sphere of an opened scene into q[8]; nonzero (with the reason
 * on stderr) when the file ends early. */
int peers_scene_sphere(peers_scene *s, double q[8]);
/* Free the arrays and close the file; keeps the counts. */
void peers_scene_free(peers_scene *s);

/* The final state, written sphere by sphere (no copy of the whole state):
 * peers_state_open, then peers_state_put for each of the n spheres, then
 * peers_state_close; each returns nonzero (NULL) on failure, with the reason
 * on stderr. */
FILE *peers_state_open(const char *path, size_t n);
int peers_state_put(FILE *f, const double pos[3], const double vel[3], const double avel[3]);
int peers_state_close(FILE *f, const char *path);

/* Monotonic clock, s. */
double peers_now(void);

/* This process's anonymous resident memory now, kB (RssAnon of
 * /proc/self/status: the heap and private mappings, without the shared
 * code and data pages of the program and its libraries), or -1 where the
 * system does not report it. */
long peers_rss_anon_kb(void);

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
