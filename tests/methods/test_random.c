/*
 * test_random.c - every method on random scenes (cases nobody wrote down):
 * spheres of mixed sizes, masses (1e-2 .. 1e2 kg), spins, off-centre masses
 * and anisotropic inertia, with friction and resistance, planes, fixed
 * spheres and mutual gravity.  Each scene steps 300 frames; the step must
 * succeed (or a method may refuse a scene with RBS_E_UNSUPPORTED, which the
 * event method does outside its scope), the state must stay finite, and in scenes
 * without external forces (no gravity, planes or fixed spheres) linear
 * momentum must be conserved to 1e-9 of its scale (impulses come in equal
 * and opposite pairs; mutual gravity is pairwise).  A small deterministic
 * generator (xorshift) makes the scenes reproducible.
 */
#include "methods_common.h"

static const rbs_method all_methods[] = {RBS_METHOD_EULER, RBS_METHOD_SELECTIVE, RBS_METHOD_EVENT,
                                         RBS_METHOD_VERLET, RBS_METHOD_RK4, RBS_METHOD_ADAPTIVE,
                                         RBS_METHOD_SOFT};
#define N_METHODS (sizeof all_methods / sizeof all_methods[0])

static double uniform(uint64_t *s, double lo, double hi)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return lo + (hi - lo) * (double)(*s >> 11) / 9007199254740992.0;
}

/* Build scene number k into a world for method m; *isolated tells whether
 * no external force acts.  Returns NULL if m is not built. */
static rbs_world *random_scene(int k, rbs_method m, int *isolated)
{
    uint64_t s = 0x9e3779b97f4a7c15ull ^ (uint64_t)(k + 1) * 0x2545f4914f6cdd1dull;
    rbs_world_def d;
    rbs_world *w;
    rbs_material_id mat[2];
    rbs_pair_def p;
    int n, i, planes, fixed;
    rbs_status st;
    rbs_world_def_init(&d);
    d.max_bodies = 16;
    d.dt = uniform(&s, 1e-3, 1e-2);
    *isolated = k % 3 == 0;
    d.gravity.z = *isolated ? 0.0 : -9.81;
    d.restitution = uniform(&s, 0.0, 1.0);
    d.mutual_gravity = k % 2;
    d.gravity_constant = uniform(&s, 0.0, 1e-3);
    d.softening = uniform(&s, 0.0, 0.01);
    d.tolerance = 1e-8;
    CHECK_OK(rbs_world_create(&d, &w));
    st = rbs_world_set_method(w, m, 0.0);
    if (st == RBS_E_UNSUPPORTED) {
        rbs_world_destroy(w);
        return NULL;
    }
    CHECK_OK(st);
    CHECK_OK(rbs_world_add_material(w, "a", &mat[0]));
    CHECK_OK(rbs_world_add_material(w, "b", &mat[1]));
    rbs_pair_def_init(&p);
    p.a = mat[0];
    p.b = mat[1];
    p.static_friction = uniform(&s, 0.0, 1.0);
    p.kinetic_friction = p.static_friction * uniform(&s, 0.0, 1.0);
    p.rolling = k % 4 == 1 ? uniform(&s, 0.0, 0.05) : 0.0;
    p.spinning = k % 4 == 2 ? uniform(&s, 0.0, 0.01) : 0.0;
    CHECK_OK(rbs_world_set_pair(w, &p));
    planes = *isolated ? 0 : 1 + k % 2;
    for (i = 0; i < planes; ++i) {
        rbs_plane_def pl;
        rbs_plane_def_init(&pl);
        pl.normal.x = i == 0 ? 0.0 : 1.0;
        pl.normal.z = i == 0 ? 1.0 : 0.2;
        pl.point.x = i == 0 ? 0.0 : -2.0;
        pl.material = mat[i % 2];
        CHECK_OK(rbs_world_add_plane(w, &pl, NULL));
    }
    n = 2 + k % 8;
    fixed = *isolated ? 0 : k % 5 == 4;
    for (i = 0; i < n; ++i) {
        rbs_sphere_def sd;
        rbs_sphere_def_init(&sd);
        sd.radius = uniform(&s, 0.05, 0.3);
        sd.mass = pow(10.0, uniform(&s, -2.0, 2.0));
        /* on a grid, so nothing starts in overlap */
        sd.position.x = -1.5 + 0.7 * (i % 4);
        sd.position.y = 0.7 * ((i / 4) % 2);
        sd.position.z = 0.35 + 0.7 * (i / 8) + uniform(&s, 0.0, 0.5);
        sd.velocity.x = uniform(&s, -3.0, 3.0);
        sd.velocity.y = uniform(&s, -1.0, 1.0);
        sd.velocity.z = uniform(&s, -3.0, 3.0);
        if (i % 3 == 1) {
            sd.angular_velocity.x = uniform(&s, -10.0, 10.0);
            sd.angular_velocity.z = uniform(&s, -10.0, 10.0);
        }
        if (i % 4 == 2)
            sd.center_of_mass.x = 0.3 * sd.radius;
        if (i % 5 == 3) {
            double I = 0.4 * sd.mass * sd.radius * sd.radius;
            sd.inertia_kind = RBS_INERTIA_PRINCIPAL;
            sd.inertia.x = I;
            sd.inertia.y = 1.3 * I;
            sd.inertia.z = 1.6 * I;
        }
        sd.material = mat[i % 2];
        sd.fixed = fixed && i == 0;
        if (sd.fixed) {
            /* (drawn all the same, so the draws after it are as before) */
            memset(&sd.velocity, 0, sizeof sd.velocity);
            memset(&sd.angular_velocity, 0, sizeof sd.angular_velocity);
        }
        CHECK_OK(rbs_world_add_sphere(w, &sd, NULL));
    }
    return w;
}

