/*
 * demo.c - the built-in demonstration: a scene compiled into the command and
 * a renderer that checks the run against exact answers.
 *
 *  - "ball" (solid rubber sphere, r = 0.1 m) falls from rest with its centre
 *    at z = 1 m onto the floor: the first impact comes at t = sqrt(2 h / g)
 *    with h = 0.9 m (centre height minus radius).
 *  - "slider" (solid steel sphere, r = 0.1 m) starts sliding at v0 = 2 m/s
 *    without spin; kinetic friction slows it and spins it up until it rolls,
 *    from then on at v = 5/7 v0 (angular momentum about the contact point is
 *    conserved: m v0 r = m v r + 2/5 m r^2 v/r).  [Any text on rolling
 *    friction, e.g. Marion & Thornton, Classical Dynamics, or
 *    https://en.wikipedia.org/wiki/Rolling#Rolling_with_slipping]
 *  - a small billiards break: "cue" hits a triangle of three balls.
 * The three groups stand far apart so they do not touch.
 */
#include "demo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char rbsf_demo_scene[] =
    "{\n"
    "  \"format\": 1,\n"
    "  \"description\": \"rbsim demonstration: a bouncing ball, a ball launched "
    "sliding that then rolls, and a small billiards break\",\n"
    "  \"simulation\": {\"steps\": 2000, \"dt\": 0.001,\n"
    "                 \"gravity\": [0, 0, -9.81], \"restitution\": 0.5},\n"
    "  \"materials\": [\n"
    "    {\"pair\": [\"rubber\", \"felt\"], \"static\": 0.6, \"kinetic\": 0.5,\n"
    "     \"restitution\": 0.8},\n"
    "    {\"pair\": [\"steel\", \"felt\"], \"static\": 0.4, \"kinetic\": 0.3,\n"
    "     \"restitution\": 0.3},\n"
    "    {\"pair\": [\"ivory\", \"felt\"], \"static\": 0.2, \"kinetic\": 0.2,\n"
    "     \"restitution\": 0.5},\n"
    "    {\"pair\": [\"ivory\", \"ivory\"], \"static\": 0.05, \"kinetic\": 0.05,\n"
    "     \"restitution\": 0.95},\n"
    "    {\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.4}\n"
    "  ],\n"
    "  \"bodies\": [\n"
    "    {\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0],\n"
    "     \"normal\": [0, 0, 1], \"material\": \"felt\", \"color\": \"#2e7d32\"},\n"
    "    {\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.1, \"mass\": 0.5,\n"
    "     \"position\": [0, -1.5, 1], \"material\": \"rubber\",\n"
    "     \"color\": \"#d03030\"},\n"
    "    {\"name\": \"slider\", \"type\": \"sphere\", \"radius\": 0.1, \"mass\": 2,\n"
    "     \"position\": [-1, 0, 0.1], \"velocity\": [2, 0, 0],\n"
    "     \"material\": \"steel\", \"color\": \"#9e9e9e\"},\n"
    "    {\"name\": \"cue\", \"type\": \"sphere\", \"radius\": 0.05, \"mass\": 0.17,\n"
    "     \"position\": [-1, 1.5, 0.05], \"velocity\": [3, 0, 0],\n"
    "     \"material\": \"ivory\", \"color\": \"#f5f5f5\", \"texture\": \"none\"},\n"
    "    {\"name\": \"one\", \"type\": \"sphere\", \"radius\": 0.05, \"mass\": 0.17,\n"
    "     \"position\": [0, 1.5, 0.05], \"material\": \"ivory\",\n"
    "     \"color\": \"#fbc02d\"},\n"
    "    {\"name\": \"two\", \"type\": \"sphere\", \"radius\": 0.05, \"mass\": 0.17,\n"
    "     \"position\": [0.087, 1.4495, 0.05], \"material\": \"ivory\",\n"
    "     \"color\": \"#1565c0\"},\n"
    "    {\"name\": \"three\", \"type\": \"sphere\", \"radius\": 0.05, \"mass\": 0.17,\n"
    "     \"position\": [0.087, 1.5505, 0.05], \"material\": \"ivory\",\n"
    "     \"color\": \"#c62828\"}\n"
    "  ]\n"
    "}\n";

/* ---- the checking renderer ---------------------------------------------- */

typedef struct demo_check {
    rbsf_demo_results *r;
    double dt, g;
    int have_first;
    double ball_z0, ball_r, prev_vz, prev_t;
    double slider_v0;
    double mu_k_slider;
} demo_check;

static const rbs_frame_body *find(const rbs_frame *f, const char *name)
{
    uint32_t i;
    for (i = 0; i < f->body_count; i++)
        if (f->bodies[i].name && strcmp(f->bodies[i].name, name) == 0)
            return &f->bodies[i];
    return NULL;
}

