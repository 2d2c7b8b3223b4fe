"""Checkpoints: exact round trips, and CorruptError/VersionError for bad
data.  A restored world is library-allocated; its state views must stay
valid as long as they live, like those of a world built in Python."""

import gc
import os
import stat
import struct

import numpy as np
import pytest

import rbsim


def make_world():
    w = rbsim.World(dt=0.001, restitution=0.8)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 1.1), velocity=(0.4, 0.0, 0.0))
    w.add_sphere("other", radius=0.1, position=(0.5, 0.0, 0.3))
    return w


def test_round_trip_continues_bit_for_bit():
    w = make_world()
    w.step(400)
    data = w.checkpoint()
    r = rbsim.World.from_checkpoint(data)
    assert r.hash() == w.hash() and r.step_count == 400 and r.time == w.time
    assert set(r.bodies) == {"ground", "ball", "other"}
    assert r.settings == w.settings
    w.step(1000)
    r.step(1000)
    assert r.hash() == w.hash()
    assert np.array_equal(r.positions, w.positions)
    assert np.array_equal(r.velocities, w.velocities)


def test_save_and_restore(tmp_path):
    w = make_world()
    w.step(250)
    path = tmp_path / "world.ckpt"
    w.save(path)
    r = rbsim.World.restore(path)
    assert r.hash() == w.hash()
    with pytest.raises(rbsim.IoError) as err:
        rbsim.World.restore(tmp_path / "missing.ckpt")
    # the path once, then why ("PATH: cannot open: ...", not "PATH: PATH: ...")
    assert str(err.value).count("missing.ckpt") == 1 and "cannot open" in str(err.value)


def test_save_never_replaces_what_is_not_a_regular_file(tmp_path):
    w = make_world()
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(rbsim.IoError, match="not a regular file"):
        w.save(fifo)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)  # still the FIFO
    with pytest.raises(rbsim.IoError, match="not a regular file"):
        w.save(tmp_path)
    with pytest.raises(rbsim.IoError, match="folder does not exist"):
        w.save(tmp_path / "no" / "such.ckpt")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]  # no temporaries left


def test_save_writes_through_a_symbolic_link(tmp_path):
    w = make_world()
    w.step(10)
    target = tmp_path / "real.ckpt"
    link = tmp_path / "link.ckpt"
    link.symlink_to(target)
    w.save(link)
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert rbsim.World.restore(target).hash() == w.hash()
    dangling = tmp_path / "dangling.ckpt"
    dangling.symlink_to(tmp_path / "gone" / "x.ckpt")
    with pytest.raises(rbsim.IoError, match="folder does not exist"):
        w.save(dangling)
    assert dangling.is_symlink()


def test_save_never_replaces_the_scene_it_was_loaded_from(tmp_path):
    # world.save(path) wrote the checkpoint over the scene file the world
    # was loaded from (a probe of session 47), where rbsim run --checkpoint
    # refuses it: now an OwnInputError (RBS_E_OWN_INPUT, -15; it was an
    # InvalidError until session 50) naming the argument, through any
    # spelling or link, for a text scene's three files too; the file stays.
    root = os.path.join(os.path.dirname(__file__), "..", "..", "scenes")
    scene = tmp_path / "s.json"
    with open(os.path.join(root, "bouncing_sphere.json"), "rb") as f:
        text = f.read()
    scene.write_bytes(text)
    (tmp_path / "link.json").symlink_to(scene)
    w = rbsim.load(str(scene))
    for p in (scene, str(scene), tmp_path / "." / "s.json", tmp_path / "link.json"):
        with pytest.raises(rbsim.OwnInputError,
                           match=r"^the output is a file the input was read from: path: .* a "
                                 r"file the world's scene was "
                                 r"read from: a checkpoint there would replace the scene"):
            w.save(p)
    assert scene.read_bytes() == text
    w.save(tmp_path / "ok.ckpt")  # elsewhere, as before
    for name in ("config.txt", "materials.txt", "objects.txt"):
        with open(os.path.join(root, "pile", name), "rb") as f:
            (tmp_path / name).write_bytes(f.read())
    t = rbsim.load(str(tmp_path / "config.txt"))
    for name in ("config.txt", "materials.txt", "objects.txt"):
        before = (tmp_path / name).read_bytes()
        with pytest.raises(rbsim.OwnInputError, match="scene was read from") as info:
            t.save(tmp_path / name)
        assert not isinstance(info.value, rbsim.InvalidError)
        assert info.value.status == -15
        assert (tmp_path / name).read_bytes() == before
    # a resumed world has no scene file: it saves over its own checkpoint
    r = rbsim.resume(tmp_path / "ok.ckpt")
    r.save(tmp_path / "ok.ckpt")


