/*
 * test_selective.c - selective rollback: only overlapping pairs go back.
 * Same exact answers as Euler within Euler's first-order bounds, and the
 * rest of the world is left alone.
 */
#include "common.h"

static const double G = 9.81;

static rbs_world *sel_world(uint32_t n, double gz, double e)
{
    rbs_world *w = make_world(n, 1e-3, gz, e);
    CHECK_OK(rbs_world_set_method(w, RBS_METHOD_SELECTIVE, 0.0));
    return w;
}

/* Dropped ball, e = 0.5: first impact in the frame containing sqrt(2h/g)
 * (+ Euler's lag, <= 2 dt) and apexes within Euler's first-order bound
 * (2 v dt, plus g dt per impact because gravity acts over the whole step on
 * both sides of the impact: 3 v dt in all). */
static void drop_ball(void **state)
{
    const double h = 1.0, r = 0.1, e = 0.5, dt = 1e-3;
    rbs_world *w = sel_world(4, -G, e);
    rbs_body_id b;
    double prev_v = 0.0, t_impact = -1.0;
    int apex = 0, k;
    (void)state;
    floor_plane(w, (rbs_material_id){0, 0});
    b = ball(w, r, 1.0, 0, 0, h + r, 0, 0, 0, (rbs_material_id){0, 0});
    for (k = 0; k < 2000 && apex < 4; ++k) {
        rbs_step_info info;
        rbs_body_state s;
        CHECK_OK(rbs_world_step(w, &info));
        s = state_of(w, b);
        assert_true(s.position.z >= r - 1e-6);
        if (info.colliding && t_impact < 0.0)
            t_impact = rbs_world_time(w);
        if (prev_v > 0.0 && s.velocity.z <= 0.0) {
            double v_launch = sqrt(2.0 * G * h) * pow(e, apex + 1);
            ASSERT_NEAR(s.position.z - r, h * pow(e, 2.0 * (apex + 1)), 3.0 * v_launch * dt + G * dt * dt);
            apex++;
        }
        prev_v = s.velocity.z;
    }
    assert_int_equal(apex, 4);
    assert_true(t_impact >= sqrt(2.0 * h / G) && t_impact <= sqrt(2.0 * h / G) + 2.0 * dt);
    rbs_world_destroy(w);
}

/* An impact far away does not disturb a free body: a ball in free flight
 * follows Euler's exact recurrence while another bounces. */
static void bystander_keeps_its_full_step(void **state)
{
    const int n = 600;
    rbs_world *w = sel_world(4, -G, 0.8);
    rbs_body_id free_ball;
    (void)state;
    floor_plane(w, (rbs_material_id){0, 0});
    ball(w, 0.1, 1.0, 0, 0, 0.5, 0, 0, 0, (rbs_material_id){0, 0});
    free_ball = ball(w, 0.1, 1.0, 5, 0, 100, 0, 0, 0, (rbs_material_id){0, 0});
    step_n(w, n);
    ASSERT_NEAR(state_of(w, free_ball).position.z, 100.0 - G * 1e-6 * n * (n + 1) / 2.0, 1e-9);
    rbs_world_destroy(w);
}

/* Newton's cradle: only the last ball moves (1e-9). */
static void cradle(void **state)
{
    rbs_world *w = sel_world(8, 0.0, 1.0);
    rbs_body_id b[5];
    (void)state;
    cradle_balls(w, b);
    step_n(w, 2000);
    cradle_check(w, b, 1e-9);
    rbs_world_destroy(w);
}

/* A pile of 125 spheres (r 0.05 m, m 0.1 kg, friction 0.5) over a
 * five-plane box, dropped from a slightly sheared lattice; with far set, one
 * more fixed sphere of the same size 1e7 m away, which touches nothing. */
static rbs_world *pile_world(int far)
{
    rbs_world_def d;
    rbs_world *w;
    rbs_material_id m;
    rbs_pair_def pd;
    const double nrm[5][3] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    const double pt[5][3] = {{0, 0, 0}, {-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}};
    int i, j, k;
    rbs_world_def_init(&d);
    d.max_bodies = 140;
    d.method = RBS_METHOD_SELECTIVE;
    CHECK_OK(rbs_world_create(&d, &w));
    CHECK_OK(rbs_world_add_material(w, "m", &m));
    rbs_pair_def_init(&pd);
    pd.static_friction = pd.kinetic_friction = 0.5;
    CHECK_OK(rbs_world_set_pair(w, &pd));
    for (i = 0; i < 5; ++i) {
        rbs_plane_def p;
        rbs_plane_def_init(&p);
        p.point.x = pt[i][0]; p.point.y = pt[i][1]; p.point.z = pt[i][2];
        p.normal.x = nrm[i][0]; p.normal.y = nrm[i][1]; p.normal.z = nrm[i][2];
        p.material = m;
        CHECK_OK(rbs_world_add_plane(w, &p, NULL));
    }
    for (i = 0; i < 5; ++i)
        for (j = 0; j < 5; ++j)
            for (k = 0; k < 5; ++k)
                ball(w, 0.05, 0.1, (i - 2) * 0.12 + 0.001 * k, (j - 2) * 0.12, 0.1 + k * 0.12, 0, 0, 0, m);
    if (far) {
        rbs_sphere_def s;
        rbs_sphere_def_init(&s);
        s.radius = 0.05;
        s.mass = 0.1;
        s.position.x = 1e7;
        s.position.z = 0.05;
        s.fixed = 1;
        s.material = m;
        CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
    }
    return w;
}

