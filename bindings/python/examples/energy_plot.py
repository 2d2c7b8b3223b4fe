#!/usr/bin/env python3
"""Energy against time, plotted to a PNG with matplotlib.

Runs a scene (default: a ball bouncing with restitution 0.8, built in code;
or any scene file given) through the projector with a Python renderer that
records kinetic, potential and total energy of every frame, then plots them.
Each impact shows as a step down in the total: a fraction 1 - e^2 of the
kinetic energy at impact is lost.

matplotlib is optional: without it the script says so and exits with
status 0 without writing anything (pip install matplotlib, or
pip install "./bindings/python[plot]").

    python3 examples/energy_plot.py [SCENE] [--steps N] [--out energy.png]
"""

import argparse
import sys

import rbsim


class EnergyRecorder:
    """A renderer: keeps (t, kinetic, potential, total) of each frame."""

    def __init__(self):
        self.rows = []

    def draw(self, frame):
        e = frame.energy
        self.rows.append((frame.time, e.kinetic, e.potential, e.total))


def demo_world():
    world = rbsim.World(dt=0.0005, restitution=0.8)
    world.add_plane("ground")
    world.add_sphere("ball", radius=0.1, mass=1.0, position=(0.0, 0.0, 1.1))
    return world


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene", nargs="?", help="a scene file (default: a bouncing ball)")
    ap.add_argument("--steps", type=int, default=None, help="steps to run")
    ap.add_argument("--out", default="energy.png", help="PNG to write")
    args = ap.parse_args(argv)

    try:
        import matplotlib
        matplotlib.use("Agg")  # no display needed
        import matplotlib.pyplot as plt
    except ImportError:
        print("energy_plot: matplotlib is not installed, so there is nothing to "
              "plot (pip install matplotlib); skipped")
        return 0

    if args.scene:
        world = rbsim.load(args.scene)
        steps = args.steps
    else:
        world = demo_world()
        steps = args.steps if args.steps is not None else 6000
    rec = EnergyRecorder()
    world.run(steps, renderers=[rec])

    t = [r[0] for r in rec.rows]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(t, [r[1] for r in rec.rows], label="kinetic")
    ax.plot(t, [r[2] for r in rec.rows], label="potential")
    ax.plot(t, [r[3] for r in rec.rows], label="total", linewidth=2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    title = world.description or "bouncing ball, e = 0.8"
    ax.set_title(title if len(title) <= 70 else title[:67] + "...")
    ax.legend()
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print("energy_plot: %d frames, total energy %.6g J -> %.6g J; wrote %s"
          % (len(rec.rows), rec.rows[0][3], rec.rows[-1][3], args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
