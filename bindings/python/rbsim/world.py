"""The world: bodies, materials, stepping, state views and diagnostics.

Design notes
------------
* The world's memory is one block owned by Python
  (``rbs_world_create_in_zeroed`` into numpy's zeros, which calloc makes:
  pages become resident as the world first writes them, as in C).  The state arrays (:attr:`World.positions`,
  ...) are numpy views into that block: no copy is made, a step changes what
  they show, and because every view keeps the block alive, a view can never
  dangle (after :meth:`World.close` it just stops changing).
* The views are read-only and cannot be made writeable: writing would bypass
  the library's validation.  Change a body through its setters
  (``world.bodies["ball"].velocity = (1, 0, 0)``).
* A World is not thread-safe, like the C world it wraps.  Every call takes a
  per-world lock without waiting: using one world from two threads at once
  raises :class:`~rbsim.BusyError` instead of corrupting memory.  Distinct
  worlds may step in distinct threads; the GIL is released while C steps.
"""

from __future__ import annotations

import inspect
import math
import os
import sys
import threading
import time
from dataclasses import dataclass
from typing import (TYPE_CHECKING, Any, Dict, Iterator, List, Mapping,
                    NamedTuple, Optional, Sequence, Tuple, Union)

import numpy as np

from . import _check
from . import errors as _e
from ._native import ffi, lib

if TYPE_CHECKING:
    from ._render import Run, RunInfo

Vector = Union[Sequence[float], np.ndarray]

_ALIGN = 16  # rbs_world_create_in wants 16-byte alignment
_DBL_MIN = sys.float_info.min  # (DBL_MIN, the library's floor of a moment of inertia)
_STEP_SLICE = 0.02  # s of stepping per C call in World.step (Ctrl-C between calls)
_STEP_SLICE_MAX = 1 << 20  # steps per C call in World.step, at most
_STEP_FIRST = 64  # steps of a World.step's first C call, at most


def _enum_names(ctype: str, prefix: str) -> Dict[str, int]:
    """{"solid": 0, ...} from an enum of the headers (the 32-bit pin and
    the COUNT sentinel left out)."""
    names = {}
    for value, cname in ffi.typeof(ctype).elements.items():
        short = cname[len(prefix):].lower()
        if short.endswith("force32") or short == "count":
            continue
        names[short] = value
    return names


#: method names accepted by World(method=...), in library order
METHODS: Tuple[str, ...] = tuple(
    ffi.string(lib.rbs_method_name(i)).decode() for i in range(lib.RBS_METHOD_COUNT))
_GRAVITY_MODES = _enum_names("rbs_gravity_mode", "RBS_GRAVITY_")
_TEXTURES = _enum_names("rbs_texture", "RBS_TEXTURE_")
_INERTIA = _enum_names("rbs_inertia_kind", "RBS_INERTIA_")
_BODY_TYPES = {v: k for k, v in _enum_names("rbs_body_type", "RBS_BODY_").items()}


# cffi pitfall: a struct field of an owning cdata (ffi.new) does not keep its
# owner alive, so `_vec3(make().field)` may read freed memory.  Always bind
# the owner to a name first (s = ...; _vec3(s.field)).


def _vec3(v: Any) -> np.ndarray:
    return np.array([v.x, v.y, v.z], dtype=np.float64)


def _quat(q: Any) -> np.ndarray:
    return np.array([q.w, q.x, q.y, q.z], dtype=np.float64)


def _set_vec3(dst: Any, v: Tuple[float, ...]) -> None:
    dst.x, dst.y, dst.z = v


def _same_file(a: bytes, b: bytes) -> bool:
    """Whether two paths name one existing file (after links)."""
    try:
        sa, sb = os.stat(a), os.stat(b)
    except (OSError, ValueError):
        return False
    return (sa.st_dev, sa.st_ino) == (sb.st_dev, sb.st_ino)


def _str(p: Any) -> str:
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""


class _Handle:
    """Base of the objects that stand for something of the library's (a
    world, a body of it, a run): none can be copied or pickled.  The
    default copy shared the C world, and deleting the copy destroyed the
    original's (a crash with threads > 1: a probe of session 41).
    _COPY_HINT says what to do instead."""

    __slots__ = ()
    _COPY_HINT = ""

    def _refuse_copy(self, *args: Any) -> Any:
        raise TypeError("cannot copy or pickle a %s: it is a handle to the library's %s"
                        % (type(self).__name__, self._COPY_HINT))

    __copy__ = _refuse_copy
    __deepcopy__ = _refuse_copy
    __reduce_ex__ = _refuse_copy
    __reduce__ = _refuse_copy


# --------------------------------------------------------------------------
# Small result types
# --------------------------------------------------------------------------

