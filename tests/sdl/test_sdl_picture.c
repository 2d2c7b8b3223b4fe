/*
 * test_sdl_picture.c - what the "sdl" renderer draws, checked against the
 * pinhole camera written out independently (sdl_test_util.c): where a sphere
 * appears and how big, its colour, occlusion, the plane's checker, the
 * texture fixed in the body frame, mounted and scripted cameras.
 *
 * Frames are built by hand (no physics).  Images are read back from the PNG
 * files with IMG_Load.  Pixel tolerances: the renderer samples each pixel at
 * its centre, so an edge is placed to within one pixel; the tests allow one
 * pixel for positions and sizes, and say so where they allow more.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sdl_test_util.h"

static const double kPi = 3.14159265358979323846;
#define W 320
#define H 240

/* Base JSON: a fixed camera, small images, no window, no contact sheet. */
static void camera_json(char *buf, size_t n, const double eye[3],
                        const double target[3], const double up[3], double fov)
{
    snprintf(buf, n,
             "{\"type\":\"sdl\",\"width\":%d,\"height\":%d,\"window\":false,"
             "\"contact_sheet\":false,\"camera\":{\"mode\":\"fixed\","
             "\"position\":[%.17g,%.17g,%.17g],\"target\":[%.17g,%.17g,%.17g],"
             "\"up\":[%.17g,%.17g,%.17g],\"fov\":%.17g}}",
             W, H, eye[0], eye[1], eye[2], target[0], target[1], target[2], up[0],
             up[1], up[2], fov);
}

/* Render one frame with json into folder name; return the loaded image. */
static SDL_Surface *render(const char *json, const char *name, tu_frame *f)
{
    void *inst = NULL;
    char err[512], path[1400];
    const rbs_renderer_class *cls = rbsf_sdl_class();
    rbs_status st = tu_create(json, tu_dir(name), &inst, err, sizeof err);
    if (st != RBS_OK) fprintf(stderr, "create: %s\n", err);
    assert_int_equal(st, RBS_OK);
    st = cls->draw(inst, &f->frame, err, sizeof err);
    if (st != RBS_OK) fprintf(stderr, "draw: %s\n", err);
    assert_int_equal(st, RBS_OK);
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    snprintf(path, sizeof path, "%s/frame_%06llu.png", tu_dir(name),
             (unsigned long long)f->frame.number);
    {
        SDL_Surface *s = tu_load(path);
        assert_non_null(s);
        assert_int_equal(s->w, W);
        assert_int_equal(s->h, H);
        return s;
    }
}

/* Saturated reds (the test spheres' 0xd03030, lit or dark). */
static int is_red(uint32_t c)
{
    int r = (c >> 16) & 0xff, g = (c >> 8) & 0xff, b = c & 0xff;
    return r > 40 && g * 2 < r && b * 2 < r;
}
static int is_green(uint32_t c)
{
    int r = (c >> 16) & 0xff, g = (c >> 8) & 0xff, b = c & 0xff;
    return g > 40 && r * 2 < g && b * 2 < g;
}

static const double kEye[3] = {0, -6, 1}, kTarget[3] = {0, 0, 1}, kUp[3] = {0, 0, 1};

/* An on-axis sphere: centred, with apparent radius f r / sqrt(d^2 - r^2)
 * (the half-angle of the tangent cone is asin(r/d)). */
static void test_sphere_on_axis(void **state)
{
    char json[1024];
    tu_frame f;
    SDL_Surface *s;
    int x0, y0, x1, y1;
    double focal = (H / 2.0) / tan(25.0 * kPi / 180.0), d = 6.0, r = 0.5;
    double rpx = focal * r / sqrt(d * d - r * r);
    (void)state;
    camera_json(json, sizeof json, kEye, kTarget, kUp, 50.0);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 1, r, 0xd03030);
    s = render(json, "on_axis", &f);
    assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
    /* Centre from pixel edges: (x0 + x1 + 1) / 2. */
    assert_true(fabs((x0 + x1 + 1) / 2.0 - W / 2.0) <= 1.0);
    assert_true(fabs((y0 + y1 + 1) / 2.0 - H / 2.0) <= 1.0);
    assert_true(fabs((x1 - x0 + 1) / 2.0 - rpx) <= 1.0);
    assert_true(fabs((y1 - y0 + 1) / 2.0 - rpx) <= 1.0);
    SDL_FreeSurface(s);
}