static rbs_status check_create(void *context, const rbs_renderer_config *config,
                               const rbs_world *world, void **instance,
                               char *err, size_t errlen)
{
    demo_check *d;
    rbs_world_def wd;
    (void)config;
    rbs_world_def_init(&wd);
    if (rbs_world_get_def(world, &wd) != RBS_OK) {
        snprintf(err, errlen, "no world");
        return RBS_E_INVALID;
    }
    d = calloc(1, sizeof *d);
    if (d == NULL) {
        snprintf(err, errlen, "out of memory");
        return RBS_E_MEMORY;
    }
    d->r = context;
    memset(d->r, 0, sizeof *d->r);
    d->dt = wd.dt;
    d->g = -wd.gravity.z;
    d->mu_k_slider = 0.3; /* the steel/felt row of the scene */
    *instance = d;
    return RBS_OK;
}

static rbs_status check_draw(void *instance, const rbs_frame *f, char *err,
                             size_t errlen)
{
    demo_check *d = instance;
    rbsf_demo_results *r = d->r;
    const rbs_frame_body *ball = find(f, "ball"), *slider = find(f, "slider");
    (void)err;
    (void)errlen;
    if (ball == NULL || slider == NULL)
        return RBS_OK; /* not the demonstration's bodies: nothing to check */
    if (!d->have_first) {
        d->have_first = 1;
        d->ball_z0 = ball->position[2];
        d->ball_r = ball->radius;
        d->slider_v0 = slider->velocity[0];
        d->prev_vz = ball->velocity[2];
        d->prev_t = f->time;
        r->impact_expected = sqrt(2 * (d->ball_z0 - d->ball_r) / d->g);
        r->rolling_expected = 5.0 / 7.0 * d->slider_v0;
        return RBS_OK;
    }
    /* The first impact lies between the last frame falling and the first
     * rising. */
    if (!r->impact_seen && d->prev_vz < 0 && ball->velocity[2] > 0) {
        r->impact_seen = 1;
        r->impact_before = d->prev_t;
        r->impact_after = f->time;
    }
    d->prev_vz = ball->velocity[2];
    d->prev_t = f->time;
    r->rolling_measured = slider->velocity[0];
    r->rolling_spin = slider->angular_velocity[1] * slider->radius;
    r->frames++;
    r->dt = d->dt;
    r->mu_k = d->mu_k_slider;
    r->g = d->g;
    return RBS_OK;
}

static rbs_status check_finish(void *instance, char *err, size_t errlen)
{
    (void)instance;
    (void)err;
    (void)errlen;
    return RBS_OK;
}

static void check_destroy(void *instance)
{
    free(instance);
}

void rbsf_demo_check_class(rbs_renderer_class *cls, rbsf_demo_results *results)
{
    memset(cls, 0, sizeof *cls);
    cls->struct_size = sizeof *cls;
    cls->name = "rbsim-demo-check";
    cls->context = results;
    cls->create = check_create;
    cls->draw = check_draw;
    cls->finish = check_finish;
    cls->destroy = check_destroy;
}

int rbsf_demo_report(const rbsf_demo_results *r, FILE *out)
{
    int failed = 0;
    double tol_t, tol_v, err_v, err_s;
    if (r->frames == 0) {
        fprintf(out, "checks: no frames were drawn\n");
        return 1;
    }
    /* Impact: the frames bracket it to within one step; semi-implicit Euler
     * falls ahead of the exact parabola by g dt t / 2 in position, which
     * moves the impact by at most half a step more.  Tolerance: 1.5 dt. */
    tol_t = 1.5 * r->dt;
    if (!r->impact_seen) {
        fprintf(out, "check: first impact of \"ball\": not seen (expected at "
                     "t = %.6f s)  FAIL\n", r->impact_expected);
        failed++;
    } else {
        double mid = 0.5 * (r->impact_before + r->impact_after);
        int ok = fabs(mid - r->impact_expected) <= tol_t;
        fprintf(out,
                "check: first impact of \"ball\" between t = %.4f s and %.4f s; "
                "exact sqrt(2h/g) = %.6f s (tolerance %.4f s)  %s\n",
                r->impact_before, r->impact_after, r->impact_expected, tol_t,
                ok ? "ok" : "FAIL");
        failed += !ok;
    }
    /* Rolling: the friction impulse of one step (mu_k g dt) bounds how far
     * the end of slipping can overshoot, in the speed, and 5/2 of it in
     * spin x radius (r alpha = 5/2 mu_k g for a solid ball); both are
     * compared -- rolling is v = omega r, and a ball sliding at 5/7 v0
     * without its spin would pass a check of the speed alone (a probe of
     * session 45). */
    tol_v = r->mu_k * r->g * r->dt;
    err_v = fabs(r->rolling_measured - r->rolling_expected);
    err_s = fabs(r->rolling_spin - r->rolling_expected);
    fprintf(out,
            "check: rolling speed of \"slider\" %.6f m/s, spin x radius %.6f m/s; "
            "exact 5/7 v0 = %.6f m/s for both (tolerance %.4f m/s, %.4f m/s)  %s\n",
            r->rolling_measured, r->rolling_spin, r->rolling_expected, tol_v, 2.5 * tol_v,
            err_v <= tol_v && err_s <= 2.5 * tol_v ? "ok" : "FAIL");
    failed += !(err_v <= tol_v && err_s <= 2.5 * tol_v);
    return failed;
}