def _same(a: Any, b: Any) -> bool:
    """Exact equality of two fields: arrays by shape and every element
    (np.array_equal; == of arrays is an array, whose truth value raised),
    anything else by ==."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return bool(np.array_equal(a, b))
    return bool(a == b)


def _fields_equal(a: Any, b: Any, names: Sequence[str]) -> bool:
    return all(_same(getattr(a, n), getattr(b, n)) for n in names)


@dataclass(frozen=True)
class StepInfo:
    """What a call of :meth:`World.step` did.  For n > 1 steps the counts
    are added up over the steps, ``contacts`` is the last step's and
    ``max_overlap`` the deepest seen."""

    contacts: int       #: contacts touching at the end of the (last) step
    colliding: int      #: impacts resolved with restitution
    resting: int        #: resting-contact impulses
    substeps: int       #: accepted sub-steps
    rollbacks: int      #: sub-steps undone because of overlap
    floor_hits: int     #: sub-steps accepted at the rollback floor
    sweep_limit: int    #: contact passes that hit max_sweeps
    events: int         #: events processed (event method)
    max_overlap: float  #: deepest overlap at the end of a step, m
    steps: int = 1      #: steps this call made
    #: steps the work cap (``World(max_substeps=)``) changed: a rollback
    #: refused or a sub-step lengthened (overlap there was pushed apart, so
    #: impacts may be missed or wrong; a ball may pass through another),
    #: adaptive's rest of a frame taken without events, or a turn past the
    #: rotation budget; 0 when every step was resolved in time (a frame that
    #: only ends at the cap in its own sub-steps is not counted)
    work_limit: int = 0

    @classmethod
    def _from_c(cls, c: Any, steps: int = 1) -> "StepInfo":
        return cls(int(c.contacts), int(c.colliding), int(c.resting),
                   int(c.substeps), int(c.rollbacks), int(c.floor_hits),
                   int(c.sweep_limit), int(c.events), float(c.max_overlap), steps,
                   int(c.work_limit))


class Energy(NamedTuple):
    """Energies, J (potential: uniform gravity relative to the origin, and
    mutual gravity when on)."""

    kinetic: float
    potential: float
    total: float


class Momentum(NamedTuple):
    """Total linear momentum (kg m/s) and angular momentum about the origin
    (kg m^2/s), as arrays of 3.  == compares every element exactly; not
    hashable (its arrays can change)."""

    linear: np.ndarray
    angular: np.ndarray

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, tuple) or len(other) != 2:
            return NotImplemented
        return _same(self[0], other[0]) and _same(self[1], other[1])

    def __ne__(self, other: object) -> bool:
        eq = self.__eq__(other)
        return eq if eq is NotImplemented else not eq

    __hash__ = None  # type: ignore[assignment]


class Usage(NamedTuple):
    """Memory use, to size worlds: run, read the high-water marks, shrink."""

    bytes: int
    bodies: int
    bodies_high: int
    materials: int
    pairs: int
    contacts_high: int


# --------------------------------------------------------------------------
# Materials and bodies
# --------------------------------------------------------------------------

class Material(_Handle):
    """A named material of a world (a handle; compare with ==)."""

    __slots__ = ("_world", "_index", "_generation", "name")
    _COPY_HINT = ("material of one world; use the Material itself (handles compare equal), "
                  "or its name")

    def __init__(self, world: "World", cid: Any, name: str) -> None:
        self._world = world
        self._index = int(cid.index)
        self._generation = int(cid.generation)
        self.name = name  #: the material's name

    def _cid(self) -> Any:
        return (self._index, self._generation)

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Material) and other._world is self._world
                and other._cid() == self._cid())

    def __hash__(self) -> int:
        return hash((id(self._world), self._cid()))

    def __repr__(self) -> str:
        return "Material(%r)" % self.name


@dataclass(frozen=True, eq=False)
class BodyState:
    """A body's full state, copied out (arrays are copies).  == compares
    every field exactly (arrays element by element); not hashable (its
    arrays can change)."""

    type: str                     #: "sphere" or "plane"
    slot: int
    name: str
    position: np.ndarray          #: sphere centre or plane point, m
    orientation: np.ndarray       #: [w, x, y, z]
    velocity: np.ndarray          #: COM velocity, m/s
    angular_velocity: np.ndarray  #: rad/s
    normal: np.ndarray            #: planes only
    radius: float                 #: spheres only, m
    mass: float                   #: kg
    force: np.ndarray             #: N
    torque: np.ndarray            #: N m
    color: int                    #: 0xRRGGBB
    texture: str
    fixed: bool

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, BodyState):
            return NotImplemented
        return _fields_equal(self, other, [f for f in self.__dataclass_fields__])

    __hash__ = None  # type: ignore[assignment]


class Body(_Handle):
    """A body of a world, by id (slot index + generation).

    Getters copy the state out; setters validate (finite numbers) and call
    the library, which holds a sphere's value to the limits add_sphere
    applies to the same argument (its energies and momenta at most 1e300 in
    SI units: ``velocity = (1e308, 0, 0)`` raises the library's
    :class:`~rbsim.InvalidError`, the world unchanged).  Using a body after it was removed raises
    :class:`~rbsim.StaleIdError`.  A Body cannot be copied or pickled (use
    it as it is, or :meth:`state` for a copy of its state).
    """

    __slots__ = ("_world", "_index", "_generation")
    _COPY_HINT = ("body of one world; use the Body itself (handles compare equal), "
                  "or body.state() for a copy of its state")

    def __init__(self, world: "World", bid: Any) -> None:
        self._world = world
        self._index = int(bid.index)
        self._generation = int(bid.generation)

    def _bid(self) -> Tuple[int, int]:
        return (self._index, self._generation)

    @property
    def world(self) -> "World":
        """The world this body belongs to."""
        return self._world

    @property
    def slot(self) -> int:
        """Row of this body in the world's state arrays."""
        return self._index

    def state(self) -> BodyState:
        """The full state, copied out."""
        s = self._world._body_state(self._bid())
        return BodyState(
            type=_BODY_TYPES.get(int(s.type), "none"), slot=int(s.slot),
            name=_str(s.name), position=_vec3(s.position),
            orientation=_quat(s.orientation), velocity=_vec3(s.velocity),
            angular_velocity=_vec3(s.angular_velocity), normal=_vec3(s.normal),
            radius=float(s.radius), mass=float(s.mass), force=_vec3(s.force),
            torque=_vec3(s.torque), color=int(s.color),
            texture=_reverse(_TEXTURES, int(s.texture)), fixed=bool(s.fixed))

    @property
    def name(self) -> str:
        """The body's name ("" if unnamed)."""
        return _str(self._world._body_state(self._bid()).name)

    @property
    def type(self) -> str:
        """"sphere" or "plane"."""
        return _BODY_TYPES.get(int(self._world._body_state(self._bid()).type), "none")

    @property
    def radius(self) -> float:
        """Radius, m (spheres; 0 for planes)."""
        return float(self._world._body_state(self._bid()).radius)

    @property
    def mass(self) -> float:
        """Mass, kg."""
        return float(self._world._body_state(self._bid()).mass)

    @property
    def center_of_mass(self) -> np.ndarray:
        """Offset of the centre of mass from the centre, body frame, m."""
        return self._world._body_inertia(self._bid())[0]

    @property
    def inertia(self) -> np.ndarray:
        """Inertia tensor about the centre of mass, body frame, kg m^2
        (3 x 3, a copy; zeros for planes)."""
        return self._world._body_inertia(self._bid())[1]

    @property
    def normal(self) -> np.ndarray:
        """Outward unit normal (planes)."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _vec3(s.normal)

    @property
    def fixed(self) -> bool:
        """True if the body never moves."""
        return bool(self._world._body_state(self._bid()).fixed)

    @property
    def position(self) -> np.ndarray:
        """Sphere centre or plane point, m (a copy; assign to move)."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _vec3(s.position)

    @position.setter
    def position(self, value: Vector) -> None:
        self._world._set_vec(lib.rbs_body_set_position, self, value, "position")

    @property
    def velocity(self) -> np.ndarray:
        """Velocity of the centre of mass, m/s."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _vec3(s.velocity)

    @velocity.setter
    def velocity(self, value: Vector) -> None:
        self._world._set_vec(lib.rbs_body_set_velocity, self, value, "velocity")

    @property
    def angular_velocity(self) -> np.ndarray:
        """Angular velocity, rad/s, world frame."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _vec3(s.angular_velocity)

    @angular_velocity.setter
    def angular_velocity(self, value: Vector) -> None:
        self._world._set_vec(lib.rbs_body_set_angular_velocity, self, value,
                             "angular_velocity")

    @property
    def orientation(self) -> np.ndarray:
        """Unit quaternion [w, x, y, z] (body frame to world frame)."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _quat(s.orientation)

    @orientation.setter
    def orientation(self, value: Vector) -> None:
        q = _check.nonzero(_check.vector(value, "orientation", 4), "orientation",
                           "quaternion [w, x, y, z]")
        cid = self._world._cbody(self)
        cq = ffi.new("rbs_quat *")
        cq.w, cq.x, cq.y, cq.z = q
        self._world._call(lib.rbs_body_set_orientation, cid[0], cq[0])

    @property
    def force(self) -> np.ndarray:
        """Constant applied force at the centre of mass, N, world frame."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _vec3(s.force)

    @force.setter
    def force(self, value: Vector) -> None:
        self._world._set_vec(lib.rbs_body_set_force, self, value, "force")

    @property
    def torque(self) -> np.ndarray:
        """Constant applied torque, N m, world frame."""
        s = self._world._body_state(self._bid())  # keep the owner alive
        return _vec3(s.torque)

    @torque.setter
    def torque(self, value: Vector) -> None:
        self._world._set_vec(lib.rbs_body_set_torque, self, value, "torque")

    def remove(self) -> None:
        """Remove the body from its world; this handle becomes stale."""
        self._world.remove_body(self)

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Body) and other._world is self._world
                and other._bid() == self._bid())

    def __hash__(self) -> int:
        return hash((id(self._world), self._bid()))

    def __repr__(self) -> str:
        try:
            s = self._world._body_state(self._bid())
            return "Body(%r, %s, slot=%d)" % (_str(s.name),
                                              _BODY_TYPES.get(int(s.type), "?"),
                                              self._index)
        except _e.Error:
            return "Body(<stale>, slot=%d)" % self._index


def _reverse(table: Mapping[str, int], value: int) -> str:
    for k, v in table.items():
        if v == value:
            return k
    return str(value)


class BodyMap(_Handle, Mapping[str, Body]):
    """The named bodies of a world: ``world.bodies["ball"]``.  Unnamed
    bodies are left out (see :meth:`World.all_bodies`).  A live view: it
    reflects bodies added or removed later."""

    _COPY_HINT = "bodies of one world (a live view); use dict(world.bodies) for a snapshot"

    def __init__(self, world: "World") -> None:
        self._world = world

    def __getitem__(self, name: str) -> Body:
        # Any str that names no body is a KeyError (NotFoundError), so that
        # [], get() and `in` agree (Mapping's get and `in` catch only
        # KeyError): one the library cannot be given (a NUL, a lone
        # surrogate) too, after a closed world has said so.  get("a\0")
        # raised body("a\0")'s InvalidError while `"a\0" in` was False (a
        # probe of session 50).
        if isinstance(name, str):
            try:
                name.encode("utf-8")
                bad = "\0" in name
            except UnicodeEncodeError:
                bad = True
            if bad:
                self._world._acquire()  # (a closed world still says so)
                self._world._lock.release()
                raise _e.error_class(lib.RBS_E_NOT_FOUND)("no body named %r" % name)
        return self._world.body(name)

    def __iter__(self) -> Iterator[str]:
        return iter([b.name for b in self._world.all_bodies() if b.name])

    def __len__(self) -> int:
        return sum(1 for b in self._world.all_bodies() if b.name)

    def __repr__(self) -> str:
        try:
            return "BodyMap(%r)" % list(self)
        except _e.Error as exc:  # (repr never raises: closed, busy, ...)
            return "BodyMap(<%s>)" % exc


# --------------------------------------------------------------------------
# World
# --------------------------------------------------------------------------

