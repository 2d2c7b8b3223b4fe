"""The package builds outside Meson: setup.py finds librbsim through
pkg-config or builds it with Meson from the source tree (static), and
`pip install ./bindings/python` installs a working package.

The installed copies are imported in a fresh interpreter with every RBSIM_*
variable removed, so they cannot fall back on the in-tree extension.
"""

import importlib.util
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from conftest import BUILD_DIR, PACKAGE_DIR

import rbsim

CHECK = r"""
import sys, rbsim
assert rbsim.__file__.startswith(sys.argv[1]), rbsim.__file__
ext = sys.modules["rbsim._rbsim"].__file__
assert ext.startswith(sys.argv[1]), ext
w = rbsim.World(dt=0.001, restitution=0.8)
w.add_plane("ground")
w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 1.1))
w.step(1500)
print(w.hash())
print(ext)
"""


def reference_hash():
    w = rbsim.World(dt=0.001, restitution=0.8)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 1.1))
    w.step(1500)
    return w.hash()


def clean_env(pythonpath):
    # Meson sets LD_LIBRARY_PATH to the build's library folder for tests:
    # drop it too, so the run-time path compiled in is what finds librbsim.
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("RBSIM_") and k != "LD_LIBRARY_PATH"}
    env["PYTHONPATH"] = str(pythonpath)
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def check_installed(where, tmp_path):
    r = subprocess.run([sys.executable, "-c", CHECK, str(where)],
                       env=clean_env(where), cwd=tmp_path, capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.split()
    assert int(lines[0]) == reference_hash()  # same library, same bits
    return pathlib.Path(lines[1])


def test_setup_py_builds_the_library_with_meson(tmp_path):
    env = dict(os.environ)
    env["RBSIM_LIBRARY"] = "meson"
    r = subprocess.run([sys.executable, "setup.py", "-q", "build",
                        "--build-base", str(tmp_path / "build")],
                       cwd=PACKAGE_DIR, env=env, capture_output=True, text=True,
                       timeout=800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    libs = list((tmp_path / "build").glob("lib*/rbsim/__init__.py"))
    assert len(libs) == 1, libs
    where = libs[0].parent.parent
    assert (where / "rbsim" / "py.typed").exists()
    ext = check_installed(where, tmp_path)
    # librbsim is linked in statically: the module needs no librbsim.so.
    ldd = subprocess.run(["ldd", str(ext)], capture_output=True, text=True,
                         env=clean_env("")).stdout
    assert "librbsim" not in ldd and "not found" not in ldd, ldd


def build_against_an_install(tmp_path, name, build):
    """Install this build into the staging folder tmp_path/name, build the
    extension with setup.py into build against it (pkg-config), check the
    installed package, and return (the staging folder, ldd's librbsim
    lines of the extension)."""
    meson = shutil.which("meson")
    if meson is None:
        pytest.fail("meson is not on PATH")
    dest = tmp_path / name
    r = subprocess.run([meson, "install", "-C", str(BUILD_DIR), "--no-rebuild",
                        "--quiet", "--destdir", str(dest)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    pcs = list(dest.rglob("rbsim.pc"))
    assert len(pcs) == 1, pcs
    env = dict(os.environ)
    env.update(RBSIM_LIBRARY="pkg-config", PKG_CONFIG_PATH=str(pcs[0].parent),
               PKG_CONFIG_SYSROOT_DIR=str(dest))
    r = subprocess.run([sys.executable, "setup.py", "-q", "build",
                        "--build-base", str(build)],
                       cwd=PACKAGE_DIR, env=env, capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    where = next(build.glob("lib*/rbsim")).parent
    ext = check_installed(where, tmp_path)
    ldd = subprocess.run(["ldd", str(ext)], capture_output=True, text=True,
                         env=clean_env("")).stdout
    return dest, [l for l in ldd.splitlines() if "librbsim" in l]


def test_setup_py_uses_an_installed_library(tmp_path):
    """pkg-config finds an installed rbsim (here: this build installed into
    a staging folder); the extension links its librbsim.so with an rpath."""
    dest, line = build_against_an_install(tmp_path, "dest", tmp_path / "build")
    assert line and str(dest) in line[0], line


def test_a_second_build_links_the_library_it_finds_now(tmp_path):
    """`pip install ./bindings/python` builds in the package's own build/
    folder, which stays.  A second install (after `git pull`, or after
    installing librbsim so that pkg-config finds it) regenerated the same C
    file, so setuptools found the extension "up to date" and shipped the
    first build's, linked to the first library (a probe of session 51).
    Here: two builds into one build folder, against two installs of the
    library; the second must link the second."""
    for name in ("dest1", "dest2"):
        dest, line = build_against_an_install(tmp_path, name, tmp_path / "build")
        assert line and str(dest) + "/" in line[0], (name, line)


def can_build_wheels_offline():
    if importlib.util.find_spec("wheel") is not None:
        return True
    import setuptools
    major, minor = (int(x) for x in setuptools.__version__.split(".")[:2])
    return (major, minor) >= (70, 1)  # bdist_wheel built into setuptools


def test_pip_install(tmp_path):
    if not can_build_wheels_offline():
        pytest.skip("pip needs the 'wheel' package (or setuptools >= 70.1) to "
                    "build without network access; install it into this "
                    "interpreter to run this test")
    target = tmp_path / "site"
    r = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps",
                        "--no-build-isolation", "--disable-pip-version-check",
                        "--no-index", "--target", str(target), str(PACKAGE_DIR)],
                       env=clean_env(""), cwd=tmp_path, capture_output=True,
                       text=True, timeout=800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    check_installed(target, tmp_path)
