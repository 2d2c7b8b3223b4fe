"""Building worlds in code, stepping, bodies, materials, settings, diagnostics.

Physics here only checks that the binding passes values through: the core's
own tests (tests/core) judge the physics.  Free fall is compared with the
exact answer of semi-implicit Euler, v_n = v0 - g n dt and
z_n = z0 + v0 n dt - g dt^2 n (n + 1) / 2, to within 1e-12 m: n additions of
numbers below 10 m lose at most about n * 2.2e-16 * 10 m = 2e-13 m for
n = 100, so 1e-12 leaves room for rounding and none for a wrong dt, g or
sign.
"""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import rbsim

G = 9.81


def make_world(**kw):
    w = rbsim.World(dt=0.001, **kw)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, mass=2.0, position=(0.0, 0.0, 1.0))
    return w


def test_free_fall_matches_semi_implicit_euler():
    w = rbsim.World(dt=0.001, gravity=(0, 0, -G))
    ball = w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 5.0),
                        velocity=(0.5, 0.0, 1.0))
    n = 100
    info = w.step(n)
    dt = 0.001
    assert info.steps == n
    assert w.step_count == n
    assert w.time == n * dt  # documented as step count * dt
    assert ball.velocity[2] == pytest.approx(1.0 - G * n * dt, abs=1e-12)
    z = 5.0 + 1.0 * n * dt - G * dt * dt * n * (n + 1) / 2
    assert ball.position[2] == pytest.approx(z, abs=1e-12)
    assert ball.position[0] == pytest.approx(0.5 * n * dt, abs=1e-12)
    assert ball.velocity[0] == 0.5


def test_step_zero_and_step_info():
    w = make_world()
    info = w.step(0)
    assert info.steps == 0 and w.step_count == 0
    info = w.step()
    assert isinstance(info, rbsim.StepInfo) and info.steps == 1
    assert info.substeps >= 1 and info.rollbacks >= 0
    # step(n) in one call equals n calls of step() bit for bit.
    a, b = make_world(), make_world()
    a.step(700)
    for _ in range(700):
        b.step()
    assert np.array_equal(a.positions, b.positions)
    assert a.hash() == b.hash()


def test_settings_round_trip():
    w = rbsim.World(max_bodies=5, max_materials=3, max_pairs=7, max_contacts=40,
                    dt=0.002, gravity=(0.0, -1.0, -3.0), gravity_mode="force",
                    restitution=0.25, tolerance=1e-7, slop=1e-5,
                    max_halvings=12, max_sweeps=20, soft_substeps=9, soft_tolerance=0.015625,
                    mutual_gravity=True, gravity_constant=1.5, softening=0.01, prune=False)
    s = w.settings
    assert s["max_bodies"] == 5 and s["max_materials"] == 3
    assert s["max_pairs"] == 7 and s["max_contacts"] == 40
    assert s["dt"] == 0.002 and s["gravity"] == (0.0, -1.0, -3.0)
    assert s["gravity_mode"] == "force" and s["restitution"] == 0.25
    assert s["tolerance"] == 1e-7 and s["slop"] == 1e-5
    assert s["max_halvings"] == 12 and s["max_sweeps"] == 20
    assert s["soft_substeps"] == 9
    assert rbsim.World().settings["soft_substeps"] == 3  # the library's default
    assert s["soft_tolerance"] == 0.015625
    assert rbsim.World().settings["soft_tolerance"] == 0.0  # the library's default
    assert s["mutual_gravity"] is True and s["gravity_constant"] == 1.5
    assert s["softening"] == 0.01 and s["prune"] is False
    assert s["method"] == "auto" == w.method and w.method_in_use == "euler"
    assert list(w.gravity) == [0.0, -1.0, -3.0]


def test_defaults_come_from_the_library():
    from rbsim._native import ffi, lib
    d = ffi.new("rbs_world_def *")
    lib.rbs_world_def_init_sized(d, ffi.sizeof("rbs_world_def"))
    s = rbsim.World().settings
    assert s["max_bodies"] == d.max_bodies and s["dt"] == d.dt
    assert s["restitution"] == d.restitution and s["tolerance"] == d.tolerance


