/*
 * sdl_camera.c - cameras: gluPerspective-style pinhole (vertical fov in
 * degrees, near and far planes along the view direction), placed fixed, on a
 * scripted path (linear in time, clamped at the ends), mounted on a body, or
 * free (moved by orbit/pan/zoom/reset).
 *
 * Default placement: looking at the centre of the spheres' bounding box from
 * azimuth -60 degrees and elevation 30 degrees (in the frame of the camera's
 * up vector), far enough that the box's bounding sphere fills about 80% of
 * the vertical field of view.
 *
 * Usable views: positions and targets within +-kCoordMax m, the target at
 * least kDistMin m from the eye (so every square in the ray caster is finite
 * and nonzero).  Commands that would leave that range are refused and leave
 * the camera as it was.  When the view direction comes within kParallel
 * (sine of the angle) of up, as a path can pass straight above its target,
 * the picture keeps the previous frame's right vector (made perpendicular to
 * the view); with no previous frame it takes up's first in-plane axis e1.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sdl_internal.h"

static const double kPi = 3.14159265358979323846;
/* Default view direction from the target: azimuth and elevation, degrees. */
static const double kDefaultAzimuth = -60.0;
static const double kDefaultElevation = 30.0;
/* Orbits keep the elevation within this many degrees of the horizon. */
static const double kMaxElevation = 89.0;
/* Limits of a usable view (see the top of the file and FORMAT.md). */
static const double kCoordMax = 1e100;
static const double kDistMin = 1e-100;
static const double kParallel = 1e-9;

static rbs_vec3 v3(double x, double y, double z)
{
    rbs_vec3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}
