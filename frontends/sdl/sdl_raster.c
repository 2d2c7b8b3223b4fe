/*
 * sdl_raster.c - draw one view of a frame by ray casting, exact per pixel.
 *
 * Camera space: x right, y up, z along the view direction (depth).  The ray
 * through the centre of pixel (i, j) is d = (ray_x[i], ray_y[j], 1) with
 * ray_x[i] = (i + 1/2 - W/2) / f and ray_y[j] = (H/2 - j - 1/2) / f, where
 * f = (H/2) / tan(fov/2) (gluPerspective's vertical field of view), so a hit
 * at ray parameter t has depth z = t.  A surface is drawn where
 * near <= z <= far and z is less than what the depth buffer holds.
 *
 * Planes: every pixel's ray meets the plane at t = ((p - eye).n) / (d.n);
 * they end at the far plane (the "finite extent").  Spheres: only the pixels
 * inside the sphere's projected bounding box are tried.  The box is exact:
 * the silhouette's extreme x/z (and y/z) are the tangents from the eye to the
 * circle the sphere projects to on the xz (yz) plane, tan(theta +- alpha)
 * with tan(theta) = x/z and sin(alpha) = r / sqrt(x^2 + z^2), valid when the
 * sphere lies wholly in front of the eye (z > r); otherwise the whole view is
 * tried.  Rays are solved with the quadratic |t d - c|^2 = r^2; when the near
 * plane cuts a sphere, its inside (far root) shows, as a clipped solid would.
 *
 * Shading: ambient + diffuse (Lambert) from a light fixed to the camera, up
 * and to the left of it.  Textures live in the body frame: the world normal
 * at a sphere's hit point is rotated by the conjugate of the body's
 * orientation q = [w x y z] (body -> world).  STRIPES: 8 sectors of longitude
 * about the body z axis alternate base and dark colours (a beach ball);
 * CHECKER: the sectors also alternate across 4 bands of body z.  Planes: a
 * checker of RBSF__PLANE_CELL metre squares on in-plane axes (x and y for a
 * normal along z; the cell with a corner at the plane's point and lying on
 * the positive axes is the light one); STRIPES: bands along the first axis.
 * Far away, where a pixel spans more than a quarter of a cell, the pattern
 * fades into the cells' mean colour instead of aliasing into moire.
 */
#include <float.h>
#include <math.h>

#include "sdl_internal.h"

/* Light direction (towards the light) in camera space, unnormalised, and the
 * ambient share of the light. */
static const double kLight[3] = {-0.35, 0.5, -1.0};
static const double kAmbient = 0.25;
/* The texture's second colour is the base colour times this. */
static const double kDark = 0.5;
/* Sky: top and bottom colours of the background gradient. */
static const uint32_t kSkyTop = 0x8fb8deu, kSkyBottom = 0xe4ecf4u;

typedef struct v3 {
    double x, y, z;
} v3;

