"""Build the cffi extension ``rbsim._rbsim`` (API, out-of-line mode).

The cdef is generated from the real public headers, never copied by hand:
the C preprocessor runs over ``rbsim/rbsim.h``, ``rbsim/scene.h`` and
``rbsim/reel.h`` with ``RBS_API`` empty and with empty stand-ins for
``<stddef.h>`` and ``<stdint.h>`` (cffi knows ``size_t``, ``uint32_t``, ...),
so the status enum comes out of the ``RBS_STATUS_LIST`` X-macro exactly as the
library sees it.  Integer macros named ``RBS_*`` are kept as cdef constants,
floating-point ones as ``static const double`` constants;
what cdef cannot take (function-like macros, strings, attributes) is dropped.

Used three ways:

* by Meson for the in-tree build (``tests/python/meson.build``)::

      python build_ffi.py --include SRC/lib/include --include BUILD/lib/include \
          --library BUILD/lib/librbsim.so --output BUILD/.../_rbsim.<EXT_SUFFIX>

* by ``setup.py`` (``pip install ./bindings/python``) through :func:`make_ffi`;
* by the tests, to check the generated cdef against the headers.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from typing import Iterable, List, Optional, Sequence

HEADERS = ("rbsim/rbsim.h", "rbsim/scene.h", "rbsim/reel.h")

# The binding's own C helpers and Python callbacks.  These are not a copy of
# the library's API: they are defined in the extension (HELPERS_SOURCE) or in
# Python (extern "Python", see rbsim/_render.py).
HELPERS_CDEF = """
rbs_status rbs_py_step(rbs_world *world, uint64_t n, rbs_step_info *sum,
                       uint64_t *done, const int32_t *stop);
int rbs_py_version_header(void);

extern "Python" {
    rbs_status rbs_py_renderer_create(void *context,
                                      const rbs_renderer_config *config,
                                      const rbs_world *world, void **instance,
                                      char *err, size_t errlen);
    rbs_status rbs_py_renderer_draw(void *instance, const rbs_frame *frame,
                                    char *err, size_t errlen);
    rbs_status rbs_py_renderer_finish(void *instance, char *err, size_t errlen);
    void rbs_py_renderer_destroy(void *instance);
}
"""

HELPERS_SOURCE = r"""
#include "rbsim/rbsim.h"
#include "rbsim/scene.h"
#include "rbsim/reel.h"

/* Step n times in one C call (the GIL is released around it).  *sum gets the
 * counts of all steps added up, contacts of the last step and the deepest
 * overlap seen; *done the steps completed (also on error).  The loop ends
 * early, with RBS_OK, when *stop becomes nonzero (another thread may set it:
 * it is read through a volatile pointer once per step). */
static rbs_status rbs_py_step(rbs_world *world, uint64_t n, rbs_step_info *sum,
                              uint64_t *done, const int32_t *stop)
{
    rbs_step_info info, total = {0, 0, 0, 0, 0, 0, 0, 0, 0.0};
    const volatile int32_t *halt = stop;
    rbs_status status = RBS_OK;
    uint64_t i;

    if (done != NULL) {
        *done = 0;
    }
    for (i = 0; i < n; i++) {
        if (halt != NULL && *halt != 0) {
            break;
        }
        status = rbs_world_step(world, &info);
        if (status != RBS_OK) {
            break;
        }
        total.contacts = info.contacts;
        total.colliding += info.colliding;
        total.resting += info.resting;
        total.substeps += info.substeps;
        total.rollbacks += info.rollbacks;
        total.floor_hits += info.floor_hits;
        total.sweep_limit += info.sweep_limit;
        total.events += info.events;
        total.work_limit += info.work_limit; /* (the steps that hit the cap) */
        if (info.max_overlap > total.max_overlap) {
            total.max_overlap = info.max_overlap;
        }
        if (done != NULL) {
            *(volatile uint64_t *)done = i + 1;
        }
    }
    if (sum != NULL) {
        *sum = total;
    }
    return status;
}

