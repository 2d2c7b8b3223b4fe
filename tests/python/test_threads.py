"""The GIL is released while C steps: two worlds step in two threads.

The proof does not rest on timing.  A worker thread makes ONE C call that
steps world A until a stop flag (read by C every step) is set.  While that
call is still running, the main thread runs Python, steps world B, sees A's
step counter (written by C) advance, and only then sets the flag.  If the
GIL were held during the C call, the main thread could not run until the
call returned by itself -- after 10^8 steps, so the checks `worker still
inside the call` and `done < n` would fail.
"""

import threading
import time

import numpy as np

import rbsim
from rbsim._native import ffi, lib


def make_world(z=1.0):
    w = rbsim.World(dt=0.0005, restitution=0.7)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, z), velocity=(0.2, 0.0, 0.0))
    w.add_sphere("other", radius=0.1, position=(0.5, 0.0, z + 0.3))
    return w


def wait_for(predicate, what, seconds=60.0):
    deadline = time.monotonic() + seconds
    while not predicate():
        assert time.monotonic() < deadline, "timed out waiting for " + what
        time.sleep(0.001)


def test_a_c_call_runs_while_python_runs_in_another_thread():
    a, b = make_world(), make_world(2.0)
    n = 10 ** 8
    stop = ffi.new("int32_t *", 0)
    done = ffi.new("uint64_t *", 0)
    info = ffi.new("rbs_step_info *")
    result = {}
    cworld = a._acquire()  # hold A's lock as World.step would

    def worker():
        result["status"] = lib.rbs_py_step(cworld, n, info, done, stop)
        result["done"] = int(done[0])

    t = threading.Thread(target=worker)
    t.start()
    try:
        wait_for(lambda: done[0] > 0, "the worker to start stepping")
        first = int(done[0])
        b.step(2000)  # Python and C on this thread while A's call runs
        assert b.step_count == 2000
        wait_for(lambda: done[0] > first + 100, "A to advance meanwhile")
        assert t.is_alive() and "status" not in result  # still in one C call
    finally:
        stop[0] = 1
        t.join(120)
        a._lock.release()
    assert not t.is_alive()
    assert result["status"] == lib.RBS_OK
    assert first < result["done"] < n
    assert a.step_count == result["done"]


def test_two_threads_step_two_worlds_to_the_sequential_result():
    steps = 20000
    ref = [make_world(), make_world(2.0)]
    for w in ref:
        w.step(steps)
    worlds = [make_world(), make_world(2.0)]
    progress = [[], []]
    errors = []

    def work(i):
        try:
            for _ in range(steps // 500):
                worlds[i].step(500)
                progress[i].append(worlds[i].step_count)
        except BaseException as e:  # reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not errors
    assert all(not t.is_alive() for t in threads)
    for i in range(2):
        assert progress[i] == list(range(500, steps + 1, 500))
        assert worlds[i].hash() == ref[i].hash()
        assert np.array_equal(worlds[i].positions, ref[i].positions)


def test_runs_of_two_worlds_in_two_threads():
    frames = [[], []]
    worlds = [make_world(), make_world(2.0)]
    errors = []

    def work(i):
        try:
            worlds[i].run(3000, renderers=[lambda f: frames[i].append(f.number)])
        except BaseException as e:
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not errors
    assert frames[0] == frames[1] == list(range(3001))


def test_one_world_from_two_threads_is_refused_not_corrupted():
    w = make_world()
    run = w.start(10 ** 9, renderers=[])  # the simulation thread owns w now
    errors = []

    def meddle():
        try:
            w.bodies["ball"].velocity = (1.0, 0.0, 0.0)
        except rbsim.BusyError as e:
            errors.append(e)

    t = threading.Thread(target=meddle)
    t.start()
    t.join(60)
    run.command("quit")
    info = run.wait()  # a quit is a clean end
    assert info.quit and info.state == "done"
    assert len(errors) == 1
    w.step()
