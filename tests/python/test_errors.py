"""Errors become Python exceptions -- never a crash of the interpreter.

Every status code has its class (checked against the header in
test_build.py); here each error the API can reach is provoked for real, the
others are mapped through rbsim.errors.raise_status, and a battery of bad
arguments (None, wrong types, NaN, infinities, huge and negative integers)
is thrown at every entry point: each must raise an rbsim.Error.
"""

import itertools
import math

import numpy as np
import pytest

import rbsim
from rbsim._native import ffi, lib

NAN, INF = float("nan"), float("inf")
# None is left out: as a keyword it means "the library's default".
BAD_REALS = ["1.0", NAN, INF, -INF, [1.0], object(), True, 1j, 10 ** 400]
# (a dict of three keys iterates its keys, a set has no order: neither is a
# vector even when it holds three numbers)
BAD_VECTORS = [1.0, "abc", [1.0, 2.0], [1.0, 2.0, 3.0, 4.0, 5.0],
               [NAN, 0, 0], [0, INF, 0], [0, 0, None], {"x": 1}, object(),
               np.array([1.0, np.nan, 0.0]), {0: 1.0, 1: 2.0, 2: 3.0},
               {1.0, 2.0, 3.0}, [10 ** 400, 0, 0],
               itertools.count()]  # (endless: refused, not read on until memory runs out)
BAD_INTS = [-1, 2 ** 40, 1.5, "3", NAN, True]


def make_world():
    w = rbsim.World(max_bodies=8)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 1.0))
    return w


def test_every_status_code_maps_to_its_class():
    for code, cls in rbsim.errors.BY_STATUS.items():
        with pytest.raises(cls) as info:
            rbsim.errors.raise_status(code, "detail")
        e = info.value
        assert isinstance(e, rbsim.Error) and e.status == code
        assert "detail" in str(e)
        assert ffi.string(lib.rbs_status_string(code)).decode() in str(e)
    rbsim.errors.raise_status(0)  # RBS_OK raises nothing
    with pytest.raises(rbsim.Error, match="unknown status"):
        rbsim.errors.raise_status(-999)


def test_builtin_bases():
    assert issubclass(rbsim.InvalidError, ValueError)
    assert issubclass(rbsim.NotFoundError, KeyError)
    assert issubclass(rbsim.IoError, OSError)
    assert issubclass(rbsim.NumericError, ArithmeticError)
    assert issubclass(rbsim.ArgumentTypeError, TypeError)
    assert issubclass(rbsim.errors.GENERATED["MemoryError"], MemoryError)


def test_invalid_from_c_names_the_field():
    w = make_world()
    with pytest.raises(rbsim.InvalidError, match="radius") as info:
        w.add_sphere(radius=-0.5)
    assert info.value.status == lib.RBS_E_INVALID
    with pytest.raises(rbsim.InvalidError, match="normal"):
        w.add_plane(normal=(0, 0, 0))
    with pytest.raises(rbsim.InvalidError, match="already"):
        w.add_sphere("ball", position=(0, 0, 3))
    with pytest.raises(rbsim.InvalidError, match="dt"):
        rbsim.World(dt=-1.0)
    with pytest.raises(rbsim.InvalidError):
        rbsim.World(max_bodies=0)


def test_names_a_scene_file_refuses_are_invalid():
    # One rule for names (the library's, core/name.h): what a scene file
    # refuses the binding refuses as an InvalidError naming the character
    # and its byte ("my ball" was accepted here, and no scene could hold it).
    w = make_world()
    cases = [
        (lambda: w.add_sphere("my ball"), "sphere name", "' ' (a space) at byte 3"),
        (lambda: w.add_plane("a#b"), "plane name", "'#' at byte 2"),
        (lambda: w.add_material("k=v"), "material name", "'=' at byte 2"),
        (lambda: w.add_material('q"'), "material name", "'\"' at byte 2"),
        (lambda: w.add_sphere("tab\tx"), "sphere name",
         "0x09 (a control character) at byte 4"),
        (lambda: w.add_sphere("ba\u200bll"), "sphere name",
         "U+200B (an invisible formatting character) at byte 3"),
    ]
    for call, who, fault in cases:
        with pytest.raises(rbsim.InvalidError) as info:
            call()
        assert info.value.status == lib.RBS_E_INVALID
        assert who in str(info.value) and fault in str(info.value), str(info.value)
    assert sorted(w.bodies) == ["ball", "ground"]
    assert w.add_sphere("kugel_\u00e4", position=(1, 0, 1)).name == "kugel_\u00e4"


def _library_says(add, name):
    """The status and message of the library's own add (sphere, plane,
    material) of name in a fresh world, called through cffi directly."""
    d = ffi.new("rbs_world_def *")
    lib.rbs_world_def_init_sized(d, ffi.sizeof("rbs_world_def"))
    out = ffi.new("rbs_world **")
    assert lib.rbs_world_create(d, out) == lib.RBS_OK
    w, raw = out[0], ffi.new("char[]", name.encode("utf-8"))
    try:
        if add == "material":
            status = lib.rbs_world_add_material(w, raw, ffi.NULL)
        else:
            sd = ffi.new("rbs_%s_def *" % add)
            getattr(lib, "rbs_%s_def_init_sized" % add)(sd, ffi.sizeof("rbs_%s_def" % add))
            sd.name = raw
            status = getattr(lib, "rbs_world_add_%s" % add)(w, sd, ffi.NULL)
        return status, ffi.string(lib.rbs_world_last_error(w)).decode()
    finally:
        lib.rbs_world_destroy(w)