static rbs_vec3 add(rbs_vec3 a, rbs_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static rbs_vec3 sub(rbs_vec3 a, rbs_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static rbs_vec3 scale(rbs_vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static double dot(rbs_vec3 a, rbs_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double len(rbs_vec3 a) { return sqrt(dot(a, a)); }
static rbs_vec3 cross(rbs_vec3 a, rbs_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* Two unit vectors e1, e2 with (e1, e2, up) right-handed; for up = z they
 * are x and y. */
static void up_frame(rbs_vec3 up, rbs_vec3 *e1, rbs_vec3 *e2)
{
    rbs_vec3 a;
    double ax = fabs(up.x), ay = fabs(up.y), az = fabs(up.z);
    if (ax <= ay && ax <= az) a = v3(1, 0, 0);
    else if (ay <= az) a = v3(0, 1, 0);
    else a = v3(0, 0, 1);
    *e1 = sub(a, scale(up, dot(a, up)));
    *e1 = scale(*e1, 1.0 / len(*e1));
    *e2 = cross(up, *e1);
}

/* Unit direction at azimuth/elevation (degrees) in the frame of up. */
static rbs_vec3 direction(rbs_vec3 up, double azimuth, double elevation)
{
    rbs_vec3 e1, e2;
    double a = azimuth * kPi / 180.0, e = elevation * kPi / 180.0;
    up_frame(up, &e1, &e2);
    return add(add(scale(e1, cos(e) * cos(a)), scale(e2, cos(e) * sin(a))),
               scale(up, sin(e)));
}

void rbsf__camera_init(rbsf__camera *camera, const rbsf__camera_def *def,
                       int track)
{
    memset(camera, 0, sizeof *camera);
    camera->def = def;
    camera->up = def->up;
    camera->fov = def->fov;
    camera->znear = def->znear;
    camera->zfar = def->zfar;
    camera->mount_index = -1;
    camera->track = track;
}

/* Bounding box of the spheres with finite places; returns their count. */
static uint32_t spheres_box(const rbs_frame *frame, rbs_vec3 *lo, rbs_vec3 *hi)
{
    uint32_t i, n = 0;
    *lo = *hi = v3(0, 0, 0);
    for (i = 0; i < frame->body_count; i++) {
        const rbs_frame_body *b = &frame->bodies[i];
        const double *p = b->position;
        double r = b->radius;
        if (b->type != RBS_BODY_SPHERE || !isfinite(p[0] + p[1] + p[2] + r)) continue;
        if (n++ == 0) {
            *lo = v3(p[0] - r, p[1] - r, p[2] - r);
            *hi = v3(p[0] + r, p[1] + r, p[2] + r);
        } else {
            *lo = v3(fmin(lo->x, p[0] - r), fmin(lo->y, p[1] - r), fmin(lo->z, p[2] - r));
            *hi = v3(fmax(hi->x, p[0] + r), fmax(hi->y, p[1] + r), fmax(hi->z, p[2] + r));
        }
    }
    return n;
}

/* Index of the body named name in frame, using and updating the cache. */
static int32_t find_body(rbsf__camera *camera, const rbs_frame *frame,
                         const char *name)
{
    uint32_t i;
    int32_t c = camera->mount_index;
    if (c >= 0 && (uint32_t)c < frame->body_count &&
        frame->bodies[c].type != RBS_BODY_NONE && frame->bodies[c].name != NULL &&
        strcmp(frame->bodies[c].name, name) == 0)
        return c;
    for (i = 0; i < frame->body_count; i++) {
        const rbs_frame_body *b = &frame->bodies[i];
        if (b->type != RBS_BODY_NONE && b->name != NULL &&
            strcmp(b->name, name) == 0) {
            camera->mount_index = (int32_t)i;
            return (int32_t)i;
        }
    }
    camera->mount_index = -1;
    return -1;
}

rbs_status rbsf__camera_resolve(rbsf__camera *camera, const rbs_frame *frame,
                                char *err, size_t errlen)
{
    const rbsf__camera_def *def = camera->def;
    rbs_vec3 lo = v3(0, 0, 0), hi = v3(0, 0, 0), centre, dir;
    double radius = 0.0, dist;
    uint32_t i, spheres = 0;
    if (camera->resolved) return RBS_OK;

    /* Bounding box of the spheres. */
    spheres = spheres_box(frame, &lo, &hi);
    centre = scale(add(lo, hi), 0.5);
    radius = spheres > 0 ? 0.5 * len(sub(hi, lo)) : 1.0;
    if (radius < 0.5) radius = 0.5;
    camera->track_origin = centre;
    dist = radius / sin(0.4 * def->fov * kPi / 180.0);
    dir = direction(def->up, kDefaultAzimuth, kDefaultElevation);

    switch (def->mode) {
    case RBSF__CAMERA_MOUNTED: {
        int32_t k = find_body(camera, frame, def->mount);
        double r;
        if (k < 0) {
            snprintf(err, errlen, "mount: no body named \"%s\" in the frame",
                     def->mount);
            return RBS_E_INVALID;
        }
        r = frame->bodies[k].type == RBS_BODY_SPHERE ? frame->bodies[k].radius : 0.1;
        camera->offset = def->has_offset ? def->offset : scale(dir, fmax(0.5, 8.0 * r));
        dist = len(camera->offset);
        radius = 2.0 * r;
        break;
    }
    case RBSF__CAMERA_FIXED:
    case RBSF__CAMERA_FREE:
    default:
        if (def->path_count > 0) {
            camera->position = def->path[0].position;
            camera->target = def->path[0].target;
            for (i = 0; i < def->path_count; i++)
                dist = fmax(dist, len(sub(def->path[i].position, def->path[i].target)));
            break;
        }
        camera->target = def->has_target ? def->target : centre;
        camera->position = def->has_position ? def->position
                                             : add(camera->target, scale(dir, dist));
        if (len(sub(camera->target, camera->position)) == 0.0) {
            snprintf(err, errlen, "position: equals the target (%g, %g, %g)",
                     camera->target.x, camera->target.y, camera->target.z);
            return RBS_E_INVALID;
        }
        dist = len(sub(camera->target, camera->position));
        break;
    }
    /* A far plane that shows the whole scene unless the scene set one. */
    if (!def->has_far && camera->zfar < 4.0 * (dist + radius))
        camera->zfar = 4.0 * (dist + radius);
    camera->home_position = camera->position;
    camera->home_target = camera->target;
    camera->home_offset = camera->offset;
    camera->resolved = 1;
    return RBS_OK;
}

int rbsf__camera_from_box(const rbsf__camera_def *def)
{
    return def->mode != RBSF__CAMERA_MOUNTED && def->path_count == 0 &&
           !(def->has_position && def->has_target);
}

/* Position and target on a path at time t (linear, clamped). */
static void path_at(const rbsf__camera_def *def, double t, rbs_vec3 *position,
                    rbs_vec3 *target)
{
    uint32_t lo = 0, hi = def->path_count - 1;
    double s;
    if (t <= def->path[0].t) {
        *position = def->path[0].position;
        *target = def->path[0].target;
        return;
    }
    if (t >= def->path[hi].t) {
        *position = def->path[hi].position;
        *target = def->path[hi].target;
        return;
    }
    while (hi - lo > 1) { /* path[lo].t <= t < path[hi].t */
        uint32_t mid = lo + (hi - lo) / 2;
        if (def->path[mid].t <= t) lo = mid;
        else hi = mid;
    }
    s = (t - def->path[lo].t) / (def->path[hi].t - def->path[lo].t);
    *position = add(def->path[lo].position,
                    scale(sub(def->path[hi].position, def->path[lo].position), s));
    *target = add(def->path[lo].target,
                  scale(sub(def->path[hi].target, def->path[lo].target), s));
}

/* The view basis from position to target: fwd, right = fwd x up (or, within
 * kParallel of up, prev_right or e1 made perpendicular to fwd) and up.
 * Returns NULL, or why position/target make no usable view. */
static const char *basis(rbs_vec3 position, rbs_vec3 target, rbs_vec3 up,
                         const rbs_vec3 *prev_right, rbs_vec3 *fwd,
                         rbs_vec3 *right, rbs_vec3 *vup)
{
    const double c[6] = {position.x, position.y, position.z,
                         target.x,   target.y,   target.z};
    rbs_vec3 r;
    double l;
    int i;
    for (i = 0; i < 6; i++)
        if (!(fabs(c[i]) <= kCoordMax))
            return i < 3 ? "position: not finite or beyond 1e100 m"
                         : "target: not finite or beyond 1e100 m";
    *fwd = sub(target, position);
    l = len(*fwd);
    if (!(l >= kDistMin)) return "target: closer than 1e-100 m to the position";
    *fwd = scale(*fwd, 1.0 / l);
    r = cross(*fwd, up);
    l = len(r);
    if (!(l > kParallel)) {
        /* Looking along up: keep the last right vector (a continuous rule). */
        rbs_vec3 e1, e2;
        up_frame(up, &e1, &e2);
        r = e1;
        if (prev_right != NULL) {
            rbs_vec3 p = sub(*prev_right, scale(*fwd, dot(*prev_right, *fwd)));
            if (len(p) > 0.5) r = *prev_right;
        }
        r = sub(r, scale(*fwd, dot(r, *fwd)));
        l = len(r);
    }
    *right = scale(r, 1.0 / l);
    *vup = cross(*right, *fwd);
    return NULL;
}

rbs_status rbsf__camera_view(rbsf__camera *camera, const rbs_frame *frame,
                             uint32_t width, uint32_t height, rbsf__view *out,
                             char *err, size_t errlen)
{
    const rbsf__camera_def *def = camera->def;
    rbs_vec3 position, target;
    const char *why;
    rbs_status st = rbsf__camera_resolve(camera, frame, err, errlen);
    if (st != RBS_OK) return st;

    if (def->mode == RBSF__CAMERA_MOUNTED) {
        int32_t k = find_body(camera, frame, def->mount);
        const double *p;
        if (k < 0) {
            snprintf(err, errlen, "mount: no body named \"%s\" in frame %llu",
                     def->mount, (unsigned long long)frame->number);
            return RBS_E_INVALID;
        }
        p = frame->bodies[k].position;
        target = v3(p[0], p[1], p[2]);
        position = add(target, camera->offset);
    } else if (def->path_count > 0) {
        path_at(def, frame->time, &position, &target);
    } else {
        position = camera->position;
        target = camera->target;
        if (camera->track) {
            /* Follow the spheres across up (not along it). */
            rbs_vec3 lo, hi, shift;
            if (spheres_box(frame, &lo, &hi) > 0) {
                shift = sub(scale(add(lo, hi), 0.5), camera->track_origin);
                shift = sub(shift, scale(camera->up, dot(shift, camera->up)));
                position = add(position, shift);
                target = add(target, shift);
            }
        }
    }
    why = basis(position, target, camera->up,
                camera->has_last_right ? &camera->last_right : NULL, &out->fwd,
                &out->right, &out->up);
    if (why != NULL) {
        /* A camera placed from the spheres' bounding box says so, and how to
         * place it instead (it said "from the camera's place", which the
         * scene never gave: a probe of session 46). */
        if (rbsf__camera_from_box(def) || camera->track)
            snprintf(err, errlen, "%s at frame %llu (the %s camera, placed from "
                     "the spheres' bounding box: give the view a \"position\" "
                     "and a \"target\")", why, (unsigned long long)frame->number,
                     camera->track ? "default" : "view's");
        else
            snprintf(err, errlen, "%s at frame %llu (from the %s)", why,
                     (unsigned long long)frame->number,
                     def->mode == RBSF__CAMERA_MOUNTED ? "mounted body and offset"
                     : def->path_count > 0 ? "path" : "camera's place");
        return RBS_E_INVALID;
    }
    out->eye = position;
    camera->last_right = out->right;
    camera->has_last_right = 1;
    out->focal = 0.5 * (double)height / tan(0.5 * camera->fov * kPi / 180.0);
    out->znear = camera->znear;
    out->zfar = camera->zfar;
    out->width = width;
    out->height = height;
    return RBS_OK;
}

/* The vector from the target to the eye that orbit and zoom change. */
static rbs_vec3 *arm(rbsf__camera *camera, rbs_vec3 *scratch)
{
    if (camera->def->mode == RBSF__CAMERA_MOUNTED) return &camera->offset;
    *scratch = sub(camera->position, camera->target);
    return scratch;
}

/* Move the camera to a new arm (and, for free cameras, target) if that
 * makes a usable view; otherwise refuse with the reason and keep the camera
 * as it was.  A mounted camera's view is checked as seen from its body. */
static rbs_status place(rbsf__camera *camera, rbs_vec3 arm_v, rbs_vec3 target,
                        const char *what, char *out, size_t outlen)
{
    rbs_vec3 f, r, u, origin = v3(0, 0, 0);
    int mounted = camera->def->mode == RBSF__CAMERA_MOUNTED;
    rbs_vec3 position = mounted ? arm_v : add(target, arm_v);
    const char *why = basis(position, mounted ? origin : target, camera->up,
                            NULL, &f, &r, &u);
    if (why != NULL) {
        snprintf(out, outlen, "%s: refused, the camera would have no usable view "
                 "(%s); it stays where it was", what, why);
        return RBS_E_INVALID;
    }
    if (mounted) {
        camera->offset = arm_v;
    } else {
        camera->position = position;
        camera->target = target;
    }
    return RBS_OK;
}

/* Commands move free cameras (and orbit/zoom mounted ones). */
static rbs_status movable(const rbsf__camera *camera, int mounted_ok,
                          const char *what, char *out, size_t outlen)
{
    if (!camera->resolved) {
        snprintf(out, outlen, "%s: the camera is placed at the first frame; "
                 "try again once a frame is drawn", what);
        return RBS_E_INVALID;
    }
    if (camera->def->mode == RBSF__CAMERA_FREE) return RBS_OK;
    if (camera->def->mode == RBSF__CAMERA_MOUNTED) {
        if (mounted_ok) return RBS_OK;
        snprintf(out, outlen, "%s: the camera is mounted on \"%s\" (orbit, zoom "
                 "and reset work)", what, camera->def->mount);
        return RBS_E_INVALID;
    }
    snprintf(out, outlen, "%s: the camera is %s (use \"mode\": \"free\" to "
             "move it)", what,
             camera->def->path_count > 0 ? "on a scripted path" : "fixed");
    return RBS_E_INVALID;
}

rbs_status rbsf__camera_orbit(rbsf__camera *camera, double dyaw, double dpitch,
                              char *out, size_t outlen)
{
    rbs_vec3 e1, e2, scratch, *a, v;
    double d, az, el;
    rbs_status st = movable(camera, 1, "orbit", out, outlen);
    if (st != RBS_OK) return st;
    if (!isfinite(dyaw) || !isfinite(dpitch)) {
        snprintf(out, outlen, "orbit: angles must be finite degrees");
        return RBS_E_INVALID;
    }
    a = arm(camera, &scratch);
    d = len(*a);
    up_frame(camera->up, &e1, &e2);
    /* (the yaw taken modulo a turn first, exactly: "orbit 1e308 0" made an
     * azimuth whose radians overflowed, and was refused as "no usable
     * view" -- a probe of session 46) */
    az = atan2(dot(*a, e2), dot(*a, e1)) * 180.0 / kPi + fmod(dyaw, 360.0);
    el = asin(fmax(-1.0, fmin(1.0, dot(*a, camera->up) / d))) * 180.0 / kPi + dpitch;
    el = fmax(-kMaxElevation, fmin(kMaxElevation, el));
    v = scale(direction(camera->up, az, el), d);
    if ((st = place(camera, v, camera->target, "orbit", out, outlen)) != RBS_OK)
        return st;
    snprintf(out, outlen, "orbit: azimuth %.1f deg, elevation %.1f deg, "
             "distance %.3g m", fmod(az + 540.0, 360.0) - 180.0, el, d);
    return RBS_OK;
}

rbs_status rbsf__camera_pan(rbsf__camera *camera, double dx, double dy,
                            char *out, size_t outlen)
{
    rbs_vec3 fwd, right, up, shift;
    rbs_status st = movable(camera, 0, "pan", out, outlen);
    if (st != RBS_OK) return st;
    if (!isfinite(dx) || !isfinite(dy)) {
        snprintf(out, outlen, "pan: distances must be finite metres");
        return RBS_E_INVALID;
    }
    if (basis(camera->position, camera->target, camera->up,
              camera->has_last_right ? &camera->last_right : NULL, &fwd, &right,
              &up) != NULL) {
        snprintf(out, outlen, "pan: the camera has no usable view to pan in");
        return RBS_E_INVALID;
    }
    shift = add(scale(right, dx), scale(up, dy));
    st = place(camera, sub(camera->position, camera->target),
               add(camera->target, shift), "pan", out, outlen);
    if (st != RBS_OK) return st;
    snprintf(out, outlen, "pan: target (%.3g, %.3g, %.3g) m", camera->target.x,
             camera->target.y, camera->target.z);
    return RBS_OK;
}

rbs_status rbsf__camera_zoom(rbsf__camera *camera, double factor, char *out,
                             size_t outlen)
{
    rbs_vec3 scratch, *a;
    double d;
    rbs_status st = movable(camera, 1, "zoom", out, outlen);
    if (st != RBS_OK) return st;
    if (!(factor > 0.0) || !isfinite(factor)) {
        snprintf(out, outlen, "zoom: factor must be a finite number > 0 "
                 "(2 = twice as close), got %g", factor);
        return RBS_E_INVALID;
    }
    a = arm(camera, &scratch);
    d = len(*a);
    if (!(d / factor > 0.0) || !isfinite(d / factor)) {
        snprintf(out, outlen, "zoom: distance %g m / %g is out of range", d, factor);
        return RBS_E_INVALID;
    }
    st = place(camera, scale(*a, 1.0 / factor), camera->target, "zoom", out, outlen);
    if (st != RBS_OK) return st;
    snprintf(out, outlen, "zoom: distance %.3g m -> %.3g m", d, d / factor);
    return RBS_OK;
}

rbs_status rbsf__camera_reset(rbsf__camera *camera, char *out, size_t outlen)
{
    if (!camera->resolved) {
        snprintf(out, outlen, "reset: nothing to reset before the first frame");
        return RBS_OK;
    }
    camera->position = camera->home_position;
    camera->target = camera->home_target;
    camera->offset = camera->home_offset;
    snprintf(out, outlen, "reset: camera back where it started");
    return RBS_OK;
}

void rbsf__camera_describe(const rbsf__camera *camera, char *out, size_t outlen)
{
    static const char *const modes[] = {"fixed", "mounted", "free"};
    const rbsf__camera_def *def = camera->def;
    const char *mode = modes[def->mode];
    if (!camera->resolved)
        snprintf(out, outlen, "%s camera, placed at the first frame", mode);
    else if (def->mode == RBSF__CAMERA_MOUNTED)
        snprintf(out, outlen, "mounted on \"%s\", offset (%.3g, %.3g, %.3g) m, "
                 "fov %g deg", def->mount, camera->offset.x, camera->offset.y,
                 camera->offset.z, camera->fov);
    else if (def->path_count > 0)
        snprintf(out, outlen, "scripted path of %u keys, fov %g deg",
                 def->path_count, camera->fov);
    else
        snprintf(out, outlen, "%s at (%.3g, %.3g, %.3g) m looking at (%.3g, "
                 "%.3g, %.3g) m, fov %g deg", mode, camera->position.x,
                 camera->position.y, camera->position.z, camera->target.x,
                 camera->target.y, camera->target.z, camera->fov);
}
