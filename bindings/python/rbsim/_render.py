"""Python renderers and runs through the projector.

Design notes
------------
A Python renderer is a callable ``f(frame)`` or an object with ``draw(frame)``
and optionally ``finish()`` (after the last frame), ``close()`` (always, at
the end), ``every`` (keep every K-th frame and the last, 1 to 2147483647; default 1) and
``live`` (True: a live view that may miss frames; default False, a recorder
that sees every frame in order).

Each renderer of a run is registered in a fresh registry as its own type
(``python0``, ``python1``, ...) whose context is a cffi handle to an adapter;
the C callbacks below (``@ffi.def_extern``) run on the projector's renderer
thread and take the GIL, which the main thread released while it waits in C.
A renderer may end the run early and cleanly by raising :class:`StopRun`
from draw() (the projector's "quit": every output is finished; that renderer
gets no further frames).  The simulation runs ahead of the renderers by up
to the reel's frames, so the world ends at the last frame made (RunInfo's
``frame``), which the other renderers still get, not at the frame that
raised StopRun.  StopRun from finish() or close(), when no frame is left,
changes nothing: the run ends as it would have.
Blocking on the run from its own renderer (:meth:`Run.wait`, or
:meth:`Run.finished` with a timeout, inside draw() or finish()) could never
see the end: the run cannot end while its renderer thread is inside a
callback.  The adapter marks the thread while it is inside one, and those
calls raise :class:`~rbsim.DeadlockError` there at once instead of hanging
the run, its world and the main thread's wait().
The frame slot is reused by the reel, so a :class:`Frame` holds copies.  An
exception raised by a renderer is kept, the callback returns
RBS_E_RENDERER, the projector stops the run, and :meth:`Run.wait` raises the
original exception again.
"""

from __future__ import annotations

import atexit
import math
import sys
import threading
import warnings
import weakref
from dataclasses import dataclass
from typing import Any, Callable, List, Optional, Sequence, Tuple

import numpy as np

from . import _check
from . import errors as _e
from ._native import ffi, lib
from .world import Energy, Momentum, StepInfo, World, _fields_equal, _Handle

_FIELDS = (("type", np.int32, ()), ("color", np.uint32, ()),
           ("texture", np.int32, ()), ("slot", np.uint32, ()),
           ("position", np.float64, (3,)), ("orientation", np.float64, (4,)),
           ("velocity", np.float64, (3,)), ("angular_velocity", np.float64, (3,)),
           ("normal", np.float64, (3,)), ("radius", np.float64, ()))
# The layout of rbs_frame_body as the compiler laid it out (offsets from cffi).
_BODY_DTYPE = np.dtype({
    "names": [f[0] for f in _FIELDS],
    "formats": [(f[1], f[2]) if f[2] else f[1] for f in _FIELDS],
    "offsets": [ffi.offsetof("rbs_frame_body", f[0]) for f in _FIELDS],
    "itemsize": ffi.sizeof("rbs_frame_body"),
})


