/*
 * drive_ode.c - runs a peers scene in the Open Dynamics Engine (ODE, C API,
 * Debian's libode-dev, double precision) and reports time and counters.
 *
 *   peers_ode --scene FILE [--steps K] [--max-wall S] [--state-out FILE]
 *
 * Settings (stated in bench/results/peers.md):
 *  - dHashSpace at its default levels (cells 2^-3 .. 2^10 m; faster here
 *    than levels fitted to the spheres), or with --method sap
 *    dSweepAndPruneSpace (XYZ), or --method simple dSimpleSpace (all pairs).
 *    Planes are non-placeable geoms tested against every sphere.
 *  - dWorldQuickStep, 20 iterations, ERP 0.2, CFM 1e-5, contact surface layer
 *    0, no auto-disable (every body simulated every step, as in rbsim).
 *  - One contact point per touching pair (dCollide flags 1), surface mode
 *    dContactBounce | dContactApprox1 (friction pyramid with mu as a Coulomb
 *    coefficient), mu = friction, bounce = restitution, bounce_vel 0.01 m/s
 *    (about g dt, rbsim's resting threshold).
 *  - Spheres: dMassSetSphereTotal (solid), no damping.
 * Only the stepping loop (collide + quickstep + empty the contact group) is
 * timed; creation is setup time.
 */
#include <ode/ode.h>
#include <stdlib.h>
#include <string.h>

#include "peers_io.h"

static const char usage[] =
    "usage: peers_ode --scene FILE [--steps K] [--max-wall S] [--state-out FILE]\n"
    "                 [--method hash|sap|simple]   (collision space; default hash)\n";

typedef struct near_ctx {
    dWorldID world;
    dJointGroupID group;
    double mu, bounce;
    unsigned long contacts;
} near_ctx;

static void near_callback(void *data, dGeomID o1, dGeomID o2)
{
    near_ctx *ctx = data;
    dContact c;
    dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    if (b1 == NULL && b2 == NULL)
        return;
    memset(&c, 0, sizeof c);
    if (dCollide(o1, o2, 1, &c.geom, sizeof(dContact)) > 0) {
        dJointID j;
        c.surface.mode = dContactBounce | dContactApprox1;
        c.surface.mu = ctx->mu;
        c.surface.bounce = ctx->bounce;
        c.surface.bounce_vel = 0.01;
        j = dJointCreateContact(ctx->world, ctx->group, &c);
        dJointAttach(j, b1, b2);
        ctx->contacts++;
    }
}