def test_names_are_judged_by_the_library_alone():
    # One rule, one message: the binding checked a name's length and a
    # material's "" and "*" itself, in words of its own ("name: must be at
    # most 63 bytes of UTF-8", "a material's name must not be empty nor
    # '*'") beside the library's for every other fault ("sphere name must
    # have 1 to 63 bytes of UTF-8 without ..."; a probe of session 50).  Now
    # each refused name raises InvalidError with the library's status and
    # message, word for word, and what the library takes the binding takes.
    long_name = "x" * 64
    cases = [("sphere", long_name), ("plane", "\u00e9" * 32), ("material", "m" * 70),
             ("material", ""), ("material", "*"), ("sphere", "a b"),
             ("material", "ba\u200bll"), ("plane", "k=v")]
    for add, name in cases:
        status, text = _library_says(add, name)
        assert status == lib.RBS_E_INVALID, (add, name)
        w = make_world()
        with pytest.raises(rbsim.InvalidError) as info:
            getattr(w, "add_" + add)(name)
        assert info.value.status == lib.RBS_E_INVALID
        assert str(info.value) == "invalid argument: " + text, (add, name, str(info.value))
    # the length, for each kind, in one form: "got N bytes"
    for add in ("sphere", "plane", "material"):
        text = _library_says(add, long_name)[1]
        assert text.startswith(add + " name must have 1 to 63 bytes of UTF-8"), text
        assert text.endswith("got 64 bytes"), text
    assert _library_says("material", "*")[1] == (
        'material name must not be "*", which means any material in a pair')
    # 63 bytes, "*" for a body, and a body's "" (unnamed, as in C) are taken
    w = make_world()
    assert w.add_sphere("y" * 63, position=(1, 0, 1)).name == "y" * 63
    assert w.add_material("z" * 63).name == "z" * 63
    assert w.add_sphere("*", position=(2, 0, 1)).name == "*"
    assert w.add_sphere("", position=(3, 0, 1)).name == ""


def test_a_body_material_star_is_refused():
    # add_sphere(material="*") / add_plane(material="*") took "*" (any
    # material, in a pair) as no material, silently, where a scene refuses
    # a body's "material": "*" (a probe of session 50).
    w = make_world()
    for add in (w.add_sphere, w.add_plane):
        with pytest.raises(rbsim.InvalidError, match=r'material: "\*" is not a material: it '
                           r"stands for any material in a pair \(set_material\)"):
            add("x", material="*")
    assert sorted(w.bodies) == ["ball", "ground"]
    # None is no material; "*" keeps its meaning in a pair
    assert w.add_sphere("y", material=None, position=(1, 0, 1)).name == "y"
    w.set_material("*", "*", static=0.4, kinetic=0.2)


def test_an_empty_name_finds_no_body():
    # "" names no body: body("") raised InvalidError ("invalid argument: no
    # body named ''", C's RBS_E_INVALID for ""), so `"" in world.bodies`
    # raised it too instead of answering (a probe of session 50).
    w = make_world()
    w.add_sphere("", position=(1, 0, 1))  # an unnamed body exists
    with pytest.raises(rbsim.NotFoundError, match="no body named ''.*all_bodies"):
        w.body("")
    assert "" not in w.bodies and "a\0b" not in w.bodies and "nosuch" not in w.bodies
    assert "ball" in w.bodies
    assert w.bodies.get("") is None
    # one rule with materials (the library's: RBS_E_NOT_FOUND for "" from
    # both finds; rbs_world_find_body said RBS_E_INVALID)
    with pytest.raises(rbsim.NotFoundError, match="no material named ''"):
        w.material("")
    # get, [] and `in` agree on any str that names no body (get("a\0")
    # raised InvalidError while `"a\0" in` was False: a probe of session 50)
    for key in ("a\0", "a\0b", "\ud800", "a b", "nosuch"):
        assert key not in w.bodies
        assert w.bodies.get(key) is None and w.bodies.get(key, 5) == 5
        with pytest.raises(rbsim.NotFoundError):
            w.bodies[key]
    assert sorted(w.bodies) == ["ball", "ground"] and len(w.all_bodies()) == 3
    w.close()
    with pytest.raises(rbsim.ClosedError):
        "" in w.bodies  # a closed world says so, whatever the name


def test_fixed_sphere_with_a_velocity_is_invalid():
    """A fixed sphere never moves: a velocity or angular velocity given with
    it is an InvalidError from the library (it was dropped, silently), as
    setting one on it afterwards is; zero vectors are fine."""
    w = rbsim.World(max_bodies=4)
    with pytest.raises(rbsim.InvalidError,
                       match=r"sphere velocity must be zero for a fixed sphere"):
        w.add_sphere("a", fixed=True, velocity=(1, 0, 0))
    with pytest.raises(rbsim.InvalidError,
                       match=r"sphere angular_velocity must be zero for a fixed sphere"):
        w.add_sphere("a", fixed=True, angular_velocity=(5, 0, 0))
    a = w.add_sphere("a", fixed=True, velocity=(0, 0, 0), angular_velocity=(0, 0, 0))
    assert a.fixed and a.velocity.tolist() == [0.0, 0.0, 0.0]
    with pytest.raises(rbsim.InvalidError, match="does not move"):
        a.velocity = (1, 0, 0)


def test_sphere_energy_at_the_start_is_bounded():
    """The library refuses a movable sphere whose energy at the start is
    beyond 1e300 J, as a scene's check does (mass 1e308 at 1 m was taken,
    and energy() then raised NumericError); a fixed one is taken."""
    w = rbsim.World(max_bodies=4)
    with pytest.raises(rbsim.InvalidError,
                       match=r"potential energy in gravity \(position, mass\) at the start "
                             r"is inf J, beyond 1e300 J"):
        w.add_sphere("a", radius=0.1, mass=1e308, position=(0, 0, 1))
    w.add_sphere("a", radius=0.1, mass=1e308, position=(0, 0, 1), fixed=True)
    w.add_sphere("b", radius=0.1, mass=1.0, position=(0, 0, 2))
    assert math.isfinite(w.energy().total)