@dataclass(frozen=True, eq=False)
class Frame:
    """One frame of a run, as a renderer receives it (arrays are copies,
    one row per body in slot order).  == compares every field exactly
    (arrays element by element); not hashable (its arrays can change)."""

    number: int                   #: k: the frame at t = k dt; 0 is the start
    time: float                   #: simulated time, s
    target_time: float            #: wall time it should stay on screen, s
    last: bool                    #: the run's last frame
    paused: bool                  #: the run is paused at this frame
    names: Tuple[str, ...]        #: body names ("" if unnamed)
    slots: np.ndarray             #: uint32, the bodies' slots
    types: np.ndarray             #: int32, 1 sphere, 2 plane
    colors: np.ndarray            #: uint32 0xRRGGBB
    positions: np.ndarray         #: n x 3, m
    orientations: np.ndarray      #: n x 4, [w x y z]
    velocities: np.ndarray        #: n x 3, m/s
    angular_velocities: np.ndarray  #: n x 3, rad/s
    normals: np.ndarray           #: n x 3 (planes)
    radii: np.ndarray             #: n, m (spheres)
    energy: Energy                #: J
    momentum: Momentum            #: kg m/s and kg m^2/s about the origin
    step: StepInfo                #: the step that made this frame (steps 0: the run's first frame, made by no step)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Frame):
            return NotImplemented
        return _fields_equal(self, other, [f for f in self.__dataclass_fields__])

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True)
class RunInfo:
    """How a run went (from rbs_projector_status)."""

    state: str             #: "ready", "running" or "done"
    paused: bool           #: paused now
    quit: bool             #: quit was asked
    realtime: bool         #: paced to the wall clock
    speed: float           #: real-time factor
    steps: int             #: steps asked
    endless: bool          #: runs until quit
    captured: int          #: frames captured by the simulation
    drawn: int             #: frames taken from the reel
    frame: int             #: number of the last frame drawn
    time: float            #: simulated time of the last frame drawn, s
    dropped: int           #: frames dropped by a latest-only reel
    substeps: int
    rollbacks: int
    collisions: int        #: impacts resolved
    energy_initial: float  #: J at frame 0
    energy_last: float     #: J at the last frame captured
    wall_time: float       #: s
    #: steps that hit their work cap (:attr:`StepInfo.work_limit`): their
    #: impacts may be missed or wrong
    work_limited: int = 0
    #: steps whose overlap was pushed apart instead of resolved
    #: (:attr:`StepInfo.floor_hits` > 0)
    floor_hit_steps: int = 0
    #: steps with a contact pass at max_sweeps (:attr:`StepInfo.sweep_limit`
    #: > 0): impulses not converged
    sweep_limited: int = 0
    #: steps in which slow motion was partly lost to the rounding of
    #: coordinates (:attr:`World.rounded_steps`)
    rounded_steps: int = 0
    #: the deepest overlap at the end of any step, m (StepInfo.max_overlap)
    max_overlap: float = 0.0


class StopRun(Exception):
    """Raise from a renderer's draw() to end the run cleanly ("quit").  The
    world ends at the last frame the simulation made (up to the reel's
    capacity after the frame that raised it), which the other renderers
    still draw.  From finish() or close() it changes nothing."""


class _Adapter:
    """One Python renderer inside one run."""

    def __init__(self, run: "Run", obj: Any, index: int) -> None:
        self.run = run
        self.obj = obj
        self.index = index
        draw = getattr(obj, "draw", None)
        if draw is None and callable(obj):
            draw = obj
        if draw is None or not callable(draw):
            raise _e.ArgumentTypeError(
                "renderers[%d]: expected a callable or an object with draw(frame), "
                "got %s" % (index, _check._describe(obj)))
        self.draw: Callable[[Frame], Any] = draw
        self.finish = getattr(obj, "finish", None)
        self.close = getattr(obj, "close", None)
        every = getattr(obj, "every", 1)
        # (the projector's range, RBS_EVERY_MAX, checked here: its message
        # named the internal type python<i> and the C field's range)
        self.every = _check.integer(every, "renderers[%d].every" % index, 1,
                                    lib.RBS_EVERY_MAX)
        self.live = _check.flag(getattr(obj, "live", False),
                                "renderers[%d].live" % index)
        self.names: dict = {}
        self.stopped = False
        self.control: Any = ffi.NULL
        self.control_context: Any = ffi.NULL
        self.handle = ffi.new_handle(self)

    def frame(self, f: Any) -> Frame:
        n = int(f.body_count)
        raw = np.frombuffer(ffi.buffer(f.bodies, n * _BODY_DTYPE.itemsize),
                            dtype=_BODY_DTYPE).copy()
        names = []
        for i in range(n):
            slot = int(raw["slot"][i])
            name = self.names.get(slot)
            if name is None:
                p = f.bodies[i].name
                name = ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""
                self.names[slot] = name  # stable for the run
            names.append(name)
        s = f.stats
        return Frame(
            number=int(f.number), time=float(f.time),
            target_time=float(f.target_time), last=bool(f.last),
            paused=bool(f.paused), names=tuple(names),
            slots=raw["slot"].copy(), types=raw["type"].copy(),
            colors=raw["color"].copy(), positions=raw["position"].copy(),
            orientations=raw["orientation"].copy(),
            velocities=raw["velocity"].copy(),
            angular_velocities=raw["angular_velocity"].copy(),
            normals=raw["normal"].copy(), radii=raw["radius"].copy(),
            energy=Energy(float(s.kinetic), float(s.potential), float(s.total)),
            momentum=Momentum(np.array(list(s.momentum), dtype=np.float64),
                              np.array(list(s.angular_momentum), dtype=np.float64)),
            step=StepInfo._from_c(s.step, 0 if int(f.number) == self.run._first_frame else 1))


