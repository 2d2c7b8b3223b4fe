"""Scenes of the peer benchmark, written once here and read by every driver.

The scene file format is described in peers_io.h (magic "RBSPEER1", a header
of 8 doubles, planes, spheres).  Every engine starts from the same bytes.

Scenes (SI units):
  pile N      N spheres (r 0.05 m, m 0.1 kg) on a lattice of spacing 0.12 m,
              at most 16 x 16 per layer (so it fits the box), lowest centres
              at z = 0.1 m, each coordinate jittered by up to +-5 mm
              (deterministic: splitmix64 of the sphere index), dropped at
              rest into a 2 m x 2 m box: floor z = 0 and walls x, y = +-1.
  billiards   16 balls (r 0.0286 m, m 0.17 kg) resting on a floor: a
              triangle of 15 (apex at x = 0.5 m, 0.1 mm gaps) and the cue
              ball at x = -0.5 m moving at 8 m/s along +x.
  ball        one sphere (r 0.1 m, m 1 kg) dropped from rest with its lowest
              point 1 m above the floor; apex n of the rebounds is
              h e^(2n) above the floor for a rigid contact.
  lattice N   (scaling, rbsim only) a falling lattice: 10 layers of spacing
              0.12 m, side ceil(sqrt(N/10)), lowest centres at z = 0.5 m, in a
              box that fits it; no contacts during the first 0.3 s.
  stack N     (scaling, rbsim only) a settled pile: 10 layers of touching
              spheres (spacing exactly 2r) resting on the floor, walls touching
              the outer columns; every sphere in resting contact.
All contacts: restitution 0.5 and friction 0.5; gravity -9.81 m/s^2 along z;
dt = 1 ms.
"""
import struct

import numpy as np

MAGIC = b"RBSPEER1"
STATE_MAGIC = b"RBSSTAT1"
DT = 0.001
G = -9.81
E = 0.5
MU = 0.5


def jitter(count, seed):
    """count uniform numbers in [-1, 1) from splitmix64 (Steele et al. 2014)."""
    with np.errstate(over="ignore"):
        z = (np.arange(count, dtype=np.uint64) + np.uint64(seed)) * np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        z = z ^ (z >> np.uint64(31))
    return (z >> np.uint64(11)).astype(np.float64) * (2.0 / 2.0**53) - 1.0


def box_planes(half):
    """Floor z = 0 and four walls at x, y = +-half, normals pointing inward."""
    return [
        (0, 0, 0, 0, 0, 1),
        (-half, 0, 0, 1, 0, 0),
        (half, 0, 0, -1, 0, 0),
        (0, -half, 0, 0, 1, 0),
        (0, half, 0, 0, -1, 0),
    ]


