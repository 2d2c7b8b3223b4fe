/*
 * test_vec.c - the core's own sine and cosine for small angles, its turns
 * by a rotation vector, and that a step of spinning spheres never calls
 * libm's.
 *
 * rbs__sincos (lib/src/core/vec.h) sums the Taylor series of sin and cos
 * for |x| <= 1/8 and calls libm beyond.  Its answers are compared with
 * sinl and cosl (x87 extended precision, 64-bit significands: their error,
 * about 2^-64 relative, is far below a double's ulp), and must be within
 * one ulp of the double nearest the true value: the series' remainders
 * are under 3e-18 and 3e-20 (x^11 / 11!, x^12 / 12! at 1/8), and the Horner
 * sums round about half an ulp each.  Beyond 1/8 the answers are libm's,
 * bit for bit.  Internal: linked against the library's objects, with
 * sin, cos and sincos wrapped at link time, so that the count of libm
 * calls made while piles of spinning spheres step can be checked: zero.
 */
#include <float.h>
#include <math.h>

#include "common.h"
#include "core/vec.h"

/* libm, counted: the library's objects call these through the wraps. */
static unsigned long libm_calls; /* (test-only counter; one thread) */
double __real_sin(double x);
double __real_cos(double x);
void __real_sincos(double x, double *s, double *c);
double __wrap_sin(double x);
double __wrap_cos(double x);
void __wrap_sincos(double x, double *s, double *c);
double __wrap_sin(double x)
{
    libm_calls++;
    return __real_sin(x);
}
double __wrap_cos(double x)
{
    libm_calls++;
    return __real_cos(x);
}
void __wrap_sincos(double x, double *s, double *c)
{
    libm_calls++;
    __real_sincos(x, s, c);
}

/* |got - want| in ulps of the double nearest want. */
static double ulps(double got, long double want)
{
    double near = (double)want;
    double ulp = nextafter(fabs(near), INFINITY) - fabs(near);
    if (near == 0.0)
        ulp = (DBL_MIN * DBL_EPSILON);
    return (double)(fabsl((long double)got - want) / ulp);
}

static void small_angles_within_an_ulp(void **state)
{
    const int n = 200000;
    double worst_s = 0.0, worst_c = 0.0;
    int i;
    (void)state;
    for (i = -n; i <= n; ++i) {
        double x = 0.125 * i / n, s, c;
        rbs__sincos(x, &s, &c);
        worst_s = fmax(worst_s, ulps(s, sinl((long double)x)));
        worst_c = fmax(worst_c, ulps(c, cosl((long double)x)));
    }
    /* tiny, subnormal and signed zero arguments: sin x = x, cos x = 1 */
    {
        const double tiny[] = {0.0, -0.0, (DBL_MIN * DBL_EPSILON), -DBL_MIN, 1e-300, 1e-8, -3e-5, 0.125, -0.125};
        for (i = 0; i < (int)(sizeof tiny / sizeof tiny[0]); ++i) {
            double s, c;
            rbs__sincos(tiny[i], &s, &c);
            worst_s = fmax(worst_s, ulps(s, sinl((long double)tiny[i])));
            worst_c = fmax(worst_c, ulps(c, cosl((long double)tiny[i])));
            assert_true(!signbit(s) == !signbit(tiny[i]));
        }
    }
    print_message("worst error: sin %.3f ulp, cos %.3f ulp\n", worst_s, worst_c);
    assert_true(worst_s <= 1.0);
    assert_true(worst_c <= 1.0);
}

static void larger_angles_are_libms(void **state)
{
    const double xs[] = {0.12500000000000003, -0.13, 0.5, 1.0, -2.0, 3.14159, 100.0, 1e6};
    int i;
    (void)state;
    for (i = 0; i < (int)(sizeof xs / sizeof xs[0]); ++i) {
        double s, c;
        rbs__sincos(xs[i], &s, &c);
        assert_true(s == sin(xs[i]));
        assert_true(c == cos(xs[i]));
    }
}

/* q_from_rotation turns by |w| h about w: on both sides of 1/8 (the
 * series and libm), a turn about an oblique axis keeps the axis and turns a
 * perpendicular vector by the angle (rounding: 1e-15). */
static void rotations_turn_by_the_angle(void **state)
{
    const double angles[] = {1e-9, 1e-4, 0.01, 0.2, 0.25, 0.26, 1.5707963267948966, 3.0};
    v3 axis = v3_scale(v3_make(1.0, 2.0, 2.0), 1.0 / 3.0), perp = v3_scale(v3_make(2.0, 1.0, -2.0), 1.0 / 3.0);
    int i;
    (void)state;
    for (i = 0; i < (int)(sizeof angles / sizeof angles[0]); ++i) {
        double a = angles[i];
        quat q = q_from_rotation(v3_scale(axis, 2.0), 0.5 * a); /* |w| h = a */
        v3 ra = q_rotate(q, axis), rp = q_rotate(q, perp);
        v3 want = v3_add(v3_scale(perp, cos(a)), v3_scale(v3_cross(axis, perp), sin(a)));
        assert_true(fabs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1.0) < 1e-15);
        assert_true(v3_len(v3_sub(ra, axis)) < 1e-15);
        assert_true(v3_len(v3_sub(rp, want)) < 1e-15);
    }
}