static double dot3(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

static uint32_t pack(double r, double g, double b)
{
    /* r, g, b in [0, 255]; round to nearest. */
    uint32_t R = (uint32_t)(fmin(255.0, fmax(0.0, r)) + 0.5);
    uint32_t G = (uint32_t)(fmin(255.0, fmax(0.0, g)) + 0.5);
    uint32_t B = (uint32_t)(fmin(255.0, fmax(0.0, b)) + 0.5);
    return 0xff000000u | (R << 16) | (G << 8) | B;
}

/* Colour 0xRRGGBB times k. */
static uint32_t tint(uint32_t rgb, double k)
{
    return pack(k * (double)((rgb >> 16) & 0xff), k * (double)((rgb >> 8) & 0xff),
                k * (double)(rgb & 0xff));
}

/* Two unit vectors spanning the plane of normal n (x and y for n = z). */
static void plane_axes(v3 n, v3 *e1, v3 *e2)
{
    v3 a = {0, 0, 0};
    double ax = fabs(n.x), ay = fabs(n.y), az = fabs(n.z), l, k;
    if (ax <= ay && ax <= az) a.x = 1;
    else if (ay <= az) a.y = 1;
    else a.z = 1;
    k = dot3(a, n);
    e1->x = a.x - k * n.x;
    e1->y = a.y - k * n.y;
    e1->z = a.z - k * n.z;
    l = sqrt(dot3(*e1, *e1));
    e1->x /= l;
    e1->y /= l;
    e1->z /= l;
    e2->x = n.y * e1->z - n.z * e1->y;
    e2->y = n.z * e1->x - n.x * e1->z;
    e2->z = n.x * e1->y - n.y * e1->x;
}

/* Rotate v by the conjugate of unit quaternion q = [w x y z]:
 * world -> body.  v' = v + 2 w (u x v) + 2 u x (u x v) with u = -q.xyz. */
static v3 to_body(const double q[4], v3 v)
{
    double w = q[0], ux = -q[1], uy = -q[2], uz = -q[3];
    double cx = uy * v.z - uz * v.y, cy = uz * v.x - ux * v.z,
           cz = ux * v.y - uy * v.x;
    v3 r;
    r.x = v.x + 2.0 * (w * cx + (uy * cz - uz * cy));
    r.y = v.y + 2.0 * (w * cy + (uz * cx - ux * cz));
    r.z = v.z + 2.0 * (w * cz + (ux * cy - uy * cx));
    return r;
}

/* 1 on the dark cells of a sphere's texture at body-frame unit normal n. */
static int sphere_dark(int32_t texture, v3 n)
{
    int sector;
    if (texture != RBS_TEXTURE_STRIPES && texture != RBS_TEXTURE_CHECKER)
        return 0;
    /* 8 sectors of 45 degrees in longitude about body z. */
    sector = (n.x > 0.0) ^ (n.y > 0.0) ^ (fabs(n.x) > fabs(n.y));
    if (texture == RBS_TEXTURE_STRIPES) return sector;
    return sector ^ ((int)floor((n.z + 1.0) * 2.0) & 1);
}

static void clear(const rbsf__canvas *cv, uint32_t w, uint32_t h)
{
    uint32_t i, j;
    for (j = 0; j < h; j++) {
        double s = h > 1 ? (double)j / (double)(h - 1) : 0.0;
        uint32_t c = pack(
            (1 - s) * ((kSkyTop >> 16) & 0xff) + s * ((kSkyBottom >> 16) & 0xff),
            (1 - s) * ((kSkyTop >> 8) & 0xff) + s * ((kSkyBottom >> 8) & 0xff),
            (1 - s) * (kSkyTop & 0xff) + s * (kSkyBottom & 0xff));
        uint32_t *row = cv->pixels + (size_t)j * cv->pitch;
        double *depth = cv->depth + (size_t)j * w;
        for (i = 0; i < w; i++) {
            row[i] = c;
            depth[i] = DBL_MAX;
        }
    }
}

/* World vector to camera space. */
static v3 to_camera(const rbsf__view *v, v3 w)
{
    v3 r;
    r.x = w.x * v->right.x + w.y * v->right.y + w.z * v->right.z;
    r.y = w.x * v->up.x + w.y * v->up.y + w.z * v->up.z;
    r.z = w.x * v->fwd.x + w.y * v->fwd.y + w.z * v->fwd.z;
    return r;
}

static v3 from_array(const double *a)
{
    v3 r;
    r.x = a[0];
    r.y = a[1];
    r.z = a[2];
    return r;
}

static void draw_plane(const rbsf__canvas *cv, const rbsf__view *v,
                       const rbs_frame_body *b, v3 light)
{
    uint32_t i, j, w = v->width, h = v->height;
    v3 n = from_array(b->normal), p = from_array(b->position), rel, nc, e1, e2;
    double l = sqrt(dot3(n, n)), num, diffuse, s0, t0, lum;
    double sR, sU, sF, tR, tU, tF;
    uint32_t col[2], mean;
    /* NONE (and any unknown value) is plain, as for spheres. */
    int patterned = b->texture == RBS_TEXTURE_STRIPES || b->texture == RBS_TEXTURE_CHECKER;
    if (!(l > 0.0) || !isfinite(l)) return; /* not a plane: nothing to draw */
    n.x /= l;
    n.y /= l;
    n.z /= l;
    rel.x = p.x - v->eye.x;
    rel.y = p.y - v->eye.y;
    rel.z = p.z - v->eye.z;
    nc = to_camera(v, n);
    num = dot3(rel, n); /* < 0: the eye is on the open side */
    /* Shade with the normal facing the eye. */
    {
        v3 f = nc;
        if (num > 0) {
            f.x = -f.x;
            f.y = -f.y;
            f.z = -f.z;
        }
        diffuse = fmax(0.0, dot3(f, light));
    }
    lum = kAmbient + (1.0 - kAmbient) * diffuse;
    col[0] = tint(b->color, lum);
    col[1] = tint(b->color, kDark * lum);
    mean = tint(b->color, 0.5 * (1.0 + kDark) * lum);
    /* In-plane coordinates of the hit eye + t D, D = rx R + ry U + F. */
    plane_axes(n, &e1, &e2);
    s0 = -dot3(rel, e1);
    t0 = -dot3(rel, e2);
    sR = v->right.x * e1.x + v->right.y * e1.y + v->right.z * e1.z;
    sU = v->up.x * e1.x + v->up.y * e1.y + v->up.z * e1.z;
    sF = v->fwd.x * e1.x + v->fwd.y * e1.y + v->fwd.z * e1.z;
    tR = v->right.x * e2.x + v->right.y * e2.y + v->right.z * e2.z;
    tU = v->up.x * e2.x + v->up.y * e2.y + v->up.z * e2.z;
    tF = v->fwd.x * e2.x + v->fwd.y * e2.y + v->fwd.z * e2.z;
    for (j = 0; j < h; j++) {
        double ry = cv->ray_y[j];
        double dny = ry * nc.y + nc.z;
        uint32_t *row = cv->pixels + (size_t)j * cv->pitch;
        double *depth = cv->depth + (size_t)j * w;
        for (i = 0; i < w; i++) {
            double rx = cv->ray_x[i];
            double den = rx * nc.x + dny, t, s, u, cells;
            int dark;
            if (den == 0.0) continue;
            t = num / den;
            if (!(t >= v->znear && t <= v->zfar) || t >= depth[i])
                continue;
            depth[i] = t;
            /* The pixel's footprint on the plane, in cells: distance / focal
             * stretched by the slant, t |d|^2 / (f |d.n|).  Where a pixel
             * spans more than a quarter of a cell the checker would alias
             * (moire), so it fades to the cells' mean colour. */
            cells = t * (rx * rx + ry * ry + 1.0) / (v->focal * fabs(den) * RBSF__PLANE_CELL);
            if (!patterned || cells >= 0.75) {
                row[i] = patterned ? mean : col[0];
                continue;
            }
            s = s0 + t * (rx * sR + ry * sU + sF);
            u = t0 + t * (rx * tR + ry * tU + tF);
            if (b->texture == RBS_TEXTURE_STRIPES)
                dark = (int)((int64_t)floor(s / RBSF__PLANE_CELL) & 1);
            else
                dark = (int)(((int64_t)floor(s / RBSF__PLANE_CELL) +
                              (int64_t)floor(u / RBSF__PLANE_CELL)) & 1);
            if (cells <= 0.25) {
                row[i] = col[dark];
            } else {
                double a = (cells - 0.25) / 0.5, k = (1.0 - a) * (dark ? kDark : 1.0) +
                                                     a * 0.5 * (1.0 + kDark);
                row[i] = tint(b->color, k * lum);
            }
        }
    }
}

/* Pixels [lo, hi] (clipped to [0, size-1]; empty if hi < lo) whose centres
 * may lie between the silhouette's tangent slopes a <= b on one axis. */
static void span(double a, double b, double focal, double half, int size,
                 int flip, int *lo, int *hi)
{
    double p0, p1;
    if (flip) { /* screen v grows downwards */
        p0 = half - focal * b;
        p1 = half - focal * a;
    } else {
        p0 = half + focal * a;
        p1 = half + focal * b;
    }
    /* Pixel k's centre is k + 1/2; one pixel of margin for rounding. */
    p0 = floor(p0 - 0.5) - 1.0;
    p1 = ceil(p1 - 0.5) + 1.0;
    *lo = p0 < 0.0 ? 0 : (p0 > (double)size ? size : (int)p0);
    *hi = p1 > (double)(size - 1) ? size - 1 : (p1 < -1.0 ? -1 : (int)p1);
}

/* Tangent slopes (x/z) of the silhouette for centre (x, z), radius r; 0 if
 * the sphere is not wholly in front of the eye. */
static int slopes(double x, double z, double r, double *a, double *b)
{
    double d2 = x * x + z * z, t;
    if (!(z > r * (1.0 + 1e-9))) return 0;
    t = sqrt(d2 - r * r);
    *a = (x * t - r * z) / (z * t + r * x);
    *b = (x * t + r * z) / (z * t - r * x);
    return 1;
}

static void draw_sphere(const rbsf__canvas *cv, const rbsf__view *v,
                        const rbs_frame_body *b, v3 light)
{
    int w = (int)v->width, h = (int)v->height, i0, i1, j0, j1, i, j;
    v3 rel, c;
    double r = b->radius, a, bb;
    double base[3], dark[3];
    uint32_t rgb = b->color;
    if (!(r > 0.0) || !isfinite(r)) return;
    rel.x = b->position[0] - v->eye.x;
    rel.y = b->position[1] - v->eye.y;
    rel.z = b->position[2] - v->eye.z;
    c = to_camera(v, rel);
    if (!isfinite(c.x + c.y + c.z)) return;
    if (c.z + r < v->znear || c.z - r > v->zfar) return;
    /* Screen box from the exact silhouette tangents. */
    if (slopes(c.x, c.z, r, &a, &bb)) {
        span(a, bb, v->focal, 0.5 * w, w, 0, &i0, &i1);
    } else {
        i0 = 0;
        i1 = w - 1;
    }
    if (slopes(c.y, c.z, r, &a, &bb)) {
        span(a, bb, v->focal, 0.5 * h, h, 1, &j0, &j1);
    } else {
        j0 = 0;
        j1 = h - 1;
    }
    base[0] = (double)((rgb >> 16) & 0xff);
    base[1] = (double)((rgb >> 8) & 0xff);
    base[2] = (double)(rgb & 0xff);
    dark[0] = kDark * base[0];
    dark[1] = kDark * base[1];
    dark[2] = kDark * base[2];
    for (j = j0; j <= j1; j++) {
        double ry = cv->ray_y[j];
        uint32_t *row = cv->pixels + (size_t)j * cv->pitch;
        double *depth = cv->depth + (size_t)j * (size_t)w;
        for (i = i0; i <= i1; i++) {
            double rx = cv->ray_x[i];
            /* Stable: tc is the ray parameter nearest the centre, q the
             * perpendicular from the centre to the ray (|c|^2 - tc^2 dd
             * would cancel catastrophically when the sphere is far away). */
            double dd = rx * rx + ry * ry + 1.0;
            double tc = (rx * c.x + ry * c.y + c.z) / dd, half, t, k, lum;
            double qx = tc * rx - c.x, qy = tc * ry - c.y, qz = tc - c.z;
            double h2 = r * r - (qx * qx + qy * qy + qz * qz);
            int inside = 0;
            const double *col;
            v3 n, nw;
            if (h2 < 0.0) continue;
            half = sqrt(h2 / dd);
            t = tc - half;
            if (t < v->znear) {
                t = tc + half;
                inside = 1;
            }
            if (t < v->znear || t > v->zfar || t >= depth[i]) continue;
            /* Unit normal in camera space, facing the eye. */
            k = (inside ? -1.0 : 1.0) / r;
            n.x = (t * rx - c.x) * k;
            n.y = (t * ry - c.y) * k;
            n.z = (t - c.z) * k;
            lum = kAmbient + (1.0 - kAmbient) * fmax(0.0, dot3(n, light));
            col = base;
            if (b->texture == RBS_TEXTURE_STRIPES || b->texture == RBS_TEXTURE_CHECKER) {
                /* Outward normal in world, then in the body frame. */
                double o = inside ? -1.0 : 1.0;
                nw.x = o * (n.x * v->right.x + n.y * v->up.x + n.z * v->fwd.x);
                nw.y = o * (n.x * v->right.y + n.y * v->up.y + n.z * v->fwd.y);
                nw.z = o * (n.x * v->right.z + n.y * v->up.z + n.z * v->fwd.z);
                if (sphere_dark(b->texture, to_body(b->orientation, nw)))
                    col = dark;
            }
            row[i] = pack(lum * col[0], lum * col[1], lum * col[2]);
            depth[i] = t;
        }
    }
}

void rbsf__raster_frame(const rbsf__canvas *cv, const rbsf__view *v,
                        const rbs_frame *frame)
{
    uint32_t i, w = v->width, h = v->height;
    v3 light = {kLight[0], kLight[1], kLight[2]};
    double l = sqrt(dot3(light, light));
    light.x /= l;
    light.y /= l;
    light.z /= l;
    for (i = 0; i < w; i++)
        cv->ray_x[i] = ((double)i + 0.5 - 0.5 * (double)w) / v->focal;
    for (i = 0; i < h; i++)
        cv->ray_y[i] = (0.5 * (double)h - (double)i - 0.5) / v->focal;
    clear(cv, w, h);
    for (i = 0; i < frame->body_count; i++)
        if (frame->bodies[i].type == RBS_BODY_PLANE)
            draw_plane(cv, v, &frame->bodies[i], light);
    for (i = 0; i < frame->body_count; i++)
        if (frame->bodies[i].type == RBS_BODY_SPHERE)
            draw_sphere(cv, v, &frame->bodies[i], light);
}
