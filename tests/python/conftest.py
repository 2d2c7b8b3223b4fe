"""Shared fixtures of the Python binding tests.

Meson runs each test file with RBSIM_BUILD_DIR (the build folder),
RBSIM_SOURCE_DIR, RBSIM_EXTENSION (the compiled rbsim._rbsim) and PYTHONPATH
(bindings/python) set; run by hand, the defaults are <root>/build and the
source tree this file sits in.
"""

import json
import os
import pathlib
import sys

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get(
    "RBSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BUILD_DIR = pathlib.Path(os.environ.get("RBSIM_BUILD_DIR", SOURCE_DIR / "build"))
PACKAGE_DIR = SOURCE_DIR / "bindings" / "python"

if str(PACKAGE_DIR) not in sys.path:
    sys.path.insert(0, str(PACKAGE_DIR))


@pytest.fixture
def write_scene(tmp_path):
    """write_scene(dict_or_text, name="scene.json") -> path of a scene file."""
    def write(scene, name="scene.json"):
        path = tmp_path / name
        text = scene if isinstance(scene, str) else json.dumps(scene, indent=2)
        path.write_text(text)
        return path
    return write


def bounce_scene(steps=2000, dt=0.001, height=1.0, restitution=0.9, radius=0.1):
    """A ball dropped on the ground: the binding tests' standard scene."""
    return {
        "format": 1,
        "description": "a ball bouncing on the ground",
        "simulation": {"steps": steps, "dt": dt, "gravity": [0, 0, -9.81],
                       "restitution": restitution},
        "materials": [{"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3,
                       "restitution": restitution}],
        "bodies": [
            {"type": "plane", "name": "ground", "point": [0, 0, 0],
             "normal": [0, 0, 1]},
            {"type": "sphere", "name": "ball", "radius": radius, "mass": 1.0,
             "position": [0, 0, height + radius]},
        ],
    }