def test_setters_apply_the_limits_of_add_sphere():
    """A setter refuses what add_sphere refuses for the same argument, with
    the library's message naming the argument and its value, and leaves
    the world as it was (velocity 1e308 was taken, and the world failed
    later: NumericError at energy() after 3 steps; a probe of session 50).
    The bound is the exact m v^2 / 2 <= 1e300 J: 1.43e150 m/s on 1 kg is
    1.022e300 J, 1.4e150 m/s 9.8e299 J (2 % either side, beyond rounding)."""
    w = rbsim.World(max_bodies=4)
    a = w.add_sphere(position=(0, 0, 1))
    h = w.hash()
    with pytest.raises(rbsim.InvalidError,
                       match=r"set_velocity: velocity \(1e\+308, 0, 0\) m/s: the sphere's "
                             r"kinetic energy m v\^2 / 2 \(velocity\) would be inf J, beyond "
                             r"1e300 J"):
        a.velocity = (1e308, 0, 0)
    assert w.hash() == h and a.velocity.tolist() == [0.0, 0.0, 0.0]
    with pytest.raises(rbsim.InvalidError):
        a.velocity = (1.43e150, 0, 0)
    with pytest.raises(rbsim.InvalidError, match=r"set_position: position \(0, 0, 1e\+300\) m: "
                                                 r"the sphere's potential energy in gravity"):
        a.position = (0, 0, 1e300)
    a.velocity = (1.4e150, 0, 0)
    a.velocity = (1, 0, 0)
    w.step(3)
    assert math.isfinite(w.energy().total)


def test_mutual_gravity_potential_at_the_start_is_bounded():
    """With mutual gravity the library refuses a sphere whose potential
    with one already there is beyond 1e300 J (G = 1e308, 1 kg, 1 m: the
    world was built and its first frame failed); softening bounds it."""
    w = rbsim.World(max_bodies=4, mutual_gravity=True, gravity_constant=1e308)
    w.add_sphere("a", radius=0.1, mass=1.0, position=(0, 0, 0))
    with pytest.raises(rbsim.InvalidError,
                       match=r'potential energy of mutual gravity with sphere 0 \("a"\) '
                             r"at the start is 1e\+308 J, beyond 1e300 J"):
        w.add_sphere("b", radius=0.1, mass=1.0, position=(1, 0, 0))
    assert len(w.all_bodies()) == 1
    w.add_sphere("b", radius=0.1, mass=1.0, position=(1e9, 0, 0))
    assert math.isfinite(w.energy().total)


def test_mutual_gravity_needs_a_positive_g():
    """With mutual gravity on, G must be > 0, as a scene's mutual_gravity.G
    (G = 0 was taken); off, G = 0 is fine."""
    with pytest.raises(rbsim.InvalidError,
                       match=r"gravity_constant must be > 0 with mutual_gravity on, got 0"):
        rbsim.World(mutual_gravity=True, gravity_constant=0)
    assert rbsim.World(mutual_gravity=False, gravity_constant=0).settings["gravity_constant"] == 0


def test_soft_substeps_out_of_range_names_it():
    """soft_substeps is 1 to 1000: 0 and 1001 are refused with the field,
    the range and the value."""
    for bad in (0, 1001):
        with pytest.raises(rbsim.InvalidError,
                           match=r"soft_substeps: must be in \[1, 1000\], got %d" % bad) as info:
            rbsim.World(soft_substeps=bad)
        assert info.value.status == lib.RBS_E_INVALID
    for good in (1, 1000):
        assert rbsim.World(soft_substeps=good).settings["soft_substeps"] == good


def test_soft_tolerance_out_of_range_names_it():
    """soft_tolerance is 0 to 1: -0.1 and 2 are refused with the field, the
    range and the value."""
    for bad in (-0.1, 2.0):
        with pytest.raises(rbsim.InvalidError,
                           match=r"soft_tolerance: must be in \[0, 1\] \(a fraction of the "
                                 r"radius\), got %r$" % bad) as info:
            rbsim.World(soft_tolerance=bad)
        assert info.value.status == lib.RBS_E_INVALID
    for good in (0.0, 1.0):
        assert rbsim.World(soft_tolerance=good).settings["soft_tolerance"] == good


def _message(fn, *args, **kw):
    with pytest.raises(rbsim.InvalidError) as info:
        fn(*args, **kw)
    assert info.value.status == lib.RBS_E_INVALID
    return str(info.value)


