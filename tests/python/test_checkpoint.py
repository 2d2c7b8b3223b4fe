"""Checkpoints: exact round trips, and CorruptError/VersionError for bad
data.  A restored world is library-allocated; its state views must stay
valid as long as they live, like those of a world built in Python."""

import gc
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
    with pytest.raises(rbsim.IoError):
        rbsim.World.restore(tmp_path / "missing.ckpt")


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
    with pytest.raises(rbsim.CorruptError):
        rbsim.World.from_checkpoint(bytes(damaged))
    with pytest.raises(rbsim.CorruptError):
        rbsim.World.from_checkpoint(data[:-1])
    with pytest.raises(rbsim.CorruptError):
        rbsim.World.from_checkpoint(b"")
    with pytest.raises(rbsim.CorruptError):
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
