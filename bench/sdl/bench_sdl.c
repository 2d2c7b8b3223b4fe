/*
 * bench_sdl.c - milliseconds per 640x480 frame of the "sdl" renderer for 10,
 * 100 and 1000 spheres piled above a ground plane (median of RUNS runs).
 *
 * Prints CSV: spheres,render_ms,draw_png_ms,brute_ms
 *   render_ms   - ray casting one view (sdl_raster.c) with the default camera:
 *                 every pixel against the planes, and each sphere only over
 *                 its exact screen-space bounding box, with a depth test
 *   draw_png_ms - the class's draw(): render + legend + the PNG file (sdl_png.c)
 *   brute_ms    - for comparison, the design the renderer avoids: every
 *                 pixel's ray against every sphere (nearest hit only, no
 *                 shading, so a lower bound; median of BRUTE_RUNS runs)
 * Usage: bench_sdl [OUTPUT_DIR]   (default ./bench-sdl-out)
 * Not a test: results per machine go to bench/results/sdl.md.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sdl_internal.h"
#include "sdl_renderer.h"

#define RUNS 15
#define BRUTE_RUNS 3
#define WIDTH 640
#define HEIGHT 480

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Deterministic pseudo-random numbers in [0, 1) (a 64-bit LCG, Knuth's
 * MMIX constants). */
static double uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

/* n spheres in a loose pile: a cubic grid of 0.5 m spacing (side
 * ceil(cbrt(n)) cells) above the ground, jittered, radii 0.1-0.25 m, seen by
 * the default camera (so the pile fills the view whatever n is). */
static void make_frame(rbs_frame *f, rbs_frame_body *b, uint32_t n)
{
    uint64_t seed = 12345;
    uint32_t i, side = (uint32_t)ceil(cbrt((double)n) - 1e-9);
    memset(f, 0, sizeof *f);
    memset(b, 0, (n + 1) * sizeof *b);
    f->bodies = b;
    f->body_count = n + 1;
    b[0].type = RBS_BODY_PLANE;
    b[0].color = 0x808080;
    b[0].texture = RBS_TEXTURE_CHECKER;
    b[0].normal[2] = 1.0;
    b[0].orientation[0] = 1.0;
    b[0].name = "ground";
    for (i = 1; i <= n; i++) {
        uint32_t k = i - 1;
        double r = 0.1 + 0.15 * uniform(&seed), a = 6.283185307179586 * uniform(&seed);
        b[i].type = RBS_BODY_SPHERE;
        b[i].name = "ball";
        b[i].radius = r;
        b[i].color = (uint32_t)(uniform(&seed) * 0xffffff);
        b[i].texture = (int32_t)(i % 3);
        b[i].position[0] = 0.5 * (k % side) + 0.1 * (uniform(&seed) - 0.5);
        b[i].position[1] = 0.5 * (k / side % side) + 0.1 * (uniform(&seed) - 0.5);
        b[i].position[2] = 0.3 + 0.5 * (k / side / side);
        b[i].orientation[0] = cos(a / 2);
        b[i].orientation[3] = sin(a / 2);
    }
}

/* Nearest sphere hit for every pixel, all spheres per pixel; returns a
 * checksum so the work cannot be optimised away. */
static double brute_force(const rbsf__view *v, const rbs_frame *f)
{
    double sum = 0.0;
    uint32_t i, j, k;
    for (j = 0; j < v->height; j++) {
        double ry = (0.5 * v->height - j - 0.5) / v->focal;
        for (i = 0; i < v->width; i++) {
            double rx = (i + 0.5 - 0.5 * v->width) / v->focal, best = v->zfar;
            /* The ray in world coordinates. */
            double d[3] = {rx * v->right.x + ry * v->up.x + v->fwd.x,
                           rx * v->right.y + ry * v->up.y + v->fwd.y,
                           rx * v->right.z + ry * v->up.z + v->fwd.z};
            double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            for (k = 0; k < f->body_count; k++) {
                const rbs_frame_body *b = &f->bodies[k];
                double c[3], dc, cc, disc, t;
                if (b->type != RBS_BODY_SPHERE) continue;
                c[0] = b->position[0] - v->eye.x;
                c[1] = b->position[1] - v->eye.y;
                c[2] = b->position[2] - v->eye.z;
                dc = d[0] * c[0] + d[1] * c[1] + d[2] * c[2];
                cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - b->radius * b->radius;
                disc = dc * dc - dd * cc;
                if (disc < 0.0) continue;
                t = (dc - sqrt(disc)) / dd;
                if (t >= v->znear && t < best) best = t;
            }
            sum += best;
        }
    }
    return sum;
}