int main(int argc, char **argv)
{
    peers_options opt;
    peers_scene sc;
    dWorldID world;
    dSpaceID space;
    dBodyID *body;
    near_ctx ctx;
    peers_apex apex;
    double t0, t1, t_setup, last = 0.0;
    long steps, k;
    size_t i;
    unsigned long contacts_max = 0;

    if (peers_parse_args(argc, argv, &opt, usage))
        return 2;
    if (opt.slop != 0.0) {
        fprintf(stderr, "peers_ode: --slop is rbsim's option\n%s", usage);
        return 2;
    }
    if (peers_scene_open(opt.scene_path, &sc))
        return 2;
    if (opt.extra != NULL && strcmp(opt.extra, "hash") != 0 && strcmp(opt.extra, "sap") != 0 &&
        strcmp(opt.extra, "simple") != 0) {
        fprintf(stderr, "peers_ode: --method wants hash, sap or simple, got \"%s\"\n", opt.extra);
        return 2;
    }
    steps = opt.steps >= 0 ? opt.steps : sc.steps;

    t0 = peers_now();
    dInitODE2(0);
    world = dWorldCreate();
    dWorldSetGravity(world, 0, 0, sc.gravity_z);
    dWorldSetERP(world, 0.2);
    dWorldSetCFM(world, 1e-5);
    dWorldSetQuickStepNumIterations(world, 20);
    dWorldSetContactSurfaceLayer(world, 0.0);
    dWorldSetAutoDisableFlag(world, 0);
    if (opt.extra != NULL && strcmp(opt.extra, "sap") == 0) {
        space = dSweepAndPruneSpaceCreate(0, dSAP_AXES_XYZ);
    } else if (opt.extra != NULL && strcmp(opt.extra, "simple") == 0) {
        space = dSimpleSpaceCreate(0);
    } else {
        space = dHashSpaceCreate(0); /* default levels 2^-3 .. 2^10 m */
    }
    for (i = 0; i < sc.n_planes; ++i) {
        const double *q = &sc.planes[6 * i];
        /* ODE's plane: n . x = d */
        dCreatePlane(space, q[3], q[4], q[5], q[0] * q[3] + q[1] * q[4] + q[2] * q[5]);
    }
    body = malloc((sc.n + 1) * sizeof *body);
    if (body == NULL) {
        fprintf(stderr, "peers_ode: out of memory\n");
        return 2;
    }
    for (i = 0; i < sc.n; ++i) {
        double q[8];
        dMass m;
        dGeomID g;
        if (peers_scene_sphere(&sc, q))
            return 2;
        g = dCreateSphere(space, q[0]);
        body[i] = dBodyCreate(world);
        dMassSetSphereTotal(&m, q[1], q[0]);
        dBodySetMass(body[i], &m);
        dBodySetPosition(body[i], q[2], q[3], q[4]);
        dBodySetLinearVel(body[i], q[5], q[6], q[7]);
        dGeomSetBody(g, body[i]);
    }
    peers_scene_free(&sc); /* keeps the counts */
    ctx.world = world;
    ctx.group = dJointGroupCreate(0);
    ctx.mu = sc.friction;
    ctx.bounce = sc.restitution;
    ctx.contacts = 0;
    peers_apex_init(&apex, sc.gravity_z);
    t1 = peers_now();
    t_setup = t1 - t0;

    t0 = peers_now();
    for (k = 0; k < steps; ++k) {
        double wall;
        ctx.contacts = 0;
        dSpaceCollide(space, &ctx, near_callback);
        if (ctx.contacts > contacts_max)
            contacts_max = ctx.contacts;
        dWorldQuickStep(world, sc.dt);
        dJointGroupEmpty(ctx.group);
        if (sc.track_apex && sc.n > 0)
            peers_apex_feed(&apex, dBodyGetPosition(body[0])[2], dBodyGetLinearVel(body[0])[2]);
        wall = peers_now() - t0;
        peers_progress(k + 1, wall, &last);
        if (opt.max_wall > 0.0 && wall >= opt.max_wall) {
            ++k;
            break;
        }
    }
    t1 = peers_now();

    if (opt.state_path) {
        FILE *f = peers_state_open(opt.state_path, sc.n);
        if (f == NULL)
            return 2;
        for (i = 0; i < sc.n; ++i)
            if (peers_state_put(f, dBodyGetPosition(body[i]), dBodyGetLinearVel(body[i]),
                                dBodyGetAngularVel(body[i]))) {
                (void)peers_state_close(f, opt.state_path);
                return 2;
            }
        if (peers_state_close(f, opt.state_path))
            return 2;
    }
    printf("RESULT {\"engine\": \"ode\", \"version\": \"%s\", \"space\": \"%s\", \"n\": %zu, "
           "\"steps\": %ld, \"dt\": %.9g, \"sim_time\": %.9g, \"wall\": %.9g, \"setup_wall\": %.9g, "
           "\"contacts_max\": %lu, \"rss_anon_kb\": %ld, \"apex\": ",
           dGetConfiguration(), opt.extra ? opt.extra : "hash", sc.n, k, sc.dt, (double)k * sc.dt, t1 - t0, t_setup, contacts_max,
           peers_rss_anon_kb());
    peers_print_apex(stdout, &apex);
    printf(", \"error\": \"\"}\n");
    dJointGroupDestroy(ctx.group);
    dSpaceDestroy(space);
    dWorldDestroy(world);
    dCloseODE();
    free(body);
    return 0;
}
