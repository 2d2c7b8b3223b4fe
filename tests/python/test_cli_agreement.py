"""The binding agrees bit for bit with the rbsim command.

The command (`rbsim run SCENE --csv FILE`) writes every number in shortest
round-trip form, so float() of its text gives back the exact double; the same
scene loaded and run in Python must give exactly those doubles -- through
the projector with a Python renderer, and by stepping directly and reading
the zero-copy views.  Tolerance: none (bit equality), since both run the
same library on the same input.
"""

import csv
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

from conftest import BUILD_DIR, SOURCE_DIR, bounce_scene

import rbsim

# The repository's scenes list a csv renderer for the command; Python
# renderers do the recording here.
pytestmark = pytest.mark.filterwarnings("ignore:the scene's renderers")

COLUMNS = ["frame", "t", "body", "name", "x", "y", "z", "qw", "qx", "qy", "qz",
           "vx", "vy", "vz", "wx", "wy", "wz"]


def cli_path():
    path = pathlib.Path(os.environ.get("RBSIM_CLI",
                                       BUILD_DIR / "frontends" / "cli" / "rbsim"))
    if not path.exists():
        pytest.fail("the rbsim command is not built: %s" % path)
    return path


def run_cli(scene, tmp_path, *extra):
    out = tmp_path / "cli.csv"
    result = subprocess.run(
        [str(cli_path()), "run", str(scene), "--csv", str(out), "--quiet"] + list(extra),
        cwd=tmp_path, stdin=subprocess.DEVNULL, capture_output=True, text=True,
        timeout=120)
    assert result.returncode == 0, result.stderr
    with open(out, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        assert header == COLUMNS
        return [row for row in reader]


def python_rows(world, steps):
    rows = []

    def draw(frame):
        for i in range(len(frame.names)):
            rows.append((frame.number, frame.time, int(frame.slots[i]),
                         frame.names[i], frame.positions[i], frame.orientations[i],
                         frame.velocities[i], frame.angular_velocities[i]))

    world.run(steps, renderers=[draw])
    return rows


def compare(cli_rows, py_rows):
    assert len(cli_rows) == len(py_rows)
    for c, p in zip(cli_rows, py_rows):
        number, time, slot, name, pos, q, v, w = p
        assert int(c[0]) == number and float(c[1]) == time
        assert int(c[2]) == slot and c[3] == name
        got = [float(x) for x in c[4:]]
        want = list(pos) + list(q) + list(v) + list(w)
        assert got == want, "frame %d body %s" % (number, name)


def copy_scene(name, tmp_path):
    src = SOURCE_DIR / "scenes" / name
    if not src.exists():
        pytest.fail("missing scene %s" % src)
    dst = tmp_path / name
    shutil.copy(src, dst)
    (tmp_path / "out").mkdir(exist_ok=True)  # for the scene's own renderers
    return dst


def test_bounce_agrees_with_the_command(write_scene, tmp_path):
    scene = write_scene(bounce_scene(steps=1500, restitution=0.8))
    cli = run_cli(scene, tmp_path)
    assert len(cli) == 2 * 1501
    compare(cli, python_rows(rbsim.load(scene), None))


@pytest.mark.parametrize("name", ["bouncing_sphere.json", "collisions.json",
                                  "newtons_cradle.json", "rolling_sphere.json"])
def test_repository_scenes_agree(name, tmp_path):
    scene = copy_scene(name, tmp_path)
    steps = 800
    cli = run_cli(scene, tmp_path, "--steps", str(steps))
    world = rbsim.load(scene, steps=steps)
    compare(cli, python_rows(world, None))


def test_stepping_directly_agrees_with_the_command(write_scene, tmp_path):
    """world.step() and the views give the same bits as the command's run."""
    steps = 1200
    scene = write_scene(bounce_scene(steps=steps, restitution=0.9))
    cli = run_cli(scene, tmp_path)
    w = rbsim.load(scene)
    p, q, v, av = w.positions, w.orientations, w.velocities, w.angular_velocities
    by_frame = {}
    for row in cli:
        by_frame.setdefault(int(row[0]), []).append(row)
    for k in range(steps + 1):
        for row in by_frame[k]:
            s = int(row[2])
            want = [float(x) for x in row[4:]]
            assert want == list(p[s]) + list(q[s]) + list(v[s]) + list(av[s]), k
        if k < steps:
            w.step()


def test_cli_names_the_memory_it_could_not_reserve(tmp_path):
    """A world whose one allocation fails: the command says how much memory
    it asked for and for which capacities (it said only "out of memory or
    buffer too small"), exit 3.  The address space is capped at 1 GB in the
    child; max_contacts 2^26 asks for about 18 GB."""
    import resource
    scene = tmp_path / "big.json"
    scene.write_text(
        '{"simulation": {"steps": 2, "dt": 0.001, "max_contacts": 67108864},\n'
        ' "bodies": [{"name": "a", "type": "sphere", "radius": 0.1, "mass": 1,'
        ' "position": [0, 0, 1]}]}\n')

    def cap():
        resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))

    for command, stream in (("run", "stderr"), ("check", "stdout")):
        result = subprocess.run([str(cli_path()), command, str(scene)], cwd=tmp_path,
                                stdin=subprocess.DEVNULL, capture_output=True, text=True,
                                timeout=120, preexec_fn=cap)
        assert result.returncode == 3, (result.stdout, result.stderr)
        text = getattr(result, stream)
        assert "cannot build the world: out of memory or buffer too small: its memory, " in text
        assert " GB for max_bodies 1 and max_contacts 67108864 (simulation.max_contacts), " \
               "could not be reserved" in text, text