/* An off-axis sphere: its centre projects to u = W/2 + f x_c / z_c.  The
 * silhouette is an ellipse whose centre lies outward of that point by about
 * f (x_c/z_c) r^2 / (z_c^2 - r^2) = 0.2 px here, inside the one-pixel
 * tolerance.  Offset only along x, so the vertical half-extent is exactly
 * f r / sqrt(z_c^2 - r^2). */
static void test_sphere_off_axis(void **state)
{
    char json[1024];
    tu_frame f;
    SDL_Surface *s;
    int x0, y0, x1, y1;
    double p[3] = {1.2, 0, 1}, u, v, z, r = 0.3;
    double focal = (H / 2.0) / tan(25.0 * kPi / 180.0);
    (void)state;
    camera_json(json, sizeof json, kEye, kTarget, kUp, 50.0);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", p[0], p[1], p[2], r, 0xd03030);
    s = render(json, "off_axis", &f);
    assert_true(tu_project(kEye, kTarget, kUp, 50.0, W, H, p, &u, &v, &z));
    assert_true(fabs(u - (W / 2.0 + focal * 1.2 / 6.0)) < 1e-9); /* the formula */
    assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
    assert_true(fabs((x0 + x1 + 1) / 2.0 - u) <= 1.0);
    assert_true(fabs((y0 + y1 + 1) / 2.0 - v) <= 1.0);
    assert_true(fabs((y1 - y0 + 1) / 2.0 - focal * r / sqrt(z * z - r * r)) <= 1.0);
    SDL_FreeSurface(s);
}

/* The lit centre pixel has the body's hue (shading scales all channels
 * alike; rounding to 8 bits moves the hue by well under 2 degrees at these
 * levels) and is brighter than ambient light alone would make it. */
static void check_colour(uint32_t color, int32_t texture, const char *name)
{
    char json[1024];
    tu_frame f;
    SDL_Surface *s;
    uint32_t c;
    double dh;
    camera_json(json, sizeof json, kEye, kTarget, kUp, 50.0);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 1, 0.5, color)->texture = texture;
    s = render(json, name, &f);
    c = tu_pixel(s, W / 2, H / 2);
    dh = fabs(tu_hue(c) - tu_hue(color));
    if (dh > 180) dh = 360 - dh;
    assert_true(dh < 2.0);
    if (texture == RBS_TEXTURE_NONE) {
        /* Ambient is 25%: a lit centre is far above a quarter. */
        int mx = (int)fmax((c >> 16) & 0xff, fmax((c >> 8) & 0xff, c & 0xff));
        int cmax = (int)fmax((color >> 16) & 0xff, fmax((color >> 8) & 0xff, color & 0xff));
        assert_true(mx > cmax / 2);
        assert_true(mx <= cmax);
    }
    SDL_FreeSurface(s);
}

static void test_colour(void **state)
{
    (void)state;
    check_colour(0x3060c0, RBS_TEXTURE_NONE, "colour_blue");
    check_colour(0xd0a020, RBS_TEXTURE_NONE, "colour_yellow");
    check_colour(0x3060c0, RBS_TEXTURE_STRIPES, "colour_stripes");
    check_colour(0x20b060, RBS_TEXTURE_CHECKER, "colour_checker");
}

/* A nearer sphere hides a farther one, whatever the order of the bodies. */
static void check_occlusion(int near_first, const char *name)
{
    char json[1024];
    tu_frame f;
    SDL_Surface *s;
    int x0, y0, x1, y1, x, y;
    double focal = (H / 2.0) / tan(25.0 * kPi / 180.0);
    double near_px = focal * 0.3 / sqrt(16.0 - 0.09); /* d = 4 */
    camera_json(json, sizeof json, kEye, kTarget, kUp, 50.0);
    tu_frame_init(&f, 0, 0.0);
    if (near_first) tu_add_sphere(&f, "near", 0, -2, 1, 0.3, 0x30c030);
    tu_add_sphere(&f, "far", 0, 2, 1, 1.0, 0xd03030);
    if (!near_first) tu_add_sphere(&f, "near", 0, -2, 1, 0.3, 0x30c030);
    s = render(json, name, &f);
    assert_true(is_green(tu_pixel(s, W / 2, H / 2)));
    /* The far sphere shows around the near one ... */
    assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
    /* ... but never inside the near one's disk (one pixel inside its edge). */
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            double dx = x + 0.5 - W / 2.0, dy = y + 0.5 - H / 2.0;
            if (sqrt(dx * dx + dy * dy) < near_px - 1.0)
                assert_false(is_red(tu_pixel(s, x, y)));
        }
    SDL_FreeSurface(s);
}