def lattice(n, side, layers_spacing, spacing, z0):
    """Centres of n spheres filling side x side layers from the bottom."""
    k = np.arange(n)
    ix, iy, iz = k % side, (k // side) % side, k // (side * side)
    off = (side - 1) / 2.0
    x = (ix - off) * spacing
    y = (iy - off) * spacing
    z = z0 + iz * layers_spacing
    return np.stack([x, y, z], axis=1)


def make(kind, n=0):
    """(planes, spheres array n x 8, steps, track_apex) of a scene."""
    if kind == "pile":
        side = min(int(np.ceil(round(n ** (1 / 3), 9))), 16)
        pos = lattice(n, side, 0.12, 0.12, 0.1)
        pos += 0.005 * jitter(3 * n, 12345).reshape(n, 3)
        spheres = np.zeros((n, 8))
        spheres[:, 0], spheres[:, 1], spheres[:, 2:5] = 0.05, 0.1, pos
        return box_planes(1.0), spheres, 2000, 0
    if kind == "billiards":
        r, gap = 0.0286, 1e-4
        d = 2 * r + gap
        rows = [(0.5 + k * d * np.sqrt(3) / 2, (j - k / 2) * d) for k in range(5) for j in range(k + 1)]
        spheres = np.zeros((16, 8))
        spheres[:, 0], spheres[:, 1], spheres[:, 4] = r, 0.17, r
        spheres[0, 2], spheres[0, 5] = -0.5, 8.0
        for i, (x, y) in enumerate(rows):
            spheres[i + 1, 2], spheres[i + 1, 3] = x, y
        return [(0, 0, 0, 0, 0, 1)], spheres, 2000, 0
    if kind == "ball":
        spheres = np.array([[0.1, 1.0, 0.0, 0.0, 1.1, 0.0, 0.0, 0.0]])
        return [(0, 0, 0, 0, 0, 1)], spheres, 2000, 1
    if kind in ("lattice", "stack"):
        side = int(np.ceil(np.sqrt(n / 10.0)))
        spheres = np.zeros((n, 8))
        spheres[:, 0], spheres[:, 1] = 0.05, 0.1
        if kind == "lattice":
            spheres[:, 2:5] = lattice(n, side, 0.12, 0.12, 0.5)
            spheres[:, 2:5] += 0.005 * jitter(3 * n, 777).reshape(n, 3)
            half = side * 0.06 + 0.05
        else:
            spheres[:, 2:5] = lattice(n, side, 0.1, 0.1, 0.05)
            half = side * 0.05
        return box_planes(half), spheres, 20, 0
    raise ValueError(f"unknown scene kind {kind!r} (pile, billiards, ball, lattice, stack)")


def write(path, kind, n=0):
    planes, spheres, steps, apex = make(kind, n)
    header = [len(spheres), len(planes), DT, steps, G, E, MU, apex]
    with open(path, "wb") as f:
        f.write(MAGIC)
        f.write(struct.pack("<8d", *header))
        np.asarray(planes, dtype="<f8").tofile(f)
        np.ascontiguousarray(spheres, dtype="<f8").tofile(f)
    return len(spheres)


class Scene:
    """A scene file read back (what the Python drivers use)."""

    def __init__(self, path):
        with open(path, "rb") as f:
            data = f.read()
        if data[:8] != MAGIC:
            raise ValueError(f"scene {path}: not a peers scene file (magic RBSPEER1)")
        h = struct.unpack("<8d", data[8:72])
        self.n, self.n_planes = int(h[0]), int(h[1])
        self.dt, self.steps, self.gravity_z = h[2], int(h[3]), h[4]
        self.restitution, self.friction, self.track_apex = h[5], h[6], h[7] != 0
        body = np.frombuffer(data, dtype="<f8", offset=72)
        if body.size != 6 * self.n_planes + 8 * self.n:
            raise ValueError(f"scene {path}: truncated ({body.size} doubles after the header)")
        self.planes = body[: 6 * self.n_planes].reshape(self.n_planes, 6)
        self.spheres = body[6 * self.n_planes:].reshape(self.n, 8)


def write_state(path, state9):
    """Final state, n x 9 (position, velocity, angular velocity)."""
    state9 = np.ascontiguousarray(state9, dtype="<f8")
    with open(path, "wb") as f:
        f.write(STATE_MAGIC)
        f.write(struct.pack("<d", float(state9.shape[0])))
        state9.tofile(f)


def rss_anon_kb():
    """This process's anonymous resident memory now, kB (RssAnon of
    /proc/self/status, as peers_io.c reads it), or -1 where it is not
    reported."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("RssAnon:"):
                    return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return -1


class Apex:
    """Apexes of sphere 0: where vz turns from > 0 to <= 0, taken as the
    ballistic peak from the step before (as peers_io.c does)."""

    def __init__(self, gravity_z):
        self.g, self.prev_z, self.prev_vz, self.z = abs(gravity_z), 0.0, 0.0, []

    def feed(self, z, vz):
        if self.prev_vz > 0.0 and vz <= 0.0 and len(self.z) < 32:
            self.z.append(self.prev_z + self.prev_vz**2 / (2 * self.g))
        self.prev_z, self.prev_vz = z, vz


def driver_args(argv, engine):
    """The drivers' common command line (see peers_io.h)."""
    import argparse

    ap = argparse.ArgumentParser(prog=f"drive_{engine}.py")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--steps", type=int, default=-1)
    ap.add_argument("--max-wall", type=float, default=0.0)
    ap.add_argument("--state-out")
    a = ap.parse_args(argv)
    if a.steps < -1 or a.max_wall < 0:
        ap.error("--steps and --max-wall must be >= 0")
    return a


if __name__ == "__main__":
    import sys

    if len(sys.argv) not in (3, 4):
        sys.exit("usage: scenes.py OUT.bin KIND [N]")
    print(write(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) == 4 else 0))
