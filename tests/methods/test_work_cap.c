/*
 * test_work_cap.c - the work cap (rbs_world_def.max_substeps): what a step
 * may spend, when it says it hit the cap (work_limit), and that a capped
 * step stays stable.
 */
#include "methods_common.h"

static const rbs_method rollback_methods[3] = {RBS_METHOD_EULER, RBS_METHOD_VERLET, RBS_METHOD_RK4};

/* A world for method m with the work cap max_substeps, gravity gz along z
 * and restitution e. */
static rbs_world *cap_world(rbs_method m, uint32_t max_substeps, double dt, double gz, double e)
{
    rbs_world_def d;
    rbs_world *w = NULL;
    rbs_world_def_init(&d);
    d.max_bodies = 8;
    d.dt = dt;
    d.gravity.z = gz;
    d.restitution = e;
    d.method = m;
    d.max_substeps = max_substeps;
    CHECK_OK(rbs_world_create(&d, &w));
    return w;
}

/* A frame taken in one clean sub-step is not capped, even at a cap of 1:
 * the two-body orbit (mutual gravity, no contact) with euler, verlet and
 * rk4, and adaptive's resting-contact rk4 path (a touching row of balls,
 * the first moving into the others).  work_limit said every step hit the
 * cap. */
static void clean_frame_at_cap_is_not_capped(void **state)
{
    int k, f;
    (void)state;
    for (k = 0; k < 3; ++k) {
        rbs_world_def d;
        rbs_world *w = NULL;
        rbs_body_id a, b;
        rbs_world_def_init(&d);
        d.max_bodies = 4;
        d.dt = 1e-3;
        d.gravity.z = 0.0;
        d.method = rollback_methods[k];
        d.mutual_gravity = 1;
        d.gravity_constant = 1.0;
        d.max_substeps = 1;
        CHECK_OK(rbs_world_create(&d, &w));
        a = point_mass(w, 1.0, 0.5, 0.0, 0.0, 0.5 * sqrt(2.0));
        b = point_mass(w, 1.0, -0.5, 0.0, 0.0, -0.5 * sqrt(2.0));
        (void)a, (void)b;
        for (f = 0; f < 100; ++f) {
            rbs_step_info info;
            CHECK_OK(rbs_world_step(w, &info));
            assert_int_equal(info.substeps, 1);
            assert_int_equal(info.work_limit, 0);
        }
        rbs_world_destroy(w);
    }
    {
        rbs_world *w = cap_world(RBS_METHOD_ADAPTIVE, 1, 1e-3, 0.0, 1.0);
        int i;
        ball(w, 0.0625, 1.0, 0.0, 0, 0, 1.0, 0, 0, (rbs_material_id){0, 0});
        for (i = 1; i < 5; ++i)
            ball(w, 0.0625, 1.0, 0.125 * i, 0, 0, 0, 0, 0, (rbs_material_id){0, 0});
        for (f = 0; f < 100; ++f) {
            rbs_step_info info;
            CHECK_OK(rbs_world_step(w, &info));
            assert_int_equal(info.work_limit, 0);
        }
        rbs_world_destroy(w);
    }
}

/* The cap bounds a step's tries strictly: sub-steps + rollbacks <= cap
 * (they overshot by up to max_halvings + 1: rollbacks were checked only
 * after an accepted sub-step).  The 1e4:1 pi billiard at dt = 10 ms (314
 * impacts, many in one frame) with caps 1 to 9; the steps past their cap
 * say so. */
static void cap_is_strict(void **state)
{
    uint32_t cap;
    int k;
    (void)state;
    for (k = 0; k < 3; ++k) {
        for (cap = 1; cap <= 9; ++cap) {
            rbs_world *w = cap_world(rollback_methods[k], cap, 1e-2, 0.0, 1.0);
            rbs_plane_def p;
            int f, capped = 0;
            rbs_plane_def_init(&p);
            p.normal.x = 1.0;
            p.normal.z = 0.0;
            CHECK_OK(rbs_world_add_plane(w, &p, NULL));
            ball(w, 0.1, 1.0, 0.5, 0, 0, 0, 0, 0, (rbs_material_id){0, 0});
            ball(w, 0.1, 1e4, 1.0, 0, 0, -1.0, 0, 0, (rbs_material_id){0, 0});
            for (f = 0; f < 300; ++f) {
                rbs_step_info info;
                CHECK_OK(rbs_world_step(w, &info));
                if (info.substeps + info.rollbacks > cap)
                    fail_msg("%s, cap %u, step %d: %u sub-steps + %u rollbacks",
                             rbs_method_name(rollback_methods[k]), (unsigned)cap, f, (unsigned)info.substeps,
                             (unsigned)info.rollbacks);
                capped += info.work_limit != 0;
            }
            assert_true(capped > 0);
            rbs_world_destroy(w);
        }
    }
}

