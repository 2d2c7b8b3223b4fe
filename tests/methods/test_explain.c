/*
 * test_explain.c - rbs_world_explain() states each stage in or out with the
 * body or pair responsible, follows the world as it changes, and handles
 * buffers like snprintf (truncate, NUL-terminate, report the size needed).
 */
#include <stdlib.h>

#include "methods_common.h"

static char text_buf[8192];

static const char *explain(const rbs_world *w)
{
    size_t need = 0;
    CHECK_OK(rbs_world_explain(w, text_buf, sizeof text_buf, &need));
    assert_int_equal(need, strlen(text_buf) + 1);
    return text_buf;
}

#define ASSERT_HAS(text, what)                                                  \
    do {                                                                        \
        if (strstr((text), (what)) == NULL)                                     \
            fail_msg("missing \"%s\" in:\n%s", (what), (text));               \
    } while (0)

/* A sphere of anisotropic inertia (1, 2, 2.5 g m^2) at (x, 0, 1) m. */
static void add_anisotropic(rbs_world *w, const char *name, double x, rbs_material_id m)
{
    rbs_sphere_def s;
    rbs_sphere_def_init(&s);
    s.name = name;
    s.inertia_kind = RBS_INERTIA_PRINCIPAL;
    s.inertia.x = 1e-3; s.inertia.y = 2e-3; s.inertia.z = 2.5e-3;
    s.position.x = x;
    s.position.z = 1.0;
    s.material = m;
    CHECK_OK(rbs_world_add_sphere(w, &s, NULL));
}