class World(_Handle):
    """A simulated world of spheres and planes.

    Every keyword is optional; None keeps the library's default (see
    rbsim.h, ``rbs_world_def``).  Capacities are fixed for the world's life.

    Args:
        max_bodies: spheres + planes, 1 to 2**24 (default 64).
        max_materials: named materials, 0 to 4096 (default 16).
        max_pairs: material-pair rows, 0 to 65536 (default 64).
        max_contacts: contacts per step, 0 to 2**26 (default and 0:
                4*max_bodies+16).
        dt: step, s, > 0 (default 0.001).
        gravity: m/s^2, or N in "force" mode (default (0, 0, -9.81)).
        gravity_mode: "acceleration" (default) or "force".
        restitution: fallback coefficient of restitution in [0, 1].
        method: one of :data:`METHODS` (default "auto": "soft" from
                64 moving spheres on without mutual gravity and with
                their masses within a ratio of 1e4, else "euler";
                see :attr:`World.method_in_use`).
        tolerance: the adaptive method's error tolerance (>= 1e-15).
        slop: allowed overlap relative to the smaller radius of a pair,
                in (0, 0.1).
        max_halvings: rollback floor dt / 2**max_halvings, 0 to 60.
        max_sweeps: impulse sweeps per contact pass, selective fix-up rounds
                and separation iterations, 1 to 100000.
        max_substeps: a step's work cap, 1 to 2**32 - 1 (default 4096):
                sub-steps + rollbacks of euler, verlet and rk4 (never
                more), contact events of adaptive in one frame; at it the
                rest of the frame is one sub-step with overlap pushed
                apart, reported in :attr:`StepInfo.work_limit` (rbsim.h,
                ``max_substeps``).
        soft_substeps: sub-steps per frame of the "soft" method, 1 to 1000
                (default 3); more make piles stiffer, at a cost in proportion.
        soft_tolerance: the "soft" method's overlap budget, a fraction of the
                smaller radius of a pair, 0 to 1 (default 0: every frame
                takes soft_substeps); > 0 lets a frame take fewer sub-steps
                (soft_substeps halved, down to 1) while every contact's
                reachable overlap stays under
                soft_tolerance * n / soft_substeps of that radius.
        mutual_gravity: Newtonian attraction between bodies.
        gravity_constant: G, m^3 kg^-1 s^-2, >= 0; > 0 with mutual_gravity on.
        softening: Plummer softening length, m, >= 0.
        prune: leave out stages that cannot change the result (default True).
        threads: threads that step the world, the caller's included, 1 to
                16 (default 1; see :attr:`World.threads`).

    A World cannot be copied or pickled (copy.copy would share the C
    world); duplicate one through :meth:`checkpoint` and
    :meth:`from_checkpoint`, or :meth:`save` and :meth:`restore`.

    Raises:
        InvalidError: a value out of range (the message names it, gives
                its range and echoes the value exactly).
        ArgumentTypeError, NumericError: a wrong type, NaN or infinity.
    """

    _COPY_HINT = ("world; duplicate it with World.from_checkpoint(world.checkpoint()), "
                  "or world.save(path) and rbsim.resume(path)")

    @_check.keywords
    def __init__(self, *, max_bodies: Optional[int] = None,
                 max_materials: Optional[int] = None,
                 max_pairs: Optional[int] = None,
                 max_contacts: Optional[int] = None,
                 dt: Optional[float] = None,
                 gravity: Optional[Vector] = None,
                 gravity_mode: Optional[str] = None,
                 restitution: Optional[float] = None,
                 method: Optional[str] = None,
                 tolerance: Optional[float] = None,
                 slop: Optional[float] = None,
                 max_halvings: Optional[int] = None,
                 max_sweeps: Optional[int] = None,
                 max_substeps: Optional[int] = None,
                 soft_substeps: Optional[int] = None,
                 soft_tolerance: Optional[float] = None,
                 mutual_gravity: Optional[bool] = None,
                 gravity_constant: Optional[float] = None,
                 softening: Optional[float] = None,
                 prune: Optional[bool] = None,
                 threads: Optional[int] = None) -> None:
        self._init_fields()
        d = ffi.new("rbs_world_def *")
        lib.rbs_world_def_init_sized(d, ffi.sizeof("rbs_world_def"))
        for key, value in (("max_bodies", max_bodies), ("max_materials", max_materials),
                           ("max_pairs", max_pairs)):
            if value is not None:
                setattr(d, key, _check.integer(value, key, *_INT_RANGES[key]))
        if max_contacts is not None:
            d.max_contacts = _check.integer(max_contacts, "max_contacts",
                                            *_INT_RANGES["max_contacts"])
        if d.max_contacts == 0 and 4 * d.max_bodies + 16 > _INT_RANGES["max_contacts"][1]:
            # (the library's message gave the default as if it were asked for)
            raise _e.error_class(lib.RBS_E_INVALID)(
                "max_contacts: its default, 4 x max_bodies + 16, is %d for max_bodies=%d, "
                "over %d: give max_contacts" % (4 * d.max_bodies + 16, d.max_bodies,
                                                _INT_RANGES["max_contacts"][1]))
        for key, value in (("max_halvings", max_halvings), ("max_sweeps", max_sweeps),
                           ("max_substeps", max_substeps), ("soft_substeps", soft_substeps)):
            if value is not None:
                setattr(d, key, _check.integer(value, key, *_INT_RANGES[key]))
        for key, value in (("dt", dt), ("restitution", restitution),
                           ("tolerance", tolerance), ("slop", slop),
                           ("soft_tolerance", soft_tolerance)):
            if value is not None:
                setattr(d, key, _check.real_in(value, key, **_REAL_RANGES[key]))
        for key, value in (("gravity_constant", gravity_constant),
                           ("softening", softening)):
            if value is not None:
                setattr(d, key, _check.real_in(value, key, 0.0))
        if gravity is not None:
            _set_vec3(d.gravity, _check.vector(gravity, "gravity"))
        if gravity_mode is not None:
            d.gravity_mode = _GRAVITY_MODES[_check.choice(
                gravity_mode, "gravity_mode", tuple(_GRAVITY_MODES))]
        if method is not None:
            d.method = _method_value(method)
        if mutual_gravity is not None:
            d.mutual_gravity = int(_check.flag(mutual_gravity, "mutual_gravity"))
        if prune is not None:
            d.prune = int(_check.flag(prune, "prune"))
        n_threads = None if threads is None else _check.integer(
            threads, "threads", 1, lib.RBS_WORKERS_MAX)
        self._create(d)
        if n_threads is not None:
            self.threads = n_threads

    # -- creation ---------------------------------------------------------

    def _create(self, d: Any) -> None:
        """Create the C world for definition d in a block owned by Python."""
        size = lib.rbs_world_memory_size(d)
        if size == 0:
            raise _e.error_class(lib.RBS_E_INVALID)(_def_problem(d))
        # numpy's zeros come from calloc: pages the world never writes (the
        # capacity a run does not reach) stay address space, not memory, as
        # with rbs_world_create -- where ffi.new's zero fill, and
        # rbs_world_create_in's, made all of it resident (2,165 bytes a body
        # at 1e5 bodies against C's few hundred: a probe of session 38).
        zeros = np.zeros(size + _ALIGN, dtype=np.uint8)
        self._mem = ffi.from_buffer("char[]", zeros)
        address = int(ffi.cast("uintptr_t", self._mem))
        self._offset = (-address) % _ALIGN
        self._base = address + self._offset
        self._size = size
        # Read-only bytes of the block: every state view is a slice of it
        # (through a read-only memoryview of zeros, which keeps it alive).
        self._block = np.frombuffer(memoryview(zeros).toreadonly(), dtype=np.uint8)
        out = ffi.new("rbs_world **")
        status = lib.rbs_world_create_in_zeroed(self._mem + self._offset, size, d, out)
        if status != lib.RBS_OK:
            raise _e.error_class(status)(_def_problem(d, status))
        self._world = out[0]
        self._lib_owned = False

    def _init_fields(self) -> None:
        """The fields every way of making a World starts from."""
        self._world: Any = ffi.NULL
        self._pool: Any = ffi.NULL  # rbs_pool lent to the world, or NULL
        self._lock = threading.Lock()
        #: whether a Run holds the world (start() until its wait()), for
        #: the busy message (a flag, not the Run: no reference cycle)
        self._held_by_run = False
        #: seconds the last step took (World.step's slices), None at first
        self._step_seconds: Optional[float] = None
        self._scene_steps: Optional[int] = None
        self._scene_pause_on_collision = False
        #: the files the scene was read from (rbs_scene_source: the scene,
        #: a text scene's materials and objects files), which save() does
        #: not write over; () for a world not loaded from a file
        self._scene_files: Tuple[bytes, ...] = ()
        #: the scene's description ("" for a world built in code)
        self.description = ""
        #: the scene's "renderers" entries (dicts); run() does not run them
        self.scene_renderers: List[Dict[str, Any]] = []

    @classmethod
    def _adopt(cls, cworld: Any) -> "World":
        """Wrap a world the library allocated (checkpoints).  Its block is
        freed by rbs_world_destroy only when the World and every state view
        are gone (a cffi gc owner kept by the views' buffer)."""
        self = cls.__new__(cls)
        self._init_fields()
        usage = ffi.new("rbs_usage *")
        status = lib.rbs_world_usage(cworld, usage)
        if status != lib.RBS_OK or usage.bytes == 0:
            lib.rbs_world_destroy(cworld)
            raise _e.error_class(status if status != lib.RBS_OK else lib.RBS_E_INVALID)(
                "cannot size the restored world")
        size = int(usage.bytes)
        self._mem = ffi.gc(ffi.cast("char *", cworld),
                           lambda p: lib.rbs_world_destroy(ffi.cast("rbs_world *", p)),
                           size=size)
        self._offset = 0
        self._base = int(ffi.cast("uintptr_t", cworld))
        self._size = size
        self._block = np.frombuffer(memoryview(ffi.buffer(self._mem, size)).toreadonly(),
                                    dtype=np.uint8)
        self._world = cworld
        self._lib_owned = True
        return self

    @classmethod
    def from_checkpoint(cls, data: Union[bytes, bytearray, memoryview]) -> "World":
        """A world restored from :meth:`checkpoint` bytes: the exact state,
        every double bit for bit, so stepping it continues the original run
        identically.

        Raises:
            CorruptError: truncated, damaged or foreign bytes.
            VersionError: another checkpoint format version.
        """
        if not isinstance(data, (bytes, bytearray, memoryview)):
            raise _e.ArgumentTypeError("data: expected bytes, got %s"
                                       % _check._describe(data))
        raw = bytes(data)
        out = ffi.new("rbs_world **")
        msg = ffi.new("char[]", 512)
        status = lib.rbs_world_create_from_checkpoint_v2(raw, len(raw), out, msg, 512)
        if status != lib.RBS_OK:
            raise _e.error_class(status)("checkpoint of %d bytes rejected: %s" % (len(raw), _str(msg)))
        return cls._adopt(out[0])

    @classmethod
    def restore(cls, path: Any) -> "World":
        """A world loaded from a file written by :meth:`save` (CorruptError,
        VersionError or IoError with the reason if it cannot be)."""
        raw = _check.path(path, "path")
        out = ffi.new("rbs_world **")
        msg = ffi.new("char[]", 512)
        status = lib.rbs_world_load(raw, out, msg, 512)
        if status != lib.RBS_OK:
            # (the library's message names the file: "PATH: REASON")
            raise _e.error_class(status)(_str(msg) or raw.decode("utf-8", "replace"))
        return cls._adopt(out[0])

    @classmethod
    def _from_def(cls, d: Any) -> "World":
        self = cls.__new__(cls)
        self._init_fields()
        self._create(d)
        return self

    def __setattr__(self, name: str, value: Any) -> None:
        # A public name is set only through a property (dt, method,
        # tolerance, threads: their setters check the value) or is one of the
        # two scene attributes.  Any other (world.slop = 1e-3, a typo such
        # as world.mehtod = "rk4", world.step = 5) made a Python attribute
        # that the simulation never read: a silent no-op.
        # (A read-only property -- time, gravity, settings -- is refused
        # here too, so its message names the settable ones as well; Python's
        # own said only "property 'time' of 'World' object has no setter".)
        prop = getattr(type(self), name, None)
        if (not name.startswith("_") and name not in ("description", "scene_renderers")
                and not (isinstance(prop, property) and prop.fset is not None)):
            settable = sorted(k for k, v in vars(World).items()
                              if isinstance(v, property) and v.fset is not None)
            hint = ""
            if name in inspect.signature(World.__init__).parameters:
                hint = (" (it is fixed when the world is made: World(%s=...), or "
                        "rbsim.load(...) from a scene)" % name)
            raise AttributeError(
                "World has no settable attribute %r%s; settable: %s"
                % (name, hint, ", ".join(settable)))
        object.__setattr__(self, name, value)

    def close(self) -> None:
        """Destroy the C world.  State arrays taken before stay readable
        (they stop changing); any other use raises ClosedError.  Idempotent."""
        if not self._lock.acquire(blocking=False):
            if self._held_by_run:
                raise _e.BusyError("cannot close the world: " + _HELD_BY_RUN)
            raise _e.BusyError("world is in use by another thread; cannot close it")
        try:
            self._release_world()
        finally:
            self._lock.release()

    def _release_world(self) -> None:
        """Destroy the C world; the memory goes when the last view does."""
        if self._world == ffi.NULL:
            return
        if self._pool != ffi.NULL:
            lib.rbs_world_set_workers(self._world, ffi.NULL)
            lib.rbs_pool_destroy(self._pool)
            self._pool = ffi.NULL
        if not self._lib_owned:
            lib.rbs_world_destroy(self._world)  # our block: nothing is freed
        self._world = ffi.NULL
        self._block = None  # views keep what they need of the memory
        self._mem = None

    def __enter__(self) -> "World":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        # (a Run not waited on still holds the world: it is left to the
        # Run, which keeps the memory alive and ends its projector -- the
        # world destroyed first, in a reference cycle at exit, had the
        # projector write into freed memory: a probe of session 40)
        if getattr(self, "_world", ffi.NULL) != ffi.NULL and not getattr(self, "_held_by_run", False):
            self._release_world()

    @property
    def threads(self) -> int:
        """Threads that step the world, the stepping thread included (1: the
        caller's alone, the default).  Setting N > 1 lends the world a pool
        of N - 1 threads of the library's (rbs_pool_create), replacing any
        earlier pool; 1 releases it.  The soft method's piles split each
        step among them; every other step runs on one thread.  The results
        are the same bits for any N.  A restored or scene-built world starts
        with 1.

        Raises:
            InvalidError: N outside 1 .. 16.
            MemoryError: the threads could not be started.
        """
        w = self._acquire()
        try:
            return int(lib.rbs_world_workers(w))
        finally:
            self._lock.release()

    @threads.setter
    def threads(self, n: int) -> None:
        n = _check.integer(n, "threads", 1, lib.RBS_WORKERS_MAX)
        w = self._acquire()
        try:
            pool = ffi.NULL
            if n > 1:
                out = ffi.new("rbs_pool **")
                status = lib.rbs_pool_create(n - 1, out)
                if status != lib.RBS_OK:
                    raise _e.error_class(status)("threads: cannot start %d threads" % (n - 1))
                pool = out[0]
                workers = ffi.new("rbs_workers *")
                lib.rbs_workers_init_sized(workers, ffi.sizeof("rbs_workers"))
                status = lib.rbs_pool_workers(pool, workers)
                if status == lib.RBS_OK:
                    status = lib.rbs_world_set_workers(w, workers)
                if status != lib.RBS_OK:
                    lib.rbs_pool_destroy(pool)
                    raise _e.error_class(status)("threads: " + _str(lib.rbs_world_last_error(w)))
            else:
                status = lib.rbs_world_set_workers(w, ffi.NULL)
                if status != lib.RBS_OK:
                    raise _e.error_class(status)("threads: " + _str(lib.rbs_world_last_error(w)))
            if self._pool != ffi.NULL:
                lib.rbs_pool_destroy(self._pool)
            self._pool = pool
        finally:
            self._lock.release()

    @property
    def closed(self) -> bool:
        """True after :meth:`close`."""
        return self._world == ffi.NULL

    # -- calling C --------------------------------------------------------

    def _acquire(self) -> Any:
        if not self._lock.acquire(blocking=False):
            if self._held_by_run:
                # (a run not waited on held it until the garbage collector
                # came, and the message blamed another thread: a probe of
                # session 40)
                raise _e.BusyError(_HELD_BY_RUN)
            raise _e.BusyError("world is in use by another thread (a World is not "
                               "thread-safe; give each thread its own)")
        if self._world == ffi.NULL:
            self._lock.release()
            raise _e.error_class(lib.RBS_E_CLOSED)("world is closed")
        return self._world

    def _call(self, fn: Any, *args: Any) -> None:
        """fn(world, *args) under the lock, for functions that change the
        world (they explain failures in rbs_world_last_error); raise on a
        negative status."""
        w = self._acquire()
        try:
            status = fn(w, *args)
            if status != lib.RBS_OK:
                raise _e.error_class(status)(_str(lib.rbs_world_last_error(w)))
        finally:
            self._lock.release()

    def _query(self, what: str, fn: Any, *args: Any) -> None:
        """fn(world, *args) under the lock, for functions on a const world
        (which cannot record an error text): what explains a failure."""
        w = self._acquire()
        try:
            status = fn(w, *args)
        finally:
            self._lock.release()
        if status != lib.RBS_OK:
            raise _e.error_class(status)(what)

    def _value(self, fn: Any, *args: Any) -> Any:
        """fn(world, *args) under the lock, for functions that cannot fail."""
        w = self._acquire()
        try:
            return fn(w, *args)
        finally:
            self._lock.release()

    def _cbody(self, body: Any) -> Any:
        if not isinstance(body, Body):
            raise _e.ArgumentTypeError("expected a Body, got %s" % _check._describe(body))
        if body._world is not self:
            raise _e.error_class(lib.RBS_E_STALE_ID)("body %r belongs to another world"
                                                     % body)
        cid = ffi.new("rbs_body_id *")
        cid.index, cid.generation = body._bid()
        return cid  # the owner: use cid[0] while cid is alive

    def _body_state(self, bid: Tuple[int, int]) -> Any:
        cid = ffi.new("rbs_body_id *")
        cid.index, cid.generation = bid
        out = ffi.new("rbs_body_state *")
        self._query("body {%d, %d}: removed, or not of this world" % bid,
                    lib.rbs_body_get_state, cid[0], out)
        return out

    def _body_inertia(self, bid: Tuple[int, int]) -> Tuple[np.ndarray, np.ndarray]:
        cid = ffi.new("rbs_body_id *")
        cid.index, cid.generation = bid
        com = ffi.new("rbs_vec3 *")
        tensor = ffi.new("double[9]")
        self._query("body {%d, %d}: removed, or not of this world" % bid,
                    lib.rbs_body_get_inertia, cid[0], com, tensor)
        return _vec3(com[0]), np.array(list(tensor), dtype=np.float64).reshape(3, 3)

    def _set_vec(self, fn: Any, body: Body, value: Vector, what: str) -> None:
        v = _check.vector(value, what)
        cid = self._cbody(body)
        cv = ffi.new("rbs_vec3 *")
        _set_vec3(cv, v)
        self._call(fn, cid[0], cv[0])

    # -- materials ----------------------------------------------------------

    def add_material(self, name: str) -> Material:
        """Add a named material (names are unique; 1 to 63 bytes of UTF-8
        under the scene files' rule: no spaces, control characters, '#',
        '"', '=', ',' nor invisible formatting characters, and not "*";
        else InvalidError naming the character and its byte)."""
        # (the library judges the name, and its message says why: one rule)
        raw = _check.text(name, "name")
        out = ffi.new("rbs_material_id *")
        self._call(lib.rbs_world_add_material, raw, out)
        return Material(self, out, name)

    def material(self, name: str) -> Material:
        """The material of that name (NotFoundError, a KeyError, if none:
        "" too, as for :meth:`body`)."""
        raw = _check.text(name, "name")
        out = ffi.new("rbs_material_id *")
        self._query("no material named %r" % name, lib.rbs_world_find_material,
                    raw, out)
        return Material(self, out, name)

    def _materials_locked(self, w: Any) -> List[Material]:
        out: List[Material] = []
        cid = ffi.new("rbs_material_id *")
        name = ffi.new("char **")
        while lib.rbs_world_material_at(w, len(out), cid, name) == lib.RBS_OK:
            out.append(Material(self, cid, ffi.string(name[0]).decode("utf-8", "replace")))
        return out

    def materials(self) -> List[Material]:
        """Every material, in the order they were added."""
        w = self._acquire()
        try:
            return self._materials_locked(w)
        finally:
            self._lock.release()

    def pairs(self) -> List[Dict[str, Any]]:
        """Every material-pair row, in the order rows were first set, as
        dicts with a, b (Material, or "*" for any), static, kinetic,
        restitution (negative: the world's), rolling and spinning."""
        out: List[Dict[str, Any]] = []
        d = ffi.new("rbs_pair_def *")
        w = self._acquire()
        try:
            mats = self._materials_locked(w)
            while True:
                lib.rbs_pair_def_init_sized(d, ffi.sizeof("rbs_pair_def"))
                if lib.rbs_world_pair_at(w, len(out), d) != lib.RBS_OK:
                    break
                out.append({
                    "a": mats[d.a.index] if d.a.generation else "*",
                    "b": mats[d.b.index] if d.b.generation else "*",
                    "static": d.static_friction, "kinetic": d.kinetic_friction,
                    "restitution": d.restitution, "rolling": d.rolling,
                    "spinning": d.spinning})
        finally:
            self._lock.release()
        return out

    def _cmaterial(self, m: Union[Material, str, None], what: str,
                   any_ok: bool = True) -> Any:
        out = ffi.new("rbs_material_id *")
        if isinstance(m, str) and m == "*" and not any_ok:
            # (a body's material="*" was taken as no material, silently; a
            # scene refuses it: a probe of session 50)
            raise _e.error_class(lib.RBS_E_INVALID)(
                "%s: \"*\" is not a material: it stands for any material in a pair "
                "(set_material); give a Material or its name, or None for none" % what)
        if m is None or (isinstance(m, str) and m == "*"):
            return out  # null: "*", any material (the owner; use out[0])
        if isinstance(m, str):
            m = self.material(m)
        if not isinstance(m, Material):
            raise _e.ArgumentTypeError("%s: expected a Material, a name or '*', got %s"
                                       % (what, _check._describe(m)))
        if m._world is not self:
            raise _e.error_class(lib.RBS_E_STALE_ID)(
                "%s: material %r belongs to another world" % (what, m.name))
        out.index, out.generation = m._cid()
        return out  # the owner: use out[0] while out is alive

    @_check.keywords
    def set_material(self, a: Union[Material, str, None],
                     b: Union[Material, str, None], *,
                     static: Optional[float] = None,
                     kinetic: Optional[float] = None,
                     restitution: Optional[float] = None,
                     rolling: Optional[float] = None,
                     spinning: Optional[float] = None) -> None:
        """Set (add or replace) the contact properties of a pair of
        materials.  a and b are Materials, names, or "*"/None for any.

        Args:
            static: static friction coefficient (>= kinetic; default 0.5).
            kinetic: kinetic friction coefficient (>= 0; default 0.3).
            restitution: in [0, 1]; None keeps the world's.
            rolling: rolling resistance, dimensionless.
            spinning: spinning resistance, m.
        """
        d = ffi.new("rbs_pair_def *")
        lib.rbs_pair_def_init_sized(d, ffi.sizeof("rbs_pair_def"))
        ma = self._cmaterial(a, "a")
        mb = self._cmaterial(b, "b")
        d.a, d.b = ma[0], mb[0]
        for key, field, value in (("static", "static_friction", static),
                                  ("kinetic", "kinetic_friction", kinetic),
                                  ("restitution", "restitution", restitution),
                                  ("rolling", "rolling", rolling),
                                  ("spinning", "spinning", spinning)):
            if value is not None:
                if key == "restitution":
                    # (C's negative "the world's" is None here, not a number)
                    x = _check.real_in(value, key, 0.0, 1.0, note=" (None keeps the world's)")
                else:
                    x = _check.real_in(value, key, 0.0)
                setattr(d, field, x)
        if d.kinetic_friction > d.static_friction:
            # (the one not given is the default, 0.5 static, 0.3 kinetic)
            if static is None:
                raise _e.error_class(lib.RBS_E_INVALID)(
                    "kinetic: must be <= static (%r, the default), got %s"
                    % (d.static_friction, _check.number(kinetic, d.kinetic_friction)))
            if kinetic is None:
                raise _e.error_class(lib.RBS_E_INVALID)(
                    "static: must be >= kinetic (%r, the default), got %s"
                    % (d.kinetic_friction, _check.number(static, d.static_friction)))
            raise _e.error_class(lib.RBS_E_INVALID)(
                "kinetic: must be <= static (%s), got %s"
                % (_check.number(static, d.static_friction),
                   _check.number(kinetic, d.kinetic_friction)))
        self._call(lib.rbs_world_set_pair, d)

    # -- bodies -------------------------------------------------------------

    @_check.keywords
    def add_sphere(self, name: Optional[str] = None, *,
                   radius: Optional[float] = None,
                   mass: Optional[float] = None,
                   density: Optional[float] = None,
                   position: Optional[Vector] = None,
                   velocity: Optional[Vector] = None,
                   angular_velocity: Optional[Vector] = None,
                   orientation: Optional[Vector] = None,
                   inertia: Union[str, Vector, None] = None,
                   center_of_mass: Optional[Vector] = None,
                   force: Optional[Vector] = None,
                   torque: Optional[Vector] = None,
                   material: Union[Material, str, None] = None,
                   color: Optional[int] = None,
                   texture: Optional[str] = None,
                   fixed: Optional[bool] = None) -> Body:
        """Add a sphere; None keeps the library's default.

        Args:
            name: optional unique name (None or "": unnamed), under the
                scene files' rule as for add_material (InvalidError with
                the library's message, naming the character and its
                byte).  An unnamed body is kept by save() and
                checkpoint(), but is not in :attr:`bodies`.
            radius: m, > 0 (default 0.1).
            mass: kg, > 0 (default 1).
            density: kg/m^3, >= 0 (default 0: use mass); mass = density
                4/3 pi r^3.  Give mass or density, not both (as a scene:
                InvalidError).
            position, velocity, angular_velocity: m, m/s, rad/s (world).
            orientation: quaternion [w, x, y, z], normalised on add.
            inertia: "solid" (default), "hollow", or principal moments
                (Ix, Iy, Iz) about the centre, kg m^2, body axes.
            center_of_mass: offset from the centre, body frame, m.
            force, torque: constant applied force (N) and torque (N m).
            material: a Material or its name (None: no material).
            color: 0xRRGGBB.  texture: "none", "stripes" or "checker".
            fixed: never moves (infinite mass); velocity and
                angular_velocity must then be zero.

        Raises:
            InvalidError: a value out of range, both mass and density
                given, a velocity for a fixed
                sphere, or an energy at the start beyond 1e300 J (or a
                momentum beyond 1e300 kg m/s, kg m^2/s)
                (message from the library).
            CapacityError: max_bodies reached (the world is unchanged).
        """
        d = ffi.new("rbs_sphere_def *")
        lib.rbs_sphere_def_init_sized(d, ffi.sizeof("rbs_sphere_def"))
        keep = []
        if name is not None:
            raw = _check.text(name, "name")
            keep.append(ffi.new("char[]", raw))
            d.name = keep[-1]
        # (the library's ranges, checked here to echo the value exactly)
        if radius is not None:
            d.radius = _check.real_in(radius, "radius", 0.0, open_low=True)
        if mass is not None and density is not None:
            # (the C def has a default mass, so only here is "both" seen)
            raise _e.error_class(-1)(
                "mass and density: give one of them, not both (got mass=%r, "
                "density=%r), as in a scene" % (mass, density))
        if density is not None:
            d.density = _check.real_in(density, "density", 0.0, note=" (0: from mass)")
        if mass is not None:
            d.mass = _check.real_in(mass, "mass", 0.0, open_low=True)
        for key, value in (("position", position), ("velocity", velocity),
                           ("angular_velocity", angular_velocity),
                           ("center_of_mass", center_of_mass),
                           ("force", force), ("torque", torque)):
            if value is not None:
                _set_vec3(getattr(d, key), _check.vector(value, key))
        if orientation is not None:
            q = _check.nonzero(_check.vector(orientation, "orientation", 4), "orientation",
                               "quaternion [w, x, y, z]")
            d.orientation.w, d.orientation.x, d.orientation.y, d.orientation.z = q
        if inertia is not None:
            if isinstance(inertia, str):
                kinds = tuple(k for k in _INERTIA if k != "principal")
                d.inertia_kind = _INERTIA[_check.choice(inertia, "inertia", kinds)]
            else:
                d.inertia_kind = _INERTIA["principal"]
                _set_vec3(d.inertia, _principal_moments(inertia))
        if material is not None:
            mat = self._cmaterial(material, "material", any_ok=False)
            d.material = mat[0]
        if color is not None:
            d.color = _check.integer(color, "color", 0, 0xFFFFFF)
        if texture is not None:
            d.texture = _TEXTURES[_check.choice(texture, "texture", tuple(_TEXTURES))]
        if fixed is not None:
            d.fixed = int(_check.flag(fixed, "fixed"))
        out = ffi.new("rbs_body_id *")
        self._call(lib.rbs_world_add_sphere, d, out)
        return Body(self, out)

    @_check.keywords
    def add_plane(self, name: Optional[str] = None, *,
                  point: Optional[Vector] = None,
                  normal: Optional[Vector] = None,
                  material: Union[Material, str, None] = None,
                  color: Optional[int] = None,
                  texture: Optional[str] = None) -> Body:
        """Add a plane: a half-space whose solid side lies behind the
        normal.  point: a point on the plane, m (default origin); normal:
        outward, nonzero, normalised on add (default (0, 0, 1))."""
        d = ffi.new("rbs_plane_def *")
        lib.rbs_plane_def_init_sized(d, ffi.sizeof("rbs_plane_def"))
        keep = []
        if name is not None:
            keep.append(ffi.new("char[]", _check.text(name, "name")))
            d.name = keep[-1]
        if point is not None:
            _set_vec3(d.point, _check.vector(point, "point"))
        if normal is not None:
            _set_vec3(d.normal, _check.nonzero(_check.vector(normal, "normal"), "normal",
                                               "vector (the plane's outward normal)"))
        if material is not None:
            mat = self._cmaterial(material, "material", any_ok=False)
            d.material = mat[0]
        if color is not None:
            d.color = _check.integer(color, "color", 0, 0xFFFFFF)
        if texture is not None:
            d.texture = _TEXTURES[_check.choice(texture, "texture", tuple(_TEXTURES))]
        out = ffi.new("rbs_body_id *")
        self._call(lib.rbs_world_add_plane, d, out)
        return Body(self, out)

    def remove_body(self, body: Body) -> None:
        """Remove a body; its handle becomes stale."""
        cid = self._cbody(body)
        self._call(lib.rbs_world_remove_body, cid[0])

    def body(self, name: str) -> Body:
        """The body of that name (NotFoundError, a KeyError, if none; ""
        names no body: unnamed ones are in :meth:`all_bodies`).  A str the
        library cannot be given (one holding a NUL, a lone surrogate) is an
        InvalidError here; ``world.bodies`` answers it as a name of no
        body."""
        raw = _check.text(name, "name")
        out = ffi.new("rbs_body_id *")
        # (the library's status decides, "" too: rbs_world_find_body's and
        # rbs_world_find_material's one rule, NotFoundError)
        self._query("no body named %r%s" % (name, "" if raw else
                                           " (unnamed bodies have no name to find: "
                                           "see all_bodies())"),
                    lib.rbs_world_find_body, raw, out)
        return Body(self, out)

    @property
    def bodies(self) -> BodyMap:
        """The named bodies, by name (a live mapping)."""
        return BodyMap(self)

    def all_bodies(self) -> List[Body]:
        """Every body, named or not, in slot order."""
        view = self._state_view()
        out = ffi.new("rbs_body_id *")
        found = []
        for slot in range(int(view.slots)):
            w = self._acquire()
            try:
                status = lib.rbs_world_body_at(w, slot, out)
            finally:
                self._lock.release()
            if status == lib.RBS_OK:
                found.append(Body(self, out))
            elif status != lib.RBS_E_NOT_FOUND:
                raise _e.error_class(status)("slot %d" % slot)
        return found

    # -- stepping -----------------------------------------------------------

    def step(self, n: int = 1) -> StepInfo:
        """Advance the world n steps of dt (the GIL is released while C
        steps).  Returns what the steps did (see :class:`StepInfo`).  On
        error the world stays at its last good state and the exception's
        ``steps_done`` tells how many steps were made.  Ctrl-C
        (KeyboardInterrupt) lands within about 20 ms, or one step if a step
        takes longer; the world is then at the last step made (see
        :attr:`step_count`) and usable."""
        count = _check.u64(n, "n")
        total = ffi.new("rbs_step_info *")
        chunk = ffi.new("rbs_step_info *")
        done = ffi.new("uint64_t *")
        made = 0
        if count == 0:
            return StepInfo._from_c(total, 0)
        fields = ("colliding", "resting", "substeps", "rollbacks", "floor_hits",
                  "sweep_limit", "events", "work_limit")
        # C steps in slices of about _STEP_SLICE s: a signal (Ctrl-C) is
        # handled when C returns, so KeyboardInterrupt lands within a slice,
        # or one step of a world slower than that, with the world at the
        # last step made (a fixed 4096 steps a call took minutes for a big
        # world: a probe of session 41).  A slice is sized from the last
        # step's time (the first of a call at most _STEP_FIRST steps, so a
        # world that became slow is not given a long one) and doubles while
        # slices are quick.  The world is held throughout.
        per = self._step_seconds
        size = 1 if per is None else max(1, min(_STEP_FIRST, int(_STEP_SLICE / max(per, 1e-9))))
        status = lib.RBS_OK
        detail = ""
        w = self._acquire()
        try:
            while made < count:
                todo = min(size, count - made)
                start = time.perf_counter()
                status = lib.rbs_py_step(w, todo, chunk, done, ffi.NULL)
                elapsed = time.perf_counter() - start
                made += int(done[0])
                if done[0] > 0:
                    self._step_seconds = elapsed / int(done[0])
                total.contacts = chunk.contacts
                for f in fields:
                    setattr(total, f, getattr(total, f) + getattr(chunk, f))
                total.max_overlap = max(total.max_overlap, chunk.max_overlap)
                if status != lib.RBS_OK:
                    detail = _str(lib.rbs_world_last_error(w))
                    break
                if elapsed > _STEP_SLICE:
                    size = max(1, int(size * _STEP_SLICE / elapsed))
                elif elapsed < _STEP_SLICE / 2 and todo == size:
                    size = min(2 * size, _STEP_SLICE_MAX)
        finally:
            self._lock.release()
        if status != lib.RBS_OK:
            exc = _e.error_class(status)(
                "%s (after %d of %d steps, t = %r s)"
                % (detail, made, count, self.time))
            exc.steps_done = made  # type: ignore[attr-defined]
            raise exc
        return StepInfo._from_c(total, made)

    @_check.keywords
    def run(self, steps: Optional[int] = None, renderers: Sequence[Any] = (), *,
            realtime: bool = False, speed: float = 1.0,
            reel_capacity: Optional[int] = None,
            endless: bool = False) -> "RunInfo":
        """Run through the projector -- the simulation on one thread, the
        renderers on another -- and wait for the end.

        Args:
            steps: steps to take, 0 to 2**53 as a scene's simulation.steps and
                ``rbsim run --steps`` (frames 0..steps; 0: frame 0 only); None: the scene's
                ``simulation.steps`` for a loaded world; steps * dt must be
                finite, as in a scene.
            renderers: a list of Python renderers (at most 4; a single
                renderer, not in a list, is a TypeError): callables ``f(frame)``
                or objects with ``draw(frame)`` and optionally ``finish()``,
                ``close()``, ``every`` and ``live`` (see :class:`Frame`).
            realtime: pace frame k at k dt / speed of wall time.
            speed: real-time factor (> 0).
            reel_capacity: frames in the reel (>= 2).
            endless: run until a renderer raises :class:`StopRun` (or
                "quit"); steps must then be None (a steps given with it is
                an InvalidError, not ignored).  The world then ends at the
                last frame made (``RunInfo.frame``), which the simulation,
                running ahead of the renderers, may have made after the
                frame that raised it; every other renderer gets it.

        Returns:
            a :class:`RunInfo`.  An exception raised by a renderer stops the
            run and is raised again here; a library failure raises its
            rbsim error.  The GIL is released while the run goes on.
        """
        from ._render import run_world
        return run_world(self, steps, renderers, realtime=realtime, speed=speed,
                         reel_capacity=reel_capacity, endless=endless)

    @_check.keywords
    def start(self, steps: Optional[int] = None, renderers: Sequence[Any] = (), *,
              realtime: bool = False, speed: float = 1.0,
              start_paused: bool = False,
              pause_on_collision: Optional[bool] = None,
              reel_capacity: Optional[int] = None,
              endless: bool = False) -> "Run":
        """Start a run (as :meth:`run`) and return at once with a
        :class:`Run` to send commands to ("pause", "resume", "step N",
        "speed X", "quit") and to wait on.  pause_on_collision None takes
        the scene's setting.  The world is busy until ``Run.wait()``.  A run
        never waited on is quit and waited for when the interpreter exits
        (a line on stderr says so)."""
        from ._render import start_world
        return start_world(self, steps, renderers, realtime=realtime, speed=speed,
                           start_paused=start_paused,
                           pause_on_collision=pause_on_collision,
                           reel_capacity=reel_capacity, endless=endless)

    @property
    def time(self) -> float:
        """Simulated time, s (= step count * dt)."""
        return float(self._value(lib.rbs_world_time))

    @property
    def step_count(self) -> int:
        """Steps taken since creation."""
        return int(self._value(lib.rbs_world_step_count))

    @property
    def rounded_steps(self) -> int:
        """Steps since creation or loading in which the rounding of a
        sphere's coordinates lost more than 1 % of a move slower than a
        thousandth of its radius (far from the origin, or a tiny dt: its
        slow motion there is partly lost; faster moves rounded so are
        refused with :class:`NumericError`).  See rbs_world_rounded_steps."""
        return int(self._value(lib.rbs_world_rounded_steps))

    def _def(self) -> Any:
        out = ffi.new("rbs_world_def *")
        lib.rbs_world_def_init_sized(out, ffi.sizeof("rbs_world_def"))
        self._query("rbs_world_get_def", lib.rbs_world_get_def, out)
        return out

    @property
    def dt(self) -> float:
        """Step size, s (settable, > 0)."""
        return float(self._def().dt)

    @dt.setter
    def dt(self, value: float) -> None:
        self._call(lib.rbs_world_set_dt, _check.real_in(value, "dt", **_REAL_RANGES["dt"]))

    @property
    def method(self) -> str:
        """Stepping method, one of :data:`METHODS` (settable)."""
        return METHODS[int(self._def().method)]

    @method.setter
    def method(self, value: str) -> None:
        self._call(lib.rbs_world_set_method, _method_value(value), 0.0)

    @property
    def method_in_use(self) -> str:
        """The method the next step takes: :attr:`method`, or for "auto" the
        one it resolves to for the world as it is now ("euler" or "soft")."""
        return METHODS[int(self._value(lib.rbs_world_method_in_use))]

    @property
    def tolerance(self) -> float:
        """The adaptive method's error tolerance (settable, >= 1e-15)."""
        return float(self._def().tolerance)

    @tolerance.setter
    def tolerance(self, value: float) -> None:
        # (0 would mean "keep the current" to the library: refused here)
        tol = _check.real_in(value, "tolerance", **_REAL_RANGES["tolerance"])
        self._call(lib.rbs_world_set_method, self._def().method, tol)

    @property
    def gravity(self) -> np.ndarray:
        """Gravity, m/s^2 (or N in force mode)."""
        d = self._def()  # keep the owner alive while reading
        return _vec3(d.gravity)

    @property
    def settings(self) -> Dict[str, Any]:
        """Capacities and settings as they are now (a copy)."""
        d = self._def()
        return {
            "max_bodies": int(d.max_bodies), "max_materials": int(d.max_materials),
            "max_pairs": int(d.max_pairs), "max_contacts": int(d.max_contacts),
            "dt": float(d.dt), "gravity": tuple(_vec3(d.gravity)),
            "gravity_mode": _reverse(_GRAVITY_MODES, int(d.gravity_mode)),
            "restitution": float(d.restitution), "method": METHODS[int(d.method)],
            "tolerance": float(d.tolerance), "slop": float(d.slop),
            "max_halvings": int(d.max_halvings), "max_sweeps": int(d.max_sweeps),
            "max_substeps": int(d.max_substeps),
            "soft_substeps": int(d.soft_substeps),
            "soft_tolerance": float(d.soft_tolerance),
            "mutual_gravity": bool(d.mutual_gravity),
            "gravity_constant": float(d.gravity_constant),
            "softening": float(d.softening), "prune": bool(d.prune),
        }

    # -- state views ---------------------------------------------------------

    def _state_view(self) -> Any:
        out = ffi.new("rbs_state_view *")
        self._query("rbs_world_state", lib.rbs_world_state, out)
        return out

    def _view(self, ptr: Any, rows: int, cols: int, dtype: Any) -> np.ndarray:
        """A read-only array over [ptr, ptr + rows*cols) inside the block."""
        item = np.dtype(dtype).itemsize
        start = int(ffi.cast("uintptr_t", ptr)) - self._base + self._offset
        nbytes = rows * cols * item
        if ptr == ffi.NULL or start < self._offset or start + nbytes > len(self._block):
            raise _e.Error("state array outside the world's memory block")
        return self._block[start:start + nbytes].view(dtype).reshape(rows, cols)

    @property
    def positions(self) -> np.ndarray:
        """Positions, m: a read-only slots x 3 float64 view of the world's
        memory (no copy; it changes as the world steps).  Row i is slot i
        (:attr:`Body.slot`); free slots hold zeros.  Bodies added later are
        not in an array taken before."""
        v = self._state_view()
        return self._view(v.position, int(v.slots), 3, np.float64)

    @property
    def velocities(self) -> np.ndarray:
        """Velocities, m/s: read-only slots x 3 view (see positions)."""
        v = self._state_view()
        return self._view(v.velocity, int(v.slots), 3, np.float64)

    @property
    def angular_velocities(self) -> np.ndarray:
        """Angular velocities, rad/s: read-only slots x 3 view."""
        v = self._state_view()
        return self._view(v.angular_velocity, int(v.slots), 3, np.float64)

    @property
    def orientations(self) -> np.ndarray:
        """Orientations [w x y z]: read-only slots x 4 view."""
        v = self._state_view()
        return self._view(v.orientation, int(v.slots), 4, np.float64)

    @property
    def types(self) -> np.ndarray:
        """Body types per slot (0 free, 1 sphere, 2 plane): read-only int32
        view of length slots."""
        v = self._state_view()
        return self._view(v.type, int(v.slots), 1, np.int32).reshape(-1)

    # -- diagnostics -----------------------------------------------------------

    def energy(self) -> Energy:
        """Kinetic, potential and total energy, J."""
        out = ffi.new("rbs_energy *")
        w = self._acquire()
        try:
            status = lib.rbs_world_energy(w, out)
        finally:
            self._lock.release()
        if status == lib.RBS_E_NUMERIC:
            # (it said only "numerical failure: rbs_world_energy")
            raise _e.error_class(status)(
                "energy: not finite at step %d (kinetic %r J, potential %r J): a sum "
                "overflows a double -- speeds, masses, spins or forces this large -- or "
                "two spheres are at one point under mutual gravity without softening"
                % (self.step_count, float(out.kinetic), float(out.potential)))
        if status != lib.RBS_OK:
            raise _e.error_class(status)("rbs_world_energy")
        return Energy(float(out.kinetic), float(out.potential), float(out.total))

    def momentum(self) -> Momentum:
        """Linear momentum (kg m/s) and angular momentum about the origin
        (kg m^2/s)."""
        lin = ffi.new("rbs_vec3 *")
        ang = ffi.new("rbs_vec3 *")
        w = self._acquire()
        try:
            status = lib.rbs_world_momentum(w, lin, ang)
        finally:
            self._lock.release()
        if status == lib.RBS_E_NUMERIC:
            raise _e.error_class(status)(
                "momentum: not finite at step %d (linear %s kg m/s, angular %s kg m^2/s): "
                "a sum overflows a double -- speeds, masses or spins this large"
                % (self.step_count, _check.numbers_text(tuple(_vec3(lin))),
                   _check.numbers_text(tuple(_vec3(ang)))))
        if status != lib.RBS_OK:
            raise _e.error_class(status)("rbs_world_momentum")
        return Momentum(_vec3(lin), _vec3(ang))

    def usage(self) -> Usage:
        """Memory use and high-water marks."""
        out = ffi.new("rbs_usage *")
        self._query("rbs_world_usage", lib.rbs_world_usage, out)
        return Usage(int(out.bytes), int(out.bodies), int(out.bodies_high),
                     int(out.materials), int(out.pairs), int(out.contacts_high))

    def hash(self) -> int:
        """Deterministic 64-bit hash of the full state bits."""
        return int(self._value(lib.rbs_world_hash))

    def checkpoint(self) -> bytes:
        """The exact state as bytes (see :meth:`from_checkpoint`)."""
        w = self._acquire()
        try:
            size = lib.rbs_world_checkpoint_size(w)
            buf = ffi.new("char[]", max(int(size), 1))
            written = ffi.new("size_t *")
            status = lib.rbs_world_checkpoint_write(w, buf, size, written)
        finally:
            self._lock.release()
        if status != lib.RBS_OK:
            raise _e.error_class(status)("checkpoint of %d bytes" % size)
        return ffi.buffer(buf, written[0])[:]

    def save(self, path: Any) -> None:
        """Save a checkpoint to a file atomically (a crash mid-write leaves
        any previous file intact); restore it with :meth:`World.restore`.
        A file the world's scene was read from (:func:`rbsim.load`'s file, a
        text scene's materials and objects files; by any path or link) is
        refused with :class:`~rbsim.OwnInputError` (the library's
        RBS_E_OWN_INPUT, which ``rbs_scene_save`` returns for a scene saved
        onto its own files), as ``rbsim run --checkpoint`` refuses it: the
        checkpoint would replace the scene."""
        raw = _check.path(path, "path")
        for src in self._scene_files:
            # (it wrote the checkpoint over the scene: a probe of session 47;
            # it raised InvalidError until session 50.)  The check is made
            # here, not by the library: rbs_world_save writes a world, which
            # keeps no scene, so only the binding knows the files the world
            # was loaded from (rbs_scene_source) -- as the rbsim command
            # checks its --checkpoint against them itself (run.c).
            if _same_file(raw, src):
                raise _e.error_class(lib.RBS_E_OWN_INPUT)(
                    "path: %r is %sa file the world's scene was read from: a "
                    "checkpoint there would replace the scene; save elsewhere"
                    % (os.fsdecode(raw), "" if raw == src
                       else "%r, " % os.fsdecode(src)))
        msg = ffi.new("char[]", 600)
        w = self._acquire()
        try:
            status = lib.rbs_world_save_v2(w, raw, msg, 600)
        finally:
            self._lock.release()
        if status != lib.RBS_OK:
            raise _e.error_class(status)("cannot save %s" % _str(msg))

    def explain(self) -> str:
        """The pipeline a step runs for this world as it is now: bodies,
        method, and each stage in or out with the reason."""
        w = self._acquire()
        try:
            needed = ffi.new("size_t *")
            lib.rbs_world_explain(w, ffi.NULL, 0, needed)
            size = int(needed[0])
            buf = ffi.new("char[]", max(size, 1))
            status = lib.rbs_world_explain(w, buf, size, needed)
        finally:
            self._lock.release()
        if status != lib.RBS_OK:
            raise _e.error_class(status)("rbs_world_explain")
        return ffi.string(buf).decode("utf-8", "replace")

    def __repr__(self) -> str:
        if self.closed:
            return "World(<closed>)"
        try:
            return "World(bodies=%d, t=%.6g s, method=%s)" % (
                len(self.all_bodies()), self.time, self.method)
        except _e.BusyError:
            return "World(<busy: in use by another thread or a run>)"
        except _e.Error as exc:  # (repr never raises)
            return "World(<%s>)" % exc


