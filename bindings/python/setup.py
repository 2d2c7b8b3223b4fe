"""Build the rbsim package: ``pip install ./bindings/python``.

The extension rbsim._rbsim (cffi, API mode) needs librbsim.  It is found:

1. through pkg-config (an installed rbsim of the same version as the source
   tree this package sits in, or of any version outside a source tree):
   linked dynamically, with a run-time path to its folder;
2. otherwise by building the library with Meson from the source tree this
   package sits in (``../..``): a static librbsim.a in
   ``<build_temp>/meson``, linked into the extension, so the
   installed package needs only GSL and cJSON from the system.

RBSIM_LIBRARY=pkg-config or RBSIM_LIBRARY=meson forces one way.  The cdef is
generated from the headers in either case (see build_ffi.py).
"""

import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import build_ffi  # noqa: E402

SOURCE_ROOT = os.path.normpath(os.path.join(HERE, os.pardir, os.pardir))


def _source_version():
    """The project version from the source tree's meson.build, or None."""
    path = os.path.join(SOURCE_ROOT, "meson.build")
    if not os.path.isfile(path):
        return None
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if not re.search(r"project\(\s*'rbsim'", text):
        return None
    m = re.search(r"version\s*:\s*'([0-9]+\.[0-9]+\.[0-9]+)'", text)
    return m.group(1) if m else None


def _pkg_config(*args, env=None):
    exe = shutil.which("pkg-config")
    if exe is None:
        return None
    r = subprocess.run([exe] + list(args), capture_output=True, text=True,
                       env=env, check=False)
    return r.stdout.strip() if r.returncode == 0 else None


def _split_flags(flags):
    """pkg-config flags -> include_dirs, library_dirs, libraries, others."""
    inc, libdirs, libs, compile_args, link_args = [], [], [], [], []
    for f in shlex.split(flags):
        if f.startswith("-I"):
            inc.append(f[2:])
        elif f.startswith("-L"):
            libdirs.append(f[2:])
        elif f.startswith("-l"):
            libs.append(f[2:])
        elif f == "-pthread":
            compile_args.append(f)
            link_args.append(f)
        else:
            link_args.append(f)
    return inc, libdirs, libs, compile_args, link_args


def _from_pkg_config():
    flags = _pkg_config("--cflags", "--libs", "rbsim")
    if flags is None:
        return None
    inc, libdirs, libs, cargs, largs = _split_flags(flags)
    system = ("/usr/lib", "/lib", "/usr/lib64", "/lib64")
    rpath = [d for d in libdirs if not d.startswith(system)]
    return dict(include_dirs=inc, library_dirs=libdirs, libraries=libs,
                runtime_library_dirs=rpath, extra_compile_args=cargs,
                extra_link_args=largs)


def _from_meson(build_temp):
    meson = shutil.which("meson")
    if meson is None:
        raise RuntimeError(
            "rbsim: librbsim was not found by pkg-config and Meson is not "
            "installed to build it from %s (apt install meson ninja-build)"
            % SOURCE_ROOT)
    builddir = os.path.abspath(os.path.join(build_temp, "meson"))
    if not os.path.isfile(os.path.join(builddir, "build.ninja")):
        subprocess.run([meson, "setup", builddir, SOURCE_ROOT,
                        "-Ddefault_library=static", "--buildtype=release",
                        "-Db_ndebug=true", "--wrap-mode=nodownload",
                        "-Dtests=false", "-Dsdl=disabled"],
                       check=True)
    subprocess.run([meson, "compile", "-C", builddir,
                    "lib/rbsim:static_library"], check=True)
    env = dict(os.environ)
    env["PKG_CONFIG_PATH"] = os.path.join(builddir, "meson-uninstalled")
    flags = _pkg_config("--static", "--cflags", "--libs", "rbsim", env=env)
    if flags is None:
        raise RuntimeError("rbsim: pkg-config cannot read %s/meson-uninstalled/"
                           "rbsim-uninstalled.pc" % builddir)
    inc, libdirs, libs, cargs, largs = _split_flags(flags)
    return dict(include_dirs=inc, library_dirs=libdirs, libraries=libs,
                runtime_library_dirs=[], extra_compile_args=cargs,
                extra_link_args=largs)


def _library(build_temp):
    how = os.environ.get("RBSIM_LIBRARY", "auto")
    if how not in ("auto", "pkg-config", "meson"):
        raise RuntimeError("RBSIM_LIBRARY must be auto, pkg-config or meson, "
                           "got %r" % how)
    version = _source_version()
    if how in ("auto", "pkg-config"):
        installed = _pkg_config("--modversion", "rbsim")
        if installed is not None and (version is None or installed == version
                                      or how == "pkg-config"):
            return _from_pkg_config()
        if how == "pkg-config":
            raise RuntimeError("rbsim: pkg-config does not know rbsim "
                               "(set PKG_CONFIG_PATH)")
    if version is None:
        raise RuntimeError(
            "rbsim: librbsim not found by pkg-config, and this package is not "
            "inside the rbsim source tree to build it from")
    return _from_meson(build_temp)


class BuildRbsim(build_ext):
    """Find or build librbsim, generate the cffi C source, compile it."""

    def run(self):
        # Always compile and link again: the extension's one source is
        # generated from the headers alone, so setuptools would call it
        # "up to date" after the library changed (a newer source tree, or
        # pkg-config now finding an installed librbsim) and keep the build
        # folder's first extension, linked to the first library.  A build
        # of the C file takes seconds.
        self.force = True
        for ext in self.extensions:
            if ext.name != "rbsim._rbsim":
                continue
            cfg = _library(self.build_temp)
            ffibuilder = build_ffi.make_ffi(cfg["include_dirs"])
            os.makedirs(self.build_temp, exist_ok=True)
            c_file = os.path.join(self.build_temp, "_rbsim.c")
            ffibuilder.emit_c_code(c_file)
            ext.sources = [c_file]
            for key in ("include_dirs", "library_dirs", "libraries",
                        "runtime_library_dirs", "extra_compile_args",
                        "extra_link_args"):
                setattr(ext, key, list(cfg[key]))
        super().run()


def _version():
    return _source_version() or _pkg_config("--modversion", "rbsim") or "0.0.0"


setup(
    version=_version(),
    packages=["rbsim"],
    package_data={"rbsim": ["py.typed"]},
    ext_modules=[Extension("rbsim._rbsim", sources=[])],
    cmdclass={"build_ext": BuildRbsim},
    zip_safe=False,
)