def test_ranges_echo_the_value_exactly():
    """A real out of its range is echoed as given (the shortest text that
    reads back as the same double), never rounded: restitution=1.0000001
    read "got 1" (the library's %g), in World(...), the setters,
    set_material, add_sphere and run's speed.  The ends of each range are
    taken (by the library too)."""
    pre = "invalid argument: "
    for key, bad, text in (
            ("restitution", 1.0000001, "must be in [0, 1], got 1.0000001"),
            ("restitution", -1e-300, "must be in [0, 1], got -1e-300"),
            ("restitution", 2, "must be in [0, 1], got 2"),
            ("dt", -1e-300, "must be > 0, got -1e-300"),
            ("dt", -0.0, "must be > 0, got -0.0"),
            ("tolerance", 9.999999999999999e-16,
             "must be >= 1e-15 (what double precision can reach), got 9.999999999999999e-16"),
            ("slop", 0.1000000001,
             "must be in (0, 0.1) (a fraction of the smaller radius), got 0.1000000001"),
            ("slop", 0.0, "must be in (0, 0.1) (a fraction of the smaller radius), got 0.0"),
            ("soft_tolerance", 1.0000000000000002,
             "must be in [0, 1] (a fraction of the radius), got 1.0000000000000002")):
        assert _message(rbsim.World, **{key: bad}) == pre + key + ": " + text
    for key, good in (("restitution", 0.0), ("restitution", 1.0), ("dt", 5e-324),
                      ("tolerance", 1e-15), ("slop", 5e-324),
                      ("slop", 0.09999999999999999), ("soft_tolerance", 0.0),
                      ("soft_tolerance", 1.0)):
        assert rbsim.World(**{key: good}).settings[key] == good
    w = make_world()
    assert _message(setattr, w, "dt", -1e-300) == pre + "dt: must be > 0, got -1e-300"
    assert _message(setattr, w, "tolerance", 9.999999999999999e-16) == (
        pre + "tolerance: must be >= 1e-15 (what double precision can reach), "
        "got 9.999999999999999e-16")
    w.dt, w.tolerance = 5e-324, 1e-15
    assert (w.dt, w.tolerance) == (5e-324, 1e-15)
    for kw, text in (
            (dict(restitution=1.0000001),
             "restitution: must be in [0, 1] (None keeps the world's), got 1.0000001"),
            (dict(static=-1e-300), "static: must be >= 0, got -1e-300"),
            (dict(kinetic=-1e-300), "kinetic: must be >= 0, got -1e-300"),
            (dict(rolling=-0.1234567891), "rolling: must be >= 0, got -0.1234567891"),
            (dict(spinning=-1e-300), "spinning: must be >= 0, got -1e-300"),
            (dict(static=0.2999999999999999),
             "static: must be >= kinetic (0.3, the default), got 0.2999999999999999"),
            (dict(kinetic=0.5000000000000001),
             "kinetic: must be <= static (0.5, the default), got 0.5000000000000001"),
            (dict(static=0.25, kinetic=0.2500000000000001),
             "kinetic: must be <= static (0.25), got 0.2500000000000001")):
        assert _message(w.set_material, "*", "*", **kw) == pre + text
    w.set_material("*", "*", static=0.3, kinetic=0.3, restitution=1.0, rolling=0.0)
    w.set_material("*", "*", kinetic=0.5)
    for kw, text in (
            (dict(radius=-1e-300), "radius: must be > 0, got -1e-300"),
            (dict(mass=-1.23456789), "mass: must be > 0, got -1.23456789"),
            (dict(density=-1e-300), "density: must be >= 0 (0: from mass), got -1e-300")):
        assert _message(w.add_sphere, position=(5, 5, 5), **kw) == pre + text
    n_before = len(w.all_bodies())
    # Both mass and density: a scene refuses them ("Give exactly one"); the
    # binding took them, using density (mass 8.3776 for radius 1, density
    # 2, even with mass=-1).
    for m, dens in ((-1.0, 2.0), (1.0, 2.0), (1.0, 0.0)):
        assert _message(w.add_sphere, position=(5, 5, 5), radius=1.0, mass=m,
                        density=dens) == pre + (
            "mass and density: give one of them, not both (got mass=%r, "
            "density=%r), as in a scene" % (m, dens))
    assert len(w.all_bodies()) == n_before
    assert w.add_sphere(position=(5, 5, 5), radius=1.0,
                        density=2.0).mass == pytest.approx(8 / 3 * math.pi, rel=1e-15)
    assert _message(w.run, 1, realtime=True, speed=-1e-300) == (
        pre + "speed: must be > 0, got -1e-300")


def _library_takes(**fields):
    """Whether rbs_world_def_validate takes a default def with fields set."""
    d = ffi.new("rbs_world_def *")
    lib.rbs_world_def_init_sized(d, ffi.sizeof("rbs_world_def"))
    for key, value in fields.items():
        setattr(d, key, value)
    return lib.rbs_world_def_validate(d, ffi.NULL, 0) == lib.RBS_OK


def test_each_world_argument_out_of_range_is_named():
    """World(max_sweeps=0) and World(max_halvings=1000) said "max_halvings
    must be <= 60 and max_sweeps in [1, 100000]", and gravity_constant or
    softening "gravity_constant and softening must be ...": now the message
    names the one argument, its range and the value.  The ends are the
    library's (it takes them and refuses one beyond)."""
    pre = "invalid argument: "
    for key, low, high in (("max_halvings", 0, 60), ("max_sweeps", 1, 100000),
                           ("soft_substeps", 1, 1000)):
        for bad in (low - 1, high + 1, 1000, 2 ** 40):
            if low <= bad <= high:
                continue
            assert _message(rbsim.World, **{key: bad}) == (
                pre + "%s: must be in [%d, %d], got %d" % (key, low, high, bad))
        for good in (low, high):
            assert rbsim.World(**{key: good}).settings[key] == good
        assert _library_takes(**{key: low}) and _library_takes(**{key: high})
        assert not _library_takes(**{key: high + 1})
        assert low == 0 or not _library_takes(**{key: low - 1})
    for key in ("gravity_constant", "softening"):
        assert _message(rbsim.World, **{key: -1e-300}) == (
            pre + "%s: must be >= 0, got -1e-300" % key)
        assert rbsim.World(**{key: 0.0}).settings[key] == 0.0
        assert not _library_takes(**{key: -5e-324})


def test_capacities_give_their_real_range():
    """max_bodies=-1 said "must be in [0, 4294967295]" (a C field's range)
    and max_bodies=0 "must be in [1, 16777216]": each capacity now gives
    the library's range, which takes each end and refuses one beyond
    (max_materials and max_pairs over theirs had one message for both).
    max_bodies from 16777213 without max_contacts said "max_contacts must
    be <= 67108864, got 67108868", a value not given: now it says that is
    the default and to give max_contacts."""
    pre = "invalid argument: "
    d = ffi.new("rbs_world_def *")
    lib.rbs_world_def_init_sized(d, ffi.sizeof("rbs_world_def"))
    assert d.max_contacts == 0  # (the default: 4 x max_bodies + 16)
    for key, low, high in (("max_bodies", 1, 16777216), ("max_materials", 0, 4096),
                           ("max_pairs", 0, 65536), ("max_contacts", 0, 67108864)):
        for bad in (-1, low - 1, high + 1, 2 ** 32, 2 ** 64):
            if low <= bad <= high:
                continue
            assert _message(rbsim.World, **{key: bad}) == (
                pre + "%s: must be in [%d, %d], got %d" % (key, low, high, bad))
        assert _library_takes(**{key: high, "max_contacts": 64})
        assert _library_takes(**{key: low, "max_contacts": 64} if key != "max_contacts"
                              else {key: low})
        assert not _library_takes(**{key: high + 1})
        assert low == 0 or not _library_takes(**{key: low - 1})
        if key in ("max_materials", "max_pairs"):  # (2^24 bodies are 33 GB)
            assert rbsim.World(**{key: high}).settings[key] == high
        assert rbsim.World(**{key: low, "max_bodies": 1}).settings[key] == (
            low if key != "max_contacts" else 4 * 1 + 16)
    for n in (16777213, 16777216):
        assert _message(rbsim.World, max_bodies=n) == (
            pre + "max_contacts: its default, 4 x max_bodies + 16, is %d for "
            "max_bodies=%d, over 67108864: give max_contacts" % (4 * n + 16, n))
    assert _library_takes(max_bodies=16777212)


