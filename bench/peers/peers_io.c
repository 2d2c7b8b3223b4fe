/*
 * peers_io.c - scene and state files, clock, progress and apex tracking for
 * the C benchmark drivers (see peers_io.h for the formats).
 */
#include "peers_io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int peers_parse_args(int argc, char **argv, peers_options *opt, const char *usage)
{
    int i;
    memset(opt, 0, sizeof *opt);
    opt->steps = -1;
    opt->soft_tolerance = -1.0;
    for (i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            printf("%s", usage);
            exit(0);
        }
        if (v == NULL) {
            fprintf(stderr, "%s: option %s needs a value\n%s", argv[0], a, usage);
            return 1;
        }
        if (strcmp(a, "--scene") == 0) {
            opt->scene_path = v;
        } else if (strcmp(a, "--state-out") == 0) {
            opt->state_path = v;
        } else if (strcmp(a, "--steps") == 0) {
            opt->steps = strtol(v, &end, 10);
            if (*v == '\0' || *end != '\0' || opt->steps < 0) {
                fprintf(stderr, "%s: --steps wants a count >= 0, got \"%s\"\n", argv[0], v);
                return 1;
            }
        } else if (strcmp(a, "--max-wall") == 0) {
            opt->max_wall = strtod(v, &end);
            if (*v == '\0' || *end != '\0' || !(opt->max_wall >= 0.0)) {
                fprintf(stderr, "%s: --max-wall wants seconds >= 0, got \"%s\"\n", argv[0], v);
                return 1;
            }
        } else if (strcmp(a, "--method") == 0) {
            opt->extra = v;
        } else if (strcmp(a, "--slop") == 0) {
            /* (its range is the library's to check) */
            opt->slop = strtod(v, &end);
            if (*v == '\0' || *end != '\0' || !(opt->slop > 0.0)) {
                fprintf(stderr, "%s: --slop wants a fraction of a radius > 0, got \"%s\"\n", argv[0], v);
                return 1;
            }
        } else if (strcmp(a, "--soft-tolerance") == 0) {
            /* (its range is the library's to check) */
            opt->soft_tolerance = strtod(v, &end);
            if (*v == '\0' || *end != '\0' || !(opt->soft_tolerance >= 0.0)) {
                fprintf(stderr, "%s: --soft-tolerance wants a fraction of a radius >= 0, got \"%s\"\n", argv[0], v);
                return 1;
            }
        } else if (strcmp(a, "--threads") == 0) {
            /* (its range is the library's to check) */
            opt->threads = strtol(v, &end, 10);
            if (*v == '\0' || *end != '\0' || opt->threads < 1) {
                fprintf(stderr, "%s: --threads wants a count >= 1, got \"%s\"\n", argv[0], v);
                return 1;
            }
        } else if (strcmp(a, "--substeps") == 0) {
            /* (its range is the library's to check) */
            opt->substeps = strtol(v, &end, 10);
            if (*v == '\0' || *end != '\0' || opt->substeps < 1) {
                fprintf(stderr, "%s: --substeps wants a count >= 1, got \"%s\"\n", argv[0], v);
                return 1;
            }
        } else {
            fprintf(stderr, "%s: unknown option \"%s\"\n%s", argv[0], a, usage);
            return 1;
        }
        ++i;
    }
    if (opt->scene_path == NULL) {
        fprintf(stderr, "%s: --scene FILE is required\n%s", argv[0], usage);
        return 1;
    }
    return 0;
}

static int read_doubles(FILE *f, double *out, size_t count)
{
    return fread(out, sizeof(double), count, f) == count ? 0 : 1;
}

int peers_scene_open(const char *path, peers_scene *s)
{
    char magic[8];
    double h[8];
    FILE *f = fopen(path, "rb");
    memset(s, 0, sizeof *s);
    s->path = path;
    if (f == NULL) {
        fprintf(stderr, "scene %s: cannot open\n", path);
        return 1;
    }
    if (fread(magic, 1, 8, f) != 8 || memcmp(magic, "RBSPEER1", 8) != 0 || read_doubles(f, h, 8)) {
        fprintf(stderr, "scene %s: not a peers scene file (magic RBSPEER1)\n", path);
        fclose(f);
        return 1;
    }
    if (!(h[0] >= 0 && h[0] < 1e8 && h[1] >= 0 && h[1] < 64 && h[2] > 0 && h[3] >= 0)) {
        fprintf(stderr, "scene %s: bad header (n=%g planes=%g dt=%g steps=%g)\n", path, h[0], h[1],
                h[2], h[3]);
        fclose(f);
        return 1;
    }
    s->n = (size_t)h[0];
    s->n_planes = (size_t)h[1];
    s->dt = h[2];
    s->steps = (long)h[3];
    s->gravity_z = h[4];
    s->restitution = h[5];
    s->friction = h[6];
    s->track_apex = h[7] != 0.0;
    s->planes = malloc((s->n_planes * 6 + 1) * sizeof(double));
    if (s->planes == NULL || read_doubles(f, s->planes, s->n_planes * 6)) {
        fprintf(stderr, "scene %s: truncated or out of memory (planes=%zu)\n", path, s->n_planes);
        fclose(f);
        peers_scene_free(s);
        return 1;
    }
    s->file = f;
    return 0;
}

