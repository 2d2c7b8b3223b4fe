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
import pytest

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


def make_pile(**kw):
    """640 spheres on a lattice over a floor, the soft method: enough for
    its gathered step to cut the pile into slabs that threads share."""
    w = rbsim.World(max_bodies=700, max_contacts=8000, method="soft", **kw)
    w.add_plane("floor")
    for k in range(640):
        i, j, l = k % 8, (k // 8) % 8, k // 64
        w.add_sphere(radius=0.05, mass=0.1,
                     position=(0.11 * i + 0.002 * (l % 3), 0.11 * j, 0.06 + 0.11 * l))
    return w


def test_world_threads_give_the_same_bits():
    """World(threads=N) and World.threads = N lend the world a pool: the
    pile steps to the same bits on 1, 2 and 3 threads (the library's
    promise: the shares a thread takes never change the order of the
    arithmetic)."""
    one = make_pile()
    assert one.threads == 1
    one.step(150)
    three = make_pile(threads=3)
    assert three.threads == 3
    three.step(150)
    two = make_pile()
    two.step(75)
    two.threads = 2          # a pool lent between steps
    assert two.threads == 2
    two.step(50)
    two.threads = 1          # and taken back
    assert two.threads == 1
    two.step(25)
    assert one.step_count == three.step_count == two.step_count == 150
    for w in (three, two):
        assert np.array_equal(one.positions, w.positions)
        assert np.array_equal(one.velocities, w.velocities)
        assert np.array_equal(one.orientations, w.orientations)
    # the pile moved and touched: the comparison is of a real run
    assert one.positions[1:, 2].min() < 0.06
    for w in (one, two, three):
        w.close()


def test_world_threads_bad_values():
    w = make_world()
    for bad in (0, 17, -1):
        with pytest.raises(rbsim.InvalidError, match=r"threads: must be in \[1, 16\]"):
            w.threads = bad
    for bad in ("2", 2.0, True, None):
        with pytest.raises(rbsim.ArgumentTypeError, match="threads: expected an integer"):
            w.threads = bad
    with pytest.raises(rbsim.InvalidError, match="threads"):
        rbsim.World(threads=0)
    assert w.threads == 1     # a refused value changed nothing
    w.threads = 4
    w.step(10)
    w.close()                 # the pool goes with the world
    with pytest.raises(rbsim.ClosedError):
        w.threads


_WAIT_FROM_THREE = r"""
import threading, rbsim
for it in range(30):
    w = rbsim.World(max_bodies=4)
    w.add_sphere(position=(0, 0, 1))
    run = w.start(50, [lambda f: None])
    got = []
    def waiter():
        got.append(run.wait().frame)
    ts = [threading.Thread(target=waiter) for k in range(3)]
    for t in ts: t.start()
    for t in ts: t.join()
    assert got == [50, 50, 50], got
print("ok")
"""


def test_wait_from_three_threads_gives_each_the_end():
    """Run.wait() from three threads at once: one waits on the projector,
    the others get its RunInfo.  (Two inside rbs_projector_wait joined the
    run's threads twice and hung within two runs: a probe of session 40.)
    In a child with a timeout, so a regression fails instead of hanging."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _WAIT_FROM_THREE],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout == "ok\n"


_RUN_NOT_WAITED = r"""
import time, rbsim
w = rbsim.World()
w.add_sphere(position=(0, 0, 1))
w._run_kept = w.start(10, [lambda f: None])  # (a cycle: the world holds its run)
time.sleep(0.3)
try:
    w.step()
except rbsim.BusyError as e:
    print(e)
"""


def test_a_run_not_waited_on():
    """A run never waited on holds its world: the BusyError says so (it
    blamed another thread), and at exit the world, in a reference cycle
    with its run, is left to the run: destroyed first, it had the projector
    write into freed memory ("free(): corrupted unsorted chunks", abort) --
    a probe of session 40."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _RUN_NOT_WAITED],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout == ("world is held by a run until its Run.wait() (or from inside that "
                          "run's renderer): call wait() on the Run that start() returned\n")


_LEFT_RUNNING = r"""
import sys, rbsim
kind = sys.argv[1]
if kind == "raise":
    w = rbsim.World(); w.add_plane(); w.add_sphere("b", position=(0, 0, 1))
    frames = []
    run = w.start(100000, renderers=[frames.append])
    raise RuntimeError("user code fails before run.wait()")
if kind == "paused-and-endless":
    a = rbsim.World(); a.add_sphere(position=(0, 0, 1))
    b = rbsim.World(); b.add_sphere(position=(0, 0, 1))
    runs = [a.start(100000, [lambda f: None], start_paused=True),
            b.start(endless=True, renderers=[lambda f: None])]
    print("end of script", flush=True)
if kind == "with":
    with rbsim.World() as w:
        w.add_sphere("b", position=(0, 0, 1))
        run = w.start(100000, renderers=[lambda f: None])
        raise ValueError("original error")
"""


@pytest.mark.parametrize("kind", ["raise", "paused-and-endless", "with"])
def test_runs_never_waited_on_end_at_exit(kind):
    """A script that ends (or raises) with a run of Python renderers never
    waited on exits at once: the interpreter never did (Run.__del__ joined
    a renderer thread that could no longer take the GIL, and Ctrl-C did
    not help: a probe of session 41).  An at-exit hook quits and waits for
    such runs and says so; World.close() in `with` says a run holds the
    world (it blamed another thread)."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _LEFT_RUNNING, kind],
                         capture_output=True, text=True, timeout=60)
    note = "rbsim: a run never waited on was stopped at exit, at frame "
    assert out.stderr.count(note) == (2 if kind == "paused-and-endless" else 1), out.stderr
    assert "(call Run.wait() before the end)" in out.stderr
    if kind == "raise":
        assert out.returncode == 1 and "RuntimeError: user code fails" in out.stderr
        assert " of 100000 " in out.stderr
    elif kind == "with":
        assert out.returncode == 1 and "ValueError: original error" in out.stderr
        assert ("BusyError: cannot close the world: world is held by a run until its "
                "Run.wait()") in out.stderr
    else:
        assert out.returncode == 0 and out.stdout == "end of script\n", out.stderr
        assert "frame 0 of 100000" in out.stderr


_BLOCKED_RENDERER = r"""
import time, rbsim
w = rbsim.World(); w.add_plane(); w.add_sphere("b", position=(0, 0, 1))
def draw(frame):
    if frame.number == 3:
        print("renderer blocks", flush=True)
        time.sleep(1000)
run = w.start(100, renderers=[draw])
time.sleep(0.2)
print("end of script", flush=True)
"""


def test_ctrl_c_at_exit_ends_a_blocked_run():
    """A run whose renderer never returns keeps the at-exit hook waiting;
    Ctrl-C then ends the process at once (it never did: the main thread
    sat in pthread_join under Run.__del__)."""
    import signal
    import subprocess
    import sys
    import time
    child = subprocess.Popen([sys.executable, "-c", _BLOCKED_RENDERER],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline() == "renderer blocks\n"
        assert child.stdout.readline() == "end of script\n"
        time.sleep(0.5)  # (in the hook now)
        child.send_signal(signal.SIGINT)
        child.wait(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    err = child.stderr.read()
    assert "rbsim: Ctrl-C: no longer waiting at exit for runs never waited on" in err, err