/* Total angular momentum (about the origin) and energy. */
static void spin_invariants(const rbs_world *w, double *L, double *E)
{
    rbs_vec3 l;
    rbs_energy e;
    CHECK_OK(rbs_world_momentum(w, NULL, &l));
    CHECK_OK(rbs_world_energy(w, &e));
    *L = sqrt(l.x * l.x + l.y * l.y + l.z * l.z);
    *E = e.total;
}

/* A top (principal moments 0.002, 0.003, 0.004 kg m^2) spinning at w0
 * about near its axis of least inertia, whose rotation needs more rotation
 * sub-steps than the step's budget (max_substeps * 256) allows; each step
 * reports work_limit.  Verlet and rk4 took the turn past the budget in one
 * sub-step of their own, which they cannot take: the energy went from 9e7
 * J to 5e306 J and NaN in three steps.  The exact motion keeps |L| and the
 * energy.  Accepted: |L| to 1e-12 relative (the stable update keeps it but
 * for rounding over up to 2e7 parts); the energy to 1e-5 relative: with
 * |L| kept the energy cannot exceed |L|^2 / (2 I_min), 8.3e-6 above the
 * start here (the spin about x is the state of most energy for its |L|);
 * a fall below would mean the spin had left its (stable) axis. */
static void spent_spin_budget_is_stable_one(rbs_method m, uint32_t cap, double dt, double w0, int steps)
{
    rbs_world *w = cap_world(m, cap, dt, 0.0, 1.0);
    rbs_sphere_def s;
    double L0, E0, L, E;
    int f;
    rbs_sphere_def_init(&s);
    s.radius = 0.1;
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = 0.002; s.inertia.y = 0.003; s.inertia.z = 0.004;
    s.angular_velocity.x = w0;
    s.angular_velocity.y = 1000.0;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    spin_invariants(w, &L0, &E0);
    for (f = 0; f < steps; ++f) {
        rbs_step_info info;
        rbs_status st = rbs_world_step(w, &info);
        if (st != RBS_OK)
            fail_msg("%s, cap %u, step %d: %s", rbs_method_name(m), (unsigned)cap, f, rbs_world_last_error(w));
        assert_int_equal(info.work_limit, 1);
        spin_invariants(w, &L, &E);
        if (!(fabs(L - L0) <= 1e-12 * L0) || !(fabs(E - E0) <= 1e-5 * E0))
            fail_msg("%s, cap %u, step %d: |L| %.17g (start %.17g), energy %.17g J (start %.17g J)",
                     rbs_method_name(m), (unsigned)cap, f, L, L0, E, E0);
    }
    rbs_world_destroy(w);
}

static void spent_spin_budget_is_stable(void **state)
{
    int k;
    (void)state;
    for (k = 1; k < 3; ++k) {
        const rbs_method m = rollback_methods[k];
        /* 3e5 rad a step at dt = 1 s: 1.2e6 sub-steps of 1/4 rad, beyond
         * the default budget of 2^20 (2 steps: 2e6 parts, about 1 s) */
        spent_spin_budget_is_stable_one(m, 4096, 1.0, 3e5, 2);
        spent_spin_budget_is_stable_one(m, 16, 1.0, 3e5, 20);
        spent_spin_budget_is_stable_one(m, 1, 1.0, 3e5, 20);
        /* 200 rad a step at dt = 1 ms: 800 sub-steps, budget 512 */
        spent_spin_budget_is_stable_one(m, 2, 1e-3, 2e5, 1000);
    }
}

/* One step of w (method k, cap cap, frame f): fails if the step hit the
 * cap and gained more than gain J; the energy after it. */
static rbs_energy capped_step(rbs_world *w, int k, uint32_t cap, int f, double gain, rbs_step_info *info)
{
    rbs_energy e0, e1;
    CHECK_OK(rbs_world_energy(w, &e0));
    CHECK_OK(rbs_world_step(w, info));
    CHECK_OK(rbs_world_energy(w, &e1));
    if (info->work_limit && !(e1.total - e0.total <= gain))
        fail_msg("%s, cap %u, step %d: a capped step gained %.3g J", rbs_method_name(rollback_methods[k]),
                 (unsigned)cap, f, e1.total - e0.total);
    return e1;
}