static void single_ball_prunes(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    const char *t;
    (void)state;
    floor_plane(w, (rbs_material_id){0, 0});
    ball(w, 0.1, 1.0, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    t = explain(w);
    ASSERT_HAS(t, "method: auto, dt = 0.001 s, slop = 1e-06 of the smaller radius, tolerance = 1e-09");
    ASSERT_HAS(t, "  auto: euler, since 1 sphere moves (soft from 64 on)\n  semi-implicit Euler sub-steps");
    ASSERT_HAS(t, "in   contacts sphere-plane: 1 moving sphere x 1 plane");
    ASSERT_HAS(t, "out  contacts sphere-sphere: fewer than two spheres");
    ASSERT_HAS(t, "out  friction, rolling and spinning resistance: no material pair");
    ASSERT_HAS(t, "out  angular velocity and orientation");
    ASSERT_HAS(t, "out  gyroscopic torque");
    ASSERT_HAS(t, "out  mutual gravity: def.mutual_gravity is 0");
    rbs_world_destroy(w);
}

static void stages_name_their_reason(void **state)
{
    rbs_world_def d;
    rbs_world *w;
    rbs_material_id m;
    const char *t;
    (void)state;
    rbs_world_def_init(&d);
    d.mutual_gravity = 1;
    d.method = RBS_METHOD_RK4;
    CHECK_OK(rbs_world_create(&d, &w));
    m = material(w, "felt", 0.4, 0.2, -1.0);
    floor_plane(w, m);
    add_anisotropic(w, "top", 0.0, m);
    ball(w, 0.1, 1.0, 1, 0, 0.1, 0, 0, 0, m);
    t = explain(w);
    ASSERT_HAS(t, "method: rk4");
    ASSERT_HAS(t, "4 force evaluations");
    ASSERT_HAS(t, "in   contacts sphere-sphere: 2 spheres, 2 moving");
    ASSERT_HAS(t, "in   friction, rolling and spinning resistance: pair \"felt\"/\"felt\" has mu_s 0.4");
    ASSERT_HAS(t, "in   angular velocity and orientation: sphere \"top\" has anisotropic inertia "
                  "(contacts can make it spin)");
    ASSERT_HAS(t, "in   gyroscopic torque -w x I w: sphere \"top\" has anisotropic inertia");
    ASSERT_HAS(t, "in   mutual gravity: G = 6.674e-11");
    ASSERT_HAS(t, "resting-contact pass: once per sub-step, on the end velocities");
    rbs_world_destroy(w);
}

static void follows_changes_and_prune_off(void **state)
{
    rbs_world_def d;
    rbs_world *w;
    rbs_body_id b;
    const char *t;
    (void)state;
    rbs_world_def_init(&d);
    CHECK_OK(rbs_world_create(&d, &w));
    b = ball(w, 0.1, 1.0, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    assert_non_null(strstr(explain(w), "out  angular velocity"));
    ball(w, 0.1, 1.0, 1, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    {
        /* a row on no body's material is not in the scene; a ball of ice is */
        rbs_material_id m = material(w, "ice", 0.1, 0.05, -1.0);
        ASSERT_HAS(explain(w), "out  friction, rolling and spinning resistance: no material pair has friction "
                               "or resistance on its bodies' materials");
        ball(w, 0.1, 1.0, 2, 0, 1, 0, 0, 0, m);
        ASSERT_HAS(explain(w), "in   angular velocity and orientation: friction can make spheres spin");
    }
    CHECK_OK(rbs_body_set_angular_velocity(w, b, (rbs_vec3){0, 0, 3}));
    t = explain(w);
    ASSERT_HAS(t, "in   angular velocity and orientation: sphere #0 spins");
    rbs_world_destroy(w);

    d.prune = 0;
    CHECK_OK(rbs_world_create(&d, &w));
    ball(w, 0.1, 1.0, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    t = explain(w);
    ASSERT_HAS(t, "pruning off");
    ASSERT_HAS(t, "in   contacts sphere-sphere: fewer than two spheres (pruning off)");
    ASSERT_HAS(t, "in   friction, rolling and spinning resistance: no material pair has friction or "
                  "resistance on its bodies' materials (pairs without a row are frictionless) (pruning off)");
    rbs_world_destroy(w);
}

static void buffers_like_snprintf(void **state)
{
    rbs_world *w = make_world(4, 1e-3, -9.81, 0.5);
    char small[16];
    size_t need = 0, need2 = 0;
    char *full;
    (void)state;
    ball(w, 0.1, 1.0, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    assert_int_equal(rbs_world_explain(w, NULL, 0, &need), RBS_E_MEMORY);
    assert_true(need > 100);
    memset(small, 'x', sizeof small);
    assert_int_equal(rbs_world_explain(w, small, sizeof small, &need2), RBS_E_MEMORY);
    assert_int_equal(need2, need);
    assert_int_equal(strlen(small), sizeof small - 1);
    full = malloc(need);
    assert_non_null(full);
    CHECK_OK(rbs_world_explain(w, full, need, NULL));
    assert_int_equal(strlen(full), need - 1);
    assert_memory_equal(full, small, sizeof small - 1);
    free(full);
    assert_int_equal(rbs_world_explain(NULL, small, sizeof small, &need), RBS_E_INVALID);
    assert_int_equal(need, 0);
    assert_int_equal(rbs_world_explain(w, NULL, 10, NULL), RBS_E_INVALID);
    rbs_world_destroy(w);
}

/* The soft method with a sub-step tolerance says what the tolerance does,
 * and that it is not used once a sphere with anisotropic inertia puts the
 * world in the general layout. */
static void soft_tolerance_is_explained(void **state)
{
    rbs_world_def d;
    rbs_world *w;
    const char *t;
    (void)state;
    rbs_world_def_init(&d);
    d.method = RBS_METHOD_SOFT;
    d.soft_tolerance = 0.01;
    CHECK_OK(rbs_world_create(&d, &w));
    floor_plane(w, (rbs_material_id){0, 0});
    ball(w, 0.1, 1.0, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    t = explain(w);
    ASSERT_HAS(t, "  3 sub-steps of dt/3;");
    ASSERT_HAS(t, "springs of omega = 2 pi/(3h)\n");
    ASSERT_HAS(t, "  soft_tolerance 0.01: a frame takes fewer (halved, down to 1) while no contact can "
                  "reach an overlap of 0.01 x n/3 of its radius\n");
    rbs_world_destroy(w);
    /* mutual gravity switched on with a single sphere cannot act: the
     * layout stays gathered, and the line does not blame it (it said "in
     * gathered body records: mutual gravity: the general rows ...") */
    d.mutual_gravity = 1;
    CHECK_OK(rbs_world_create(&d, &w));
    floor_plane(w, (rbs_material_id){0, 0});
    ball(w, 0.1, 1.0, 0, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    t = explain(w);
    ASSERT_HAS(t, "  soft_tolerance 0.01: a frame takes fewer");
    ASSERT_HAS(t, "in   gathered body records: centred isotropic spheres");
    /* a second moving sphere: now it acts, and takes the general layout */
    ball(w, 0.1, 1.0, 1, 0, 1, 0, 0, 0, (rbs_material_id){0, 0});
    t = explain(w);
    ASSERT_HAS(t, "out  gathered body records: mutual gravity: the general rows");
    ASSERT_HAS(t, "  soft_tolerance 0.01: not used,");
    add_anisotropic(w, NULL, 2.0, (rbs_material_id){0, 0});
    t = explain(w);
    ASSERT_HAS(t, "  soft_tolerance 0.01: not used, every frame takes all sub-steps (this world steps "
                  "in the general layout");
    rbs_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(single_ball_prunes),
        cmocka_unit_test(stages_name_their_reason),
        cmocka_unit_test(follows_changes_and_prune_off),
        cmocka_unit_test(buffers_like_snprintf),
        cmocka_unit_test(soft_tolerance_is_explained),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
