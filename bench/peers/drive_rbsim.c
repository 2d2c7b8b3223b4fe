/*
 * drive_rbsim.c - runs a peers scene in rbsim and reports time and counters.
 *
 *   peers_rbsim --scene FILE [--steps K] [--max-wall S] [--state-out FILE]
 *               [--method NAME] [--slop X] [--soft-tolerance X]
 *               [--substeps K]
 *
 * Contacts: one "*"/"*" material-pair row with mu_s = mu_k = friction and
 * e = restitution, and the world's restitution the same, so every contact
 * (sphere-sphere and sphere-plane) has the scene's coefficients.  Everything
 * else is the library's default (the method -- auto: soft from 64 moving
 * spheres on, else euler -- unless --method names one; max_halvings,
 * max_sweeps, contacts; the slop and soft_tolerance too unless --slop and
 * --soft-tolerance give them).
 * Only the stepping loop is timed; creation is reported as setup time.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "peers_io.h"
#include "rbsim/rbsim.h"
#include "rbsim/reel.h"

static const char usage[] =
    "usage: peers_rbsim --scene FILE [--steps K] [--max-wall S] [--state-out FILE] [--method NAME]\n"
    "                   [--slop X]   (rbs_world_def.slop, a fraction of the radius; default the library's)\n"
    "                   [--soft-tolerance X]   (rbs_world_def.soft_tolerance; default the library's)\n"
    "                   [--substeps K]   (rbs_world_def.soft_substeps; default the library's)\n"
    "                   [--threads K]   (threads that step the world, its own included: a pool of\n"
    "                                    K - 1 (rbs_pool_create); default 1)\n"
    "       peers_rbsim --layout    (bytes of the world per body and per contact)\n";

/* Bytes the world takes per body and per contact slot, from the public
 * rbs_world_memory_size() alone: differences between capacities. */
static int print_layout(void)
{
    rbs_world_def d;
    size_t a, b, c;
    rbs_world_def_init(&d);
    d.max_bodies = 100000;
    d.max_contacts = 400000;
    a = rbs_world_memory_size(&d);
    d.max_bodies = 200000;
    b = rbs_world_memory_size(&d);
    d.max_contacts = 800000;
    c = rbs_world_memory_size(&d);
    if (a == 0 || b == 0 || c == 0) {
        fprintf(stderr, "peers_rbsim: rbs_world_memory_size refused the layout probe\n");
        return 2;
    }
    printf("{\"body_bytes\": %.2f, \"contact_bytes\": %.2f, \"body_bytes_with_default_contacts\": %.2f}\n",
           (double)(b - a) / 100000.0, (double)(c - b) / 400000.0,
           (double)(b - a) / 100000.0 + 4.0 * (double)(c - b) / 400000.0);
    return 0;
}

static int check(rbs_world *w, rbs_status st, const char *what)
{
    if (st == RBS_OK)
        return 0;
    fprintf(stderr, "peers_rbsim: %s: %s (%s)\n", what, rbs_status_string(st),
            w ? rbs_world_last_error(w) : "");
    return 1;
}