def _fail(adapter: _Adapter, exc: BaseException, err: Any, errlen: int) -> int:
    """Keep the first exception of the run; explain it to the projector."""
    if adapter.run._error is None:
        adapter.run._error = exc
    if errlen > 0:
        text = ("python renderer %d raised %s: %s"
                % (adapter.index, type(exc).__name__, exc)).encode("utf-8", "replace")
        text = text[:int(errlen) - 1]
        ffi.memmove(err, text + b"\0", len(text) + 1)
    return lib.RBS_E_RENDERER


@ffi.def_extern(error=lib.RBS_E_RENDERER)
def rbs_py_renderer_create(context: Any, config: Any, world: Any, instance: Any,
                           err: Any, errlen: int) -> int:
    adapter = ffi.from_handle(context)
    adapter.control = config.control
    adapter.control_context = config.control_context
    instance[0] = context  # the adapter, kept alive by its Run
    return lib.RBS_OK


@ffi.def_extern(error=lib.RBS_E_RENDERER)
def rbs_py_renderer_draw(instance: Any, frame: Any, err: Any, errlen: int) -> int:
    adapter = ffi.from_handle(instance)
    if adapter.stopped:
        return lib.RBS_OK
    adapter.run._callback_thread = threading.get_ident()
    try:
        adapter.draw(adapter.frame(frame))
    except StopRun:
        adapter.stopped = True
        adapter.run._stopped = True
        if adapter.control != ffi.NULL:
            adapter.control(adapter.control_context, b"quit")
    except BaseException as exc:  # noqa: B902 - everything goes back to run()
        return _fail(adapter, exc, err, errlen)
    finally:
        adapter.run._callback_thread = None
    return lib.RBS_OK


@ffi.def_extern(error=lib.RBS_E_RENDERER)
def rbs_py_renderer_finish(instance: Any, err: Any, errlen: int) -> int:
    adapter = ffi.from_handle(instance)
    if adapter.finish is None:
        return lib.RBS_OK
    adapter.run._callback_thread = threading.get_ident()
    try:
        adapter.finish()
    except StopRun:
        pass  # (no frame is left to stop: the run ends as it would have)
    except BaseException as exc:  # noqa: B902
        return _fail(adapter, exc, err, errlen)
    finally:
        adapter.run._callback_thread = None
    return lib.RBS_OK


@ffi.def_extern()
def rbs_py_renderer_destroy(instance: Any) -> None:
    adapter = ffi.from_handle(instance)
    if adapter.close is None:
        return
    try:
        adapter.close()
    except StopRun:
        pass  # (as in finish)
    except BaseException as exc:  # noqa: B902
        if adapter.run._error is None:
            adapter.run._error = exc


