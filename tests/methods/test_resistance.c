/*
 * test_resistance.c - rolling and spinning resistance against the exact
 * motion their model (docs/physics.md, step 4) gives, for every method.
 *
 * The model: at a contact of normal force N a couple resists the relative
 * turning, up to mu_r r N about the tangent axes (rolling; mu_r
 * dimensionless, r the sphere's radius) and up to mu_sp N about the
 * normal (spinning; mu_sp in m), each held below its bound as static
 * friction is.  For a solid sphere (I = 2/5 m r^2) rolling without slip on
 * a plane inclined at th, the angular momentum about the contact line
 * (Marion & Thornton, Classical Dynamics, sec. 11; Meriam & Kraige,
 * Dynamics, rolling resistance): (I + m r^2) dw/dt = m g r sin th -+ mu_r r
 * N, N = m g cos th, so the ball accelerates along the slope at
 *   a = 5/7 g (sin th -+ mu_r cos th),
 * the couple against the rolling.  (On a level floor, rolling and spinning
 * to a stop at 5/7 mu_r g and mu_sp m g / I: test_mechanics.c,
 * rolling_and_spinning_resistance_stop_the_ball.)
 *
 * event does not take rolling or spinning resistance (its scope):
 * RBS_E_UNSUPPORTED.  auto takes euler here (one sphere), bit for bit.
 */
#include "methods_common.h"

#define G_ 9.81

static const rbs_method every_method[] = {RBS_METHOD_EULER,  RBS_METHOD_SELECTIVE, RBS_METHOD_EVENT,
                                          RBS_METHOD_VERLET, RBS_METHOD_RK4,       RBS_METHOD_ADAPTIVE,
                                          RBS_METHOD_SOFT,   RBS_METHOD_AUTO};
#define N_METHODS ((int)(sizeof every_method / sizeof every_method[0]))

/* A world for method m: dt, gravity -g z. */
static rbs_world *res_world(rbs_method m, double dt)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = 4;
    d.dt = dt;
    d.gravity.z = -G_;
    d.method = m;
    d.restitution = 0.0;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

/* One material, mu_s = mu_k = 0.5, rolling mur, spinning msp. */
static rbs_material_id res_material(rbs_world *w, double mur, double msp)
{
    rbs_material_id m;
    rbs_pair_def p;
    CHECK_OK(rbs_world_add_material(w, "m", &m));
    rbs_pair_def_init(&p);
    p.a = p.b = m;
    p.static_friction = p.kinetic_friction = 0.5;
    p.restitution = 0.0;
    p.rolling = mur;
    p.spinning = msp;
    CHECK_OK(rbs_world_set_pair(w, &p));
    return m;
}

/* ---- up an incline and back down ---------------------------------------- */

/* The same ball launched rolling at v0 = 1 m/s up a 10-degree incline, mu_r
 * = 0.05 < tan 10 deg (so it does not stay at the top): up at a_u = 5/7 g
 * (sin th + mu_r cos th), to d = v0^2 / (2 a_u) at t1 = v0 / a_u, then
 * back at a_d = 5/7 g (sin th - mu_r cos th), at the start at t2 = t1 +
 * sqrt(2 d / a_d) = 1.49730 s.  Compared at every frame up to t2: the
 * speed and distance along the slope, and rolling without slip (|u - r w|
 * to rounding, 1e-12 m/s; soft's contacts are springs: within 1e-2 dt,
 * measured 8.5e-3 dt).  Bounds, first order at dt = 1 ms and 0.1 ms (and
 * the error must fall 10^(1 +- 0.2) times): the frame of the turn takes one
 * deceleration throughout, off by at most (a_u - a_d) dt in speed, carried
 * to t2; so verlet, rk4 and adaptive within (a_u - a_d) dt (t2 - t1 + dt)
 * (5.9e-4 m at 1 ms; measured 1.9e-4), euler, selective and soft that plus
 * Euler's lag a_u h t2 / 2 (h = dt / 3 for soft). */
static double incline_run(rbs_method m, double dt, double *slip, rbs_status *status);