def test_capacity_stale_notfound_closed():
    w = rbsim.World(max_bodies=1)
    w.add_sphere("a")
    with pytest.raises(rbsim.CapacityError):
        w.add_sphere("b", position=(0, 0, 1))
    body = w.body("a")
    body.remove()
    with pytest.raises(rbsim.StaleIdError):
        body.velocity = (0, 0, 1)
    with pytest.raises(rbsim.NotFoundError):
        w.body("a")
    w.close()
    with pytest.raises(rbsim.ClosedError):
        w.add_sphere("c")


def test_numeric_from_python_and_from_c():
    w = make_world()
    ball = w.bodies["ball"]
    with pytest.raises(rbsim.NumericError, match="velocity"):
        ball.velocity = (NAN, 0, 0)
    # The library checks too: call it directly with a NaN.
    cid = w._cbody(ball)
    v = ffi.new("rbs_vec3 *", {"x": NAN, "y": 0.0, "z": 0.0})
    with pytest.raises(rbsim.NumericError, match="finite"):
        w._call(lib.rbs_body_set_velocity, cid[0], v[0])
    assert ball.velocity.tolist() == [0.0, 0.0, 0.0]  # unchanged


def test_io_and_scene_errors(tmp_path):
    with pytest.raises(rbsim.IoError) as info:
        rbsim.load(tmp_path / "missing.json")
    assert "missing.json" in str(info.value)
    bad = tmp_path / "bad.json"
    bad.write_text('{\n  "format": 1,\n  "simulation": {"steps": 10},\n'
                   '  "bodies": [{"type": "sphere", "name": "b", "mass": 1,\n'
                   '              "position": [0, 0, 1], "radius": -1}]\n}\n')
    with pytest.raises(rbsim.SceneError) as info:
        rbsim.load(bad)
    e = info.value
    assert e.status == lib.RBS_E_SCENE and e.file.endswith("bad.json")
    assert len(e.errors) == 1 and e.count == 1
    assert e.line == 5 and e.column == 48 and "must be > 0" in e.message
    assert e.path == "bodies[0].radius"
    assert "bad.json:5:48:" in str(e)


def test_scene_error_lists_every_error(tmp_path):
    bad = tmp_path / "many.json"
    bad.write_text('{"format": 1, "simulation": {"steps": 10, "dt": -1},\n'
                   ' "bodies": [{"type": "sphere", "radius": -1},\n'
                   '            {"type": "sphere", "mass": "heavy"}]}\n')
    with pytest.raises(rbsim.SceneError) as info:
        rbsim.load(bad)
    e = info.value
    assert len(e.errors) >= 3
    lines = [x.line for x in e.errors]
    assert 1 in lines and 2 in lines and 3 in lines
    for x in e.errors:
        assert x.file.endswith("many.json") and x.message and x.text


def test_busy_when_a_world_is_used_during_its_run():
    w = make_world()

    def meddle(frame):
        w.step()

    with pytest.raises(rbsim.BusyError):
        w.run(5, renderers=[meddle])
    w.step()  # usable again after the run


def check_raises_rbsim(fn, *args, **kw):
    try:
        fn(*args, **kw)
    except rbsim.Error:
        return
    pytest.fail("%s(%r, %r) did not raise an rbsim.Error" % (fn, args, kw))


def test_bad_arguments_to_the_world_constructor():
    for key in ("max_bodies", "max_materials", "max_pairs", "max_contacts",
                "max_halvings", "max_sweeps", "soft_substeps"):
        for bad in BAD_INTS:
            check_raises_rbsim(rbsim.World, **{key: bad})
    for key in ("dt", "restitution", "tolerance", "slop", "soft_tolerance",
                "gravity_constant", "softening"):
        for bad in BAD_REALS:
            check_raises_rbsim(rbsim.World, **{key: bad})
    for bad in BAD_VECTORS:
        check_raises_rbsim(rbsim.World, gravity=bad)
    for bad in ("sideways", 3, None):
        if bad is not None:
            check_raises_rbsim(rbsim.World, gravity_mode=bad)
        check_raises_rbsim(rbsim.World, method=bad if bad is not None else 7)
    for bad in ("yes", 2, 0.5):
        check_raises_rbsim(rbsim.World, prune=bad)
        check_raises_rbsim(rbsim.World, mutual_gravity=bad)


