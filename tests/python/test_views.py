"""The state arrays are zero-copy, read-only views of the world's memory."""

import gc

import numpy as np
import pytest

import rbsim


def address(a):
    return a.__array_interface__["data"][0]


def make_world():
    w = rbsim.World(dt=0.001)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 1.0),
                 velocity=(0.25, 0.0, 0.0), angular_velocity=(0.0, 0.0, 2.0))
    return w


@pytest.mark.parametrize("name,cols", [("positions", 3), ("velocities", 3),
                                       ("angular_velocities", 3),
                                       ("orientations", 4)])
def test_shape_dtype_and_read_only(name, cols):
    w = make_world()
    a = getattr(w, name)
    assert a.dtype == np.float64 and a.shape == (2, cols)
    assert a.flags.c_contiguous and not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0] = 1.0
    with pytest.raises(ValueError):
        a.setflags(write=True)
    with pytest.raises(ValueError):
        a.base.setflags(write=True)


def test_a_view_reflects_a_step_without_copying():
    w = make_world()
    p, v, q, wv = w.positions, w.velocities, w.orientations, w.angular_velocities
    before = p.copy(), v.copy(), q.copy()
    addr = address(p), address(v), address(q), address(wv)
    w.step(10)
    # The same arrays (no new object, no copy) now show the new state...
    assert address(p) == addr[0] and address(v) == addr[1]
    assert address(q) == addr[2] and address(wv) == addr[3]
    assert p[1, 2] < before[0][1, 2] and p[1, 0] > 0.0
    assert v[1, 2] < 0.0
    assert not np.array_equal(q[1], before[2][1])  # spinning about z
    # ...equal to what a fresh call and the body's getters say.
    assert address(w.positions) == addr[0]
    assert np.array_equal(p[1], w.bodies["ball"].position)
    assert np.array_equal(v[1], w.bodies["ball"].velocity)
    assert np.shares_memory(p, w.positions)


def test_rows_are_slots_and_setters_show_through():
    w = make_world()
    ball = w.bodies["ball"]
    p = w.positions
    ball.position = (3.0, 2.0, 1.0)
    assert p[ball.slot].tolist() == [3.0, 2.0, 1.0]
    assert w.types.tolist() == [2, 1]
    assert w.orientations[0].tolist() == [1.0, 0.0, 0.0, 0.0]


def test_removed_slot_reads_zero_and_new_bodies_need_a_new_view():
    w = make_world()
    p = w.positions
    w.bodies["ball"].remove()
    assert w.types.tolist() == [2, 0]
    assert w.positions[1].tolist() == [0.0, 0.0, 0.0]
    w.add_sphere("a", position=(0, 0, 5))
    w.add_sphere("b", position=(0, 0, 7))
    assert p.shape == (2, 3)  # taken before: still 2 rows
    assert w.positions.shape == (3, 3)
    assert w.positions[2].tolist() == [0.0, 0.0, 7.0]


def test_views_outlive_the_world_safely():
    w = make_world()
    w.step(5)
    p = w.positions
    last = p.copy()
    w.close()
    assert np.array_equal(p, last)  # memory still owned by the view
    w = make_world()
    p = w.positions
    del w
    gc.collect()
    assert p.shape == (2, 3) and p[1, 2] == 1.0