static void test_occlusion(void **state)
{
    (void)state;
    check_occlusion(1, "occlusion_a");
    check_occlusion(0, "occlusion_b");
}

/* The ground's checker: cells of 0.5 m on x and y, alternating, the dark
 * one half as bright (the renderer's documented texture); a sphere below the
 * ground is hidden by it. */
static void test_plane_checker(void **state)
{
    static const double eye[3] = {0.1, 0.2, 10}, target[3] = {0.1, 0.2, 0},
                        up[3] = {0, 1, 0};
    char json[1024];
    tu_frame f;
    SDL_Surface *s;
    uint32_t light = 0, dark = 0;
    int i, j, x0, y0, x1, y1;
    (void)state;
    camera_json(json, sizeof json, eye, target, up, 50.0);
    tu_frame_init(&f, 0, 0.0);
    tu_add_plane(&f, 0, 0, 0, 0, 0, 1, 0x808080);
    tu_add_sphere(&f, "buried", 0.1, 0.2, -3, 1.0, 0xd03030);
    s = render(json, "checker", &f);
    for (i = -3; i <= 3; i++)
        for (j = -3; j <= 3; j++) {
            double p[3] = {0.25 + 0.5 * i, 0.25 + 0.5 * j, 0}, u, v, z;
            uint32_t c;
            assert_true(tu_project(eye, target, up, 50.0, W, H, p, &u, &v, &z));
            c = tu_pixel(s, (int)u, (int)v);
            if (((i + j) & 1) == 0) {
                if (light == 0) light = c;
                assert_int_equal(c, light);
            } else {
                if (dark == 0) dark = c;
                assert_int_equal(c, dark);
            }
        }
    assert_int_not_equal(light, dark);
    /* Dark = light / 2 per channel, within rounding. */
    assert_true(abs((int)((light >> 8) & 0xff) - 2 * (int)((dark >> 8) & 0xff)) <= 2);
    assert_int_equal(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1), 0);
    SDL_FreeSurface(s);
}

/* Identity quaternion vs a rotation by angle about unit axis (x, y, z). */
static void set_rotation(rbs_frame_body *b, double angle, double x, double y, double z)
{
    b->orientation[0] = cos(angle / 2);
    b->orientation[1] = x * sin(angle / 2);
    b->orientation[2] = y * sin(angle / 2);
    b->orientation[3] = z * sin(angle / 2);
}

static long differing(SDL_Surface *a, SDL_Surface *b)
{
    long n = 0;
    int x, y;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            if (tu_pixel(a, x, y) != tu_pixel(b, x, y)) n++;
    return n;
}

/* The texture is fixed in the body: rotating a striped sphere about the
 * view axis changes the picture (22.5 degrees: half a stripe), except by
 * the pattern's own symmetry (8 stripes: 90 degrees gives the same picture);
 * rotating the body and orbiting the camera by the same angle about the same
 * axis gives the same picture (the light moves with the camera). */