def test_dt_method_and_tolerance_are_settable():
    w = make_world()
    w.dt = 0.0005
    assert w.dt == 0.0005
    w.step(10)
    assert w.time == pytest.approx(10 * 0.0005, rel=1e-15)
    w.tolerance = 1e-6
    assert w.tolerance == 1e-6
    w.method = "euler"
    assert w.method == "euler"
    assert "euler" in rbsim.METHODS
    with pytest.raises(rbsim.InvalidError, match="method"):
        w.method = "leapfrog"
    with pytest.raises(rbsim.InvalidError, match="tolerance"):
        w.tolerance = 0.0
    with pytest.raises(rbsim.InvalidError, match="dt"):
        w.dt = -1.0
    assert w.dt == 0.0005 and w.tolerance == 1e-6


def test_only_the_settable_settings_can_be_set():
    """world.slop = 1e-3 (or restitution, max_sweeps, a typo such as
    world.mehtod = "rk4", or world.step = 5 over a method) made a plain
    Python attribute the simulation never read: the run went on with the
    old value and nothing said so (a probe of session 46).  It is an
    AttributeError naming the settable ones, and the world is unchanged."""
    w = make_world()
    before = w.settings
    with pytest.raises(AttributeError, match=r"'slop' \(it is fixed when the world is "
                       r"made: World\(slop=\.\.\.\).*settable: dt, method, threads, tolerance"):
        w.slop = 1e-3
    for name, value in [("restitution", 1.0), ("max_sweeps", 5), ("mehtod", "rk4"),
                        ("step", 5), ("energy", 0.0)]:
        with pytest.raises(AttributeError, match="World has no settable attribute %r" % name):
            setattr(w, name, value)
    # a read-only property too, named with the settable ones (Python's own
    # message said only that it has no setter)
    with pytest.raises(AttributeError, match=r"'gravity' \(it is fixed when the world is "
                       r"made.*settable: dt, method, threads, tolerance"):
        w.gravity = (0, 0, 1)
    with pytest.raises(AttributeError, match=r"'time'; settable: dt, method, threads, tolerance"):
        w.time = 5.0
    assert w.settings == before and callable(w.step) and not hasattr(w, "mehtod")
    w.description = "mine"  # the scene's attributes stay the caller's to set
    w.dt = 0.002
    assert w.description == "mine" and w.settings["dt"] == 0.002