def test_bad_arguments_to_bodies_and_materials():
    w = make_world()
    ball = w.bodies["ball"]
    for key in ("radius", "mass", "density"):
        for bad in BAD_REALS + [-1.0] + ([0.0] if key != "density" else []):
            check_raises_rbsim(w.add_sphere, **{key: bad})
    for key in ("position", "velocity", "angular_velocity", "center_of_mass",
                "force", "torque", "inertia"):
        for bad in BAD_VECTORS:
            check_raises_rbsim(w.add_sphere, **{key: bad})
    for bad in BAD_VECTORS + [[0, 0, 0, 0]]:
        check_raises_rbsim(w.add_sphere, orientation=bad)
        check_raises_rbsim(w.add_plane, normal=bad)
        check_raises_rbsim(w.add_plane, point=bad)
    for bad in (3, b"name", "a\0b", "x" * 100):
        check_raises_rbsim(w.add_sphere, bad)
        check_raises_rbsim(w.add_material, bad)
        check_raises_rbsim(w.body, bad)
    for bad in (-1, 2 ** 24, "red", 1.5):
        check_raises_rbsim(w.add_sphere, color=bad)
    for bad in ("plaid", 1):
        check_raises_rbsim(w.add_sphere, texture=bad)
        check_raises_rbsim(w.add_sphere, inertia=bad if bad != 1 else "dense")
    for bad in (5, object(), "nonexistent"):
        check_raises_rbsim(w.add_sphere, material=bad)
        check_raises_rbsim(w.set_material, bad, "*")
    for key in ("static", "kinetic", "restitution", "rolling", "spinning"):
        for bad in BAD_REALS:
            check_raises_rbsim(w.set_material, "*", "*", **{key: bad})
    for attr in ("position", "velocity", "angular_velocity", "force", "torque",
                 "orientation"):
        for bad in BAD_VECTORS + [None]:
            check_raises_rbsim(setattr, ball, attr, bad)
    for bad in (None, "ball", 3, object()):
        check_raises_rbsim(w.remove_body, bad)
    assert ball.position.tolist() == [0.0, 0.0, 1.0]  # nothing got through


def test_bad_arguments_to_stepping_and_settings():
    w = make_world()
    for bad in [None, -1, 2 ** 64, 1.5, "3", NAN, True]:
        check_raises_rbsim(w.step, bad)
    for bad in BAD_REALS + [None, 0.0, -1.0]:
        check_raises_rbsim(setattr, w, "dt", bad)
        check_raises_rbsim(setattr, w, "tolerance", bad)
    for bad in (None, 3, "nope", ""):
        check_raises_rbsim(setattr, w, "method", bad)
    for bad in (None, 3, object(), "", "a\0b"):
        check_raises_rbsim(rbsim.load, bad)
    check_raises_rbsim(rbsim.load, "x.json", format="xml")
    check_raises_rbsim(rbsim.parse_json, None)
    check_raises_rbsim(rbsim.parse_json, "{", name=None)
    check_raises_rbsim(w.run, -1)
    check_raises_rbsim(w.run, 5, renderers=[1])
    check_raises_rbsim(w.run, 5, renderers=3)
    check_raises_rbsim(w.run, 5, renderers=[print] * 5)
    check_raises_rbsim(w.run, 5, speed=NAN)
    check_raises_rbsim(w.run, 5, reel_capacity=1)
    assert w.step_count == 0 and not math.isnan(w.time)


def test_text_that_is_not_unicode_names_the_argument(tmp_path):
    w = make_world()
    for call in (lambda: w.body("\udcff"), lambda: w.add_material("rub\ud800ber"),
                 lambda: w.add_sphere("\ud800", position=(1, 0, 1)),
                 lambda: rbsim.parse_json('{"bodies": []}', name="\ud800"),
                 lambda: rbsim.parse_json('{"bodies": [], "x": "\ud800"}')):
        with pytest.raises(rbsim.InvalidError, match="lone surrogate"):
            call()
    with pytest.raises(rbsim.InvalidError, match="path: cannot be encoded"):
        rbsim.World.restore(str(tmp_path) + "/\ud800.ckpt")


def test_names_from_c_must_be_utf8():
    w = make_world()
    out = ffi.new("rbs_material_id *")
    raw = w._acquire()
    try:
        assert lib.rbs_world_add_material(raw, b"rub\xffber", out) == lib.RBS_E_INVALID
        assert b"UTF-8" in ffi.string(lib.rbs_world_last_error(raw))
        # overlong "/" and a UTF-16 surrogate encoded in UTF-8: not UTF-8
        assert lib.rbs_world_add_material(raw, b"\xc0\xaf", out) == lib.RBS_E_INVALID
        assert lib.rbs_world_add_material(raw, b"\xed\xa0\x80", out) == lib.RBS_E_INVALID
        assert lib.rbs_world_add_material(raw, "gummi-\u00e4\U0001f600".encode(), out) == lib.RBS_OK
    finally:
        w._lock.release()
    assert [m.name for m in w.materials()] == ["gummi-\u00e4\U0001f600"]
    with pytest.raises(rbsim.InvalidError):
        w.add_sphere(b"b\xffall".decode("utf-8", "surrogateescape"), position=(1, 0, 1))


def test_pair_restitution_outside_0_1_is_refused():
    w = make_world()
    for bad in (-0.5, 1.5):
        with pytest.raises(rbsim.InvalidError, match="restitution: must be in"):
            w.set_material("*", "*", restitution=bad)
    assert w.pairs() == []
    w.set_material("*", "*", restitution=0.25)
    assert w.pairs()[0]["restitution"] == 0.25


def test_star_import_keeps_the_builtins():
    """`from rbsim import *` replaced the built-in MemoryError with rbsim's
    (__all__ held every generated class): names of built-in exceptions are
    left out of the star import and stay attributes (a probe of session
    41)."""
    import builtins
    for module in ("rbsim", "rbsim.errors"):
        ns = {}
        exec("from %s import *" % module, ns)
        hidden = [n for n in ns if n != "__builtins__" and hasattr(builtins, n)]
        assert hidden == [], (module, hidden)
        assert "InvalidError" in ns and "CapacityError" in ns
    assert rbsim.MemoryError is rbsim.errors.GENERATED["MemoryError"]
    assert rbsim.MemoryError is not builtins.MemoryError
    assert issubclass(rbsim.MemoryError, builtins.MemoryError)
    assert rbsim.errors.SHADOWING == ["MemoryError"]


def _raise_in_worker(_):
    rbsim.World(dt=-1)


