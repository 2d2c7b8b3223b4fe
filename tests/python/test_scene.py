"""Loading scenes: rbsim.load (JSON and the seed's text format),
rbsim.parse_json, overrides, and scene errors with their places."""

import json
import os
import threading
import warnings

import numpy as np
import pytest

from conftest import SOURCE_DIR, bounce_scene

import rbsim

SCENES = SOURCE_DIR / "scenes"


def test_load_builds_the_scene(write_scene):
    path = write_scene(bounce_scene(steps=123, dt=0.002, restitution=0.7))
    w = rbsim.load(path)
    assert set(w.bodies) == {"ground", "ball"}
    s = w.settings
    assert s["dt"] == 0.002 and s["restitution"] == 0.7
    assert s["gravity"] == (0.0, 0.0, -9.81)
    assert w.bodies["ball"].position.tolist() == [0.0, 0.0, 1.1]
    assert w.bodies["ball"].radius == 0.1
    assert w.description == "a ball bouncing on the ground"
    frames = []
    info = w.run(renderers=[lambda f: frames.append(f.number)])
    assert frames == list(range(124)) and info.steps == 123  # the scene's steps
    assert w.step_count == 123


def test_load_accepts_pathlike_and_str(write_scene):
    path = write_scene(bounce_scene())
    assert rbsim.load(str(path)).hash() == rbsim.load(path).hash()


def test_json_and_text_formats_give_the_same_world():
    json_path = SCENES / "bouncing_sphere.json"
    text_path = SCENES / "bouncing_sphere" / "config.txt"
    if not json_path.exists() or not text_path.exists():
        pytest.fail("the repository's scenes are missing: %s" % SCENES)
    a = rbsim.load(json_path)
    b = rbsim.load(text_path, format="text")
    c = rbsim.load(text_path)  # auto
    assert a.settings == b.settings == c.settings
    assert a.hash() == b.hash() == c.hash()
    a.step(500)
    b.step(500)
    assert np.array_equal(a.positions, b.positions)


def test_load_from_a_pipe():
    # /dev/fd/N of a pipe, no .json name: read once, the format told from
    # the bytes read (the first read used to be lost to telling it)
    path = SCENES / "pile.json"
    data = path.read_bytes()
    r, w = os.pipe()

    def feed():
        with os.fdopen(w, "wb") as f:
            f.write(data)

    t = threading.Thread(target=feed)
    t.start()
    try:
        world = rbsim.load("/dev/fd/%d" % r)
    finally:
        t.join()
        os.close(r)
    assert world.hash() == rbsim.load(path).hash()
    assert world.settings == rbsim.load(path).settings


def test_every_repository_scene_loads_and_steps():
    paths = sorted(SCENES.glob("*.json"))
    assert paths, "no scenes in %s" % SCENES
    for path in paths:
        w = rbsim.load(path)
        assert len(w.all_bodies()) > 0, path
        w.step(20)
        assert np.isfinite(w.positions).all(), path


def test_overrides(write_scene):
    path = write_scene(bounce_scene(steps=1000, dt=0.001))
    w = rbsim.load(path, steps=7, dt=0.0005, method="euler")
    assert w.dt == 0.0005 and w.method == "euler"
    assert w.run().steps == 7
    with pytest.raises(rbsim.InvalidError, match="^invalid argument: method: unknown"):
        rbsim.load(path, method="nope")
    with pytest.raises(rbsim.InvalidError, match="dt"):
        rbsim.load(path, dt=0.0)
    # steps=0 is frame 0 only, as --steps 0 and "steps": 0 (before session
    # 38 it was refused); a negative count is not a count
    w0 = rbsim.load(path, steps=0)
    assert w0.run().steps == 0 and w0.time == 0.0
    with pytest.raises(rbsim.InvalidError, match="steps"):
        rbsim.load(path, steps=-1)
    # the range named is the real one, 2^53 (it said 2^64 - 1; session 45)
    with pytest.raises(rbsim.InvalidError, match=r"\[0, 9007199254740992\]"):
        rbsim.load(path, steps=-1)
    with pytest.raises(rbsim.InvalidError, match="steps"):
        rbsim.load(path, steps=2 ** 53 + 2)