def test_auto_method_follows_the_bodies():
    """The default method "auto" takes "euler" below 64 moving spheres and
    "soft" from 64 on; method_in_use says which, and the state after 50
    steps is the one the named method gives, bit for bit."""
    assert rbsim.METHODS[-1] == "auto"

    def heap(n, method=None):
        kw = {} if method is None else {"method": method}
        w = rbsim.World(max_bodies=n + 1, dt=0.001, **kw)
        w.add_plane("ground")
        for i in range(n):
            w.add_sphere(radius=0.05, mass=0.1,
                         position=(0.11 * (i % 8), 0.11 * (i // 8 % 8), 0.06 + 0.11 * (i // 64)))
        return w

    for n, chosen in ((63, "euler"), (64, "soft")):
        a, b = heap(n), heap(n, chosen)
        assert a.method == "auto" and a.method_in_use == chosen
        assert b.method_in_use == chosen
        a.step(50)
        b.step(50)
        assert a.hash() == b.hash() and np.array_equal(a.positions, b.positions)
    a.method = "euler"
    assert a.method == a.method_in_use == "euler"


def test_soft_tolerance():
    """soft_tolerance reaches the world and reads back exactly, at both ends
    of its range and between; out of range, it is refused with the range
    and the value; a "soft" world with it steps like the others."""
    from rbsim._native import ffi, lib
    d = ffi.new("rbs_world_def *")
    lib.rbs_world_def_init_sized(d, ffi.sizeof("rbs_world_def"))
    assert rbsim.World().settings["soft_tolerance"] == d.soft_tolerance == 0.0
    for good in (0.0, 0.015625, 1.0, 1):
        assert rbsim.World(soft_tolerance=good).settings["soft_tolerance"] == good
    with pytest.raises(rbsim.InvalidError,
                       match=r"soft_tolerance: must be in \[0, 1\] \(a fraction of the "
                             r"radius\), got 2$") as info:
        rbsim.World(soft_tolerance=2)
    assert info.value.status == lib.RBS_E_INVALID
    w = make_world(method="soft", soft_substeps=8, soft_tolerance=0.25)
    assert w.settings["soft_tolerance"] == 0.25 and w.settings["soft_substeps"] == 8
    w.step(1500)
    assert 0.09 < w.bodies["ball"].position[2] < 0.2


def test_soft_method():
    """"soft" is a method like the others: listed, accepted by World(),
    the property and the settings, and it steps (a ball falls onto the
    ground and stays above it, up to the overlap a soft contact allows)."""
    assert "soft" in rbsim.METHODS
    assert rbsim.METHODS.index("soft") == 6  # RBS_METHOD_SOFT
    w = make_world(method="soft", soft_substeps=8)
    assert w.method == "soft" and w.settings["method"] == "soft"
    assert w.settings["soft_substeps"] == 8
    w.step(1500)
    ball = w.bodies["ball"]
    assert 0.09 < ball.position[2] < 0.2
    w.method = "euler"
    assert w.method == "euler"
    w.method = "soft"
    assert w.method == "soft"
    w.step(10)


def test_every_method_is_accepted_or_refused_cleanly():
    for name in rbsim.METHODS:
        w = make_world()
        try:
            w.method = name
        except rbsim.UnsupportedError as e:
            assert name in str(e)
            assert w.method == "euler"
            continue
        assert w.method == name
        w.step(10)


def test_bodies_by_name():
    w = make_world()
    anon = w.add_sphere(radius=0.05, position=(1.0, 0.0, 1.0))
    assert set(w.bodies) == {"ground", "ball"}
    assert len(w.bodies) == 2
    assert "ball" in w.bodies and "nope" not in w.bodies
    ball = w.bodies["ball"]
    assert ball == w.body("ball") and ball.name == "ball"
    assert ball.type == "sphere" and w.bodies["ground"].type == "plane"
    assert ball.radius == 0.1 and ball.mass == 2.0
    assert list(w.bodies["ground"].normal) == [0.0, 0.0, 1.0]
    assert anon.name == "" and anon in w.all_bodies()
    assert len(w.all_bodies()) == 3
    with pytest.raises(KeyError):
        w.bodies["nope"]
    with pytest.raises(rbsim.NotFoundError, match="nope"):
        w.body("nope")


def test_body_setters_and_state():
    w = make_world()
    ball = w.bodies["ball"]
    ball.position = (0.5, 0.0, 2.0)
    ball.velocity = np.array([1.0, 2.0, 3.0])
    ball.angular_velocity = [0.0, 0.0, 4.0]
    ball.force = (0.0, 0.0, 1.0)
    ball.torque = (0.1, 0.0, 0.0)
    half = math.sqrt(0.5)
    ball.orientation = (half, 0.0, 0.0, half)
    s = ball.state()
    assert list(s.position) == [0.5, 0.0, 2.0]
    assert list(s.velocity) == [1.0, 2.0, 3.0]
    assert list(s.angular_velocity) == [0.0, 0.0, 4.0]
    assert list(s.force) == [0.0, 0.0, 1.0] and list(s.torque) == [0.1, 0.0, 0.0]
    assert s.orientation == pytest.approx([half, 0.0, 0.0, half], abs=1e-15)
    assert s.type == "sphere" and s.radius == 0.1 and not s.fixed
    assert w.velocities[ball.slot].tolist() == [1.0, 2.0, 3.0]


def test_body_inertia_and_centre_of_mass():
    # I about the centre: 2/5 m r^2 (solid), 2/3 m r^2 (hollow); about a
    # centre of mass offset c along x (parallel-axis rule): I - m c^2 on
    # the y and z axes, unchanged on x.
    w = rbsim.World(max_bodies=4)
    solid = w.add_sphere("solid", radius=0.2, mass=3.0, position=(0, 0, 1))
    hollow = w.add_sphere("hollow", radius=0.2, mass=3.0, inertia="hollow",
                          position=(1, 0, 1))
    off = w.add_sphere("off", radius=0.2, mass=3.0, center_of_mass=(0.05, 0, 0),
                       position=(2, 0, 1))
    floor = w.add_plane("floor")
    i0 = 0.4 * 3.0 * 0.2 ** 2
    assert np.allclose(solid.inertia, np.diag([i0] * 3), rtol=1e-15, atol=0)
    assert np.allclose(hollow.inertia, np.diag([3.0 * 0.04 * 2 / 3] * 3), rtol=1e-15, atol=0)
    assert solid.center_of_mass.tolist() == [0.0, 0.0, 0.0]
    assert off.center_of_mass.tolist() == [0.05, 0.0, 0.0]
    want = np.diag([i0, i0 - 3.0 * 0.05 ** 2, i0 - 3.0 * 0.05 ** 2])
    assert np.allclose(off.inertia, want, rtol=1e-14, atol=0)
    assert floor.inertia.tolist() == [[0.0] * 3] * 3
    w.remove_body(off)
    with pytest.raises(rbsim.StaleIdError):
        off.inertia


def test_remove_body_makes_handles_stale():
    w = make_world()
    ball = w.bodies["ball"]
    ball.remove()
    assert "ball" not in w.bodies
    with pytest.raises(rbsim.StaleIdError):
        ball.position
    with pytest.raises(rbsim.StaleIdError):
        ball.velocity = (0, 0, 0)
    with pytest.raises(rbsim.StaleIdError):
        w.remove_body(ball)
    again = w.add_sphere("ball", position=(0, 0, 3))
    assert again != ball and again.slot == ball.slot
    with pytest.raises(rbsim.StaleIdError):
        ball.position  # the old generation stays stale


def test_body_of_another_world_is_refused():
    a, b = make_world(), make_world()
    with pytest.raises(rbsim.StaleIdError, match="another world"):
        b.remove_body(a.bodies["ball"])


def test_materials_and_pairs():
    w = rbsim.World(max_materials=2)
    rubber = w.add_material("rubber")
    steel = w.add_material("steel")
    assert w.material("rubber") == rubber and rubber.name == "rubber"
    w.set_material(rubber, "steel", static=0.9, kinetic=0.7, restitution=0.8,
                   rolling=0.01, spinning=0.001)
    w.set_material("*", None, static=0.5, kinetic=0.4)
    w.set_material(steel, "*", kinetic=0.1, static=0.2)
    ball = w.add_sphere("ball", material=rubber)
    w.add_plane("ground", material="steel")
    assert ball.name == "ball"
    with pytest.raises(rbsim.CapacityError):
        w.add_material("glass")
    with pytest.raises(rbsim.InvalidError, match="kinetic"):
        w.set_material(rubber, steel, static=0.1, kinetic=0.5)
    with pytest.raises(rbsim.InvalidError, match="restitution"):
        w.set_material(rubber, steel, restitution=1.5)
    with pytest.raises(rbsim.NotFoundError, match="glass"):
        w.set_material("glass", steel)
    other = rbsim.World()
    with pytest.raises(rbsim.StaleIdError):
        other.add_sphere(material=rubber)
    # read back: materials in order, rows as set (a replaced row in place;
    # the refused ones above changed nothing)
    assert w.materials() == [rubber, steel]
    assert [m.name for m in w.materials()] == ["rubber", "steel"]
    rows = w.pairs()
    assert rows == [
        {"a": rubber, "b": steel, "static": 0.9, "kinetic": 0.7,
         "restitution": 0.8, "rolling": 0.01, "spinning": 0.001},
        {"a": "*", "b": "*", "static": 0.5, "kinetic": 0.4,
         "restitution": rows[1]["restitution"], "rolling": 0.0,
         "spinning": 0.0},
        {"a": steel, "b": "*", "static": 0.2, "kinetic": 0.1,
         "restitution": rows[2]["restitution"], "rolling": 0.0,
         "spinning": 0.0},
    ]
    assert rows[1]["restitution"] < 0  # the world's
    assert other.materials() == [] and other.pairs() == []


def test_energy_and_momentum():
    w = rbsim.World(gravity=(0, 0, -G))
    ball = w.add_sphere("ball", mass=2.0, position=(0.0, 0.0, 3.0))
    e = w.energy()
    assert isinstance(e, rbsim.Energy)
    # Potential relative to the origin: m g z; nothing moves yet.
    assert e.potential == pytest.approx(2.0 * G * 3.0, rel=1e-15)
    assert e.kinetic == 0.0 and e.total == pytest.approx(e.potential, rel=1e-15)
    ball.velocity = (1.0, 0.0, 0.0)
    ball.position = (0.0, 2.0, 3.0)
    m = w.momentum()
    assert m.linear.tolist() == [2.0, 0.0, 0.0]
    # L = r x p = (0, 2, 3) x (2, 0, 0) = (0, 6, -4)
    assert m.angular.tolist() == pytest.approx([0.0, 6.0, -4.0], abs=1e-15)
    assert w.energy().kinetic == pytest.approx(0.5 * 2.0 * 1.0, rel=1e-15)


def test_usage_and_hash():
    w = make_world()
    u = w.usage()
    assert u.bodies == 2 and u.bodies_high == 2 and u.bytes > 0
    h0 = w.hash()
    w.step()
    assert w.hash() != h0
    assert make_world().hash() == h0


def test_capacity():
    w = rbsim.World(max_bodies=2)
    w.add_plane()
    w.add_sphere(position=(0, 0, 1))
    with pytest.raises(rbsim.CapacityError):
        w.add_sphere(position=(0, 0, 2))
    assert len(w.all_bodies()) == 2  # unchanged


def test_a_full_world_names_a_bad_definition_first():
    # On a full world a bad argument of add_sphere/add_plane is named, not
    # the capacity: the wrapper and the library check the definition before
    # taking a slot (a probe of session 47 suspected the other order).
    w = rbsim.World(max_bodies=1)
    w.add_sphere("a")
    cases = [
        (dict(name="a"), rbsim.InvalidError, 'sphere "a": name already used'),
        (dict(name="b" * 64), rbsim.InvalidError, "sphere name must have 1 to 63 bytes"),
        (dict(name="a\0b"), rbsim.InvalidError, "name: must not contain NUL"),
        (dict(name="\udcff"), rbsim.InvalidError, "name: not valid Unicode"),
        (dict(name=3), TypeError, "name: expected a string"),
        (dict(radius=-1), rbsim.InvalidError, "radius: must be > 0"),
        (dict(mass=0), rbsim.InvalidError, "mass: must be > 0"),
        (dict(material="nosuch"), rbsim.NotFoundError, "no material named 'nosuch'"),
        (dict(color=-1), rbsim.InvalidError, "color: must be in"),
        (dict(texture="x"), rbsim.InvalidError, "texture: expected one of"),
        (dict(fixed=True, velocity=(1, 0, 0)), rbsim.InvalidError,
         "velocity must be zero for a fixed sphere"),
        (dict(center_of_mass=(1, 0, 0)), rbsim.InvalidError, "centre of mass offset"),
    ]
    for kw, cls, text in cases:
        with pytest.raises(cls) as e:
            w.add_sphere(**kw)
        assert text in str(e.value), (kw, str(e.value))
    with pytest.raises(rbsim.InvalidError) as e:
        w.add_plane("a")
    assert 'plane "a": name already used' in str(e.value)
    with pytest.raises(rbsim.InvalidError) as e:
        w.add_plane(normal=(0, 0, 0))
    assert "normal: must be a nonzero vector" in str(e.value)
    with pytest.raises(rbsim.CapacityError):
        w.add_sphere("b", radius=0.2)
    assert len(w.all_bodies()) == 1


def test_step_error_says_the_time_in_its_shortest_form():
    # A step that fails part way names the time as it reads back
    # (t = 0.301 s, not %.17g's 0.30099999999999999).  Here: contacts
    # outgrow max_contacts when three balls land on the floor at once.
    w = rbsim.World(max_bodies=4, max_contacts=2, method="euler")
    w.add_plane()
    for k in range(3):
        w.add_sphere(radius=0.1, position=(0.3 * k, 0, 0.1 + 0.05))
    with pytest.raises(rbsim.CapacityError) as e:
        w.step(1000)
    t = w.time
    assert ("t = %r s)" % t) in str(e.value), str(e.value)
    assert "9999999" not in str(e.value) and "0000000" not in str(e.value)


def test_close_and_context_manager():
    with make_world() as w:
        w.step(3)
    assert w.closed
    with pytest.raises(rbsim.ClosedError):
        w.step()
    with pytest.raises(rbsim.ClosedError):
        w.time
    w.close()  # idempotent
    assert repr(w) == "World(<closed>)"


def test_the_method_reaches_the_library():
    """Free fall under constant g: velocity Verlet and RK4 integrate it
    exactly, z = z0 - g t^2 / 2 (to rounding, 1e-12 m), while semi-implicit
    Euler is low by g dt t / 2 = 4.9e-4 m at t = 0.1 s, dt = 1e-3 s.  So the
    results tell which method ran."""
    t = 0.1
    exact = 5.0 - G * t * t / 2
    for name in ("rk4", "verlet", "euler"):
        if name not in rbsim.METHODS:
            continue
        w = rbsim.World(dt=0.001, gravity=(0, 0, -G), method=name)
        assert w.method == name
        ball = w.add_sphere("ball", position=(0.0, 0.0, 5.0))
        w.step(100)
        if name == "euler":
            assert ball.position[2] == pytest.approx(exact - G * 0.001 * t / 2,
                                                     abs=1e-12)
        else:
            assert ball.position[2] == pytest.approx(exact, abs=1e-12), name
    w = rbsim.World(dt=0.001, gravity=(0, 0, -G))
    ball = w.add_sphere("ball", position=(0.0, 0.0, 5.0))
    w.method = "rk4"  # switched by the property
    w.step(100)
    assert ball.position[2] == pytest.approx(exact, abs=1e-12)



_RESIDENT_PROBE = """
import rbsim
def rss():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmRSS:"))
before = rss()
w = rbsim.World(max_bodies=100005)
grew = rss() - before
w.add_sphere("b", position=(0.0, 0.0, 1.0))
w.step(10)
assert w.positions[0][2] < 1.0
print(grew, w.usage().bytes)
"""


@pytest.mark.skipif(not os.path.exists("/proc/self/status"),
                    reason="needs /proc/self/status (Linux)")
def test_capacity_not_reached_is_not_resident():
    """A world's block is reserved whole, but pages the world never writes
    stay address space, as rbs_world_create promises in C: an empty world
    sized for 100,005 bodies (216 MB of block) takes a few MB of resident
    memory, not its size (before session 38 the Python block was zero-filled
    and all of it resident).  Bound: a tenth of the block -- the world's
    header and per-slot tables it writes at creation are far less.  Measured
    in a child without MALLOC_PERTURB_ (which meson sets, and under which
    glibc's calloc writes every page)."""
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_PERTURB_"}
    out = subprocess.run([sys.executable, "-c", _RESIDENT_PROBE], env=env,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    grew, block = (int(x) for x in out.stdout.split())
    assert block > 100e6
    assert grew < 0.1 * block, (grew, block)


def _pi_billiard(**kw):
    """Galperin's billiard 1e6:1: a wall (x = 0), a 1 kg ball at rest and a
    1e6 kg ball moving to it at 1 m/s, e = 1, no gravity: 3141 impacts."""
    w = rbsim.World(max_bodies=3, dt=1e-3, gravity=(0, 0, 0), restitution=1.0,
                    method="euler", **kw)
    w.add_plane("wall", point=(0, 0, 0), normal=(1, 0, 0))
    w.add_sphere("light", radius=0.1, mass=1.0, position=(0.5, 0, 0))
    w.add_sphere("heavy", radius=0.1, mass=1e6, position=(1.0, 0, 0),
                 velocity=(-1.0, 0, 0))
    return w


def test_work_cap_is_reported_and_set():
    """The work cap (max_substeps) was set and seen only from C: Python's
    StepInfo had no work_limit and World() no max_substeps, so a ball that
    passed through another when the cap cut a frame short looked clean."""
    w = _pi_billiard()
    assert w.settings["max_substeps"] == 4096  # the library's default
    info = w.step(2000)
    assert 0 < info.work_limit <= info.steps
    # past the cap the light ball went through the heavy one
    assert w.bodies["light"].position[0] > w.bodies["heavy"].position[0]
    w = _pi_billiard(max_substeps=20000)
    assert w.settings["max_substeps"] == 20000
    info = w.step(2000)
    assert info.work_limit == 0 and info.colliding == 3141
    assert w.bodies["light"].velocity[0] == pytest.approx(0.406299066323439, abs=1e-9)
    assert w.bodies["heavy"].velocity[0] == pytest.approx(0.999999917460534, abs=1e-9)
    # a run through the projector counts them too
    assert _pi_billiard().run(2000).work_limited == 1
    assert _pi_billiard(max_substeps=20000).run(2000).work_limited == 0
    # one step's own report: 0 or 1
    w = _pi_billiard(max_substeps=1)
    assert w.step().work_limit in (0, 1)
    for bad in (0, -1, 2 ** 32):
        with pytest.raises(rbsim.InvalidError,
                           match=r"max_substeps: must be in \[1, 4294967295\], got %d" % bad):
            rbsim.World(max_substeps=bad)
    assert rbsim.World(max_substeps=2 ** 32 - 1).settings["max_substeps"] == 2 ** 32 - 1


@pytest.mark.parametrize("how", ["copy", "deepcopy", "pickle"])
def test_handles_cannot_be_copied_or_pickled(how):
    """copy.copy(world) shared the C world, and deleting the copy destroyed
    the original's (with threads > 1, a segfault: a probe of session 41).
    Every handle -- World, Body, Material, BodyMap, Run -- refuses to be
    copied or pickled, with a TypeError saying what to do instead; the
    world is untouched."""
    import copy
    import pickle
    fn = {"copy": copy.copy, "deepcopy": copy.deepcopy, "pickle": pickle.dumps}[how]
    w = make_world(threads=2)
    ball = w.bodies["ball"]
    mat = w.add_material("rubber")
    hints = {"World": "checkpoint", "Body": "state()", "Material": "name",
             "BodyMap": "dict(world.bodies)"}
    for obj in (w, ball, mat, w.bodies):
        name = type(obj).__name__
        with pytest.raises(TypeError, match="cannot copy or pickle a %s" % name) as info:
            fn(obj)
        assert hints[name] in str(info.value)
    run = w.start(3, [lambda frame: None])
    with pytest.raises(TypeError, match="cannot copy or pickle a Run"):
        fn(run)
    run.wait()
    w.step(10)
    assert w.step_count == 13 and ball.position[2] < 1.0


def test_repr_never_raises(monkeypatch):
    """repr() of a world whose library calls fail says why instead of
    raising (it raised InvalidError: a probe of session 41)."""
    w = make_world()

    def broken(self):
        raise rbsim.InvalidError("rbs_world_state")
    # (on the class: a World takes no attributes of its own, not even a mock)
    monkeypatch.setattr(rbsim.World, "all_bodies", broken)
    assert repr(w) == "World(<invalid argument: rbs_world_state>)"
    monkeypatch.undo()
    w2 = make_world()
    w2.close()
    assert repr(w2.bodies) == "BodyMap(<closed or interrupted: world is closed>)"


def test_values_with_arrays_compare_exactly_and_are_unhashable():
    """== on BodyState and Momentum raised ("truth value of an array is
    ambiguous") and hash() raised from numpy (a probe of session 41): they
    compare every element exactly, and are plainly unhashable."""
    w = make_world()
    ball = w.bodies["ball"]
    s0, m0 = ball.state(), w.momentum()
    assert s0 == ball.state() and not (s0 != ball.state())
    assert m0 == w.momentum() and not (m0 != w.momentum())
    assert m0 == (m0.linear.copy(), m0.angular.copy())
    assert s0 != w.bodies["ground"].state() and s0 != "ball"
    w.step()
    assert ball.state() != s0 and w.momentum() != m0
    nudged = ball.state()
    assert nudged == ball.state()
    nudged.position[2] = np.nextafter(nudged.position[2], 2.0)  # one ulp
    assert nudged != ball.state()
    for value in (s0, m0):
        with pytest.raises(TypeError, match="unhashable type: '%s'" % type(value).__name__):
            hash(value)
    assert w.energy() == w.energy() and hash(w.energy()) == hash(w.energy())


def _gravitating(n=1000):
    """A world whose step takes milliseconds: n spheres under mutual
    gravity, far apart."""
    w = rbsim.World(max_bodies=n, mutual_gravity=True, gravity_constant=1e-9,
                    gravity=(0, 0, 0), method="euler")
    rng = np.random.default_rng(1)
    for p in rng.uniform(-100.0, 100.0, (n, 3)):
        w.add_sphere(radius=0.01, position=tuple(p))
    return w


def test_ctrl_c_during_step_lands_within_about_a_step():
    """Ctrl-C during step(n) was seen only after a C call of 4096 steps
    (minutes for a big world: a probe of session 41).  It lands within a
    slice of about 20 ms or one step, and the world is usable, exactly at
    the step count it reports: its state is the same bits as a world
    stepped that many times."""
    import _thread
    import threading
    import time
    w = _gravitating()
    w.step(2)  # (a slow step, about 10 ms on the test machine)
    signalled = []

    def interrupt():
        signalled.append(time.perf_counter())
        _thread.interrupt_main()
    timer = threading.Timer(0.3, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            w.step(10 ** 9)
        landed = time.perf_counter()
    finally:
        timer.cancel()
    assert landed - signalled[0] < 2.0  # (a 4096-step call: some 40 s)
    made = w.step_count
    assert made > 2
    w.step()
    assert w.step_count == made + 1 and w.time == pytest.approx((made + 1) * w.dt)
    reference = _gravitating()
    reference.step(made + 1)
    assert reference.hash() == w.hash()


def test_run_counts_jams_and_sweep_limits():
    """RunInfo counts the steps whose overlap was pushed apart instead of
    resolved and those with a contact pass at max_sweeps, as StepInfo's
    floor_hits and sweep_limit do a step: a ball at 1000 m/s between walls
    20 um wider than it jams every selective step (2,000 impacts a body a
    step); at 1 m/s none does."""
    def rattle(speed):
        w = rbsim.World(dt=0.001, gravity=(0, 0, 0), restitution=1.0, method="selective")
        w.add_plane("l", point=(-0.10001, 0, 0), normal=(1, 0, 0))
        w.add_plane("r", point=(0.10001, 0, 0), normal=(-1, 0, 0))
        w.add_sphere("b", radius=0.1, mass=1.0, velocity=(speed, 0, 0))
        return w
    info = rattle(1000.0).run(20)
    assert info.floor_hit_steps == 20 and info.sweep_limited == 20
    info = rattle(1.0).run(20)
    assert info.floor_hit_steps == 0 and info.sweep_limited == 0


def test_slow_motion_lost_to_rounding_is_counted():
    """A 0.1 m ball at 0.05 m/s 1e12 m from the origin moves 5e-5 m a
    frame, where coordinates round in steps of 1.2e-4 m: it does not move,
    and every step says so (World.rounded_steps, RunInfo.rounded_steps); at
    the origin none does.  A run counts its own steps."""
    def far(x):
        w = rbsim.World(dt=0.001, gravity=(0, 0, 0))
        w.add_sphere("b", radius=0.1, mass=1.0, position=(x, 0, 0), velocity=(0.05, 0, 0))
        return w
    w = far(1e12)
    w.step(10)
    assert w.rounded_steps == 10
    info = w.run(20)
    assert info.rounded_steps == 20 and w.rounded_steps == 30
    w = far(0.0)
    assert w.run(20).rounded_steps == 0 and w.rounded_steps == 0
