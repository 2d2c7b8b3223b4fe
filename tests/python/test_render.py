"""Python renderers through the projector: every frame, in order, with the
state; exceptions stop the run and come out of world.run()."""

import threading

import numpy as np
import pytest

import rbsim


def make_world(dt=0.001):
    w = rbsim.World(dt=dt, restitution=0.8)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 0.5),
                 velocity=(0.3, 0.0, 0.0))
    w.add_sphere(radius=0.05, position=(1.0, 0.0, 0.2))  # unnamed
    return w


class Recorder:
    def __init__(self, every=1):
        self.every = every
        self.frames = []
        self.finished = 0
        self.closed = 0
        self.threads = set()

    def draw(self, frame):
        self.threads.add(threading.get_ident())
        self.frames.append(frame)

    def finish(self):
        self.finished += 1

    def close(self):
        self.closed += 1


def test_a_renderer_sees_every_frame_with_the_state():
    steps = 600
    w = make_world()
    rec = Recorder()
    info = w.run(steps, renderers=[rec])
    assert [f.number for f in rec.frames] == list(range(steps + 1))
    assert info.drawn == steps + 1 and info.captured == steps + 1
    assert rec.finished == 1 and rec.closed == 1
    assert rec.frames[-1].last and not any(f.last for f in rec.frames[:-1])
    assert threading.get_ident() not in rec.threads  # the renderer thread
    # Each frame equals the state of a twin world stepped by hand, bit for bit.
    twin = make_world()
    for f in rec.frames:
        assert f.time == twin.time
        assert f.names == ("ground", "ball", "")
        assert f.slots.tolist() == [0, 1, 2] and f.types.tolist() == [2, 1, 1]
        assert f.positions.shape == (3, 3) and f.orientations.shape == (3, 4)
        assert np.array_equal(f.positions, twin.positions)
        assert np.array_equal(f.velocities, twin.velocities)
        assert np.array_equal(f.angular_velocities, twin.angular_velocities)
        assert np.array_equal(f.orientations, twin.orientations)
        e = twin.energy()
        assert f.energy == e
        assert np.array_equal(f.momentum.linear, twin.momentum().linear)
        if f.number < steps:
            twin.step()
    assert w.hash() == twin.hash()
    assert rec.frames[0].radii.tolist() == [0.0, 0.1, 0.05]
    assert rec.frames[0].normals[0].tolist() == [0.0, 0.0, 1.0]


def test_frames_are_copies():
    w = make_world()
    frames = []
    w.run(50, renderers=[frames.append])
    z = [f.positions[1, 2] for f in frames]
    assert len(set(z)) > 40  # not all the same reused slot
    assert all(f.positions.flags.owndata or f.positions.base is not None
               for f in frames)


def test_every_keeps_every_kth_and_the_last():
    w = make_world()
    a, b, c = Recorder(every=7), Recorder(), Recorder(every=100)
    w.run(50, renderers=[a, b, c])
    assert [f.number for f in a.frames] == list(range(0, 50, 7)) + [50]
    assert [f.number for f in b.frames] == list(range(51))
    assert [f.number for f in c.frames] == [0, 50]


def test_every_out_of_range_is_refused_up_front():
    """every is 1 to 2147483647 (RBS_EVERY_MAX): every=0 said "[1,
    4294967295]" while 2**31 failed later with "python0 renderer: every
    must be from 1 to 2147483647 (0 means 1)", an internal name and another
    range; both ends are taken."""
    w = make_world()
    for bad in (0, -1, 2 ** 31, 2 ** 32 - 1, 2 ** 32, 2 ** 64):
        with pytest.raises(rbsim.InvalidError) as info:
            w.run(3, renderers=[Recorder(), Recorder(every=bad)])
        assert str(info.value) == ("invalid argument: renderers[1].every: must be in "
                                   "[1, 2147483647], got %d" % bad)
    assert w.step_count == 0
    a, b = Recorder(every=1), Recorder(every=2 ** 31 - 1)
    w.run(3, renderers=[a, b])
    assert [f.number for f in a.frames] == [0, 1, 2, 3]
    assert [f.number for f in b.frames] == [0, 3]


def test_a_single_renderer_not_in_a_list_is_refused():
    # renderers=print was wrapped in a list quietly; the API takes a list,
    # so a single renderer is a TypeError naming renderers (session 47).
    w = make_world()

    class Drawer:
        def draw(self, frame):
            pass

    for single in (print, Drawer(), lambda f: None):
        for call in (w.run, w.start):
            with pytest.raises(TypeError) as info:
                call(3, renderers=single)
            assert isinstance(info.value, rbsim.ArgumentTypeError)
            assert str(info.value).startswith(
                "renderers: expected a list of renderers, got a single renderer ")
            assert "pass a list, renderers=[...]" in str(info.value)
        with pytest.raises(TypeError) as info:
            rbsim.Run(w, 3, single, False, 1.0, False, False, None, False)
        assert "renderers: expected a list" in str(info.value)
    with pytest.raises(TypeError) as info:
        w.run(3, renderers=3)
    assert str(info.value) == "renderers: expected a list of renderers, got int 3"
    assert w.step_count == 0
    w.run(3, renderers=(print,) * 0)