#: why a world held by a run refuses calls (BusyError)
_HELD_BY_RUN = ("world is held by a run until its Run.wait() (or from inside that run's "
                "renderer): call wait() on the Run that start() returned")


#: World(...)'s integer ranges, as rbs_world_def_validate (world.c) has
#: them; checked here so that the message names the argument (the library's
#: one message for max_halvings and max_sweeps named both) and gives the
#: real range (not a C field's: max_bodies=-1 read "[0, 4294967295]")
_INT_RANGES: Dict[str, Tuple[int, int]] = {
    "max_bodies": (1, 1 << 24),
    "max_materials": (0, 1 << 12),
    "max_pairs": (0, 1 << 16),
    "max_contacts": (0, 1 << 26),  # (0: 4 x max_bodies + 16)
    "max_halvings": (0, 60),
    "max_sweeps": (1, 100000),
    "max_substeps": (1, (1 << 32) - 1),
    "soft_substeps": (1, 1000),  # (RBS__SOFT_SUBSTEPS_MAX)
}

#: World(...)'s real ranges, as rbs_world_def_validate (world.c) has them;
#: checked here so that the message echoes the value exactly (the
#: library's %g rounds it: 1.0000001 read "got 1")
_REAL_RANGES: Dict[str, Dict[str, Any]] = {
    "dt": dict(low=0.0, open_low=True),
    "restitution": dict(low=0.0, high=1.0),
    "tolerance": dict(low=1e-15, note=" (what double precision can reach)"),
    "slop": dict(low=0.0, high=0.1, open_low=True, open_high=True,
                 note=" (a fraction of the smaller radius)"),
    "soft_tolerance": dict(low=0.0, high=1.0, note=" (a fraction of the radius)"),
}


