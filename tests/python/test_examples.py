"""The examples run and check themselves."""

import importlib.util
import os
import subprocess
import sys

from conftest import PACKAGE_DIR

EXAMPLES = PACKAGE_DIR / "examples"


def run(script, *args, cwd=None):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(PACKAGE_DIR) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run([sys.executable, str(EXAMPLES / script)] + list(args),
                          capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=120)


def test_bouncing_ball_matches_exact_apexes():
    r = run("bouncing_ball.py")
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    rows = [l.split() for l in lines if l.strip()[:1].isdigit()]
    assert [int(x[0]) for x in rows] == [1, 2, 3, 4]
    for n, exact, got, _ in rows:
        # Checked here against the formula, not the script's own column.
        want = 0.8 ** (2 * int(n))
        assert float(exact) == round(want, 6)
        assert abs(float(got) - want) < 8.9e-4  # 2*sqrt(2 g h)*dt, see the script
    assert "all apexes within" in r.stdout


def test_bouncing_ball_other_parameters():
    r = run("bouncing_ball.py", "--height", "2", "--restitution", "0.5",
            "--bounces", "3")
    assert r.returncode == 0, r.stdout + r.stderr
    rows = [l.split() for l in r.stdout.splitlines() if l.strip()[:1].isdigit()]
    # h e^(2n) = 0.5, 0.125, 0.03125; tolerance 2*sqrt(2*9.81*2)*1e-4 m.
    for (n, exact, got, _), want in zip(rows, [0.5, 0.125, 0.03125]):
        assert float(exact) == want
        assert abs(float(got) - want) < 2 * (2 * 9.81 * 2) ** 0.5 * 1e-4


def test_energy_plot(tmp_path):
    out = tmp_path / "energy.png"
    r = run("energy_plot.py", "--steps", "2000", "--out", str(out), cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    if importlib.util.find_spec("matplotlib") is None:
        assert "matplotlib is not installed" in r.stdout
        assert not out.exists()
    else:
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert "2001 frames" in r.stdout
