#!/usr/bin/env python3
"""Write the demonstration scenes scenes/NAME.json (format version 1).

The JSON files are the source of truth; the text versions NAME/config.txt,
materials.txt and objects.txt are written from them with `rbsim convert`
(rbs_scene_save) -- except bouncing_sphere/, kept by hand with comments as an
example -- and tests/scene checks that both load to the same world.
Run from anywhere: python3 scenes/make_scenes.py
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
G = 9.81


def num(x):
    """Shortest text that reads back as the same double."""
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, int):
        return str(x)
    r = repr(float(x))
    if r.endswith(".0"):
        r = r[:-2]
    return r


def dump(v):
    if isinstance(v, dict):
        return "{" + ", ".join(json.dumps(k) + ": " + dump(x) for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(dump(x) for x in v) + "]"
    if isinstance(v, str):
        return json.dumps(v)
    return num(v)


def write(name, description, simulation, materials, bodies, renderers):
    lines = ["{", '  "description": ' + json.dumps(description) + ","]
    lines.append('  "simulation": ' + dump(simulation) + ",")
    lines.append('  "materials": [')
    lines.append(",\n".join("    " + dump(m) for m in materials))
    lines.append("  ],")
    lines.append('  "bodies": [')
    lines.append(",\n".join("    " + dump(b) for b in bodies))
    lines.append("  ],")
    lines.append('  "renderers": [')
    lines.append(",\n".join("    " + dump(r) for r in renderers))
    lines.append("  ]")
    lines.append("}")
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        f.write("\n".join(lines) + "\n")


def csv(name, every=1):
    return {"type": "csv", "path": "out/%s.csv" % name, "every": every}


def floor(material="floor", color="#808080"):
    return {"name": "floor", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1],
            "material": material, "color": color, "texture": "checker"}


# ---------------------------------------------------------------- bouncing
h, e = 1.0, 0.8
write("bouncing_sphere",
      "A rubber ball (r = 0.1 m) dropped from rest with its bottom h = 1 m above a "
      "concrete floor; g = 9.81 m/s^2, restitution e = 0.8, no air drag. Look at z "
      "of 'ball' in out/bouncing_sphere.csv. Exact answers: first impact at "
      "t1 = sqrt(2h/g) = %.6f s with speed sqrt(2gh) = %.6f m/s; after the n-th "
      "bounce the bottom rises to h*e^(2n) (0.64, 0.4096, 0.262144 m, centre 0.1 m "
      "higher), reached t1*(1 + 2e + ... + 2e^(n-1) + e^n) after release; the n-th "
      "flight lasts 2*e^n*t1." % (math.sqrt(2 * h / G), math.sqrt(2 * G * h)),
      {"steps": 3000, "dt": 0.001, "gravity": [0, 0, -G], "gravity_mode": "acceleration",
       "method": "euler", "restitution": 0.5, "pause_on_collision": False},
      [{"pair": ["rubber", "concrete"], "static": 1.0, "kinetic": 0.8, "restitution": e}],
      [{"name": "ball", "type": "sphere", "radius": 0.1, "mass": 1.0, "inertia": "solid",
        "position": [0, 0, 1.1], "material": "rubber", "color": "#d03030",
        "texture": "stripes"},
       floor("concrete")],
      [csv("bouncing_sphere")])

# ---------------------------------------------------------------- rolling
v0, r = 1.0, 0.1
write("rolling_sphere",
      "A solid ball (r = 0.1 m, m = 1 kg) resting on a floor, launched rolling "
      "without slipping: v = 1 m/s along +x, omega = v/r = 10 rad/s about +y; "
      "no rolling resistance. Look at x, vx and wy of 'ball'. Exact answer: it "
      "keeps rolling, x(t) = v t, vx = 1 m/s, wy = 10 rad/s, z = 0.1 m, "
      "kinetic energy 7/10 m v^2 = 0.7 J for all t (friction does no work).",
      {"steps": 2000, "dt": 0.001, "gravity": [0, 0, -G]},
      [{"pair": ["wood", "felt"], "static": 0.4, "kinetic": 0.3, "restitution": 0.0,
        "rolling": 0.0, "spinning": 0.0}],
      [{"name": "ball", "type": "sphere", "radius": r, "mass": 1.0, "inertia": "solid",
        "position": [0, 0, r], "velocity": [v0, 0, 0], "angular_velocity": [0, v0 / r, 0],
        "material": "wood", "color": "#3060d0", "texture": "stripes"},
       floor("felt", "#207040")],
      [csv("rolling_sphere")])

# ---------------------------------------------------------------- sliding
v0, mu = 2.0, 0.2
t_roll = 2 * v0 / (7 * mu * G)
write("sliding_sphere",
      "A solid ball (r = 0.1 m) set on a floor sliding at v0 = 2 m/s along +x with "
      "no spin; kinetic friction mu_k = 0.2, g = 9.81. Look at vx and wy of 'ball'. "
      "Exact answer: while it slips vx = v0 - mu_k g t and wy = 5 mu_k g t/(2r); it "
      "rolls from t = 2 v0/(7 mu_k g) = %.6f s at vx = 5/7 v0 = %.6f m/s, having "
      "travelled x = 12 v0^2/(49 mu_k g) = %.6f m, and rolls on at that speed."
      % (t_roll, 5 / 7 * v0, 12 * v0 * v0 / (49 * mu * G)),
      {"steps": 1000, "dt": 0.001, "gravity": [0, 0, -G]},
      [{"pair": ["steel", "felt"], "static": 0.25, "kinetic": mu, "restitution": 0.0}],
      [{"name": "ball", "type": "sphere", "radius": 0.1, "mass": 1.0, "inertia": "solid",
        "position": [0, 0, 0.1], "velocity": [v0, 0, 0], "material": "steel",
        "color": "#c0c0c0", "texture": "stripes"},
       floor("felt", "#207040")],
      [csv("sliding_sphere")])

# ---------------------------------------------------------------- collisions
R, m = 0.028575, 0.17
gap = 1e-4
d = 2 * R + gap
balls = []
colors = ["#f0d020", "#2040c0", "#d02020", "#602080", "#f08020", "#107030", "#801010",
          "#101010", "#f0d020", "#2040c0", "#d02020", "#602080", "#f08020", "#107030",
          "#801010"]
k = 0
for row in range(5):
    for j in range(row + 1):
        x = 0.5 + row * d * math.sqrt(3) / 2
        y = (j - row / 2) * d
        balls.append({"name": "ball%d" % (k + 1), "type": "sphere", "radius": R, "mass": m,
                      "position": [round(x, 9), round(y, 9), R], "material": "resin",
                      "color": colors[k], "texture": "stripes" if k >= 8 else "none"})
        k += 1
balls.insert(0, {"name": "cue", "type": "sphere", "radius": R, "mass": m,
                 "position": [-0.5, 0, R], "velocity": [6.0, 0, 0], "material": "resin",
                 "color": "#f0f0f0", "texture": "none"})
write("collisions",
      "Billiards break: a cue ball at 6 m/s along +x hits a triangle of 15 balls "
      "(r = 28.575 mm, m = 0.17 kg, 0.1 mm apart, none touching) on a cloth table "
      "plane. Look at the spread of the balls and at momentum and energy in the "
      "stats. Exact answers: ball-ball impacts conserve momentum, so the "
      "horizontal momentum just after the break equals the cue ball's just "
      "before it (1.02 kg m/s at the start, less what cloth friction takes on "
      "the way); the cue ball slides (no spin) on cloth with mu_k = 0.2 and rolls "
      "from t = 2 v0/(7 mu_k g) = %.6f s at 5/7 v0 = %.6f m/s if it has not hit "
      "the rack by then; no ball may overlap another or leave z = r." %
      (2 * 6.0 / (7 * 0.2 * G), 5 / 7 * 6.0),
      {"steps": 2000, "dt": 0.0005, "gravity": [0, 0, -G]},
      [{"pair": ["resin", "resin"], "static": 0.06, "kinetic": 0.05, "restitution": 0.95},
       {"pair": ["resin", "cloth"], "static": 0.25, "kinetic": 0.2, "restitution": 0.5,
        "rolling": 0.01}],
      balls + [{"name": "table", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1],
                "material": "cloth", "color": "#106030", "texture": "none"}],
      [csv("collisions", 4)])

# ---------------------------------------------------------------- cradle
r = 0.0625  # exact in binary, so the balls touch exactly (gap 0)
write("newtons_cradle",
      "Newton's cradle without strings: 5 equal steel balls (r = 0.0625 m, 1 kg) "
      "in a row along x, each touching the next (gap 0), zero gravity, restitution "
      "1, frictionless; the first ball moves at +1 m/s. Look at the velocities. "
      "Exact answer: momentum (1 kg m/s) and kinetic energy (0.5 J) are conserved; "
      "the impulse passes through the row, ball 5 leaves at 1 m/s and balls 1-4 "
      "end at rest.",
      {"steps": 1000, "dt": 0.001, "gravity": [0, 0, 0], "restitution": 1.0},
      [{"pair": ["steel", "steel"], "static": 0.0, "kinetic": 0.0, "restitution": 1.0}],
      [{"name": "ball%d" % (i + 1), "type": "sphere", "radius": r, "mass": 1.0,
        "position": [2 * r * i, 0, 0], "velocity": [1.0 if i == 0 else 0.0, 0, 0],
        "material": "steel", "color": "#c0c0c8", "texture": "stripes"} for i in range(5)],
      [csv("newtons_cradle")])

# ---------------------------------------------------------------- incline
th = math.radians(30)
n = [math.sin(th), 0.0, math.cos(th)]
r = 0.1
mu_roll, mu_slide = 0.5, 0.05
write("incline",
      "Two solid balls (r = 0.1 m) released from rest on a plane tilted 30 degrees "
      "(downhill is +x and -z). Look at the distance s along the slope and the "
      "spin of each ball. Exact answers: a solid sphere rolls without slipping iff "
      "tan(theta) <= 7/2 mu_s. 'roller' (rubber on the ramp, mu_s = 0.5: 0.577 <= "
      "1.75) rolls with acceleration 5/7 g sin(theta) = %.6f m/s^2 along the slope; "
      "'slider' (ice, mu_s = mu_k = 0.05: 0.577 > 0.175) slides with acceleration "
      "g (sin(theta) - mu_k cos(theta)) = %.6f m/s^2 while its spin grows at "
      "5 mu_k g cos(theta)/(2 r) = %.6f rad/s^2; both start from rest, so "
      "s = a t^2/2." % (5 / 7 * G * math.sin(th),
                               G * (math.sin(th) - mu_slide * math.cos(th)),
                               5 * mu_slide * G * math.cos(th) / (2 * r)),
      {"steps": 1000, "dt": 0.001, "gravity": [0, 0, -G]},
      [{"pair": ["rubber", "ramp"], "static": mu_roll, "kinetic": 0.4, "restitution": 0.0},
       {"pair": ["ice", "ramp"], "static": mu_slide, "kinetic": mu_slide, "restitution": 0.0},
       {"pair": ["*", "*"], "static": 0.3, "kinetic": 0.2}],
      [{"name": "roller", "type": "sphere", "radius": r, "mass": 1.0,
        "position": [r * n[0], -0.3, r * n[2]], "material": "rubber", "color": "#d03030",
        "texture": "stripes"},
       {"name": "slider", "type": "sphere", "radius": r, "mass": 1.0,
        "position": [r * n[0], 0.3, r * n[2]], "material": "ice", "color": "#80c0f0",
        "texture": "stripes"},
       {"name": "ramp", "type": "plane", "point": [0, 0, 0], "normal": n,
        "material": "ramp", "color": "#a08060", "texture": "checker"}],
      [csv("incline")])

# ---------------------------------------------------------------- pile
r = 0.04
half = 0.5
bodies = []
palette = ["#d03030", "#30a050", "#3060d0", "#e0b020", "#a040c0", "#20b0b0"]
k = 0
for layer in range(8):
    off = 0.02 if layer % 2 else -0.02
    for i in range(6):
        for j in range(6):
            x = -0.25 + 0.1 * i + off
            y = -0.25 + 0.1 * j - off
            z = 0.3 + 0.1 * layer
            bodies.append({"name": "s%03d" % k, "type": "sphere", "radius": r,
                           "mass": 0.2, "position": [round(x, 6), round(y, 6), round(z, 6)],
                           "material": "plastic", "color": palette[k % 6],
                           "texture": "stripes"})
            k += 1
walls = [("floor", [0, 0, 0], [0, 0, 1]),
         ("wall_east", [half, 0, 0], [-1, 0, 0]),
         ("wall_west", [-half, 0, 0], [1, 0, 0]),
         ("wall_north", [0, half, 0], [0, -1, 0]),
         ("wall_south", [0, -half, 0], [0, 1, 0])]
for name, p, nn in walls:
    bodies.append({"name": name, "type": "plane", "point": p, "normal": nn,
                   "material": "wood", "color": "#a08060", "texture": "checker"})
write("pile",
      "288 plastic spheres (r = 0.04 m) on a staggered grid fall into an open box "
      "of five planes (floor and four walls 1 m apart). Look at the heap settling, "
      "the kinetic energy decaying to 0, the contact counts and overlaps in the "
      "stats. Exact answers: no sphere ever leaves the box (|x|, |y| <= 0.46 m, "
      "z >= 0.04 m up to the slop), the potential energy only decreases once "
      "everything is at rest, and the final heap (at most 288 spheres in 1 m^2) "
      "is at most a few layers high. Method: selective (only colliding pairs roll "
      "back; euler's whole-world rollback is far slower on a heap).",
      {"steps": 3000, "dt": 0.001, "gravity": [0, 0, -G], "restitution": 0.3,
       "method": "selective"},
      [{"pair": ["plastic", "plastic"], "static": 0.4, "kinetic": 0.3, "restitution": 0.3},
       {"pair": ["plastic", "wood"], "static": 0.5, "kinetic": 0.4, "restitution": 0.4}],
      bodies,
      [csv("pile", 10)])

# ---------------------------------------------------------------- orbit
Gc, m, dist = 1.0, 1.0, 1.0
v = math.sqrt(Gc * m / (2 * dist))
T = 2 * math.pi * math.sqrt(dist ** 3 / (Gc * 2 * m))
write("orbit",
      "Two equal spheres (m = 1 kg, r = 0.05 m) 1 m apart attract each other with "
      "mutual gravity, G = 1 (a scaled unit, not the SI value), softening 0, no "
      "uniform gravity; each moves at v = sqrt(G m/(2 d)) = %.9f m/s "
      "perpendicular to the line between them. Look at the separation and the "
      "energy. Exact answer: a circular orbit about the origin: separation stays "
      "1 m, period T = 2 pi sqrt(d^3/(2 G m)) = %.9f s (the run is one period), "
      "kinetic 0.5 J, potential -1 J, total -0.5 J, momentum 0, angular momentum "
      "2 m (d/2) v = %.9f kg m^2/s about +z." % (v, T, 2 * m * (dist / 2) * v),
      {"steps": int(round(T / 0.001)), "dt": 0.001, "gravity": [0, 0, 0],
       "mutual_gravity": {"G": Gc, "softening": 0.0}},
      [{"pair": ["*", "*"], "static": 0.0, "kinetic": 0.0, "restitution": 1.0}],
      [{"name": "a", "type": "sphere", "radius": 0.05, "mass": m,
        "position": [-dist / 2, 0, 0], "velocity": [0, -v, 0], "color": "#f0c040",
        "texture": "none"},
       {"name": "b", "type": "sphere", "radius": 0.05, "mass": m,
        "position": [dist / 2, 0, 0], "velocity": [0, v, 0], "color": "#4080f0",
        "texture": "none"}],
      [csv("orbit", 10)])