def _principal_moments(value: Any) -> Tuple[float, ...]:
    """add_sphere's inertia=(Ix, Iy, Iz), checked as the library does (its
    message named neither the argument nor the values)."""
    v = _check.vector(value, "inertia")
    if not all(x > 0.0 for x in v):
        raise _e.error_class(lib.RBS_E_INVALID)(
            "inertia: principal moments must be > 0 kg m^2, got %s" % _check.numbers_text(v))
    if not all(x >= _DBL_MIN for x in v):
        raise _e.error_class(lib.RBS_E_INVALID)(
            "inertia: principal moments must be >= %r kg m^2 (the smallest normal double: "
            "their inverses must be finite), got %s" % (_DBL_MIN, _check.numbers_text(v)))
    a, b, c = v
    if not math.isfinite(a + b + c):
        # (the library's message read "must be finite and > 0" of finite ones)
        raise _e.error_class(lib.RBS_E_INVALID)(
            "inertia: principal moments must have a finite sum (the world takes the "
            "inertia's trace), got %s" % _check.numbers_text(v))
    if a + b < c or b + c < a or a + c < b:
        raise _e.error_class(lib.RBS_E_INVALID)(
            "inertia: principal moments must satisfy the triangle inequality (each <= the "
            "sum of the other two), got %s" % _check.numbers_text(v))
    return v


def _method_value(name: Any) -> int:
    raw = _check.text(name, "method")
    out = ffi.new("rbs_method *")
    if lib.rbs_method_from_name(raw, out) != lib.RBS_OK:
        raise _e.error_class(lib.RBS_E_INVALID)(
            "method: expected one of %s, got %r" % (", ".join(METHODS), name))
    return int(out[0])


def _def_problem(d: Any, status: int = -1) -> str:
    """Why the library rejects a world definition (its own words)."""
    if status == lib.RBS_E_UNSUPPORTED and 0 <= d.method < len(METHODS):
        return "method %r is not available in this build" % METHODS[d.method]
    msg = ffi.new("char[]", 512)
    status = lib.rbs_world_def_validate(d, msg, 512)
    if status != lib.RBS_OK and msg[0] != b"\0":
        return ffi.string(msg).decode("utf-8", "replace")
    return ("world definition rejected (max_bodies=%d, max_contacts=%d, dt=%r)"
            % (d.max_bodies, d.max_contacts, d.dt))