/* The version of the headers the extension was compiled against. */
static int rbs_py_version_header(void) { return RBS_VERSION_NUMBER; }
"""

_INT_LITERAL = re.compile(r"^-?(0[xX][0-9a-fA-F]+|\d+)[uUlL]*$")
_FLOAT_LITERAL = re.compile(r"^-?(\d+\.\d*|\.\d+|\d+)([eE][-+]?\d+)?$")
_INT_EXPR = re.compile(r"^[\s()+\-*/%<>|&~^0-9a-fA-FxXuUlL_A-Z]+$")
_MACRO_NAME = re.compile(r"^RBS_[A-Z0-9_]+$")


def _preprocess(include_dirs: Sequence[str], cc: Optional[str]) -> str:
    """Run the C preprocessor over the public headers; return its output
    with macro definitions (-dD) and without line markers (-P)."""
    compiler = (cc or os.environ.get("CC") or sysconfig.get_config_var("CC")
                or "cc")
    if shutil.which(compiler.split()[0]) is None:
        raise RuntimeError(
            "rbsim: no C compiler '%s' to preprocess the headers (set CC)" % compiler)
    with tempfile.TemporaryDirectory(prefix="rbsim-cdef-") as stubs:
        # Empty stand-ins: cffi knows the standard integer types itself.
        for name in ("stddef.h", "stdint.h"):
            with open(os.path.join(stubs, name), "w") as f:
                f.write("/* cffi knows these types */\n")
        source = "".join('#include "%s"\n' % h for h in HEADERS)
        command = compiler.split() + ["-E", "-P", "-dD", "-undef", "-nostdinc",
                                      "-DRBS_API=", "-x", "c", "-I", stubs]
        for d in include_dirs:
            command += ["-I", d]
        command.append("-")
        result = subprocess.run(command, input=source, capture_output=True,
                                text=True, check=False)
        if result.returncode != 0:
            raise RuntimeError("rbsim: preprocessing the headers failed:\n%s\n%s"
                               % (" ".join(command), result.stderr))
        return result.stdout


def _strip_attributes(text: str) -> str:
    """Remove __attribute__((...)) and __extension__ (cdef takes neither)."""
    out = []
    i = 0
    key = "__attribute__"
    while True:
        j = text.find(key, i)
        if j < 0:
            out.append(text[i:])
            break
        out.append(text[i:j])
        k = text.find("(", j)
        depth = 0
        while k < len(text):
            if text[k] == "(":
                depth += 1
            elif text[k] == ")":
                depth -= 1
                if depth == 0:
                    break
            k += 1
        i = k + 1
    return "".join(out).replace("__extension__", "")


def generate_cdef(include_dirs: Sequence[str], cc: Optional[str] = None) -> str:
    """The cdef of the public API, generated from the headers found in
    include_dirs (which must also hold the generated rbsim/version.h)."""
    text = _preprocess(include_dirs, cc)
    macros = {}
    doubles = {}  # floating-point macros: cdef constants of type double
    body: List[str] = []
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("#define"):
            parts = stripped.split(None, 2)
            name = parts[1] if len(parts) > 1 else ""
            value = parts[2].strip() if len(parts) > 2 else ""
            if "(" in name or not _MACRO_NAME.match(name) or value == "":
                continue  # function-like, foreign or empty (RBS_API)
            if _INT_LITERAL.match(value):
                macros[name] = value
            elif _FLOAT_LITERAL.match(value):
                doubles[name] = value
            elif _INT_EXPR.match(value) and not value.startswith('"'):
                macros[name] = "..."  # computed by the compiler (API mode)
            continue
        if stripped.startswith("#undef"):
            parts = stripped.split()
            if len(parts) > 1:
                macros.pop(parts[1], None)
                doubles.pop(parts[1], None)
            continue
        if stripped.startswith("#") or not stripped:
            continue
        body.append(line)
    decls = _strip_attributes("\n".join(body))
    decls = re.sub(r"_Static_assert\s*\([^;]*\)\s*;", "", decls)
    defines = "".join("#define %s %s\n" % (k, v) for k, v in sorted(macros.items()))
    defines += "".join("static const double %s;\n" % k for k in sorted(doubles))
    return defines + decls + "\n"


def make_ffi(include_dirs: Sequence[str], library_dirs: Sequence[str] = (),
             libraries: Sequence[str] = ("rbsim",),
             extra_link_args: Sequence[str] = (),
             runtime_library_dirs: Sequence[str] = (),
             extra_objects: Sequence[str] = (),
             cc: Optional[str] = None):
    """An FFI builder for rbsim._rbsim against the headers and library given."""
    import cffi

    ffibuilder = cffi.FFI()
    ffibuilder.cdef(generate_cdef(include_dirs, cc))
    ffibuilder.cdef(HELPERS_CDEF)
    ffibuilder.set_source(
        "rbsim._rbsim", HELPERS_SOURCE,
        include_dirs=list(include_dirs),
        library_dirs=list(library_dirs),
        libraries=list(libraries),
        runtime_library_dirs=list(runtime_library_dirs),
        extra_objects=list(extra_objects),
        extra_link_args=list(extra_link_args))
    return ffibuilder


def _main(argv: Optional[Iterable[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--include", action="append", default=[],
                        help="include directory (repeat): the public headers "
                             "and the generated rbsim/version.h")
    parser.add_argument("--library", required=False,
                        help="path of librbsim.so to link (its folder becomes "
                             "the run-time search path)")
    parser.add_argument("--output", help="where to put the extension module")
    parser.add_argument("--tmpdir", help="scratch folder for the C file and objects")
    parser.add_argument("--cc", help="C compiler (preprocessor) to run; default "
                        "$CC, else Python's, else cc")
    parser.add_argument("--print-cdef", action="store_true",
                        help="print the generated cdef and exit")
    args = parser.parse_args(list(argv) if argv is not None else None)

    if args.print_cdef:
        sys.stdout.write(generate_cdef(args.include, args.cc))
        return 0
    if not args.library or not args.output:
        parser.error("--library and --output are required to build")
    libdir = os.path.dirname(os.path.abspath(args.library))
    ffibuilder = make_ffi(args.include, library_dirs=[libdir],
                          runtime_library_dirs=[libdir], cc=args.cc)
    tmpdir = args.tmpdir or tempfile.mkdtemp(prefix="rbsim-ffi-")
    os.makedirs(tmpdir, exist_ok=True)
    built = ffibuilder.compile(tmpdir=tmpdir, verbose=False)
    shutil.copyfile(built, args.output + ".tmp")
    os.replace(args.output + ".tmp", args.output)
    return 0


if __name__ == "__main__":
    sys.exit(_main())