def test_a_plain_callable_and_four_renderers():
    w = make_world()
    seen = [[] for _ in range(4)]
    renderers = [lambda f, i=i: seen[i].append(f.number) for i in range(4)]
    w.run(20, renderers=renderers)
    assert all(s == list(range(21)) for s in seen)


def test_an_exception_stops_the_run_and_propagates():
    w = make_world()
    boom = ValueError("boom at frame 30")
    seen = []
    other = Recorder()

    def bad(frame):
        seen.append(frame.number)
        if frame.number == 30:
            raise boom

    with pytest.raises(ValueError) as info:
        w.run(100000, renderers=[bad, other])
    assert info.value is boom
    assert seen == list(range(31))
    # The run stopped early: far fewer than 100000 steps were made.
    assert w.step_count < 100000
    assert other.finished == 1 and other.closed == 1  # outputs finished
    w.step()  # the world is usable again


def test_an_exception_in_finish_propagates():
    class BadFinish(Recorder):
        def finish(self):
            raise RuntimeError("cannot flush")

    with pytest.raises(RuntimeError, match="cannot flush"):
        make_world().run(5, renderers=[BadFinish()])


def test_keyboard_interrupt_in_a_renderer_propagates():
    def interrupt(frame):
        if frame.number == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        make_world().run(1000, renderers=[interrupt])


def test_stop_run_ends_cleanly():
    w = make_world()
    seen = []

    def until(frame):
        seen.append(frame.number)
        if frame.number == 25:
            raise rbsim.StopRun

    # (steps with endless=True were ignored, silently: a probe of session 46)
    with pytest.raises(rbsim.InvalidError, match=r"steps: 10 with endless=True, which "
                       r"runs until quit or StopRun and would ignore it"):
        w.run(10, endless=True, renderers=[until])
    assert seen == [] and w.step_count == 0
    info = w.run(endless=True, renderers=[until])
    # That renderer gets no frame after StopRun; frames already made still
    # go through the reel (to other renderers) before the run ends.
    assert seen == list(range(26))
    assert info.endless and info.quit and info.state == "done"
    assert info.frame >= 25 and w.step_count >= info.frame
    # endless given as 1 or numpy's True is the flag too: with steps it was
    # not refused (the check read "endless is True") and the run went on
    # past them; without, "steps: required" (a probe of session 50)
    def five(frame):
        # (stops any run after 5 frames: a regression fails, never hangs)
        seen.append(frame.number)
        if len(seen) == 6:
            raise rbsim.StopRun

    for flag in (1, np.True_):
        seen.clear()
        with pytest.raises(rbsim.InvalidError, match=r"steps: 10 with endless=True"):
            w.run(10, endless=flag, renderers=[five])
    seen.clear()
    start = w.step_count
    info = w.run(endless=np.True_, renderers=[five])
    assert info.endless and info.quit and seen[:6] == list(range(start, start + 6))
    with pytest.raises(rbsim.ArgumentTypeError, match="endless: expected True or False"):
        w.run(endless=2)


def test_stop_run_others_get_every_frame_made():
    # The world ends at the last frame made, which may be after the frame
    # that raised StopRun; a second renderer gets every frame up to it.
    w = make_world()
    rec = []

    class Stopper:
        def draw(self, frame):
            if frame.number == 5:
                raise rbsim.StopRun

    info = w.run(1000, renderers=[Stopper(), lambda f: rec.append(f.number)],
                 reel_capacity=8)
    assert info.quit and info.state == "done"
    assert rec == list(range(info.frame + 1))
    assert 5 <= info.frame <= 5 + 8 + 1
    assert w.step_count == info.frame


def test_stop_run_from_finish_or_close_changes_nothing():
    class Late:
        def __init__(self):
            self.frames = 0

        def draw(self, frame):
            self.frames += 1

        def finish(self):
            raise rbsim.StopRun

        def close(self):
            raise rbsim.StopRun

    late = Late()
    w = make_world()
    info = w.run(10, renderers=[late])
    assert late.frames == 11 and not info.quit and w.step_count == 10


