#!/usr/bin/env python3
"""A ball bouncing on the ground, compared with its exact apex heights.

A sphere dropped from rest with its bottom h above the ground, restitution e,
no drag: after the n-th bounce it leaves the ground with e^n times the impact
speed sqrt(2 g h), so its bottom rises to h * e^(2n).  This script builds the
scene in code, steps it, reads the height from the zero-copy state view,
finds each apex and prints it beside the exact value.

Tolerance: semi-implicit Euler is first order.  Each flight loses about
g*dt of speed (the step that resolves the impact), and the bounces carry it
on: the k-th rebound leaves at e(v_(k-1) - g dt), so the n-th at
e^n v1 - g dt S_n, S_n = e + e^2 + ... + e^n, v1 = sqrt(2 g h), and the n-th
apex is low by about v1 dt e^n S_n (within 3 % for e = 0.95, dt = 1e-4 s).
That grows with n at first and falls again as the bounces shrink.  Its
largest value over the bounces checked, with v1*dt/2 more for where a step
places an apex and a margin of 1.5, is the tolerance (8.3e-4 m for h = 1 m, e = 0.8, dt = 1e-4 s, 4
bounces; e = 0.95 needs 2.2e-3 m).  That still catches a wrong e: e = 0.79
instead of 0.8 moves the first apex by 0.016 m.  The script exits with
status 1 if an apex is off by more.

    python3 examples/bouncing_ball.py [--height H] [--restitution E] [--dt DT]
"""

import argparse
import math
import sys

import rbsim


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--height", type=float, default=1.0, help="drop height h, m")
    ap.add_argument("--restitution", type=float, default=0.8, help="e in [0, 1)")
    ap.add_argument("--dt", type=float, default=1e-4, help="time step, s")
    ap.add_argument("--bounces", type=int, default=4, help="apexes to compare")
    args = ap.parse_args(argv)

    g, r, h, e = 9.81, 0.1, args.height, args.restitution
    world = rbsim.World(dt=args.dt, gravity=(0.0, 0.0, -g), restitution=e)
    world.add_plane("ground")
    world.add_sphere("ball", radius=r, mass=1.0, position=(0.0, 0.0, h + r))

    # Simulate up to the n-th apex: time of flight to it is
    # t1 (1 + 2e + ... + 2e^(n-1) + e^n), t1 = sqrt(2h/g).
    t1 = math.sqrt(2 * h / g)
    t_end = t1 * (1 + 2 * sum(e ** k for k in range(1, args.bounces + 1))) + 0.05
    z = world.positions[:, 2]           # a view: it follows the world, no copy
    vz = world.velocities[:, 2]
    ball = world.bodies["ball"].slot
    apexes = []
    rising = False
    while world.time < t_end and len(apexes) < args.bounces:
        world.step()
        if vz[ball] > 0:
            rising = True
        elif rising:                    # velocity turned down: an apex
            rising = False
            apexes.append(z[ball] - r)

    # the first-order error bound of the docstring, 1.5 x its largest value
    v1, s_n, bound = math.sqrt(2 * g * h), 0.0, 0.0
    for n in range(1, args.bounces + 1):
        s_n += e ** n
        bound = max(bound, e ** n * (s_n + 0.5))
    tol = 1.5 * v1 * args.dt * bound
    print("bounce  exact h*e^(2n) (m)  simulated (m)  difference (m)")
    worst = 0.0
    for n, got in enumerate(apexes, start=1):
        exact = h * e ** (2 * n)
        diff = got - exact
        worst = max(worst, abs(diff))
        print("%6d  %18.6f  %13.6f  %+14.2e" % (n, exact, got, diff))
    if len(apexes) < args.bounces:
        print("error: found %d apexes, expected %d" % (len(apexes), args.bounces))
        return 1
    if worst > tol:
        print("error: an apex differs by more than the first-order bound %.3g m" % tol)
        return 1
    print("all apexes within the first-order bound %.3g m of h*e^(2n)" % tol)
    return 0


if __name__ == "__main__":
    sys.exit(main())