int main(int argc, char **argv)
{
    static const uint32_t counts[] = {10, 100, 1000};
    const char *dir = argc > 1 ? argv[1] : "bench-sdl-out";
    const rbs_renderer_class *cls = rbsf_sdl_class();
    rbs_frame_body *bodies = malloc(1001 * sizeof *bodies);
    double *depth = malloc((size_t)WIDTH * HEIGHT * sizeof *depth);
    uint32_t *pixels = malloc((size_t)WIDTH * HEIGHT * sizeof *pixels);
    double *rx = malloc(WIDTH * sizeof *rx), *ry = malloc(HEIGHT * sizeof *ry);
    double render[RUNS], full[RUNS], brute[BRUTE_RUNS], checksum = 0.0;
    size_t c;
    if (!bodies || !depth || !pixels || !rx || !ry) {
        fprintf(stderr, "bench_sdl: out of memory\n");
        return 1;
    }
    printf("spheres,render_ms,draw_png_ms,brute_ms\n");
    for (c = 0; c < sizeof counts / sizeof counts[0]; c++) {
        rbs_frame f;
        rbsf__config cfg;
        rbsf__camera cam;
        rbsf__view view;
        rbsf__canvas cv = {pixels, WIDTH, depth, rx, ry};
        void *inst = NULL;
        char err[512];
        int k;
        make_frame(&f, bodies, counts[c]);

        /* Render only, default camera. */
        rbsf__config_defaults(&cfg);
        rbsf__camera_init(&cam, &cfg.cameras[0], 1);
        if (rbsf__camera_view(&cam, &f, WIDTH, HEIGHT, &view, err, sizeof err) != RBS_OK) {
            fprintf(stderr, "bench_sdl: %s\n", err);
            return 1;
        }
        for (k = 0; k < RUNS; k++) {
            double t0 = now_ms();
            rbsf__raster_frame(&cv, &view, &f);
            render[k] = now_ms() - t0;
        }
        for (k = 0; k < BRUTE_RUNS; k++) {
            double t0 = now_ms();
            checksum += brute_force(&view, &f);
            brute[k] = now_ms() - t0;
        }

        /* The whole draw() with PNG output. */
        {
            rbs_renderer_config rc;
            memset(&rc, 0, sizeof rc);
            rc.struct_size = sizeof rc;
            rc.type = "sdl";
            rc.path = dir;
            rc.every = 1;
            rc.json = "{\"window\":false,\"contact_sheet\":false}";
            if (cls->create(NULL, &rc, NULL, &inst, err, sizeof err) != RBS_OK) {
                fprintf(stderr, "bench_sdl: %s\n", err);
                return 1;
            }
        }
        for (k = 0; k < RUNS; k++) {
            double t0;
            f.number = (uint64_t)k;
            t0 = now_ms();
            if (cls->draw(inst, &f, err, sizeof err) != RBS_OK) {
                fprintf(stderr, "bench_sdl: %s\n", err);
                return 1;
            }
            full[k] = now_ms() - t0;
        }
        cls->destroy(inst);
        printf("%u,%.2f,%.2f,%.1f\n", counts[c], median(render, RUNS), median(full, RUNS),
               median(brute, BRUTE_RUNS));
        fflush(stdout);
    }
    if (checksum == 42.0) printf("#\n"); /* keep the brute force's work */
    free(bodies);
    free(depth);
    free(pixels);
    free(rx);
    free(ry);
    return 0;
}