def test_commands_from_threads_while_wait_ends_the_run():
    # Run.command is thread-safe: from other threads while wait() ends the
    # run and frees the projector, each command answers or raises
    # ClosedError (the projector was freed under a command in flight: a
    # hang within ~1000 runs, or a crash).
    import threading
    w = make_world()
    closed = [0]
    for _ in range(2000):
        run = w.start(0, renderers=[lambda f: None])
        stop = threading.Event()

        def hammer():
            while not stop.is_set():
                try:
                    run.command("status")
                except rbsim.ClosedError:
                    closed[0] += 1

        threads = [threading.Thread(target=hammer) for _ in range(3)]
        for t in threads:
            t.start()
        run.wait()
        stop.set()
        for t in threads:
            t.join(timeout=10)
            assert not t.is_alive()
    assert closed[0] > 0


def test_pause_after_the_end_says_the_run_is_over():
    # Before wait(), a finished run takes no pause or resume (it answered
    # "paused at frame 20"); status still answers.
    w = make_world()
    run = w.start(20, renderers=[lambda f: None])
    assert run.finished(30.0)
    for word in ("pause", "resume"):
        with pytest.raises(rbsim.ClosedError, match="the run is over"):
            run.command(word)
    assert "frame 20 of 20" in run.command("status")
    run.wait()


def test_steps_zero_gives_frame_zero_only():
    frames = []
    make_world().run(0, renderers=[frames.append])
    assert [f.number for f in frames] == [0]


def test_no_renderers():
    w = make_world()
    info = w.run(10)
    assert w.step_count == 10 and info.steps == 10


def test_run_without_steps_needs_a_scene():
    with pytest.raises(rbsim.InvalidError, match="steps"):
        make_world().run()


def test_start_with_commands():
    w = make_world()
    rec = Recorder()
    run = w.start(1000, renderers=[rec], start_paused=True)
    with pytest.raises(rbsim.BusyError):
        w.step()  # the world belongs to the simulation thread now
    assert run.status().state == "running" and not run.finished(0)
    while not run.status().paused:
        run.finished(0.01)
    assert run.status().captured == 1  # paused after frame 0
    # run.paused = False and run.speed = 2 made Python attributes the
    # projector never read, a silent no-op (a probe of session 46)
    for name, value in [("paused", False), ("speed", 2.0)]:
        with pytest.raises(AttributeError, match=r"Run has no settable attribute %r: "
                           r"steer a run with command" % name):
            setattr(run, name, value)
    assert run.status().paused and run.status().captured == 1
    with pytest.raises(rbsim.InvalidError, match=r"timeout: must be >= 0 seconds, got -1"):
        run.finished(-1)  # (it was taken as 0, silently)
    run.command("step 4")
    while run.status().captured < 5:
        run.finished(0.01)
    assert run.status().paused and run.status().captured == 5
    assert run.command("status")
    run.command("resume")
    info = run.wait()
    assert [f.number for f in rec.frames] == list(range(1001))
    assert info.drawn == 1001
    with pytest.raises(rbsim.ClosedError):
        run.command("pause")
    # status() after wait() is the final snapshot (it raised ClosedError)
    assert run.status() == info and run.status().state == "done"
    w.step()


def test_status_after_a_failed_run_is_its_final_state():
    # A run whose renderer failed: wait() raises, status() then says how it
    # ended (it raised ClosedError).
    w = make_world()

    def bad(frame):
        if frame.number == 3:
            raise ValueError("boom")

    run = w.start(10, renderers=[bad])
    with pytest.raises(ValueError):
        run.wait()
    info = run.status()
    assert info.state == "done" and info.drawn == 3


def test_frame_step_info():
    w = rbsim.World(dt=0.001, restitution=1.0)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0, 0, 0.1005),
                 velocity=(0, 0, -1.0))
    frames = []
    w.run(20, renderers=[frames.append])
    assert sum(f.step.colliding for f in frames) >= 1
    # the run's first frame is the world as it stood, made by no step
    # (it said steps=1 with every counter 0); each later one by one step
    assert frames[0].step.steps == 0 and frames[0].step.substeps == 0
    assert all(f.step.steps == 1 and f.step.substeps >= 1 for f in frames[1:])
    later = []
    w.run(3, renderers=[later.append])
    assert [f.number for f in later] == [20, 21, 22, 23]
    assert [f.step.steps for f in later] == [0, 1, 1, 1]


def test_ctrl_c_during_a_run_stops_it_and_propagates():
    import _thread
    w = make_world()
    seen = []
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            w.run(endless=True, renderers=[lambda f: seen.append(f.number)])
    finally:
        timer.cancel()
    assert len(seen) > 1
    w.step()  # the run is over and the world usable
    assert "busy" not in repr(w)


def test_repr_never_raises_during_a_run():
    w = make_world()
    reprs = []
    w.run(3, renderers=[lambda f: reprs.append(repr(w))])
    assert reprs and all("busy" in r for r in reprs)


