"""Exceptions of rbsim.

One class per status code of the C library, generated at import from the
``rbs_status`` enum, which the C preprocessor expanded from the
``RBS_STATUS_LIST`` X-macro when the extension was built: ``E_STALE_ID``
becomes :class:`StaleIdError`, ``E_NUMERIC`` :class:`NumericError`, and so
on.  All derive from :class:`Error`; some also from the built-in exception of
the same meaning (:class:`InvalidError` is a ``ValueError``,
:class:`NotFoundError` a ``KeyError``, :class:`MemoryError` the built-in
``MemoryError``, :class:`IoError` an ``OSError``), so ordinary Python
handlers work too.  ``from rbsim import *`` leaves out the classes named as
a built-in exception (:data:`SHADOWING`: ``MemoryError``), so as not to hide
the built-in; use ``rbsim.MemoryError``.
"""

from __future__ import annotations

import builtins
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Type

from ._native import ffi, lib


class Error(Exception):
    """Base of every rbsim error.

    Attributes:
        status: the C status code (negative int), or None for errors found
            in Python only.
        name: the code's name without prefix, e.g. ``"E_CAPACITY"``.
        detail: the library's detail message (``rbs_world_last_error``) or
            the Python-side explanation.
    """

    status: Optional[int] = None
    name: str = ""

    def __init__(self, detail: str = "", *, status: Optional[int] = None) -> None:
        cls = type(self)
        if status is None:
            status = cls.status
        self.status = status
        self.detail = detail
        if status is not None:
            self.name = _name(status)
            text = _text(status)
            message = "%s: %s" % (text, detail) if detail else text
        else:
            message = detail
        super().__init__(message)

    def __str__(self) -> str:
        # KeyError would quote the message; every rbsim error reads alike.
        return str(self.args[0]) if self.args else ""

    def __reduce__(self) -> Any:
        # (the default rebuilt the error from args, the message with its
        # prefix, and the prefix came twice: "invalid argument: invalid
        # argument: ...", in a multiprocessing worker's error too)
        return (_rebuild, (type(self), self.detail, self.status), self.__dict__)


def _rebuild(cls: Type["Error"], detail: str, status: Optional[int]) -> "Error":
    """An error of class cls unpickled: the message made from detail as
    when it was raised (a SceneError's detail already holds its list);
    __reduce__'s state gives the other attributes."""
    return cls(detail, status=status)


def _name(status: int) -> str:
    return ffi.string(lib.rbs_status_name(status)).decode()


def _text(status: int) -> str:
    return ffi.string(lib.rbs_status_string(status)).decode()


# Built-in exceptions that a status code also is (kept to simple layouts).
_ALSO = {
    "E_INVALID": (ValueError,),
    "E_NOT_FOUND": (KeyError,),
    "E_MEMORY": (builtins.MemoryError,),
    "E_IO": (OSError,),
    "E_NUMERIC": (ArithmeticError,),
}


def _class_name(name: str) -> str:
    """E_STALE_ID -> StaleIdError."""
    words = name[2:] if name.startswith("E_") else name
    return "".join(w.capitalize() for w in words.split("_")) + "Error"


#: status code -> exception class, for every error code of the library
BY_STATUS: Dict[int, Type[Error]] = {}
#: class name -> class (the generated ones)
GENERATED: Dict[str, Type[Error]] = {}


class SceneError(Error):
    """A scene file was rejected.

    Attributes:
        file, line, column, path, message: the first error (line and column
            are 1-based; 0 when not tied to a place).
        errors: every error kept, as :class:`SceneIssue` tuples.
        count: errors found (more than ``len(errors)`` when some were only
            counted).
    """

    def __init__(self, detail: str = "", *, status: Optional[int] = None,
                 errors: Sequence["SceneIssue"] = (), count: int = 0) -> None:
        self.errors: List[SceneIssue] = list(errors)
        self.count = max(count, len(self.errors))
        first = self.errors[0] if self.errors else None
        self.file = first.file if first else ""
        self.line = first.line if first else 0
        self.column = first.column if first else 0
        self.path = first.path if first else ""
        self.message = first.message if first else detail
        if self.errors:
            lines = [e.text for e in self.errors]
            if self.count > len(self.errors):
                lines.append("... and %d more" % (self.count - len(self.errors)))
            detail = "\n" + "\n".join(lines) if len(lines) > 1 else lines[0]
        super().__init__(detail, status=status)


