"""Argument checks done in Python before calling C (C checks again).

Wrong types raise :class:`ArgumentTypeError` (a TypeError), NaN and infinity
raise :class:`NumericError`, out-of-range integers :class:`InvalidError`;
every message names the argument.  Names of bodies and materials are the
library's to judge (one rule, core/name.h, whose message names the
character and its byte): here only what C cannot be given is refused (not a
str, a NUL, a lone surrogate).
"""

from __future__ import annotations

import collections.abc
import functools
import inspect
import itertools
import math
import numbers
import os
from typing import Any, Callable, Optional, Sequence, Tuple, TypeVar

import numpy as np

from . import errors as _e

_U32 = 2 ** 32
_U64 = 2 ** 64
#: most steps of a run: a scene's simulation.steps and the rbsim command's
#: --steps are capped so (frames 0 .. steps at t = k dt, k exact in a double)
STEPS_MAX = 2 ** 53


def real(value: Any, what: str) -> float:
    """A finite float from an int/float (not bool, not None)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise _e.ArgumentTypeError("%s: expected a real number, got %s"
                                   % (what, _describe(value)))
    try:
        x = float(value)
    except OverflowError:
        raise _e.error_class(-4)("%s: must be finite, got an integer too large for a double (%s)"
                                 % (what, _describe(value))) from None
    if not math.isfinite(x):
        raise _e.error_class(-4)("%s: must be finite, got %r" % (what, x))
    return x


def real_in(value: Any, what: str, low: Optional[float] = None,
            high: Optional[float] = None, *, open_low: bool = False,
            open_high: bool = False, note: str = "") -> float:
    """real(), then in the range: low/high None for no bound, open_* to
    leave the bound out.  The message gives the range and echoes the value
    exactly (repr: the shortest text that reads back as the same double)."""
    x = real(value, what)
    if ((low is not None and not (x > low if open_low else x >= low)) or
            (high is not None and not (x < high if open_high else x <= high))):
        if low is not None and high is not None:
            bounds = "in %s%s, %s%s" % ("(" if open_low else "[", _bound(low),
                                        _bound(high), ")" if open_high else "]")
        elif low is not None:
            bounds = "%s %s" % (">" if open_low else ">=", _bound(low))
        else:
            bounds = "%s %s" % ("<" if open_high else "<=", _bound(high))
        raise _e.error_class(-1)("%s: must be %s%s, got %s"
                                 % (what, bounds, note, number(value, x)))
    return x


def number(value: Any, x: float) -> str:
    """The exact text of a number given as value and taken as x: an
    integer's digits, else the repr of the double."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return str(int(value))
    return repr(x)


def _bound(b: float) -> str:
    # 0 and 1 as such, 1e-15 and 0.1 in their shortest form
    return str(int(b)) if float(b).is_integer() and abs(b) < 1e15 else repr(float(b))