int peers_scene_sphere(peers_scene *s, double q[8])
{
    if (s->file == NULL || s->next >= s->n || read_doubles(s->file, q, 8)) {
        fprintf(stderr, "scene %s: truncated at sphere %zu of %zu\n", s->path, s->next, s->n);
        return 1;
    }
    s->next++;
    return 0;
}

int peers_scene_read(const char *path, peers_scene *s)
{
    size_t i;
    if (peers_scene_open(path, s))
        return 1;
    s->spheres = malloc((s->n * 8 + 1) * sizeof(double));
    if (s->spheres == NULL) {
        fprintf(stderr, "scene %s: out of memory (n=%zu)\n", path, s->n);
        peers_scene_free(s);
        return 1;
    }
    for (i = 0; i < s->n; ++i)
        if (peers_scene_sphere(s, &s->spheres[8 * i])) {
            peers_scene_free(s);
            return 1;
        }
    fclose(s->file);
    s->file = NULL;
    return 0;
}

void peers_scene_free(peers_scene *s)
{
    free(s->planes);
    free(s->spheres);
    s->planes = s->spheres = NULL;
    if (s->file != NULL)
        fclose(s->file);
    s->file = NULL;
}

FILE *peers_state_open(const char *path, size_t n)
{
    double dn = (double)n;
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        fprintf(stderr, "state %s: cannot create\n", path);
        return NULL;
    }
    if (fwrite("RBSSTAT1", 1, 8, f) != 8 || fwrite(&dn, sizeof dn, 1, f) != 1) {
        fprintf(stderr, "state %s: write failed\n", path);
        fclose(f);
        return NULL;
    }
    return f;
}

int peers_state_put(FILE *f, const double pos[3], const double vel[3], const double avel[3])
{
    return fwrite(pos, sizeof(double), 3, f) != 3 || fwrite(vel, sizeof(double), 3, f) != 3 ||
           fwrite(avel, sizeof(double), 3, f) != 3;
}

int peers_state_close(FILE *f, const char *path)
{
    int bad = ferror(f) != 0;
    bad |= fclose(f) != 0;
    if (bad)
        fprintf(stderr, "state %s: write failed\n", path);
    return bad;
}

double peers_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

long peers_rss_anon_kb(void)
{
    char line[256];
    long kb = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (f == NULL)
        return -1;
    while (fgets(line, sizeof line, f) != NULL)
        if (strncmp(line, "RssAnon:", 8) == 0) {
            char *end = NULL;
            long v = strtol(line + 8, &end, 10);
            if (end != line + 8 && v >= 0)
                kb = v;
            break;
        }
    fclose(f);
    return kb;
}

void peers_apex_init(peers_apex *a, double gravity_z)
{
    memset(a, 0, sizeof *a);
    a->g = fabs(gravity_z);
}

void peers_apex_feed(peers_apex *a, double z, double vz)
{
    if (a->prev_vz > 0.0 && vz <= 0.0 && a->count < 32)
        a->z[a->count++] = a->prev_z + a->prev_vz * a->prev_vz / (2.0 * a->g);
    a->prev_z = z;
    a->prev_vz = vz;
}

void peers_progress(long steps, double wall, double *last_print)
{
    if (wall - *last_print >= 1.0) {
        printf("# progress %ld %.6f\n", steps, wall);
        fflush(stdout);
        *last_print = wall;
    }
}

void peers_print_apex(FILE *f, const peers_apex *a)
{
    int i;
    fputc('[', f);
    for (i = 0; i < a->count; ++i)
        fprintf(f, "%s%.9g", i ? ", " : "", a->z[i]);
    fputc(']', f);
}