class Run(_Handle):
    """A run of a world through the projector (see :meth:`World.start`).

    From start until :meth:`wait` returns, the world belongs to the
    simulation thread: using it raises BusyError.  :meth:`command`,
    :meth:`status` and :meth:`finished` are thread-safe.  From the run's own
    renderers (inside draw() or finish()), :meth:`wait` and
    :meth:`finished` with a timeout raise DeadlockError: the run cannot end
    while its renderer is drawing.  A Run cannot be copied or pickled."""

    _COPY_HINT = ("run (its threads); wait() on it, and copy its RunInfo or the world's "
                  "checkpoint()")

    def __init__(self, world: World, steps: int, renderers: Sequence[Any],
                 realtime: bool, speed: float, start_paused: bool,
                 pause_on_collision: bool, reel_capacity: Optional[int],
                 endless: bool) -> None:
        self._error: Optional[BaseException] = None
        # the RunInfo taken as the run was closed: status() after wait()
        self._final: Optional[RunInfo] = None
        self._stopped = False
        # the thread inside one of this run's renderer callbacks (draw,
        # finish), None between them: see _refuse_from_renderer
        self._callback_thread: Optional[int] = None
        self._world = world
        self._projector: Any = ffi.NULL
        # command/status/finished from other threads hold the projector
        # through _use/_unuse; _close_projector waits until none does (it
        # was destroyed under a command in flight: a hang or a crash)
        self._users = 0
        self._cond = threading.Condition()
        # wait() from several threads: one waits on the projector, the
        # others after it get its outcome (two in rbs_projector_wait joined
        # the same threads twice: a hang).  Re-entrant: a renderer's close(),
        # run inside wait(), may call wait() (it is told the run is over).
        self._wait_lock = threading.RLock()
        self._outcome: Optional[Any] = None  # (RunInfo, or the exception)
        self._in_wait = False
        self._registry: Any = ffi.NULL
        self._result: Optional[int] = None
        self._adapters = [_Adapter(self, r, i)
                          for i, r in enumerate(_renderer_list(renderers))]
        self._keep: List[Any] = []
        self._cworld = world._acquire()  # held until wait() ends
        # the run's first frame: the world as it stands, made by no step
        self._first_frame = int(lib.rbs_world_step_count(self._cworld))
        world._held_by_run = True
        self._world_mem = world._mem  # (the world's memory, alive while the run holds it)
        try:
            self._make(steps, realtime, speed, start_paused, pause_on_collision,
                       reel_capacity, endless)
        except BaseException:
            self._release()
            raise
        _LIVE_RUNS.add(self)

    def __setattr__(self, name: str, value: Any) -> None:
        # A Run has no settable attribute: run.speed = 2 or run.paused =
        # False made a plain Python attribute the projector never read (a
        # silent no-op, a probe of session 46).  Commands steer a run.
        if not name.startswith("_"):
            raise AttributeError(
                "Run has no settable attribute %r: steer a run with command(...) "
                "(\"pause\", \"resume\", \"step N\", \"speed X\", \"quit\"); "
                "status() reads its state" % name)
        object.__setattr__(self, name, value)

    def _make(self, steps: int, realtime: bool, speed: float, start_paused: bool,
              pause_on_collision: bool, reel_capacity: Optional[int],
              endless: bool) -> None:
        n = len(self._adapters)
        reg = ffi.new("rbs_renderer_registry **")
        status = lib.rbs_renderer_registry_create(reg)
        if status != lib.RBS_OK:
            raise _e.error_class(status)("cannot make a renderer registry")
        self._registry = reg[0]
        configs = ffi.new("rbs_renderer_config[]", max(n, 1))
        for i, a in enumerate(self._adapters):
            name = ffi.new("char[]", b"python%d" % i)
            cls = ffi.new("rbs_renderer_class *")
            cls.struct_size = ffi.sizeof("rbs_renderer_class")
            cls.name = name
            cls.context = a.handle
            cls.create = lib.rbs_py_renderer_create
            cls.draw = lib.rbs_py_renderer_draw
            cls.finish = lib.rbs_py_renderer_finish
            cls.destroy = lib.rbs_py_renderer_destroy
            cls.flags = lib.RBS_RENDERER_LIVE if a.live else 0
            self._keep += [name, cls]
            status = lib.rbs_renderer_register(self._registry, cls)
            if status != lib.RBS_OK:
                raise _e.error_class(status)("cannot register python renderer %d" % i)
            configs[i].struct_size = ffi.sizeof("rbs_renderer_config")
            configs[i].type = name
            configs[i].every = a.every
        self._keep.append(configs)
        d = ffi.new("rbs_projector_def *")
        lib.rbs_projector_def_init_sized(d, ffi.sizeof("rbs_projector_def"))
        d.steps = steps
        d.realtime = int(realtime)
        d.speed = speed
        d.start_paused = int(start_paused)
        d.pause_on_collision = int(pause_on_collision)
        d.endless = int(endless)
        if reel_capacity is not None:
            d.reel_capacity = reel_capacity
        out = ffi.new("rbs_projector **")
        status = lib.rbs_projector_create(self._cworld, self._registry,
                                          configs if n else ffi.NULL, n, d, out)
        self._projector = out[0]
        if status != lib.RBS_OK:
            detail = (_text(lib.rbs_projector_last_error(self._projector))
                      if self._projector != ffi.NULL else "projector definition rejected")
            self._close_projector()
            if self._error is not None:
                raise self._error
            raise _e.error_class(status)(detail)
        status = lib.rbs_projector_start(self._projector)
        if status != lib.RBS_OK:
            detail = _text(lib.rbs_projector_last_error(self._projector))
            self._close_projector()
            raise _e.error_class(status)(detail)

    def _refuse_from_renderer(self, call: str) -> None:
        """Raise DeadlockError when called from inside this run's own
        renderer: the renderer thread must return for the run to end."""
        if self._callback_thread == threading.get_ident():
            raise _e.DeadlockError(
                "%s from the run's own renderer (inside draw() or finish()) "
                "would never return: the run cannot end until the renderer "
                "returns; raise StopRun to end the run, and wait() from "
                "another thread" % call)

    def _use(self) -> Any:
        """The projector, held until _unuse(); ClosedError once the run is
        over."""
        with self._cond:
            if self._projector == ffi.NULL:
                raise _e.error_class(lib.RBS_E_CLOSED)("the run is over")
            self._users += 1
            return self._projector

    def _unuse(self) -> None:
        with self._cond:
            self._users -= 1
            self._cond.notify_all()

    def command(self, line: str) -> str:
        """Send a command line ("pause", "resume", "step [N]", "speed X",
        "quit", "status"); returns the reply.  Thread-safe."""
        raw = _check.text(line, "line")
        reply = ffi.new("char[]", 512)
        projector = self._use()
        try:
            if line.split()[:1] == ["quit"]:
                self._stopped = True  # wait() then treats RBS_E_CLOSED as the end
            status = lib.rbs_projector_command(projector, raw, reply, 512)
        finally:
            self._unuse()
        text = _text(reply)
        if status != lib.RBS_OK:
            raise _e.error_class(status)("%r: %s" % (line, text))
        return text

    def finished(self, timeout: float = 0.0) -> bool:
        """Wait up to timeout seconds (>= 0; 0: just look) for the run to
        end; True if it has.  From the run's own renderer only
        ``finished(0)`` is allowed (it is False there): a wait would last the
        whole timeout for nothing."""
        # (a negative timeout was taken as 0, silently: finished(-1) looked)
        t = _check.real_in(timeout, "timeout", 0.0, note=" seconds")
        if t > 0:
            self._refuse_from_renderer("finished(%r)" % t)
        try:
            projector = self._use()
        except _e.Error:
            return True
        try:
            return bool(lib.rbs_projector_finished(projector, max(t, 0.0)))
        finally:
            self._unuse()

    def status(self) -> RunInfo:
        """A snapshot of the run (also after it ended); after wait(), the
        final one (the RunInfo wait() returned, or the state of a run that
        failed, its ``result`` the error)."""
        out = ffi.new("rbs_run_info *")
        with self._cond:
            if self._projector == ffi.NULL and self._final is not None:
                return self._final
        projector = self._use()
        try:
            status = lib.rbs_projector_status_sized(projector, out,
                                                    ffi.sizeof("rbs_run_info"))
        finally:
            self._unuse()
        if status != lib.RBS_OK:
            raise _e.error_class(status)("projector status")
        return _run_info(out)

    def wait(self) -> RunInfo:
        """Wait for the end of the run; raise what stopped it early (a
        renderer's own exception, or the library's error).  Raises
        DeadlockError from the run's own renderer (it would never return).
        Thread-safe: waiters in several threads each get the same outcome."""
        self._refuse_from_renderer("wait()")
        with self._wait_lock:
            if self._outcome is not None:
                if isinstance(self._outcome, BaseException):
                    raise self._outcome
                return self._outcome
            if self._in_wait:  # (a renderer's close(), inside our own wait())
                raise _e.error_class(lib.RBS_E_CLOSED)("the run is over")
            self._in_wait = True
            try:
                info = self._wait()
            except (KeyboardInterrupt, SystemExit):
                raise
            except BaseException as e:
                if self._projector == ffi.NULL:  # (the run is over: for later waiters too)
                    self._outcome = e
                raise
            finally:
                self._in_wait = False
            self._outcome = info
            return info

    def _wait(self) -> RunInfo:
        if self._projector == ffi.NULL:
            raise _e.error_class(lib.RBS_E_CLOSED)("the run is over")
        try:
            # Wait in slices so Ctrl-C (KeyboardInterrupt) is seen.
            while not lib.rbs_projector_finished(self._projector, 0.05):
                pass
        except BaseException:
            lib.rbs_projector_command(self._projector, b"quit", ffi.NULL, 0)
            lib.rbs_projector_wait(self._projector)
            try:
                self._final = self.status()
            finally:
                self._close_projector()
            raise
        status = lib.rbs_projector_wait(self._projector)
        info = self.status()
        self._final = info
        detail = _text(lib.rbs_projector_last_error(self._projector))
        self._close_projector()
        if self._error is not None:
            raise self._error
        if status == lib.RBS_E_CLOSED and self._stopped:
            return info  # StopRun or a "quit" command: a clean end
        if status != lib.RBS_OK:
            raise _e.error_class(status)(detail)
        return info

    def _close_projector(self) -> None:
        _LIVE_RUNS.discard(self)
        with self._cond:
            projector = self._projector
            self._projector = ffi.NULL  # (new callers: ClosedError)
            while self._users > 0:
                self._cond.wait()
        if projector != ffi.NULL:
            lib.rbs_projector_destroy(projector)
        self._release()

    def _release(self) -> None:
        if self._registry != ffi.NULL:
            lib.rbs_renderer_registry_destroy(self._registry)
            self._registry = ffi.NULL
        if self._cworld is not None:
            self._cworld = None
            self._world._held_by_run = False
            self._world._lock.release()

    def _end_at_exit(self) -> None:
        """Quit the run and wait for it (the interpreter is exiting and no
        one waited on it); say so on stderr."""
        try:
            projector = self._use()
        except _e.Error:
            return  # (over already)
        try:
            self._stopped = True  # (a clean end: wait() returns the RunInfo)
            lib.rbs_projector_command(projector, b"quit", ffi.NULL, 0)
            # in slices, so that Ctrl-C is seen (the renderer thread draws
            # the frames left in the reel meanwhile)
            while not lib.rbs_projector_finished(projector, 0.05):
                pass
            info = _run_info_of(projector)
        finally:
            self._unuse()
        ending = ""
        if self._wait_lock.acquire(blocking=False):  # (else a thread is in wait())
            try:
                self.wait()
            except Exception as exc:  # noqa: B902 - reported below, the process is ending
                ending = "; it ended with %s: %s" % (type(exc).__name__, exc)
            finally:
                self._wait_lock.release()
        sys.stderr.write("rbsim: a run never waited on was stopped at exit, at frame %d%s "
                         "(call Run.wait() before the end)%s\n"
                         % (info.frame, "" if info.endless else " of %d" % info.steps, ending))

    def __del__(self) -> None:
        if getattr(self, "_projector", ffi.NULL) == ffi.NULL:
            return
        try:
            finalizing = sys.is_finalizing()
        except Exception:  # noqa: B902 - (sys torn down: the very end)
            finalizing = True
        if finalizing:
            # The at-exit hook ended every run it could; one left (Ctrl-C
            # in the hook) cannot be waited for now: its Python renderers'
            # thread can no longer take the GIL, and joining it never
            # returned (a probe of session 41).  Quit it; if it does not end
            # within a second, leave it to the end of the process.
            lib.rbs_projector_command(self._projector, b"quit", ffi.NULL, 0)
            if not lib.rbs_projector_finished(self._projector, 1.0):
                return
        self._close_projector()