static void rolling_up_and_down_an_incline(void **state)
{
    const double mur = 0.05, th = 10.0 * PI_ / 180.0;
    const double au = 5.0 / 7.0 * G_ * (sin(th) + mur * cos(th)), ad = 5.0 / 7.0 * G_ * (sin(th) - mur * cos(th));
    const double t1 = 1.0 / au, t2 = t1 + sqrt(2.0 * (0.5 / au) / ad);
    int k, j;
    (void)state;
    for (k = 0; k < N_METHODS; ++k) {
        rbs_method m = every_method[k];
        double e[2], sl[2];
        const double dts[2] = {1e-3, 1e-4};
        for (j = 0; j < 2; ++j) {
            rbs_status st;
            double dt = dts[j], h = m == RBS_METHOD_SOFT ? dt / 3 : dt;
            double turn = (au - ad) * dt * (t2 - t1 + dt);
            e[j] = incline_run(m, dt, &sl[j], &st);
            if (m == RBS_METHOD_EVENT) {
                assert_int_equal(st, RBS_E_UNSUPPORTED);
                continue;
            }
            assert_int_equal(st, RBS_OK);
            assert_true(sl[j] < (m == RBS_METHOD_SOFT ? 1e-2 * dt : 1e-12));
            if (m == RBS_METHOD_VERLET || m == RBS_METHOD_RK4 || m == RBS_METHOD_ADAPTIVE)
                assert_true(e[j] < turn);
            else
                assert_true(e[j] < turn + au * h * t2 / 2);
        }
        if (m != RBS_METHOD_EVENT) {
            print_message("%-9s: order %.2f\n", rbs_method_name(m), log10(e[0] / e[1]));
            ASSERT_NEAR(log10(e[0] / e[1]), 1.0, 0.2);
        }
    }
}


static double incline_run(rbs_method m, double dt, double *slip, rbs_status *status_out)
{
    const double r = 0.1, v0 = 1.0, mur = 0.05, th = 10.0 * PI_ / 180.0;
    const double au = 5.0 / 7.0 * G_ * (sin(th) + mur * cos(th)), ad = 5.0 / 7.0 * G_ * (sin(th) - mur * cos(th));
    const double t1 = v0 / au, d = v0 * v0 / (2.0 * au), t2 = t1 + sqrt(2.0 * d / ad);
    {
        rbs_world *w = res_world(m, dt);
        rbs_material_id mat = res_material(w, mur, 0.0);
        rbs_sphere_def s;
        rbs_plane_def p;
        rbs_body_id b;
        rbs_status status = RBS_OK;
        double worst = 0.0, wslip = 0.0;
        long f, n = (long)(t2 / dt);
        rbs_plane_def_init(&p);
        p.normal.x = -sin(th);
        p.normal.z = cos(th);
        p.material = mat;
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
        rbs_sphere_def_init(&s);
        s.radius = r;
        s.position.x = -r * sin(th);
        s.position.z = r * cos(th);
        s.velocity.x = v0 * cos(th);
        s.velocity.z = v0 * sin(th);
        s.angular_velocity.y = v0 / r;
        s.material = mat;
        CHECK_OK(rbs_world_add_sphere(w, &s, &b));
        for (f = 1; f <= n && status == RBS_OK; ++f) {
            rbs_body_state st;
            double t, u, su, ue, se;
            status = rbs_world_step(w, NULL);
            t = rbs_world_time(w);
            st = state_of(w, b);
            /* speed and distance up the slope */
            u = st.velocity.x * cos(th) + st.velocity.z * sin(th);
            su = (st.position.x + r * sin(th)) * cos(th) + (st.position.z - r * cos(th)) * sin(th);
            if (t < t1) {
                ue = v0 - au * t;
                se = v0 * t - 0.5 * au * t * t;
            } else {
                ue = -ad * (t - t1);
                se = d - 0.5 * ad * (t - t1) * (t - t1);
            }
            if (fabs(u - ue) > worst) worst = fabs(u - ue);
            if (fabs(su - se) > worst) worst = fabs(su - se);
            if (fabs(u - r * st.angular_velocity.y) > wslip) wslip = fabs(u - r * st.angular_velocity.y);
        }
        print_message("%-9s dt %.0e: %s worst %.3e m, m/s, slip %.3e m/s\n", rbs_method_name(m), dt,
                      rbs_status_name(status), worst, wslip);
        rbs_world_destroy(w);
        *slip = wslip;
        *status_out = status;
        return worst;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rolling_up_and_down_an_incline),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