int main(int argc, char **argv)
{
    peers_options opt;
    peers_scene sc;
    rbs_world_def def;
    rbs_world *w = NULL;
    rbs_pool *pool = NULL;
    rbs_pair_def pair;
    rbs_state_view view;
    rbs_usage usage_info;
    rbs_energy energy;
    peers_apex apex;
    rbs_status st = RBS_OK;
    double t0, t1, t_setup, last = 0.0;
    long steps, k;
    size_t i, slot0 = 0;
    uint64_t substeps = 0, rollbacks = 0, floor_hits = 0, sweep_limit = 0;
    uint32_t contacts_max = 0;
    double overlap_max = 0.0;
    const char *error = "";
    char errbuf[512];

    if (argc == 2 && strcmp(argv[1], "--layout") == 0)
        return print_layout();
    if (peers_parse_args(argc, argv, &opt, usage) || peers_scene_open(opt.scene_path, &sc))
        return 2;
    steps = opt.steps >= 0 ? opt.steps : sc.steps;

    /* Build the world. */
    t0 = peers_now();
    rbs_world_def_init(&def);
    def.max_bodies = (uint32_t)(sc.n + sc.n_planes);
    def.max_contacts = 0; /* the library's default, 4 per body + 16 */
    def.dt = sc.dt;
    def.gravity.x = def.gravity.y = 0.0;
    def.gravity.z = sc.gravity_z;
    def.restitution = sc.restitution;
    if (opt.extra != NULL && check(NULL, rbs_method_from_name(opt.extra, &def.method), "--method"))
        return 2;
    if (opt.slop != 0.0)
        def.slop = opt.slop;
    if (opt.soft_tolerance >= 0.0)
        def.soft_tolerance = opt.soft_tolerance;
    if (opt.substeps > 0)
        def.soft_substeps = (uint32_t)opt.substeps;
    {
        char why[256];
        if (rbs_world_def_validate(&def, why, sizeof why) != RBS_OK) {
            fprintf(stderr, "peers_rbsim: the world's settings: %s\n", why);
            return 2;
        }
    }
    if (check(NULL, rbs_world_create(&def, &w), "rbs_world_create"))
        return 2;
    rbs_pair_def_init(&pair);
    pair.static_friction = pair.kinetic_friction = sc.friction;
    pair.restitution = sc.restitution;
    if (check(w, rbs_world_set_pair(w, &pair), "rbs_world_set_pair"))
        return 2;
    for (i = 0; i < sc.n_planes; ++i) {
        rbs_plane_def p;
        const double *q = &sc.planes[6 * i];
        rbs_plane_def_init(&p);
        p.point.x = q[0], p.point.y = q[1], p.point.z = q[2];
        p.normal.x = q[3], p.normal.y = q[4], p.normal.z = q[5];
        if (check(w, rbs_world_add_plane(w, &p, NULL), "rbs_world_add_plane"))
            return 2;
    }
    for (i = 0; i < sc.n; ++i) {
        rbs_sphere_def s;
        rbs_body_id id;
        double q[8];
        if (peers_scene_sphere(&sc, q))
            return 2;
        rbs_sphere_def_init(&s);
        s.radius = q[0];
        s.mass = q[1];
        s.position.x = q[2], s.position.y = q[3], s.position.z = q[4];
        s.velocity.x = q[5], s.velocity.y = q[6], s.velocity.z = q[7];
        if (check(w, rbs_world_add_sphere(w, &s, &id), "rbs_world_add_sphere"))
            return 2;
        if (i == 0)
            slot0 = id.index;
    }
    peers_scene_free(&sc); /* keeps the counts */
    if (opt.threads > 1) {
        rbs_workers workers;
        if (check(NULL, rbs_pool_create((uint32_t)(opt.threads - 1), &pool), "rbs_pool_create"))
            return 2;
        rbs_workers_init(&workers);
        if (check(NULL, rbs_pool_workers(pool, &workers), "rbs_pool_workers") ||
            check(w, rbs_world_set_workers(w, &workers), "rbs_world_set_workers"))
            return 2;
    }
    rbs_world_state(w, &view);
    peers_apex_init(&apex, sc.gravity_z);
    t1 = peers_now();
    t_setup = t1 - t0;

    /* Step, timed. */
    t0 = peers_now();
    for (k = 0; k < steps; ++k) {
        rbs_step_info info;
        double wall;
        st = rbs_world_step(w, &info);
        if (st != RBS_OK) {
            snprintf(errbuf, sizeof errbuf, "step %ld: %s: %s", k + 1, rbs_status_string(st),
                     rbs_world_last_error(w));
            error = errbuf;
            break;
        }
        substeps += info.substeps;
        rollbacks += info.rollbacks;
        floor_hits += info.floor_hits;
        sweep_limit += info.sweep_limit;
        if (info.contacts > contacts_max)
            contacts_max = info.contacts;
        if (info.max_overlap > overlap_max)
            overlap_max = info.max_overlap;
        if (sc.track_apex)
            peers_apex_feed(&apex, view.position[3 * slot0 + 2], view.velocity[3 * slot0 + 2]);
        wall = peers_now() - t0;
        peers_progress(k + 1, wall, &last);
        if (opt.max_wall > 0.0 && wall >= opt.max_wall) {
            ++k;
            break;
        }
    }
    t1 = peers_now();

    /* Final state (the spheres, in scene order: slots after the planes). */
    if (opt.state_path) {
        size_t first = sc.n_planes;
        FILE *f = peers_state_open(opt.state_path, sc.n);
        if (f == NULL)
            return 2;
        for (i = 0; i < sc.n; ++i)
            if (peers_state_put(f, &view.position[3 * (first + i)], &view.velocity[3 * (first + i)],
                                &view.angular_velocity[3 * (first + i)])) {
                (void)peers_state_close(f, opt.state_path);
                return 2;
            }
        if (peers_state_close(f, opt.state_path))
            return 2;
    }
    rbs_world_get_def(w, &def);
    rbs_world_usage(w, &usage_info);
    rbs_world_energy(w, &energy);

    printf("RESULT {\"engine\": \"rbsim\", \"version\": \"%s\", \"method\": \"%s\", \"method_in_use\": \"%s\", \"n\": %zu, "
           "\"steps\": %ld, \"dt\": %.9g, \"sim_time\": %.9g, \"wall\": %.9g, \"setup_wall\": %.9g, "
           "\"substeps\": %llu, \"rollbacks\": %llu, \"floor_hits\": %llu, \"sweep_limit\": %llu, "
           "\"contacts_max\": %u, \"contacts_high\": %u, \"step_max_overlap\": %.9g, "
           "\"world_bytes\": %zu, \"max_contacts\": %u, \"slop\": %.9g, \"threads\": %u, \"energy_lib\": %.12g, \"rss_anon_kb\": %ld, \"apex\": ",
           rbs_version(), rbs_method_name(def.method), rbs_method_name(rbs_world_method_in_use(w)), sc.n, k, sc.dt, (double)k * sc.dt, t1 - t0,
           t_setup, (unsigned long long)substeps, (unsigned long long)rollbacks,
           (unsigned long long)floor_hits, (unsigned long long)sweep_limit, contacts_max,
           usage_info.contacts_high, overlap_max, usage_info.bytes, def.max_contacts,
           def.slop, rbs_world_workers(w), energy.total, peers_rss_anon_kb());
    peers_print_apex(stdout, &apex);
    printf(", \"error\": \"");
    for (; *error; ++error)
        putchar(*error == '"' || *error == '\\' ? '\'' : *error);
    printf("\"}\n");
    rbs_world_destroy(w);
    rbs_pool_destroy(pool);
    return st == RBS_OK ? 0 : 1;
}
