"""rbsim: a fixed-memory rigid-body simulator of spheres and planes.

Python binding of librbsim (cffi, API mode)::

    import rbsim
    world = rbsim.load("scenes/bounce.json")      # or rbsim.World(...)
    world.step(100)
    print(world.time, world.positions, world.energy())
    world.bodies["ball"].velocity = (1.0, 0.0, 0.0)
    world.run(1000, renderers=[lambda frame: print(frame.number)])

Errors raise :class:`Error` subclasses: :class:`SceneError` (with file, line,
column, message and every error), :class:`CapacityError`,
:class:`StaleIdError`, :class:`NumericError`, ... -- one class per status code
of the library, generated from its ``RBS_STATUS_LIST``.
"""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, List, Optional, Union

from . import _check
from . import errors as _e
from ._native import ffi, lib
from ._render import Frame, Run, RunInfo, StopRun
from .errors import (ArgumentTypeError, BusyError, DeadlockError, Error,
                     SceneError, SceneIssue, error_class)
from .errors import *  # noqa: F401,F403 - the generated classes
# (those named as a built-in exception are not in errors.__all__, so that
# "from rbsim import *" keeps the built-in: here as attributes only)
globals().update({n: _e.GENERATED[n] for n in _e.SHADOWING})
from .world import (METHODS, Body, BodyMap, BodyState, Energy, Material,
                    Momentum, StepInfo, Usage, World)

#: version of the loaded library, "MAJOR.MINOR.PATCH"
__version__: str = ffi.string(lib.rbs_version()).decode()

_FORMATS = {"auto": lib.RBS_SCENE_AUTO, "json": lib.RBS_SCENE_JSON,
            "text": lib.RBS_SCENE_TEXT}


def _scene_issues(scene: Any) -> List[SceneIssue]:
    issues = []
    item = ffi.new("rbs_scene_error *")
    count = lib.rbs_scene_error_count(scene)
    for i in range(min(count, lib.RBS_SCENE_ERRORS_MAX)):
        if lib.rbs_scene_error_get(scene, i, item) != lib.RBS_OK:
            break
        s = lambda p: ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""
        issues.append(SceneIssue(s(item.file), int(item.line), int(item.column),
                                 s(item.path), s(item.message), s(item.text)))
    return issues


def _raise_scene(status: int, scene: Any, name: str) -> None:
    issues = _scene_issues(scene) if scene != ffi.NULL else []
    count = lib.rbs_scene_error_count(scene) if scene != ffi.NULL else 0
    if status == lib.RBS_E_SCENE:
        raise SceneError(name, status=status, errors=issues, count=count)
    detail = "; ".join(i.text for i in issues) if issues else name
    raise error_class(status)(detail)


def _raise_override(status: int, scene: Any, name: str) -> None:
    """An override the library refused: an InvalidError in the argument's
    own name ("slop: must be ...", as dt= and steps= are checked here), not
    the command line's ("command line: --slop: ...")."""
    for issue in _scene_issues(scene):
        if issue.path in ("--slop", "--method", "--dt", "--steps"):
            raise error_class(lib.RBS_E_INVALID)("%s: %s" % (issue.path[2:], issue.message))
    _raise_scene(status, scene, name)


def _from_scene(scene: Any, name: str, steps: Optional[int], dt: Optional[float],
                method: Optional[str], slop: Optional[float] = None) -> World:
    if slop is not None:
        status = lib.rbs_scene_override_slop(scene, _check.real(slop, "slop"))
        if status != lib.RBS_OK:
            _raise_override(status, scene, name)
    if steps is not None or dt is not None or method is not None:
        # (steps=0: frame 0 only, as --steps 0 and "steps": 0; the C
        # override's 0 keeps the scene's, so the world is told below)
        # (a scene's steps are at most 2^53, as the C override says)
        n = 0 if steps is None else _check.integer(steps, "steps", 0, 2 ** 53)
        step = 0.0
        if dt is not None:
            step = _check.real_in(dt, "dt", 0.0, open_low=True)
        raw = None if method is None else _check.text(method, "method")
        status = lib.rbs_scene_override(scene, n, step, raw if raw is not None else ffi.NULL)
        if status != lib.RBS_OK:
            _raise_override(status, scene, name)
    d = ffi.new("rbs_world_def *")
    status = lib.rbs_scene_world_def(scene, d)
    if status != lib.RBS_OK:
        _raise_scene(status, scene, name)
    world = World._from_def(d)
    w = world._acquire()
    try:
        status = lib.rbs_scene_populate(scene, w)
        detail = ffi.string(lib.rbs_world_last_error(w)).decode("utf-8", "replace")
    finally:
        world._lock.release()
    if status != lib.RBS_OK:
        if lib.rbs_scene_error_count(scene) > 0:
            _raise_scene(status, scene, name)
        raise error_class(status)("%s: %s" % (name, detail))
    world._scene_steps = 0 if steps == 0 else int(lib.rbs_scene_steps(scene))
    world._scene_pause_on_collision = bool(lib.rbs_scene_pause_on_collision(scene))
    entries = []
    item = ffi.new("rbs_scene_renderer *")
    for i in range(lib.rbs_scene_renderer_count(scene)):
        if lib.rbs_scene_renderer_get(scene, i, item) == lib.RBS_OK:
            raw = item.json
            entries.append(json.loads(ffi.string(raw).decode("utf-8", "replace"))
                           if raw != ffi.NULL else {})
    world.scene_renderers = entries
    files = []
    while True:
        src = lib.rbs_scene_source(scene, len(files))
        if src == ffi.NULL:
            break
        files.append(ffi.string(src))
    world._scene_files = tuple(files)
    text = lib.rbs_scene_description(scene)
    world.description = ffi.string(text).decode("utf-8", "replace") if text != ffi.NULL else ""
    # The scene's warnings (rbs_scene_warning_get: a material named in a
    # row that no body has), as the rbsim command prints them; the world is
    # built all the same.  stacklevel 4: the caller of load()/parse_json()
    # (past _check.keywords' frame).
    warning = ffi.new("rbs_scene_error *")
    for i in range(lib.rbs_scene_warning_count(scene)):
        if lib.rbs_scene_warning_get(scene, i, warning) == lib.RBS_OK:
            warnings.warn(ffi.string(warning.text).decode("utf-8", "replace"),
                          SceneWarning, stacklevel=4)
    return world