def test_slop_override(write_scene):
    """slop= sets the world's slop (as --slop and simulation.slop do); out of
    (0, 0.1) it is an InvalidError naming slop, as Python names it (it was
    a SceneError "command line: --slop: ..."), a non-number a type error."""
    import json
    path = write_scene(bounce_scene(steps=10))
    assert rbsim.load(path).settings["slop"] == 1e-6
    assert rbsim.load(path, slop=0.005).settings["slop"] == 0.005
    assert rbsim.parse_json(json.dumps(bounce_scene()), "inline", slop=0.02).settings["slop"] == 0.02
    for bad in (0.0, 0.1, -1e-3):
        with pytest.raises(rbsim.InvalidError) as info:
            rbsim.load(path, slop=bad)
        assert str(info.value).startswith(
            "invalid argument: slop: must be in (0, 0.1) (a fraction of the smaller "
            "radius), got ")
        assert "--slop" not in str(info.value)
        with pytest.raises(rbsim.InvalidError, match="^invalid argument: slop: "):
            rbsim.parse_json(json.dumps(bounce_scene()), slop=bad)
    for bad in ("", "leapfrog"):
        with pytest.raises(rbsim.InvalidError) as info:
            rbsim.parse_json(json.dumps(bounce_scene()), method=bad)
        assert str(info.value) == (
            'invalid argument: method: unknown method "%s"; expected euler, selective, '
            'event, verlet, rk4, adaptive, soft or auto' % bad)
    with pytest.raises(rbsim.ArgumentTypeError, match="slop"):
        rbsim.load(path, slop="loose")


def test_parse_json():
    import json
    w = rbsim.parse_json(json.dumps(bounce_scene()), "inline")
    assert set(w.bodies) == {"ground", "ball"}
    with pytest.raises(rbsim.SceneError) as info:
        rbsim.parse_json('{"format": 1,\n "simulation": {"steps": 3}', "trunc")
    e = info.value
    assert e.file == "trunc" and e.line == 2 and e.column > 1
    assert "truncated" in e.message or "end of input" in e.message


def test_unknown_key_error_points_at_it(write_scene):
    scene = bounce_scene()
    scene["bodies"][1]["radius_m"] = 0.2
    path = write_scene(scene)
    with pytest.raises(rbsim.SceneError) as info:
        rbsim.load(path)
    e = info.value
    assert e.file == str(path) and e.line > 1 and e.column > 1
    assert "radius_m" in e.message or "radius_m" in e.path
    assert str(path) in str(e)


def test_text_format_errors_carry_places(tmp_path):
    (tmp_path / "config.txt").write_text(
        "steps = 10\ndt = -1\nmaterials = materials.txt\nobjects = objects.txt\n")
    (tmp_path / "materials.txt").write_text("")
    (tmp_path / "objects.txt").write_text("")
    with pytest.raises(rbsim.SceneError) as info:
        rbsim.load(tmp_path / "config.txt")
    e = info.value
    assert any(x.line == 2 and x.file.endswith("config.txt") for x in e.errors)


def test_scene_renderers_are_listed_and_not_silently_dropped():
    w = rbsim.load(SCENES / "bouncing_sphere.json")
    assert w.scene_renderers and w.scene_renderers[0]["type"] == "csv"
    with pytest.warns(UserWarning, match="csv") as record:
        w.run(3)
    assert record[0].filename == __file__  # points at the caller
    w.run(3)  # warned once per world
    w2 = rbsim.load(SCENES / "bouncing_sphere.json")
    with pytest.warns(UserWarning, match="csv") as record:
        w2.start(3).wait()
    assert record[0].filename == __file__  # start() too