def test_errors_round_trip_through_pickle():
    """A pickled rbsim error came back with its prefix twice ("invalid
    argument: invalid argument: ..."), also from a multiprocessing worker
    (a probe of session 41): every attribute now comes back as it was."""
    import multiprocessing
    import pickle
    w = make_world()
    cases = [rbsim.InvalidError("radius: must be > 0, got -1"),
             rbsim.errors.GENERATED["MemoryError"]("out"),
             rbsim.Error("unknown status -999: x", status=-999),
             rbsim.BusyError("world is busy"), rbsim.ArgumentTypeError("n: int")]
    try:
        w.step(10 ** 30)
    except rbsim.Error as e:
        cases.append(e)
    try:
        rbsim.parse_json('{"format": 1, "bodies": [{"type": "cube"}]}', "s.json")
    except rbsim.SceneError as e:
        cases.append(e)
    try:
        w.bodies["nope"]
    except rbsim.NotFoundError as e:
        cases.append(e)
    assert len(cases) == 8
    for e in cases:
        r = pickle.loads(pickle.dumps(e))
        assert type(r) is type(e)
        assert str(r) == str(e) and r.args == e.args
        assert (r.status, r.name, r.detail) == (e.status, e.name, e.detail)
        assert vars(r).keys() == vars(e).keys()
    scene = cases[6]
    back = pickle.loads(pickle.dumps(scene))
    assert [i.text for i in back.errors] == [i.text for i in scene.errors]
    assert (back.file, back.line, back.message) == (scene.file, scene.line, scene.message)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        with pytest.raises(rbsim.InvalidError) as info:
            pool.map(_raise_in_worker, [0])
    assert str(info.value) == "invalid argument: dt: must be > 0, got -1"


def test_numpy_bools_are_flags():
    """numpy's booleans were refused as "expected True or False, got bool
    np.True_" (numpy 2 names its bool_ "bool"): they are flags, as numpy's
    0 and 1 are; other values are refused with numpy's full type name."""
    w = rbsim.World(mutual_gravity=np.True_, gravity_constant=1.0, prune=np.False_)
    assert w.settings["mutual_gravity"] is True and w.settings["prune"] is False
    assert w.add_sphere(fixed=np.bool_(True)).fixed
    assert not w.add_sphere(fixed=np.int64(0), position=(0, 0, 1)).fixed
    run = w.start(2, [], realtime=np.False_, start_paused=np.False_)
    run.wait()
    for bad, text in ((2, "got int 2"), (np.float64(1.0), "got numpy.float64"),
                      (np.array([True]), "got numpy.ndarray")):
        with pytest.raises(rbsim.ArgumentTypeError, match="fixed: expected True or False, " + text):
            w.add_sphere(fixed=bad, position=(0, 0, 3))
    with pytest.raises(rbsim.ArgumentTypeError, match="radius: expected a real number, got numpy.bool"):
        w.add_sphere(radius=np.True_)


def test_messages_name_the_argument_and_echo_the_value():
    """The library's messages for these named neither the argument nor the
    value ("sphere principal moments must be finite and > 0", "...:
    rbs_world_energy": a probe of session 41): Python checks them first and
    says which argument and what it got.  (Names are the library's alone:
    test_names_are_judged_by_the_library_alone.)"""
    w = make_world()
    cases = [
        (lambda: w.add_sphere(inertia=[-1, 1, 1]),
         "inertia: principal moments must be > 0 kg m^2, got (-1, 1, 1)"),
        (lambda: w.add_sphere(inertia=[1e-320, 1, 1]),
         "inertia: principal moments must be >= 2.2250738585072014e-308 kg m^2"),
        (lambda: w.add_sphere(inertia=[1, 1, 3]),
         "inertia: principal moments must satisfy the triangle inequality"),
        # (each finite, their sum not: the library said "must be finite and
        # > 0"; and a density's overflowing mass was "sphere mass must be
        # finite and > 0, got inf": a probe of session 50)
        (lambda: w.add_sphere(inertia=[6e307, 6e307, 6e307]),
         "inertia: principal moments must have a finite sum (the world takes the inertia's "
         "trace), got (6e+307, 6e+307, 6e+307)"),
        (lambda: w.add_sphere(density=1e308),
         "sphere mass from density 1e+308 kg/m^3 and radius 0.1 m (density * 4/3 pi r^3) "
         "overflows a double"),
        (lambda: w.add_sphere(orientation=(0, 0, 0, 0)),
         "orientation: must be a nonzero quaternion [w, x, y, z], got (0, 0, 0, 0)"),
        (lambda: setattr(w.bodies["ball"], "orientation", (0, 0, 0.0, 0)),
         "orientation: must be a nonzero quaternion [w, x, y, z], got (0, 0, 0, 0)"),
        (lambda: w.add_plane(normal=(0, 0, 0)),
         "normal: must be a nonzero vector"),
    ]
    for call, text in cases:
        with pytest.raises(rbsim.InvalidError) as info:
            call()
        assert str(info.value).startswith("invalid argument: " + text), str(info.value)
    assert w.add_sphere("y" * 63, position=(1, 0, 1)).name == "y" * 63
    assert w.add_sphere(inertia=[1, 1, 2], position=(2, 0, 1)).inertia[2][2] == 2.0
    # (a setter no longer takes a state whose sums overflow -- velocity
    # 1e200 m/s is beyond add_sphere's limits -- but stepping can reach
    # one: 1e160 N on 1 kg for 1 ms gives 1e157 m/s, 5e313 J; 1e308 N for
    # 10 s gives 1e10 kg a momentum of 1e309 kg m/s)
    hot = rbsim.World(gravity=(0, 0, 0))
    hot.add_sphere(position=(1, 0, 0), force=(1e160, 0, 0))
    hot.step(1)
    with pytest.raises(rbsim.NumericError, match=r"energy: not finite at step 1 "
                       r"\(kinetic inf J, potential -inf J\): a sum overflows a double"):
        hot.energy()
    hot = rbsim.World(gravity=(0, 0, 0), dt=10.0)
    hot.add_sphere(mass=1e10, force=(1e308, 0, 0))
    hot.step(1)
    with pytest.raises(rbsim.NumericError, match=r"momentum: not finite at step 1 "
                       r"\(linear \(inf, 0, 0\) kg m/s"):
        hot.momentum()