#: the runs started and not over yet (weak: a Run that is collected ends
#: its own run), for _end_runs_at_exit
_LIVE_RUNS: "weakref.WeakSet[Run]" = weakref.WeakSet()


def _end_runs_at_exit() -> None:
    """At exit, quit and wait for every run no one waited on (the script
    ended, or raised, before Run.wait()) while the interpreter can still
    run their Python renderers.  Left to finalisation, Run.__del__ joined a
    renderer thread that could no longer take the GIL, and the interpreter
    never exited, Ctrl-C or not (a probe of session 41)."""
    for run in list(_LIVE_RUNS):
        try:
            run._end_at_exit()
        except KeyboardInterrupt:
            # (the rest are left to Run.__del__, which gives up on them)
            sys.stderr.write("rbsim: Ctrl-C: no longer waiting at exit for runs never "
                             "waited on\n")
            return


atexit.register(_end_runs_at_exit)


_STATES = {v: k[len("RBS_RUN_"):].lower()
           for v, k in ffi.typeof("rbs_run_state").elements.items()}


def _text(p: Any) -> str:
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""


def _run_info_of(projector: Any) -> RunInfo:
    out = ffi.new("rbs_run_info *")
    status = lib.rbs_projector_status_sized(projector, out, ffi.sizeof("rbs_run_info"))
    if status != lib.RBS_OK:
        raise _e.error_class(status)("projector status")
    return _run_info(out)