def test_scene_without_method_is_auto():
    """A scene that names no method gets "auto": "euler" for a few spheres,
    "soft" for a heap of 64, and loading it with method="euler" keeps
    Euler whatever the count."""
    import json

    def scene(n):
        bodies = [{"type": "plane", "name": "floor", "normal": [0, 0, 1], "point": [0, 0, 0]}]
        bodies += [{"type": "sphere", "name": "s%d" % i, "radius": 0.05, "mass": 0.1,
                    "position": [0.11 * (i % 8), 0.11 * (i // 8 % 8), 0.06 + 0.11 * (i // 64)]}
                   for i in range(n)]
        return json.dumps({"simulation": {"steps": 10, "dt": 0.001}, "bodies": bodies,
                           "materials": [{"pair": ["*", "*"], "static": 0.5, "kinetic": 0.4}]})

    few, heap = rbsim.parse_json(scene(3)), rbsim.parse_json(scene(64))
    assert few.method == heap.method == "auto"
    assert few.method_in_use == "euler" and heap.method_in_use == "soft"
    assert rbsim.parse_json(scene(64), method="euler").method_in_use == "euler"
    heap.step(10)


def test_max_substeps_from_json_and_config_txt(write_scene, tmp_path):
    """simulation.max_substeps (config.txt: max_substeps = N) sets the work
    cap; the scene format had no key for it."""
    scene = bounce_scene()
    assert rbsim.load(write_scene(scene)).settings["max_substeps"] == 4096
    scene["simulation"]["max_substeps"] = 100
    assert rbsim.load(write_scene(scene)).settings["max_substeps"] == 100
    (tmp_path / "objects.txt").write_text("sphere ball\n  radius 0.1\n  mass 1\n"
                                          "  position 0 0 1\n")
    config = write_scene("format = 1\nsteps = 10\nmax_substeps = 77\nobjects = objects.txt\n",
                         name="config.txt")
    assert rbsim.load(config).settings["max_substeps"] == 77
    for bad in (0, 2 ** 32, 1.5):
        scene["simulation"]["max_substeps"] = bad
        with pytest.raises(rbsim.SceneError,
                           match=r"simulation\.max_substeps: must be an integer from 1 to "
                                 r"4294967295 \(2\^32 - 1\), got"):
            rbsim.load(write_scene(scene))


def test_a_material_on_no_body_warns(write_scene):
    # A row naming a material no body has ("stel", a typo of "steel") left
    # the ball to the "*" row without a word (a probe of session 50): load()
    # now warns with the library's text, a rbsim.SceneWarning (a
    # UserWarning) pointing at the caller, and builds the world all the same.
    scene = bounce_scene()
    scene["materials"] = [{"pair": ["steel", "*"], "static": 0.9, "kinetic": 0.8},
                          {"pair": ["stel", "*"], "static": 0.1, "kinetic": 0.1},
                          {"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3}]
    scene["bodies"][0]["material"] = "steel"
    path = write_scene(scene)
    with pytest.warns(rbsim.SceneWarning) as caught:
        w = rbsim.load(path)
    assert len(caught) == 1
    text = str(caught[0].message)
    assert text.startswith(str(path) + ":") and text.endswith(
        ': materials[1].pair[0]: material "stel" is on no body, so this row applies to no '
        'contact (did you mean "steel"?)'), text
    assert caught[0].filename == __file__
    assert issubclass(rbsim.SceneWarning, UserWarning) and "SceneWarning" in rbsim.__all__
    assert [m.name for m in w.materials()] == ["steel", "stel"]
    with pytest.warns(rbsim.SceneWarning):
        rbsim.parse_json(json.dumps(scene))
    # every material on a body: no warning
    scene["materials"].pop(1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rbsim.load(write_scene(scene, "fine.json"))