static void random_scenes_every_method(void **state)
{
    int k, runs = 0;
    size_t j;
    (void)state;
    for (k = 0; k < 24; ++k) {
        for (j = 0; j < N_METHODS; ++j) {
            int isolated, f, refused = 0;
            rbs_world *w = random_scene(k, all_methods[j], &isolated);
            rbs_vec3 p0, p1;
            rbs_state_view v;
            double scale = 0.0;
            uint32_t i;
            if (w == NULL)
                continue;
            CHECK_OK(rbs_world_momentum(w, &p0, NULL));
            CHECK_OK(rbs_world_state(w, &v));
            for (i = 0; i < v.slots; ++i) {
                rbs_body_id id;
                if (rbs_world_body_at(w, i, &id) == RBS_OK) {
                    rbs_body_state s = state_of(w, id);
                    scale += s.mass * (fabs(s.velocity.x) + fabs(s.velocity.y) + fabs(s.velocity.z));
                }
            }
            for (f = 0; f < 300; ++f) {
                rbs_step_info info;
                rbs_status st = rbs_world_step(w, &info);
                if (st == RBS_E_UNSUPPORTED) {
                    refused = 1;
                    break;
                }
                if (st != RBS_OK)
                    fail_msg("scene %d, %s, frame %d: %s: %s", k, rbs_method_name(all_methods[j]), f,
                             rbs_status_name(st), rbs_world_last_error(w));
            }
            if (!refused) {
                for (i = 0; i < 3 * v.slots; ++i)
                    if (!isfinite(v.position[i]) || !isfinite(v.velocity[i]) ||
                        !isfinite(v.angular_velocity[i]))
                        fail_msg("scene %d, %s: state not finite", k, rbs_method_name(all_methods[j]));
                if (isolated) {
                    CHECK_OK(rbs_world_momentum(w, &p1, NULL));
                    if (!(fabs(p1.x - p0.x) + fabs(p1.y - p0.y) + fabs(p1.z - p0.z) <= 1e-9 * scale))
                        fail_msg("scene %d, %s: momentum (%g %g %g) -> (%g %g %g), scale %g", k,
                                 rbs_method_name(all_methods[j]), p0.x, p0.y, p0.z, p1.x, p1.y, p1.z,
                                 scale);
                }
                runs++;
            }
            rbs_world_destroy(w);
        }
    }
    print_message("%d scene x method runs\n", runs);
    assert_true(runs >= 24 * 4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(random_scenes_every_method),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
