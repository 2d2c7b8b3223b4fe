"""Runs a peers scene in Bullet through PyPI's pybullet and reports time.

    drive_bullet.py --scene FILE [--steps K] [--max-wall S] [--state-out FILE]

Settings (stated in bench/results/peers.md):
  - DIRECT mode (no GUI), setTimeStep(dt), gravity along z, one stepSimulation
    per step; every other engine parameter at pybullet's default
    (numSolverIterations 50, sleeping allowed after Bullet's deactivation time).
  - Spheres are rigid bodies (useMaximalCoordinates=True: btRigidBody, the
    usual way to simulate free bodies; Featherstone multibodies would be
    slower), created in one batch from one shared sphere shape; planes are
    static GEOM_PLANE bodies.
  - Bullet combines coefficients of a contact by multiplying the two bodies'
    values, so every body gets restitution sqrt(e) and lateral friction
    sqrt(mu): each contact then has e and mu exactly.  Rolling and spinning
    friction 0; linear and angular damping 0 (pybullet's default is 0.04).
Only the stepping loop is timed; creation is setup time.
"""
import json
import math
import sys
import time

import numpy as np
import pybullet as p

import scenes


def main(argv):
    a = scenes.driver_args(argv, "bullet")
    sc = scenes.Scene(a.scene)
    steps = a.steps if a.steps >= 0 else sc.steps

    t0 = time.perf_counter()
    cid = p.connect(p.DIRECT)
    p.setGravity(0, 0, sc.gravity_z, physicsClientId=cid)
    p.setTimeStep(sc.dt, physicsClientId=cid)
    e, mu = math.sqrt(sc.restitution), math.sqrt(sc.friction)
    for q in sc.planes:
        shape = p.createCollisionShape(p.GEOM_PLANE, planeNormal=list(q[3:6]), physicsClientId=cid)
        b = p.createMultiBody(0, shape, basePosition=list(q[0:3]), physicsClientId=cid)
        p.changeDynamics(b, -1, restitution=e, lateralFriction=mu, rollingFriction=0,
                         spinningFriction=0, physicsClientId=cid)
    bodies = []
    # one batch per distinct (radius, mass)
    kinds = {}
    for i, s in enumerate(sc.spheres):
        kinds.setdefault((s[0], s[1]), []).append(i)
    order = [None] * sc.n
    for (r, m), idx in kinds.items():
        shape = p.createCollisionShape(p.GEOM_SPHERE, radius=r, physicsClientId=cid)
        for start in range(0, len(idx), 4096):
            chunk = idx[start:start + 4096]
            ids = p.createMultiBody(baseMass=m, baseCollisionShapeIndex=shape,
                                    batchPositions=[list(sc.spheres[i, 2:5]) for i in chunk],
                                    useMaximalCoordinates=True, physicsClientId=cid)
            ids = [ids] if isinstance(ids, int) else list(ids)
            if len(ids) != len(chunk):
                raise RuntimeError(f"pybullet made {len(ids)} bodies for a batch of {len(chunk)}")
            for i, b in zip(chunk, ids):
                order[i] = b
    for i, b in enumerate(order):
        p.changeDynamics(b, -1, restitution=e, lateralFriction=mu, rollingFriction=0,
                         spinningFriction=0, linearDamping=0, angularDamping=0, physicsClientId=cid)
        v = sc.spheres[i, 5:8]
        if v.any():
            p.resetBaseVelocity(b, list(v), [0, 0, 0], physicsClientId=cid)
    bodies = order
    params = p.getPhysicsEngineParameters(physicsClientId=cid)
    apex = scenes.Apex(sc.gravity_z)
    t_setup = time.perf_counter() - t0

    t0 = time.perf_counter()
    last = 0.0
    k = 0
    while k < steps:
        p.stepSimulation(physicsClientId=cid)
        k += 1
        if sc.track_apex:
            z = p.getBasePositionAndOrientation(bodies[0], physicsClientId=cid)[0][2]
            vz = p.getBaseVelocity(bodies[0], physicsClientId=cid)[0][2]
            apex.feed(z, vz)
        wall = time.perf_counter() - t0
        if wall - last >= 1.0:
            print(f"# progress {k} {wall:.6f}", flush=True)
            last = wall
        if a.max_wall > 0 and wall >= a.max_wall:
            break
    wall = time.perf_counter() - t0

    if a.state_out:
        st = np.zeros((sc.n, 9))
        for i, b in enumerate(bodies):
            st[i, 0:3] = p.getBasePositionAndOrientation(b, physicsClientId=cid)[0]
            v, w = p.getBaseVelocity(b, physicsClientId=cid)
            st[i, 3:6], st[i, 6:9] = v, w
        scenes.write_state(a.state_out, st)
    res = {"engine": "bullet", "version": f"pybullet API {p.getAPIVersion()}",
           "n": sc.n, "steps": k, "dt": sc.dt, "sim_time": k * sc.dt, "wall": wall,
           "setup_wall": t_setup, "solver_iterations": params.get("numSolverIterations"),
           "apex": apex.z, "rss_anon_kb": scenes.rss_anon_kb(), "error": ""}
    print("RESULT " + json.dumps(res), flush=True)
    p.disconnect(physicsClientId=cid)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
