"""Numbers that go through the C library stay in the "C" locale whatever
Python's: after locale.setlocale(locale.LC_ALL, "") under German settings
(a decimal comma), run.command("speed 0.5") raised InvalidError while
"speed 0,5" was taken, and World.explain() read "dt = 0,001 s".

Python's own formatting ignores the locale; the library's C does not.  The
German locale is made here with localedef (Debian's "locales" package) in
the build folder, as tests/german_locale.h does for the C tests; if it
cannot be made the test fails and says to run .ci/setup.
"""

import locale
import os
import shutil
import subprocess

import pytest

import rbsim

GERMAN = "de_DE.UTF-8"


@pytest.fixture(scope="module")
def german():
    folder = os.path.join(os.path.abspath(os.environ.get("RBSIM_BUILD_DIR", "build")),
                          "tests", "python", "locale")
    target = os.path.join(folder, GERMAN)
    os.makedirs(folder, exist_ok=True)
    shutil.rmtree(target, ignore_errors=True)  # a leftover would hide a missing tool
    try:
        made = subprocess.run(["localedef", "-i", "de_DE", "-f", "UTF-8", target],
                              capture_output=True, text=True).returncode
    except FileNotFoundError:
        made = "localedef not found"
    os.environ["LOCPATH"] = folder  # (putenv: the C library's setlocale reads it)
    try:
        locale.setlocale(locale.LC_ALL, GERMAN)
    except locale.Error:
        pytest.fail("could not make the %s locale in %s (localedef: %s): it needs "
                    "localedef (libc-bin) and Debian's 'locales' package; run .ci/setup"
                    % (GERMAN, folder, made))
    try:
        # the premise: this locale writes a comma
        assert locale.localeconv()["decimal_point"] == ","
        yield
    finally:
        locale.setlocale(locale.LC_ALL, "C")


def make_world():
    w = rbsim.World(dt=0.001)
    w.add_plane("ground")
    w.add_sphere("ball", radius=0.1, position=(0.0, 0.0, 0.5))
    return w


def test_speed_command(german):
    run = make_world().start(10, start_paused=True)
    try:
        assert run.command("speed 0.5") == "speed 0.5 (used in real-time runs)"
        assert run.status().speed == 0.5
        with pytest.raises(rbsim.InvalidError, match="got '0,5'"):
            run.command("speed 0,5")
    finally:
        run.command("quit")
        run.wait()


def test_explain(german):
    text = make_world().explain()
    assert "dt = 0.001 s" in text
    assert "-9.81" in text and "0,001" not in text