/* q_from_turn (the soft step's write-back): for half angles up to 1/8 its
 * components within 2 ulps of cos x and th sin x / (2 x) in extended
 * precision (the series: about an ulp, and one more rounding in the
 * product with th), about axes along and across the coordinates; beyond,
 * q_from_rotation's bit for bit. */
static void turns_within_two_ulps(void **state)
{
    const double axes[3][3] = {{1.0, 0.0, 0.0}, {0.6, -0.8, 0.0}, {1.0 / 3.0, 2.0 / 3.0, -2.0 / 3.0}};
    const int n = 20000;
    double worst = 0.0;
    int i, k;
    (void)state;
    for (k = 0; k < 3; ++k)
        for (i = -n; i <= n; ++i) {
            const double a = 0.25 * i / n; /* the angle: x = |a| / 2 up to 1/8 */
            const v3 th = v3_make(a * axes[k][0], a * axes[k][1], a * axes[k][2]);
            const quat q = q_from_turn(th);
            const long double x = 0.5L * sqrtl((long double)th.x * th.x + (long double)th.y * th.y +
                                               (long double)th.z * th.z);
            const long double so = x > 0.0L ? sinl(x) / (2.0L * x) : 0.5L;
            worst = fmax(worst, ulps(q.w, cosl(x)));
            worst = fmax(worst, ulps(q.x, th.x * so));
            worst = fmax(worst, ulps(q.y, th.y * so));
            worst = fmax(worst, ulps(q.z, th.z * so));
        }
    print_message("worst error of a turn: %.3f ulp\n", worst);
    assert_true(worst <= 2.0);
    for (i = 0; i < 4; ++i) {
        const double a = (double[]){0.2500001, -0.3, 1.0, 3.0}[i];
        const v3 th = v3_make(a * axes[2][0], a * axes[2][1], a * axes[2][2]);
        const quat q = q_from_turn(th), r = q_from_rotation(th, 1.0);
        assert_true(q.w == r.w && q.x == r.x && q.y == r.y && q.z == r.z);
    }
}

/* A heap of spheres, each spinning at up to 40 rad/s, on a floor with
 * friction: stepped by the pile's method and by euler, no call of libm's
 * sine or cosine, and every sphere has turned. */
static void spinning_piles_never_call_libm(void **state)
{
    const rbs_method methods[] = {RBS_METHOD_SOFT, RBS_METHOD_EULER, RBS_METHOD_AUTO};
    int m;
    (void)state;
    for (m = 0; m < 3; ++m) {
        rbs_world_def d;
        rbs_world *w = NULL;
        rbs_plane_def p;
        rbs_body_id id[40];
        int i, k;
        rbs_world_def_init(&d);
        d.max_bodies = 41;
        d.gravity.z = -9.81;
        d.method = methods[m];
        CHECK_OK(rbs_world_create(&d, &w));
        rbs_plane_def_init(&p);
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        for (i = 0; i < 40; ++i) {
            rbs_sphere_def s;
            rbs_sphere_def_init(&s);
            s.radius = 0.05;
            s.position.x = 0.1 * (i % 5);
            s.position.y = 0.1 * ((i / 5) % 4);
            s.position.z = 0.05 + 0.11 * (i / 20);
            s.angular_velocity.x = (double)(i % 7) - 3.0;
            s.angular_velocity.z = 40.0 * ((i % 3) - 1);
            s.angular_velocity.y = 5.0;
            CHECK_OK(rbs_world_add_sphere(w, &s, &id[i]));
        }
        libm_calls = 0;
        for (k = 0; k < 200; ++k)
            CHECK_OK(rbs_world_step(w, NULL));
        assert_int_equal(libm_calls, 0);
        for (i = 0; i < 40; ++i) {
            rbs_body_state bs;
            CHECK_OK(rbs_body_get_state(w, id[i], &bs));
            assert_true(fabs(bs.orientation.w) < 1.0 - 1e-6);
        }
        rbs_world_destroy(w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(small_angles_within_an_ulp),
        cmocka_unit_test(larger_angles_are_libms),
        cmocka_unit_test(rotations_turn_by_the_angle),
        cmocka_unit_test(turns_within_two_ulps),
        cmocka_unit_test(spinning_piles_never_call_libm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