def _run_info(s: Any) -> RunInfo:
    return RunInfo(_STATES.get(int(s.state), str(int(s.state))), bool(s.paused),
                   bool(s.quit), bool(s.realtime), float(s.speed),
                   int(s.steps), bool(s.endless), int(s.captured), int(s.drawn), int(s.frame),
                   float(s.time), int(s.dropped), int(s.substeps),
                   int(s.rollbacks), int(s.collisions), float(s.energy_initial),
                   float(s.energy_last), float(s.wall_time), int(s.work_limited),
                   int(s.floor_hit_steps), int(s.sweep_limited), int(s.rounded_steps),
                   float(s.max_overlap))


def _renderer_list(renderers: Any) -> List[Any]:
    """renderers as a list, or an ArgumentTypeError (a TypeError) naming it.
    A single renderer (renderers=print) is refused, not wrapped: the API and
    its docs take a list, and a renderer object that is also a sequence
    would read as a list of renderers."""
    if isinstance(renderers, (str, bytes)) or not isinstance(renderers, Sequence):
        if callable(renderers) or hasattr(renderers, "draw"):
            raise _e.ArgumentTypeError(
                "renderers: expected a list of renderers, got a single renderer "
                "%s: pass a list, renderers=[...]" % _check._describe(renderers))
        raise _e.ArgumentTypeError("renderers: expected a list of renderers, got %s"
                                   % _check._describe(renderers))
    if len(renderers) > lib.RBS_RENDERERS_MAX:
        raise _e.error_class(lib.RBS_E_INVALID)(
            "renderers: at most %d, got %d" % (lib.RBS_RENDERERS_MAX, len(renderers)))
    return list(renderers)


