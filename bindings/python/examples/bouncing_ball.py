#!/usr/bin/env python3
"""A ball bouncing on the ground, compared with its exact apex heights.

A sphere dropped from rest with its bottom h above the ground, restitution e,
no drag: after the n-th bounce it leaves the ground with e^n times the impact
speed sqrt(2 g h), so its bottom rises to h * e^(2n).  This script builds the
scene in code, steps it, reads the height from the zero-copy state view,
finds each apex and prints it beside the exact value.

Tolerance: semi-implicit Euler is first order; over one rise or fall at
speeds up to v1 = sqrt(2 g h) it misplaces the height by about v1*dt/2, and a
bounce is resolved within one step, so every apex should lie within
2*v1*dt of h*e^(2n) (8.9e-4 m for h = 1 m, dt = 1e-4 s; the error does not
grow with n because each flight starts afresh from the impact speed).  That
still catches a wrong e: e = 0.79 instead of 0.8 moves the first apex by
0.016 m.  The script exits with status 1 if an apex is off by more.

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

    tol = 2 * math.sqrt(2 * g * h) * args.dt
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
        print("error: an apex differs by more than 2*v1*dt = %.3g m" % tol)
        return 1
    print("all apexes within 2*v1*dt = %.3g m of h*e^(2n)" % tol)
    return 0


if __name__ == "__main__":
    sys.exit(main())