/* A ball (r = 0.05 m, 1 kg) dropped from 1 m onto a floor with e = 0.9 at
 * caps 1 to 5: each bounce's impact step is capped (its rest of the frame
 * overtravels into the floor and is pushed out).  The push kept the
 * approach speed, so each capped step gained m g d (verlet at cap 3: +2.5e-4
 * J a bounce, a 0.11 mm bounce forever, 0.49158 J at t = 116 s).  Exact:
 * the bounces lose energy and the ball is at rest after about 8.5 s, as
 * uncapped (7.7 s euler, 8.3 s verlet and rk4).  Accepted: no capped step
 * gains more than 1e-12 J (rounding of the 0.49 J total is ~1e-16 J); from
 * 10 s on the ball's speed is below 1e-12 m/s and the energy within 1e-6
 * J of m g r = 0.4905 J (euler rests within its slop, 4.9e-7 J above). */
static void capped_impact_adds_no_energy(void **state)
{
    uint32_t cap;
    int k;
    (void)state;
    for (k = 0; k < 3; ++k) {
        for (cap = 1; cap <= 5; ++cap) {
            rbs_world *w = cap_world(rollback_methods[k], cap, 1e-3, -9.81, 0.9);
            rbs_body_id b;
            rbs_energy e1;
            int f, capped = 0;
            floor_plane(w, (rbs_material_id){0, 0});
            b = ball(w, 0.05, 1.0, 0, 0, 1.0, 0, 0, 0, (rbs_material_id){0, 0});
            for (f = 0; f < 12000; ++f) {
                rbs_step_info info;
                e1 = capped_step(w, k, cap, f, 1e-12, &info);
                capped += info.work_limit != 0;
                if (f >= 10000 && !(fabs(state_of(w, b).velocity.z) <= 1e-12))
                    fail_msg("%s, cap %u, step %d: still moving at %.3g m/s",
                             rbs_method_name(rollback_methods[k]), (unsigned)cap, f,
                             state_of(w, b).velocity.z);
            }
            assert_true(capped > 0);
            ASSERT_NEAR(e1.total, 0.05 * 9.81, 1e-6);
            rbs_world_destroy(w);
        }
    }
}

/* A ball dropped 0.3 m onto a ball resting on a floor, e = 0.9, at caps
 * 1 to 3: the capped sub-steps overtravel and the pushes lift the upper
 * ball off the lower one while the lower one's push out of the floor finds
 * it at rest, so counting only pushes against fixed bodies gave nothing
 * back and verlet kept the pair hopping 62 um forever, with 250 capped
 * steps in the 20th second (a review of session 43).  Exact: the bounces
 * lose energy and the pair comes to rest, as uncapped.  Accepted: in the
 * 20th second no step is capped and the kinetic energy is below 1e-20 J
 * (at rest, rounding), and no capped step gains more than 1e-6 J (euler at
 * cap 1 gained 4.5e-3 J in one; what is left, 2.8e-7 J at most, is a push
 * whose body has too little speed along it to pay for the lift). */
static void capped_stack_comes_to_rest(void **state)
{
    uint32_t cap;
    int k;
    (void)state;
    for (k = 0; k < 3; ++k) {
        for (cap = 1; cap <= 3; ++cap) {
            rbs_world *w = cap_world(rollback_methods[k], cap, 1e-3, -9.81, 0.9);
            rbs_energy e1;
            int f, late_capped = 0;
            double ke = 0.0;
            floor_plane(w, (rbs_material_id){0, 0});
            ball(w, 0.1, 1.0, 0, 0, 0.1, 0, 0, 0, (rbs_material_id){0, 0});
            ball(w, 0.1, 1.0, 0, 0, 0.6, 0, 0, 0, (rbs_material_id){0, 0});
            for (f = 0; f < 20000; ++f) {
                rbs_step_info info;
                e1 = capped_step(w, k, cap, f, 1e-6, &info);
                if (f >= 19000) {
                    late_capped += info.work_limit != 0;
                    if (e1.kinetic > ke)
                        ke = e1.kinetic;
                }
            }
            print_message("%s, cap %u: kinetic energy in the 20th second up to %.3g J, %d capped steps\n",
                          rbs_method_name(rollback_methods[k]), (unsigned)cap, ke, late_capped);
            assert_int_equal(late_capped, 0);
            assert_true(ke < 1e-20);
            rbs_world_destroy(w);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clean_frame_at_cap_is_not_capped),
        cmocka_unit_test(cap_is_strict),
        cmocka_unit_test(spent_spin_budget_is_stable),
        cmocka_unit_test(capped_impact_adds_no_energy),
        cmocka_unit_test(capped_stack_comes_to_rest),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