class SceneIssue:
    """One error in a scene: where (file, 1-based line and column, key path)
    and what (message); text is the whole "file:line:col: path: message"."""

    __slots__ = ("file", "line", "column", "path", "message", "text")

    def __init__(self, file: str, line: int, column: int, path: str,
                 message: str, text: str) -> None:
        self.file = file
        self.line = line
        self.column = column
        self.path = path
        self.message = message
        self.text = text

    def __repr__(self) -> str:
        return "SceneIssue(%r)" % self.text


class BusyError(Error, RuntimeError):
    """A world was used from two threads at once (a World is not
    thread-safe; distinct worlds may be used from distinct threads)."""


class DeadlockError(Error, RuntimeError):
    """A blocking call that could never return, such as Run.wait() from the
    run's own renderer (the run cannot end while its renderer is drawing)."""


class ArgumentTypeError(Error, TypeError):
    """An argument of the wrong type, found in Python before calling C."""


def _build() -> None:
    elements = ffi.typeof("rbs_status").elements
    for value, cname in sorted(elements.items(), reverse=True):
        if value >= 0:
            continue  # RBS_OK and the 32-bit pin
        name = cname[len("RBS_"):]
        cls_name = _class_name(name)
        if name == "E_SCENE":
            cls: Type[Error] = SceneError
        else:
            bases = (Error,) + _ALSO.get(name, ())
            doc = "Status %s (%d): %s." % (name, value, _text(value))
            cls = type(cls_name, bases, {"__doc__": doc, "__module__": __name__})
        cls.status = value
        cls.name = name
        BY_STATUS[value] = cls
        GENERATED[cls_name] = cls
        globals()[cls_name] = cls


_build()

if TYPE_CHECKING:  # pragma: no cover
    # For type checkers only: the classes above are made at run time from the
    # library's status list.  tests/python/test_build.py checks that this list
    # names exactly the generated classes.
    class InvalidError(Error, ValueError): ...
    class CapacityError(Error): ...
    class StaleIdError(Error): ...
    class NumericError(Error, ArithmeticError): ...
    class OverlapError(Error): ...
    class MemoryError(Error, builtins.MemoryError): ...  # noqa: A001
    class IoError(Error, OSError): ...
    class UnsupportedError(Error): ...
    class NotFoundError(Error, KeyError): ...
    class RendererError(Error): ...
    class ClosedError(Error): ...
    class VersionError(Error): ...
    class CorruptError(Error): ...
    class OwnInputError(Error): ...


def error_class(status: int) -> Type[Error]:
    """The exception class of a status code (Error for an unknown code)."""
    return BY_STATUS.get(status, Error)


def raise_status(status: int, detail: str = "") -> None:
    """Raise the exception of a negative status; do nothing for RBS_OK."""
    if status == 0:
        return
    cls = BY_STATUS.get(status)
    if cls is None:
        raise Error("unknown status %d: %s" % (status, detail), status=status)
    raise cls(detail, status=status)


#: the generated classes that ``import *`` leaves out: their names are
#: built-in exceptions' (MemoryError), which a star import would hide;
#: reach them as ``rbsim.MemoryError``
SHADOWING = sorted(n for n in GENERATED if hasattr(builtins, n))

__all__ = ["Error", "SceneError", "SceneIssue", "BusyError", "DeadlockError",
           "ArgumentTypeError",
           "BY_STATUS", "error_class", "raise_status"] + sorted(
               n for n in GENERATED if n not in SHADOWING)