def test_speed_needs_realtime():
    """speed= sets the pace of realtime=True; without it a run goes as fast
    as it can, so a speed other than 1 is refused, as the command line's
    --speed without --realtime is (before session 38 it was taken and did
    nothing)."""
    w = rbsim.World()
    w.add_sphere("b", position=(0.0, 0.0, 1.0))
    with pytest.raises(rbsim.InvalidError, match="realtime"):
        w.run(5, speed=2.0)
    assert w.step_count == 0
    assert w.run(5, speed=1.0).steps == 5          # the default: no pace asked for
    assert w.run(5, speed=50.0, realtime=True).steps == 5


_WAIT_FROM_RENDERER = r"""
import json, threading, rbsim
ready = threading.Event()  # (run is set: draw may reach frame 5 before start returns)
w = rbsim.World(dt=0.001, restitution=0.8)
w.add_plane("ground")
w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 0.5))
seen, calls = [], {}

def attempt(where, name, call):
    try:
        calls[where + " " + name] = "returned %r" % (call(),)
    except rbsim.Error as e:
        calls[where + " " + name] = "%s: %s" % (type(e).__name__, e)

class Waiter:
    def draw(self, frame):
        seen.append(frame.number)
        if frame.number == 5:
            ready.wait()
            attempt("draw", "wait", run.wait)
            attempt("draw", "finished3", lambda: run.finished(3.0))
            attempt("draw", "finished0", lambda: run.finished(0))
            attempt("draw", "status", lambda: run.status().state)
    def finish(self):
        ready.wait()
        attempt("finish", "wait", run.wait)
        attempt("finish", "finished1", lambda: run.finished(1.0))
    def close(self):
        attempt("close", "wait", run.wait)

run = w.start(50, renderers=[Waiter()])
ready.set()
info = run.wait()
w.step()  # the world is free again
print(json.dumps({"seen": seen, "calls": calls, "frame": info.frame,
                  "quit": info.quit, "steps": w.step_count}))
"""


def test_wait_from_the_runs_own_renderer_raises_at_once():
    """Run.wait() (and finished(timeout)) from inside the run's own
    renderer can never see the end -- the run cannot end while its renderer
    thread is in draw() or finish() -- so it raises DeadlockError at once
    and the run goes on to its normal end.  (It hung for good: finished(3)
    waited 3 s for False, the world stayed busy and the main thread's wait()
    never returned.)  Run in a child with a timeout so a regression fails
    instead of hanging the suite.  close() runs during the main thread's
    wait(), after the run is over: wait() there is "the run is over"."""
    import json
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _WAIT_FROM_RENDERER],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert got["seen"] == list(range(51))
    assert got["frame"] == 50 and not got["quit"] and got["steps"] == 51
    why = ("from the run's own renderer (inside draw() or finish()) would never "
           "return: the run cannot end until the renderer returns; raise StopRun "
           "to end the run, and wait() from another thread")
    assert got["calls"] == {
        "draw wait": "DeadlockError: wait() " + why,
        "draw finished3": "DeadlockError: finished(3.0) " + why,
        "draw finished0": "returned False",
        "draw status": "returned 'running'",
        "finish wait": "DeadlockError: wait() " + why,
        "finish finished1": "DeadlockError: finished(1.0) " + why,
        "close wait": "ClosedError: closed or interrupted: the run is over",
    }


_WAIT_UNCAUGHT = r"""
import threading, rbsim
w = rbsim.World(dt=0.001)
w.add_sphere("ball", radius=0.1)
box = {}
ready = threading.Event()  # (box["run"] is set: draw may reach frame 5 before start returns)

def draw(frame):
    if frame.number == 5:
        ready.wait()
        box["run"].wait()

box["run"] = w.start(100000, renderers=[draw])
ready.set()
try:
    box["run"].wait()
except rbsim.DeadlockError as e:
    print("%s; steps < 100000: %s" % (str(e)[:34], w.step_count < 100000))
w.step()  # the world is usable again
"""


def test_wait_from_the_renderer_left_uncaught_stops_the_run():
    """The DeadlockError, not caught in draw(), is that renderer's exception:
    it stops the run early and the main thread's wait() raises it; the world
    is usable afterwards.  (In a child with a timeout, as above.)"""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _WAIT_UNCAUGHT],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout == "wait() from the run's own renderer; steps < 100000: True\n"
    assert issubclass(rbsim.DeadlockError, rbsim.Error)
    assert issubclass(rbsim.DeadlockError, RuntimeError)  # as Thread.join on itself


def test_frames_compare_exactly_and_are_unhashable():
    """Frame == Frame raised (its arrays' truth value): it compares every
    field exactly, and is plainly unhashable."""
    a, b = [], []
    make_world().run(3, renderers=[a.append])
    make_world().run(3, renderers=[b.append])
    assert a == b and a[1] != a[2] and a[0] != "frame"
    with pytest.raises(TypeError, match="unhashable type: 'Frame'"):
        hash(a[0])