def test_views_of_a_restored_world_outlive_it():
    r = rbsim.World.from_checkpoint(make_world().checkpoint())
    p = r.positions
    r.step(10)
    assert p[1, 2] < 1.1  # zero-copy: the view followed the step
    last = p.copy()
    r.close()
    del r
    gc.collect()
    assert np.array_equal(p, last)  # memory kept until the view goes


def test_corrupt_and_truncated_data():
    data = make_world().checkpoint()
    damaged = bytearray(data)
    damaged[len(damaged) // 2] ^= 0x40
    # (each with its reason, as World.restore gives it for a file)
    with pytest.raises(rbsim.CorruptError, match="checksum mismatch"):
        rbsim.World.from_checkpoint(bytes(damaged))
    with pytest.raises(rbsim.CorruptError, match="truncated: %d bytes, expected %d"
                       % (len(data) - 1, len(data))):
        rbsim.World.from_checkpoint(data[:-1])
    with pytest.raises(rbsim.CorruptError, match="shorter than a checkpoint header"):
        rbsim.World.from_checkpoint(b"")
    with pytest.raises(rbsim.CorruptError, match="bad magic"):
        rbsim.World.from_checkpoint(b"not a checkpoint at all" * 10)
    with pytest.raises(rbsim.ArgumentTypeError):
        rbsim.World.from_checkpoint("text")


def test_another_format_version(tmp_path):
    data = bytearray(make_world().checkpoint())
    # Header: magic[8], then uint32 version (native byte order).
    (version,) = struct.unpack_from("=I", data, 8)
    struct.pack_into("=I", data, 8, version + 1)
    with pytest.raises(rbsim.VersionError):
        rbsim.World.from_checkpoint(bytes(data))
    path = tmp_path / "future.ckpt"
    path.write_bytes(bytes(data))
    with pytest.raises(rbsim.VersionError, match="version"):
        rbsim.World.restore(path)


def test_explain():
    text = make_world().explain()
    assert "euler" in text and "stages" in text


def test_resume_is_restore_and_steps_on_bit_for_bit(tmp_path):
    # save() then rbsim.resume(): the resumed world and an uninterrupted one
    # take the same 1000 steps to the same bits (hash and raw arrays).
    w = make_world()
    w.step(300)
    path = tmp_path / "w.ckpt"
    w.save(path)
    assert not [p for p in tmp_path.iterdir() if ".tmp" in p.name]
    r = rbsim.resume(path)
    assert isinstance(r, rbsim.World)
    assert r.step_count == 300 and r.time == w.time and r.hash() == w.hash()
    straight = make_world()
    straight.step(1300)
    r.step(1000)
    assert r.step_count == 1300
    assert r.hash() == straight.hash()
    assert np.array_equal(r.positions, straight.positions)
    assert np.array_equal(r.velocities, straight.velocities)
    assert np.array_equal(r.orientations, straight.orientations)
    assert rbsim.resume(str(path)).hash() == rbsim.World.restore(path).hash()
    assert "resume" in rbsim.__all__ and rbsim.resume.__doc__


def test_resume_bad_files(tmp_path):
    data = make_world().checkpoint()
    cases = {"flipped": bytearray(data), "truncated": data[: len(data) // 2],
             "empty": b"", "foreign": b"frame,t,body\n" * 40}
    cases["flipped"][len(data) // 2] ^= 0x01
    for name, content in cases.items():
        p = tmp_path / (name + ".ckpt")
        p.write_bytes(bytes(content))
        with pytest.raises(rbsim.CorruptError, match=name):
            rbsim.resume(p)
    with pytest.raises(rbsim.IoError, match="missing"):
        rbsim.resume(tmp_path / "missing.ckpt")


def test_resume_a_checkpoint_of_the_command(tmp_path):
    # `rbsim run --steps 200 --checkpoint` saves the world at step 200: the
    # same as loading the scene in Python and stepping it 200 times.
    import os
    import pathlib
    import subprocess
    cli = pathlib.Path(os.environ.get("RBSIM_CLI", ""))
    if not cli.is_file():
        pytest.fail("RBSIM_CLI does not name the built rbsim command")
    scene = pathlib.Path(os.environ["RBSIM_SOURCE_DIR"]) / "scenes" / "bouncing_sphere.json"
    (tmp_path / "out").mkdir()  # the scene's own renderers write there
    r = subprocess.run([str(cli), "run", str(scene), "--steps", "200",
                        "--checkpoint", "c.ckpt", "--quiet"], cwd=tmp_path,
                       stdin=subprocess.DEVNULL, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    resumed = rbsim.resume(tmp_path / "c.ckpt")
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        w = rbsim.load(scene)
    w.step(200)
    assert resumed.step_count == 200 and resumed.hash() == w.hash()
    resumed.step(300)
    w.step(300)
    assert resumed.hash() == w.hash()


def test_an_unnamed_body_round_trips_and_a_scene_resume_names_it(write_scene, tmp_path):
    # A body added without a name (None or "": no scene file can hold one)
    # is kept by save() and checkpoint(), unnamed, in its slot; a scene
    # cannot be resumed from that checkpoint, and the command says which
    # slot and why ("an unnamed sphere"; it read "sphere ''": a probe of
    # session 50).
    import subprocess
    from test_cli_agreement import cli_path
    scene = {"format": 1, "simulation": {"dt": 0.001, "steps": 100},
             "materials": [{"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3}],
             "bodies": [{"name": "a", "type": "sphere", "radius": 0.1, "mass": 1,
                         "position": [0, 0, 1]},
                        {"name": "floor", "type": "plane", "point": [0, 0, 0],
                         "normal": [0, 0, 1]}]}
    path = write_scene(scene)
    w = rbsim.load(path)
    settings = dict(w.settings)
    del settings["gravity_mode"]
    u = rbsim.World(**settings)
    u.set_material("*", "*", static=0.5, kinetic=0.3)
    u.add_sphere(radius=0.1, mass=1, position=(0, 0, 1))
    u.add_plane("floor", point=(0, 0, 0), normal=(0, 0, 1))
    u.step(10)
    u.save(tmp_path / "u.ck")
    r = rbsim.resume(tmp_path / "u.ck")
    assert [b.name for b in r.all_bodies()] == ["", "floor"]
    assert r.hash() == u.hash() and list(r.bodies) == ["floor"]
    out = subprocess.run([str(cli_path()), "run", str(path), "--resume", str(tmp_path / "u.ck"),
                          "--quiet"], cwd=tmp_path, stdin=subprocess.DEVNULL,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 3, out.stderr
    assert ("body slot 0: the scene has sphere 'a', the checkpoint an unnamed sphere"
            in out.stderr), out.stderr
    # the scene's own world, saved, resumes (the refusal is the name's)
    w.step(10)
    w.save(tmp_path / "n.ck")
    out = subprocess.run([str(cli_path()), "run", str(path), "--resume", str(tmp_path / "n.ck"),
                          "--quiet"], cwd=tmp_path, stdin=subprocess.DEVNULL,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
