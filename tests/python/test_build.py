"""The extension is generated from the real headers and matches the library.

These checks read the headers and the built library independently of the
generator (regular expressions over the header text, nm over the .so), so a
generator that dropped a declaration, or a hand-kept copy that drifted,
fails here.
"""

import pathlib
import re
import subprocess
import sys

import pytest

from conftest import BUILD_DIR, PACKAGE_DIR, SOURCE_DIR

import rbsim
from rbsim._native import ffi, lib

HEADERS = [SOURCE_DIR / "lib" / "include" / "rbsim" / h
           for h in ("rbsim.h", "scene.h", "reel.h")]


def header_text():
    return "\n".join(h.read_text() for h in HEADERS)


def declared_functions():
    """Names of every RBS_API function of the three headers."""
    text = re.sub(r"/\*.*?\*/", " ", header_text(), flags=re.S)
    names = re.findall(r"RBS_API\b[^;{]*?\b(rbs_\w+)\s*\(", text)
    assert len(names) > 60, "the header parse found too little: %r" % names
    return sorted(set(names))


def status_list():
    """(name, value, text) of each X(...) line of RBS_STATUS_LIST."""
    text = header_text()
    block = text[text.index("#define RBS_STATUS_LIST(X)"):]
    block = block[:block.index("\n\n")]
    items = re.findall(r'X\((\w+),\s*(-?\d+),\s*"([^"]*)"\)', block)
    assert len(items) >= 10
    return [(n, int(v), t) for n, v, t in items]


def test_every_header_function_is_in_the_extension():
    missing = [n for n in declared_functions() if not hasattr(lib, n)]
    assert missing == []


def test_every_exported_symbol_is_in_the_extension():
    so = BUILD_DIR / "lib" / "librbsim.so"
    if not so.exists():
        pytest.fail("no %s: build the library first" % so)
    out = subprocess.run(["nm", "-D", "--defined-only", str(so)],
                         capture_output=True, text=True, check=True).stdout
    exported = sorted(set(re.findall(r"\bT (rbs_\w+)(?:@@?\w+)?$", out, flags=re.M)))
    assert exported, "nm found no rbs_ functions"
    assert [n for n in exported if not hasattr(lib, n)] == []


def test_generated_cdef_has_constants_and_no_attributes():
    inc = [str(SOURCE_DIR / "lib" / "include"), str(BUILD_DIR / "lib" / "include")]
    out = subprocess.run([sys.executable, str(PACKAGE_DIR / "build_ffi.py"),
                          "--print-cdef"] + sum((["--include", d] for d in inc), []),
                         capture_output=True, text=True, check=True).stdout
    assert "__attribute__" not in out
    assert "#define RBS_NAME_MAX 64" in out
    assert "rbs_world_step" in out
    assert lib.RBS_NAME_MAX == 64
    assert lib.RBS_RENDERERS_MAX >= 1


def test_status_enum_and_classes_follow_the_x_macro():
    items = status_list()
    for name, value, text in items:
        assert getattr(lib, "RBS_" + name) == value
        assert ffi.string(lib.rbs_status_string(value)).decode() == text
        assert ffi.string(lib.rbs_status_name(value)).decode() == name
        if value == 0:
            continue
        words = name[2:].split("_")
        cls_name = "".join(w.capitalize() for w in words) + "Error"
        cls = getattr(rbsim, cls_name)
        assert issubclass(cls, rbsim.Error)
        assert cls.status == value and cls.name == name
        assert rbsim.error_class(value) is cls
    # The examples exist under their names.
    for cls_name in ("StaleIdError", "NumericError", "CapacityError", "SceneError"):
        assert issubclass(getattr(rbsim, cls_name), rbsim.Error)
    # Every negative code of the enum got a class (nothing extra, nothing lost).
    codes = sorted(v for _, v, _ in items if v < 0)
    assert sorted(rbsim.errors.BY_STATUS) == codes


def test_python_callbacks_match_the_renderer_class():
    fields = dict(ffi.typeof("rbs_renderer_class").fields)
    for name in ("create", "draw", "finish", "destroy"):
        assert ffi.typeof(getattr(lib, "rbs_py_renderer_" + name)) is \
            fields[name].type, name


def test_versions_agree():
    meson = (SOURCE_DIR / "meson.build").read_text()
    version = re.search(r"version\s*:\s*'([0-9.]+)'", meson).group(1)
    assert rbsim.__version__ == version == rbsim.version()
    assert lib.rbs_version_number() == lib.rbs_py_version_header()


def test_package_is_typed():
    assert (PACKAGE_DIR / "rbsim" / "py.typed").exists()
    assert rbsim.World.step.__annotations__
    assert rbsim.World.__doc__ and rbsim.load.__doc__


def test_type_checking_names_match_the_generated_classes():
    """errors.py lists the generated classes for type checkers; the list
    must name exactly the classes generated from RBS_STATUS_LIST."""
    src = (PACKAGE_DIR / "rbsim" / "errors.py").read_text()
    block = src[src.index("if TYPE_CHECKING:"):]
    declared = set(re.findall(r"^    class (\w+)\(", block, flags=re.M))
    generated = set(rbsim.errors.GENERATED) - {"SceneError"}
    assert declared == generated