/* The pile after 1.5 s: nothing has escaped and no overlap exceeds 1 % of a
 * radius (the quality bound), and every step is a single sub-step. */
static void pile_quality(void **state)
{
    rbs_world *w = pile_world(0);
    rbs_state_view v;
    rbs_step_info info;
    int i, k;
    (void)state;
    for (k = 0; k < 1500; ++k) {
        CHECK_OK(rbs_world_step(w, &info));
        assert_int_equal(info.substeps, 1);
    }
    assert_true(info.max_overlap <= 0.01 * 0.05);
    CHECK_OK(rbs_world_state(w, &v));
    for (i = 5; i < (int)v.slots; ++i) {
        const double *p = &v.position[3 * i];
        assert_true(fabs(p[0]) <= 1.0 - 0.05 * 0.99 && fabs(p[1]) <= 1.0 - 0.05 * 0.99);
        assert_true(p[2] >= 0.05 * 0.99 && p[2] < 2.0);
    }
    rbs_world_destroy(w);
}

/* The broad phase indexes its grid densely when the spheres' box of cells
 * fits its table and hashes the cells otherwise; both must find the same
 * pairs in the same order.  The same pile with and without a far, fixed,
 * untouched sphere (whose cell puts the box far beyond the table, so that
 * world hashes) must move bit for bit alike over 600 steps of piling up. */
static void grid_index_does_not_change_the_pile(void **state)
{
    rbs_world *dense = pile_world(0), *hashed = pile_world(1);
    rbs_state_view a, b;
    int k;
    (void)state;
    for (k = 0; k < 600; ++k) {
        CHECK_OK(rbs_world_step(dense, NULL));
        CHECK_OK(rbs_world_step(hashed, NULL));
    }
    CHECK_OK(rbs_world_state(dense, &a));
    CHECK_OK(rbs_world_state(hashed, &b));
    assert_int_equal(a.slots + 1, b.slots);
    assert_memory_equal(a.position, b.position, 3 * a.slots * sizeof(double));
    assert_memory_equal(a.velocity, b.velocity, 3 * a.slots * sizeof(double));
    assert_memory_equal(a.angular_velocity, b.angular_velocity, 3 * a.slots * sizeof(double));
    assert_memory_equal(a.orientation, b.orientation, 4 * a.slots * sizeof(double));
    ASSERT_NEAR(b.position[3 * a.slots], 1e7, 0.0);
    rbs_world_destroy(dense);
    rbs_world_destroy(hashed);
}

/* A struck ball that crosses far more than the fix-up rounds' skin (0.1
 * radius) in what is left of the step still hits the next ball in that step:
 * its path leaves its ball of the first round, so the search goes back to
 * the grid.  Three equal balls on a line, no gravity, e = 1, dt = 10 ms: A
 * at 5 m/s is 0.5 mm from B, B is 20 mm from C.  Exact (elastic exchange at
 * each touch): A stops at 0.5 mm on, B stops after 20 mm at t = 4.1 ms and C
 * leaves at 5 m/s, 29.5 mm on at the end of the step (1e-12 m: rounding). */
static void struck_ball_hits_the_next_in_the_same_step(void **state)
{
    const double r = 0.05, v = 5.0, dt = 0.01;
    rbs_world *w = make_world(4, dt, 0.0, 1.0);
    rbs_material_id m = material(w, "m", 0.0, 0.0, 1.0);
    rbs_body_id a, b, c;
    rbs_step_info info;
    (void)state;
    CHECK_OK(rbs_world_set_method(w, RBS_METHOD_SELECTIVE, 0.0));
    a = ball(w, r, 1.0, 0.0, 0, 0, v, 0, 0, m);
    b = ball(w, r, 1.0, 2 * r + 0.0005, 0, 0, 0, 0, 0, m);
    c = ball(w, r, 1.0, 4 * r + 0.0205, 0, 0, 0, 0, 0, m);
    CHECK_OK(rbs_world_step(w, &info));
    assert_int_equal(info.colliding, 2);
    ASSERT_NEAR(state_of(w, a).velocity.x, 0.0, 1e-12);
    ASSERT_NEAR(state_of(w, b).velocity.x, 0.0, 1e-12);
    ASSERT_NEAR(state_of(w, c).velocity.x, v, 1e-12);
    ASSERT_NEAR(state_of(w, a).position.x, 0.0005, 1e-12);
    ASSERT_NEAR(state_of(w, b).position.x, 2 * r + 0.0205, 1e-12);
    ASSERT_NEAR(state_of(w, c).position.x, 4 * r + 0.0205 + v * (dt - 0.0205 / v), 1e-12);
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(drop_ball),
        cmocka_unit_test(bystander_keeps_its_full_step),
        cmocka_unit_test(cradle),
        cmocka_unit_test(pile_quality),
        cmocka_unit_test(grid_index_does_not_change_the_pile),
        cmocka_unit_test(struck_ball_hits_the_next_in_the_same_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