def integer(value: Any, what: str, low: int = 0, high: int = _U32 - 1) -> int:
    """An int in [low, high] (not bool, not float)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise _e.ArgumentTypeError("%s: expected an integer, got %s"
                                   % (what, _describe(value)))
    n = int(value)
    if n < low or n > high:
        raise _e.error_class(-1)("%s: must be in [%d, %d], got %d"
                                 % (what, low, high, n))
    return n


def u32(value: Any, what: str, low: int = 0) -> int:
    return integer(value, what, low, _U32 - 1)


def u64(value: Any, what: str, low: int = 0) -> int:
    return integer(value, what, low, _U64 - 1)


def steps(value: Any, what: str = "steps") -> int:
    """A run's step count: an int in [0, 2^53], the cap of a scene's
    simulation.steps and the rbsim command's --steps, with the scene's
    message (rbs_scene_override's)."""
    n = u64(value, what)
    if n > STEPS_MAX:
        raise _e.error_class(-1)("%s: must be at most 2^53, got %d" % (what, n))
    return n


def flag(value: Any, what: str) -> bool:
    """A bool, numpy's included, or an integer 0/1 (Python's or numpy's)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, numbers.Integral) and int(value) in (0, 1):
        return bool(value)
    raise _e.ArgumentTypeError("%s: expected True or False, got %s"
                               % (what, _describe(value)))


def vector(value: Any, what: str, size: int = 3) -> Tuple[float, ...]:
    """A tuple of `size` finite floats from any sequence or array."""
    if value is None or isinstance(value, (str, bytes)):
        raise _e.ArgumentTypeError("%s: expected %d numbers, got %s"
                                   % (what, size, _describe(value)))
    if isinstance(value, (collections.abc.Mapping, collections.abc.Set)):
        # a dict iterates its keys and a set has no order: neither says
        # which number is x
        raise _e.ArgumentTypeError("%s: expected %d numbers in order (a sequence or an "
                                   "array), got %s" % (what, size, _describe(value)))
    shape = getattr(value, "shape", None)
    if isinstance(shape, tuple) and len(shape) >= 1 and shape != (size,):
        # an array is named by its shape: np.zeros((2, 3)) iterates its 2
        # rows, and "expected 3 numbers, got 2" read as if 2 numbers were
        # given (a probe of session 50)
        raise _e.error_class(-1)("%s: expected %d numbers, got an array of shape %s"
                                 % (what, size, shape))
    try:
        # (one more than needed at most: an endless iterator is not read on)
        items = list(itertools.islice(iter(value), size + 1))
    except TypeError:
        raise _e.ArgumentTypeError("%s: expected %d numbers, got %s"
                                   % (what, size, _describe(value))) from None
    if len(items) > size:
        raise _e.error_class(-1)("%s: expected %d numbers, got more" % (what, size))
    if len(items) != size:
        # a list of vectors, [[0, 0, 1], [0, 0, 2]], is named as such: "got
        # 2" alone read as two numbers (as an array's rows did, above)
        for i, x in enumerate(items):
            if isinstance(x, collections.abc.Iterable) and not isinstance(x, (str, bytes)):
                raise _e.error_class(-1)(
                    "%s: expected %d numbers, got %d item%s, %s[%d] a %s (one vector at "
                    "a time)" % (what, size, len(items), "" if len(items) == 1 else "s",
                                 what, i, type(x).__name__))
        raise _e.error_class(-1)("%s: expected %d numbers, got %d"
                                 % (what, size, len(items)))
    return tuple(real(x, "%s[%d]" % (what, i)) for i, x in enumerate(items))


def text(value: Any, what: str, optional: bool = False) -> Optional[bytes]:
    """UTF-8 bytes of a str without NUL (None allowed if optional)."""
    if value is None and optional:
        return None
    if not isinstance(value, str):
        raise _e.ArgumentTypeError("%s: expected a string, got %s"
                                   % (what, _describe(value)))
    if "\0" in value:
        raise _e.error_class(-1)("%s: must not contain NUL characters" % what)
    try:
        return value.encode("utf-8")
    except UnicodeEncodeError as exc:
        raise _e.error_class(-1)("%s: not valid Unicode text: a lone surrogate %r at "
                                 "position %d" % (what, value[exc.start], exc.start)) from None


def numbers_text(values: Tuple[float, ...]) -> str:
    """"(1, -0.5, 1e-320)": checked numbers echoed, each in its shortest
    exact form."""
    return "(%s)" % ", ".join(_bound(x) if math.isfinite(x) else repr(float(x))
                              for x in values)


def nonzero(values: Tuple[float, ...], what: str, kind: str) -> Tuple[float, ...]:
    """values (from vector()) not all zero: kind names what they are."""
    if all(x == 0.0 for x in values):
        raise _e.error_class(-1)("%s: must be a nonzero %s, got %s"
                                 % (what, kind, numbers_text(values)))
    return values


def path(value: Any, what: str) -> bytes:
    """File-system bytes of a str or os.PathLike."""
    if isinstance(value, (str, bytes)) or isinstance(value, os.PathLike):
        try:
            raw = os.fsencode(value)
        except UnicodeEncodeError as exc:
            raise _e.error_class(-1)("%s: cannot be encoded for the file system: %r at "
                                     "position %d" % (what, exc.object[exc.start], exc.start)) from None
        if b"\0" in raw:
            raise _e.error_class(-1)("%s: must not contain NUL characters" % what)
        if not raw:
            raise _e.error_class(-1)("%s: empty path" % what)
        return raw
    raise _e.ArgumentTypeError("%s: expected a path, got %s" % (what, _describe(value)))


def choice(value: Any, what: str, names: Tuple[str, ...]) -> str:
    """One of names (a str)."""
    if not isinstance(value, str):
        raise _e.ArgumentTypeError("%s: expected one of %s, got %s"
                                   % (what, ", ".join(names), _describe(value)))
    if value not in names:
        raise _e.error_class(-1)("%s: expected one of %s, got %r"
                                 % (what, ", ".join(names), value))
    return value


def suggest(word: str, names: Sequence[str]) -> Optional[str]:
    """The one of names nearest to word by the library's "did you mean" rule
    (rbs_scene_suggest, so Python suggests as scenes and the command do), or
    None."""
    from ._native import ffi, lib
    keep = [ffi.new("char[]", n.encode()) for n in names]
    got = lib.rbs_scene_suggest(word.split("\0")[0].encode("utf-8", "replace"),
                                ffi.new("const char *[]", keep), len(keep))
    return None if got == ffi.NULL else ffi.string(got).decode()


_F = TypeVar("_F", bound=Callable[..., Any])


def keywords(f: _F) -> _F:
    """f, whose unknown keyword arguments are refused with the library's
    "did you mean" and the known ones listed (Python 3.11's own TypeError
    names the word only).  A call with known keywords runs f as it is."""
    params = inspect.signature(f).parameters
    known = tuple(n for n, p in params.items() if n != "self" and p.kind in (
        p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY))
    label = f.__qualname__.replace(".__init__", "")

    @functools.wraps(f)
    def checked(*args: Any, **kwargs: Any) -> Any:
        try:
            return f(*args, **kwargs)
        except TypeError:
            # (an unknown keyword fails the call before f's body runs, so a
            # TypeError with one among kwargs is that one)
            unknown = [k for k in kwargs if k not in known]
            if not unknown:
                raise
            near = suggest(unknown[0], known)
            raise _e.ArgumentTypeError(
                "%s(): unknown keyword argument %r%s; known: %s"
                % (label, unknown[0], " (did you mean %r?)" % near if near else "",
                   ", ".join(known))) from None
    return checked  # type: ignore[return-value]


def _describe(value: Any) -> str:
    if value is None:
        return "None"
    text = repr(value)
    if len(text) > 40:
        text = text[:37] + "..."
    kind = type(value)
    # (numpy's scalar types by their full name: numpy 2's bool_ is named
    # "bool", and "got bool np.True_" read as if a bool were refused)
    name = kind.__name__ if kind.__module__ == "builtins" else "%s.%s" % (
        kind.__module__, kind.__name__)
    return "%s %s" % (name, text)