static void test_texture_rotates(void **state)
{
    static const double eye[3] = {0, 0, 5}, target[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    char json[1024];
    tu_frame f;
    SDL_Surface *s0, *s1, *s2, *s3, *s4;
    double a = 37.0 * kPi / 180.0;
    double eye2[3] = {5 * sin(a), -5 * cos(a), 0}, eye3[3] = {0, -5, 0}, zup[3] = {0, 0, 1};
    rbs_frame_body *b;
    (void)state;
    camera_json(json, sizeof json, eye, target, up, 50.0);
    tu_frame_init(&f, 0, 0.0);
    /* Slightly off the axis, so that no pixel centre lies exactly on a
     * stripe edge (the image diagonals), where rounding would decide. */
    b = tu_add_sphere(&f, "ball", 0.0123, 0.0071, 0, 1.0, 0xd03030);
    b->texture = RBS_TEXTURE_STRIPES;
    s0 = render(json, "rot_0", &f);
    set_rotation(b, kPi / 8, 0, 0, 1);
    s1 = render(json, "rot_22", &f);
    set_rotation(b, kPi / 2, 0, 0, 1);
    s2 = render(json, "rot_90", &f);
    /* The disk covers ~ pi (f r / sqrt(24))^2 ~ 8600 px; half a stripe
     * turn recolours about half of it. */
    assert_true(differing(s0, s1) > 2000);
    assert_true(differing(s0, s2) < 20);

    /* Body turned by a about z, camera orbited by a about z. */
    b->texture = RBS_TEXTURE_CHECKER;
    b->position[0] = b->position[1] = 0.0;
    set_rotation(b, 0, 0, 0, 1);
    camera_json(json, sizeof json, eye3, target, zup, 50.0);
    s3 = render(json, "orbit_0", &f);
    set_rotation(b, a, 0, 0, 1);
    camera_json(json, sizeof json, eye2, target, zup, 50.0);
    s4 = render(json, "orbit_37", &f);
    /* Equal up to pixels whose centre lies on a texture edge within rounding
     * (none were seen; a few would be acceptable). */
    assert_true(differing(s3, s4) < 10);
    SDL_FreeSurface(s0);
    SDL_FreeSurface(s1);
    SDL_FreeSurface(s2);
    SDL_FreeSurface(s3);
    SDL_FreeSurface(s4);
}

/* A mounted camera keeps its body in the middle of the picture while the
 * body moves; another body moves across the picture. */
static void test_mounted_camera(void **state)
{
    static const double pos[3][3] = {{0, 0, 0.5}, {2, 1, 0.5}, {-3, 4, 2}};
    const char *json = "{\"type\":\"sdl\",\"width\":320,\"height\":240,\"window\":false,"
                       "\"contact_sheet\":false,\"camera\":{\"mode\":\"mounted\","
                       "\"mount\":\"ball\",\"offset\":[0,-3,1],\"fov\":50}}";
    const rbs_renderer_class *cls = rbsf_sdl_class();
    void *inst = NULL;
    char err[512], path[1400];
    int k, gx[3];
    (void)state;
    assert_int_equal(tu_create(json, tu_dir("mounted"), &inst, err, sizeof err), RBS_OK);
    for (k = 0; k < 3; k++) {
        tu_frame f;
        tu_frame_init(&f, (uint64_t)k, 0.1 * k);
        tu_add_sphere(&f, "other", 0.7, 1, 0.5, 0.2, 0x30c030);
        tu_add_sphere(&f, "ball", pos[k][0], pos[k][1], pos[k][2], 0.3, 0xd03030);
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    }
    assert_int_equal(cls->finish(inst, err, sizeof err), RBS_OK);
    cls->destroy(inst);
    for (k = 0; k < 3; k++) {
        SDL_Surface *s;
        int x0, y0, x1, y1;
        snprintf(path, sizeof path, "%s/frame_%06d.png", tu_dir("mounted"), k);
        s = tu_load(path);
        assert_non_null(s);
        assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
        assert_true(fabs((x0 + x1 + 1) / 2.0 - W / 2.0) <= 1.0);
        assert_true(fabs((y0 + y1 + 1) / 2.0 - H / 2.0) <= 1.0);
        gx[k] = tu_bbox(s, 0, 0, W, H, is_green, &x0, &y0, &x1, &y1) > 0 ? x0 : -1;
        SDL_FreeSurface(s);
    }
    /* The other body is seen at different places (or leaves the view). */
    assert_true(gx[0] != gx[1] || gx[1] != gx[2]);
}

/* A scripted path: linear in t between keys, clamped after the last. */
static void test_scripted_path(void **state)
{
    const char *json =
        "{\"type\":\"sdl\",\"width\":320,\"height\":240,\"window\":false,"
        "\"contact_sheet\":false,\"camera\":{\"fov\":50,\"path\":["
        "{\"t\":0,\"position\":[0,-5,1],\"target\":[0,0,1]},"
        "{\"t\":1,\"position\":[5,0,1],\"target\":[0,0,1]},"
        "{\"t\":2,\"position\":[5,0,6],\"target\":[0,0,1]}]}}";
    static const double times[3] = {0.5, 1.5, 7.0};
    static const double eyes[3][3] = {{2.5, -2.5, 1}, {5, 0, 3.5}, {5, 0, 6}};
    static const double target[3] = {0, 0, 1}, up[3] = {0, 0, 1};
    static const double p[3] = {0.8, 0.4, 1.2};
    const rbs_renderer_class *cls = rbsf_sdl_class();
    void *inst = NULL;
    char err[512], path[1400];
    int k;
    (void)state;
    assert_int_equal(tu_create(json, tu_dir("path"), &inst, err, sizeof err), RBS_OK);
    for (k = 0; k < 3; k++) {
        tu_frame f;
        tu_frame_init(&f, (uint64_t)k, times[k]);
        tu_add_sphere(&f, "ball", p[0], p[1], p[2], 0.1, 0xd03030);
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    }
    cls->destroy(inst);
    for (k = 0; k < 3; k++) {
        SDL_Surface *s;
        int x0, y0, x1, y1;
        double u, v, z;
        snprintf(path, sizeof path, "%s/frame_%06d.png", tu_dir("path"), k);
        s = tu_load(path);
        assert_non_null(s);
        assert_true(tu_project(eyes[k], target, up, 50.0, W, H, p, &u, &v, &z));
        assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
        /* Small sphere (~10 px), so the ellipse offset is < 0.1 px. */
        assert_true(fabs((x0 + x1 + 1) / 2.0 - u) <= 1.0);
        assert_true(fabs((y0 + y1 + 1) / 2.0 - v) <= 1.0);
        SDL_FreeSurface(s);
    }
}

/* With no camera in the entry, the default camera follows the spheres'
 * bounding-box centre across its up vector (z): a ball rolling 10 m along x
 * stays at the same pixels; a ball rising 1 m moves up in the picture. */
static void test_default_camera_follows(void **state)
{
    const char *json = "{\"type\":\"sdl\",\"width\":320,\"height\":240,"
                       "\"window\":false,\"contact_sheet\":false}";
    static const double pos[3][3] = {{0, 0, 0.5}, {10, 0, 0.5}, {10, 0, 1.5}};
    const rbs_renderer_class *cls = rbsf_sdl_class();
    void *inst = NULL;
    char err[512], path[1400];
    int k, cx[3], cy[3];
    (void)state;
    assert_int_equal(tu_create(json, tu_dir("follow"), &inst, err, sizeof err), RBS_OK);
    for (k = 0; k < 3; k++) {
        tu_frame f;
        tu_frame_init(&f, (uint64_t)k, 0.1 * k);
        tu_add_plane(&f, 0, 0, 0, 0, 0, 1, 0x808080);
        tu_add_sphere(&f, "ball", pos[k][0], pos[k][1], pos[k][2], 0.5, 0xd03030);
        assert_int_equal(cls->draw(inst, &f.frame, err, sizeof err), RBS_OK);
    }
    cls->destroy(inst);
    for (k = 0; k < 3; k++) {
        SDL_Surface *s;
        int x0, y0, x1, y1;
        snprintf(path, sizeof path, "%s/frame_%06d.png", tu_dir("follow"), k);
        s = tu_load(path);
        assert_non_null(s);
        assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
        cx[k] = x0 + x1;
        cy[k] = y0 + y1;
        SDL_FreeSurface(s);
    }
    /* Same place after the roll (one pixel of rounding) ... */
    assert_true(abs(cx[1] - cx[0]) <= 2 && abs(cy[1] - cy[0]) <= 2);
    /* ... higher after the rise (1 m at ~4 m is tens of pixels). */
    assert_true(cy[0] - cy[2] > 20);
}

/* A path that passes straight above its target (the view along up at
 * t = 1) draws every frame: there the picture keeps the previous frame's
 * right vector; a first frame already along up takes up's first in-plane
 * axis.  The target sphere stays centred throughout. */
static void test_path_over_target(void **state)
{
    const char *json =
        "{\"type\":\"sdl\",\"width\":320,\"height\":240,\"window\":false,"
        "\"contact_sheet\":false,\"camera\":{\"path\":["
        "{\"t\":0,\"position\":[1,0,3],\"target\":[0,0,0]},"
        "{\"t\":2,\"position\":[-1,0,3],\"target\":[0,0,0]}]}}";
    static const double times[2][3] = {{0.0, 1.0, 2.0}, {1.0, 1.5, 2.0}};
    const rbs_renderer_class *cls = rbsf_sdl_class();
    int run, k;
    (void)state;
    for (run = 0; run < 2; run++) {
        void *inst = NULL;
        char err[512], path[1400], name[32];
        snprintf(name, sizeof name, "over%d", run);
        assert_int_equal(tu_create(json, tu_dir(name), &inst, err, sizeof err), RBS_OK);
        for (k = 0; k < 3; k++) {
            tu_frame f;
            rbs_status st;
            tu_frame_init(&f, (uint64_t)k, times[run][k]);
            tu_add_sphere(&f, "ball", 0, 0, 0, 0.3, 0xd03030);
            st = cls->draw(inst, &f.frame, err, sizeof err);
            if (st != RBS_OK) fprintf(stderr, "draw t=%g: %s\n", times[run][k], err);
            assert_int_equal(st, RBS_OK);
        }
        cls->destroy(inst);
        for (k = 0; k < 3; k++) {
            SDL_Surface *s;
            int x0, y0, x1, y1;
            snprintf(path, sizeof path, "%s/frame_%06d.png", tu_dir(name), k);
            s = tu_load(path);
            assert_non_null(s);
            assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
            assert_true(fabs((x0 + x1 + 1) / 2.0 - W / 2.0) <= 1.0);
            assert_true(fabs((y0 + y1 + 1) / 2.0 - H / 2.0) <= 1.0);
            SDL_FreeSurface(s);
        }
    }
}

/* fov 1e-6 degrees, the eye 1.7e8 m away: the sphere is still a disc of
 * radius f r / d = 40 px (the ray-sphere test must not cancel |c|^2 against
 * tc^2).  The corners of its bounding square, 0.93 radii out along each
 * diagonal (1.3 radii from the centre), are background; its centre is red. */
static void test_narrow_fov_disc(void **state)
{
    char json[1024];
    tu_frame f;
    SDL_Surface *s;
    int x0, y0, x1, y1;
    double fov = 1e-6, r = 0.5;
    double focal = (H / 2.0) / tan(0.5 * fov * kPi / 180.0), rpx = 40.0;
    double d = focal * r / rpx;
    const double eye[3] = {0, -d, 1};
    (void)state;
    camera_json(json, sizeof json, eye, kTarget, kUp, fov);
    tu_frame_init(&f, 0, 0.0);
    tu_add_sphere(&f, "ball", 0, 0, 1, r, 0xd03030);
    s = render(json, "narrow_fov", &f);
    assert_true(tu_bbox(s, 0, 0, W, H, is_red, &x0, &y0, &x1, &y1) > 0);
    assert_true(fabs((x1 - x0 + 1) / 2.0 - rpx) <= 1.0);
    assert_true(fabs((y1 - y0 + 1) / 2.0 - rpx) <= 1.0);
    assert_true(is_red(tu_pixel(s, W / 2, H / 2)));
    assert_false(is_red(tu_pixel(s, x0 + 3, y0 + 3)));
    assert_false(is_red(tu_pixel(s, x1 - 3, y0 + 3)));
    assert_false(is_red(tu_pixel(s, x0 + 3, y1 - 3)));
    assert_false(is_red(tu_pixel(s, x1 - 3, y1 - 3)));
    SDL_FreeSurface(s);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_on_axis),
        cmocka_unit_test(test_sphere_off_axis),
        cmocka_unit_test(test_colour),
        cmocka_unit_test(test_occlusion),
        cmocka_unit_test(test_plane_checker),
        cmocka_unit_test(test_texture_rotates),
        cmocka_unit_test(test_mounted_camera),
        cmocka_unit_test(test_scripted_path),
        cmocka_unit_test(test_path_over_target),
        cmocka_unit_test(test_narrow_fov_disc),
        cmocka_unit_test(test_default_camera_follows),
    };
    tu_set_base(argc > 1 ? argv[1] : ".");
    return cmocka_run_group_tests(tests, NULL, NULL);
}
