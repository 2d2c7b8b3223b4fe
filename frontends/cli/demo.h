/*
 * demo.h - the built-in demonstration of the rbsim command.
 */
#ifndef RBSF_DEMO_H
#define RBSF_DEMO_H

#include <stdio.h>

#include "rbsim/reel.h"

/** The demonstration scene (JSON). */
extern const char rbsf_demo_scene[];

/** What the checking renderer saw. */
typedef struct rbsf_demo_results {
    uint64_t frames;
    double dt, g, mu_k;
    int impact_seen;
    double impact_before, impact_after, impact_expected;
    double rolling_measured, rolling_spin, rolling_expected;
} rbsf_demo_results;

/** Fill cls with the checking renderer type ("rbsim-demo-check"); its
 * instance writes into *results (which must outlive it). */
void rbsf_demo_check_class(rbs_renderer_class *cls, rbsf_demo_results *results);
/** Print the checks against the exact answers; returns how many failed. */
int rbsf_demo_report(const rbsf_demo_results *results, FILE *out);

#endif