def test_run_steps_are_capped_at_2_53_as_a_scene_and_the_command():
    """run()/start() take at most 2^53 steps, the cap of a scene's
    simulation.steps and of rbsim --steps, with the scene's message
    (run(steps=2**60) was taken: a probe of session 50); 2^53 itself is
    taken."""
    w = rbsim.World(max_bodies=2)
    for bad in (2 ** 53 + 1, 2 ** 60):
        try:
            r = w.start(bad)
        except rbsim.InvalidError as exc:
            assert str(exc) == "invalid argument: steps: must be at most 2^53, got %d" % bad
        else:
            r.command("quit")
            r.wait()
            pytest.fail("start(%d) was taken" % bad)
    r = w.start(2 ** 53)
    r.command("quit")
    assert r.wait().steps == 2 ** 53


def test_run_steps_times_dt_must_be_finite_as_in_a_scene():
    """A run whose last frame would be at t = inf is refused before it
    starts, as a scene's simulation.steps * dt is (World(dt=1e300)
    .start(2**53) was taken: a probe of session 50); 1e300 * 100 is fine."""
    w = rbsim.World(max_bodies=2, dt=1e300)
    with pytest.raises(rbsim.InvalidError,
                       match=r"steps \* dt overflows \(9007199254740992 \* 1e\+300 s\)"):
        w.start(2 ** 53)
    with pytest.raises(rbsim.InvalidError, match=r"steps \* dt overflows"):
        w.run(2 ** 30)
    assert w.run(100).steps == 100


def test_an_array_of_the_wrong_shape_is_named_by_its_shape():
    """np.zeros((2, 3)) as a position said "expected 3 numbers, got 2" (its
    2 rows); the message names the shape (a probe of session 50)."""
    w = rbsim.World(max_bodies=2)
    cases = [(np.zeros((2, 3)), "(2, 3)"), (np.zeros((1, 3)), "(1, 3)"),
             (np.zeros(4), "(4,)")]
    for value, shape in cases:
        with pytest.raises(rbsim.InvalidError) as info:
            w.add_sphere(position=value)
        assert str(info.value) == ("invalid argument: position: expected 3 numbers, got an "
                                   "array of shape %s" % shape), str(info.value)
    assert w.add_sphere(position=np.array([0.0, 0.0, 1.0])).position.tolist() == [0, 0, 1]
    assert w.all_bodies()[0].position.tolist() == [0, 0, 1]


def test_a_list_of_vectors_is_named_as_such():
    """A list of two positions, [[0, 0, 1], [0, 0, 2]], said "expected 3
    numbers, got 2" as np.zeros((2, 3)) did before session 50: read as two
    numbers.  The message names the nested item (a probe of session 51)."""
    w = rbsim.World(max_bodies=2)
    cases = [([[0, 0, 1], [0, 0, 2]], "position", "got 2 items, position[0] a list"),
             (((0, 0, 1),), "position", "got 1 item, position[0] a tuple"),
             ([[1, 0, 0, 0]], "orientation", "got 1 item, orientation[0] a list")]
    for value, key, msg in cases:
        with pytest.raises(rbsim.InvalidError) as info:
            w.add_sphere(**{key: value})
        assert str(info.value) == ("invalid argument: %s: expected %d numbers, %s (one "
                                   "vector at a time)" % (key, 4 if key == "orientation" else 3,
                                                          msg)), str(info.value)
    with pytest.raises(rbsim.InvalidError) as info:
        w.add_sphere(position=(1, 2))
    assert str(info.value) == "invalid argument: position: expected 3 numbers, got 2"
    assert w.all_bodies() == []


def test_an_unknown_keyword_is_named_with_the_nearest_known_one(tmp_path):
    # Python 3.11's own TypeError names the keyword only; the binding adds
    # the library's "did you mean" (rbs_scene_suggest, the rule of scenes
    # and the command) and the known keywords.
    w = rbsim.World()
    cases = [
        (lambda: rbsim.World(max_bodys=3), "World()", "max_bodys", "max_bodies"),
        (lambda: w.add_sphere("a", radus=1.0), "add_sphere()", "radus", "radius"),
        (lambda: w.add_plane(normall=(0, 0, 1)), "add_plane()", "normall", "normal"),
        (lambda: w.set_material("a", "b", statc=1.0), "set_material()", "statc", "static"),
        (lambda: w.run(stesp=3), "run()", "stesp", "steps"),
        (lambda: w.start(reel_capacty=3), "start()", "reel_capacty", "reel_capacity"),
        (lambda: rbsim.load(tmp_path / "x.json", fromat="json"), "load()", "fromat", "format"),
        (lambda: rbsim.parse_json("{}", step=3), "parse_json()", "step", "steps"),
    ]
    for call, where, word, near in cases:
        with pytest.raises(rbsim.ArgumentTypeError) as e:
            call()
        text = str(e.value)
        assert where in text and repr(word) in text, text
        assert "(did you mean %r?)" % near in text, text
        assert isinstance(e.value, TypeError)
    # nothing near: no suggestion, the known ones listed
    with pytest.raises(TypeError, match=r"'zzzzzzzz'; known: max_bodies, "):
        rbsim.World(zzzzzzzz=1)
    # a TypeError of the call itself (not a keyword) is Python's, unchanged
    with pytest.raises(TypeError, match="multiple values"):
        w.add_sphere("a", name="b")
    # the known keywords still work, and the signature is the function's
    assert rbsim.World(max_bodies=3, dt=0.01).dt == 0.01
    import inspect
    assert "radius" in inspect.signature(rbsim.World.add_sphere).parameters
