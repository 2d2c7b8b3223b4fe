"""Runs a peers scene in MuJoCo through PyPI's mujoco and reports time.

    drive_mujoco.py --scene FILE [--steps K] [--max-wall S] [--state-out FILE]

Settings (stated in bench/results/peers.md):
  - MJCF generated here: each sphere a body with a free joint and one sphere
    geom (mass given, so inertia 2/5 m r^2); each plane a world geom of type
    plane (infinite for collision) whose z axis is the plane's normal.
  - timestep dt, gravity along z, integrator Euler, pyramidal cone, condim 3
    (sliding friction mu; no rolling or torsional friction), solver and
    iterations at MuJoCo's defaults (Newton, 100 iterations, tolerance 1e-8).
  - MuJoCo's contacts are soft; restitution is approximated through solref
    = (timeconst, dampratio) = (0.02 s, 0.2154): MuJoCo's default time
    constant, and the damping ratio z of a linear spring-damper whose bounce
    has e = exp(-pi z / sqrt(1 - z^2)) = 0.5.  solimp at its default.  The
    bouncing-ball row shows how close this gets (shorter time constants such
    as 0.005 s bounce far higher than e = 0.5 at dt = 1 ms).
  - The arena (<size memory>) is sized from the sphere count (40 kB per
    sphere plus 2.5 bytes per pair of spheres, which MuJoCo's collision stage
    needs); if contacts overflow it MuJoCo warns and the driver reports it.
Only the stepping loop is timed; compiling the model is setup time.
"""
import json
import math
import sys
import time

import mujoco
import numpy as np

import scenes

TIMECONST = 0.02  # MuJoCo's default time constant


def dampratio(e):
    """Damping ratio of a linear spring-damper whose bounce has restitution e."""
    if e <= 0:
        return 1.0
    l = math.log(e)
    return -l / math.sqrt(math.pi**2 + l * l)


def num(x):
    """Shortest exact text of a float (numpy scalars print with a type name)."""
    return repr(float(x))


def mjcf(sc):
    # about 40 kB per sphere, plus what MuJoCo's collision stage takes per
    # pair of geoms (~2 bytes each: 1.46 GB at N = 27,000)
    mem_mb = max(64, int(sc.n * 0.04 + sc.n * sc.n * 2.5e-6) + 16)
    z = dampratio(sc.restitution)
    out = [
        '<mujoco model="peers">',
        f'  <option timestep="{num(sc.dt)}" gravity="0 0 {num(sc.gravity_z)}" integrator="Euler" cone="pyramidal"/>',
        f'  <size memory="{mem_mb}M"/>',
        '  <default>',
        f'    <geom condim="3" friction="{num(sc.friction)} 0 0" solref="{num(TIMECONST)} {num(z)}"/>',
        '  </default>',
        '  <worldbody>',
    ]
    for i, q in enumerate(sc.planes):
        out.append(f'    <geom name="plane{i}" type="plane" size="0 0 1" '
                   f'pos="{num(q[0])} {num(q[1])} {num(q[2])}" zaxis="{num(q[3])} {num(q[4])} {num(q[5])}"/>')
    for i, s in enumerate(sc.spheres):
        out.append(f'    <body pos="{num(s[2])} {num(s[3])} {num(s[4])}"><freejoint/>'
                   f'<geom type="sphere" size="{num(s[0])}" mass="{num(s[1])}"/></body>')
    out += ['  </worldbody>', '</mujoco>']
    return "\n".join(out), mem_mb


def main(argv):
    a = scenes.driver_args(argv, "mujoco")
    sc = scenes.Scene(a.scene)
    steps = a.steps if a.steps >= 0 else sc.steps

    t0 = time.perf_counter()
    xml, mem_mb = mjcf(sc)
    m = mujoco.MjModel.from_xml_string(xml)
    del xml
    d = mujoco.MjData(m)
    if m.nbody - 1 != sc.n:
        raise RuntimeError(f"model has {m.nbody - 1} bodies for {sc.n} spheres")
    qvel = d.qvel.reshape(sc.n, 6) if sc.n else d.qvel
    if sc.n:
        qvel[:, 0:3] = sc.spheres[:, 5:8]
    mujoco.mj_forward(m, d)
    apex = scenes.Apex(sc.gravity_z)
    t_setup = time.perf_counter() - t0

    t0 = time.perf_counter()
    last = 0.0
    k = 0
    ncon_max = 0
    while k < steps:
        mujoco.mj_step(m, d)
        k += 1
        if d.ncon > ncon_max:
            ncon_max = int(d.ncon)
        if sc.track_apex:
            apex.feed(float(d.qpos[2]), float(d.qvel[2]))
        wall = time.perf_counter() - t0
        if wall - last >= 1.0:
            print(f"# progress {k} {wall:.6f}", flush=True)
            last = wall
        if a.max_wall > 0 and wall >= a.max_wall:
            break
    wall = time.perf_counter() - t0

    warnings = {mujoco.mjtWarning(i).name: int(d.warning[i].number)
                for i in range(len(d.warning)) if d.warning[i].number > 0}
    if a.state_out:
        st = np.zeros((sc.n, 9))
        if sc.n:
            qpos = d.qpos.reshape(sc.n, 7)
            qv = d.qvel.reshape(sc.n, 6)
            st[:, 0:3], st[:, 3:6], st[:, 6:9] = qpos[:, 0:3], qv[:, 0:3], qv[:, 3:6]
        scenes.write_state(a.state_out, st)
    res = {"engine": "mujoco", "version": mujoco.__version__, "n": sc.n, "steps": k,
           "dt": sc.dt, "sim_time": k * sc.dt, "wall": wall, "setup_wall": t_setup,
           "contacts_max": ncon_max, "arena_mb": mem_mb,
           "solref": [TIMECONST, dampratio(sc.restitution)], "warnings": warnings,
           "apex": apex.z, "rss_anon_kb": scenes.rss_anon_kb(),
           "error": ("MuJoCo warnings: " + json.dumps(warnings)) if warnings else ""}
    print("RESULT " + json.dumps(res), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
