"""Find and load the compiled cffi extension ``rbsim._rbsim``.

Search order (the first that exists wins; nothing is compiled at import):

1. ``rbsim/_rbsim<EXT_SUFFIX>`` beside this file (``pip install``);
2. ``$RBSIM_EXTENSION``, a path to the module file;
3. the Meson build folder ``$RBSIM_BUILD_DIR``, else ``build/`` at the root of
   the source tree this package sits in (the README's build): Meson puts the
   module at ``<build>/tests/python/_rbsim<EXT_SUFFIX>``.

The extension must have been compiled against the headers of the library it
loads: the versions are compared here and a mismatch raises ImportError.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import sys
from typing import Any, List, Tuple

_NAME = "rbsim._rbsim"


def _candidates() -> List[str]:
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    found = []
    env = os.environ.get("RBSIM_EXTENSION")
    if env:
        found.append(env)
    build = os.environ.get("RBSIM_BUILD_DIR")
    if not build:
        here = os.path.dirname(os.path.abspath(__file__))
        build = os.path.join(here, os.pardir, os.pardir, os.pardir, "build")
    for sub in ("tests/python", "bindings/python"):
        found.append(os.path.join(build, sub, "_rbsim" + suffix))
    return found


def _load() -> Tuple[Any, Any]:
    here = os.path.dirname(os.path.abspath(__file__))
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        if os.path.isfile(os.path.join(here, "_rbsim" + suffix)):
            from . import _rbsim  # type: ignore[attr-defined]
            return _rbsim.ffi, _rbsim.lib
    tried = _candidates()
    for path in tried:
        if os.path.isfile(path):
            spec = importlib.util.spec_from_file_location(_NAME, path)
            if spec is None or spec.loader is None:
                continue
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            sys.modules[_NAME] = module
            return module.ffi, module.lib
    raise ImportError(
        "rbsim: the compiled extension rbsim._rbsim was not found. Install the "
        "package (pip install ./bindings/python) or build the source tree "
        "(meson setup build && meson compile -C build) and set RBSIM_BUILD_DIR "
        "if the build folder is not <root>/build. Looked at: " + ", ".join(tried),
        name=_NAME)


ffi, lib = _load()

if lib.rbs_version_number() != lib.rbs_py_version_header():
    raise ImportError(
        "rbsim: library version %s does not match the headers the extension "
        "was built with (%d); rebuild the extension"
        % (ffi.string(lib.rbs_version()).decode(), lib.rbs_py_version_header()),
        name=_NAME)