class SceneWarning(UserWarning):
    """A scene that loads, with something that is likely a mistake (a
    material named in a "materials" row that no body has: the row applies
    to no contact).  The message is the library's, "FILE:LINE:COLUMN: PATH:
    MESSAGE"."""


@_check.keywords
def load(path: Union[str, "os.PathLike[str]"], *, format: str = "auto",
         steps: Optional[int] = None, dt: Optional[float] = None,
         method: Optional[str] = None, slop: Optional[float] = None) -> World:
    """Load a scene file and build its world.

    Args:
        path: a JSON scene, or a seed-format config.txt (see scenes/FORMAT.md).
        format: "auto" (by content/extension), "json" or "text".
        steps, dt, method, slop: override the scene's simulation settings
            (as the command line's --steps/--dt/--method/--slop do; slop in
            (0, 0.1) of the smaller radius).

    Returns:
        the World; :meth:`World.run` without steps uses the scene's.

    Raises:
        SceneError: the scene was rejected; ``.file``, ``.line``,
            ``.column``, ``.message`` describe the first error and
            ``.errors`` lists all of them.
        InvalidError: an override out of its range, named as the argument
            ("slop: must be in (0, 0.1) ...", "method: unknown method ...").
        IoError: the file cannot be read.
    """
    raw = _check.path(path, "path")
    fmt = _FORMATS[_check.choice(format, "format", tuple(_FORMATS))]
    out = ffi.new("rbs_scene **")
    status = lib.rbs_scene_load(raw, fmt, out)
    scene = out[0]
    name = os.fsdecode(raw)
    try:
        if status != lib.RBS_OK:
            _raise_scene(status, scene, name)
        return _from_scene(scene, name, steps, dt, method, slop)
    finally:
        lib.rbs_scene_free(scene)


@_check.keywords
def parse_json(text: str, name: str = "<string>", *, steps: Optional[int] = None,
               dt: Optional[float] = None, method: Optional[str] = None,
               slop: Optional[float] = None) -> World:
    """Build a world from a JSON scene held in a string (name labels
    errors).  Same errors as :func:`load`."""
    if not isinstance(text, str):
        raise ArgumentTypeError("text: expected a str, got %s" % type(text).__name__)
    try:
        data = text.encode("utf-8")
    except UnicodeEncodeError as exc:
        # (a scene's text may hold NUL -- the parser names it -- so not _check.text)
        raise error_class(lib.RBS_E_INVALID)(
            "text: not valid Unicode text: a lone surrogate %r at position %d"
            % (text[exc.start], exc.start)) from None
    label = _check.text(name, "name")
    out = ffi.new("rbs_scene **")
    status = lib.rbs_scene_parse_json(data, len(data), label, out)
    scene = out[0]
    try:
        if status != lib.RBS_OK:
            _raise_scene(status, scene, name)
        return _from_scene(scene, name, steps, dt, method, slop)
    finally:
        lib.rbs_scene_free(scene)


def resume(path: Union[str, "os.PathLike[str]"]) -> World:
    """Load a checkpoint file: the world exactly as it was saved, bit for
    bit, at the saved step count; stepping it on gives the same states as
    the world that was saved would have.  Files written by
    :meth:`World.save` and by ``rbsim run --checkpoint FILE`` are the same
    format.  The same as :meth:`World.restore`.

    Raises:
        CorruptError: a damaged, truncated or foreign file.
        VersionError: a checkpoint of another format version.
        IoError: the file cannot be read.
    """
    return World.restore(path)


def version() -> str:
    """Version of the loaded library ("MAJOR.MINOR.PATCH")."""
    return __version__


__all__ = ["World", "Body", "BodyMap", "BodyState", "Material", "StepInfo",
           "Energy", "Momentum", "Usage", "Frame", "Run", "RunInfo", "StopRun", "METHODS",
           "load", "parse_json", "resume", "version", "Error", "SceneError", "SceneIssue",
           "SceneWarning", "BusyError", "DeadlockError", "ArgumentTypeError", "error_class"] + sorted(
               n for n in _e.GENERATED if n not in _e.SHADOWING)