def start_world(world: World, steps: Optional[int] = None,
                renderers: Sequence[Any] = (), *, realtime: bool = False,
                speed: float = 1.0, start_paused: bool = False,
                pause_on_collision: Optional[bool] = None,
                reel_capacity: Optional[int] = None, endless: bool = False,
                _stacklevel: int = 4) -> Run:
    """Start a run of world; see World.start.  (_stacklevel: the warning's,
    the caller of World.start past _check.keywords' frame.)"""
    if world.scene_renderers and not getattr(world, "_warned_renderers", False):
        world._warned_renderers = True
        warnings.warn(
            "the scene's renderers (%s) are front-end renderers of the rbsim "
            "command and are not run from Python; pass Python renderers to "
            "run()/start() (world.scene_renderers lists them)"
            % ", ".join(str(r.get("type")) for r in world.scene_renderers),
            UserWarning, stacklevel=_stacklevel)
    # (checked first: endless=1 or numpy's True passed the flag check at the
    # end but not "is True" here, so run(5, endless=np.True_) ran on past 5,
    # and run(endless=1) said "steps: required": a probe of session 50)
    endless = _check.flag(endless, "endless")
    if endless:
        if steps is not None:
            # (it was ignored, silently: run(10, endless=True) ran on past
            # step 10, until quit or StopRun)
            raise _e.error_class(lib.RBS_E_INVALID)(
                "steps: %r with endless=True, which runs until quit or StopRun and "
                "would ignore it: pass one of them" % (steps,))
        steps = 0  # not used: the run goes on until quit
    if steps is None:
        steps = world._scene_steps
        if steps is None:
            raise _e.error_class(lib.RBS_E_INVALID)(
                "steps: required (the world was not loaded from a scene)")
    # (at most 2^53, as a scene and the rbsim command: run(steps=2**60) was
    # taken; a probe of session 50)
    n = _check.steps(steps, "steps")
    if not endless and not math.isfinite(float(n) * world.dt):
        # (as a scene's check: the run's last frame would be at t = inf;
        # World(dt=1e300).start(2**53) was taken -- a probe of session 50)
        raise _e.error_class(lib.RBS_E_INVALID)(
            "steps * dt overflows (%d * %r s)" % (n, world.dt))
    renderers = _renderer_list(renderers)
    if pause_on_collision is None:
        pause_on_collision = world._scene_pause_on_collision
    cap = None if reel_capacity is None else _check.u32(reel_capacity, "reel_capacity", 2)
    realtime = _check.flag(realtime, "realtime")
    speed = _check.real_in(speed, "speed", 0.0, open_low=True)
    if speed != 1.0 and not realtime:
        # (as the command line's --speed without --realtime)
        raise _e.error_class(lib.RBS_E_INVALID)(
            "speed: %r sets the pace of realtime=True, and a run without it goes "
            "as fast as it can: pass realtime=True too" % speed)
    return Run(world, n, renderers, realtime,
               speed, _check.flag(start_paused, "start_paused"),
               _check.flag(pause_on_collision, "pause_on_collision"), cap,
               endless)


def run_world(world: World, steps: Optional[int] = None,
              renderers: Sequence[Any] = (), *, realtime: bool = False,
              speed: float = 1.0, reel_capacity: Optional[int] = None,
              endless: bool = False) -> RunInfo:
    """Run to the end and wait; see World.run.  (Pausing needs someone to
    resume: use World.start and Run.command for that.)"""
    return start_world(world, steps, renderers, realtime=realtime, speed=speed,
                       start_paused=False, pause_on_collision=False,
                       reel_capacity=reel_capacity, endless=endless,
                       _stacklevel=5).wait()

