#!/bin/sh
# Peer benchmark: rbsim against ODE, Bullet and MuJoCo (see README.md).
#   bench/peers/run.sh [--quick] [run.py options]
# Builds with meson in ./build (or $BUILD_DIR), then runs bench/peers/run.py
# with the repository's .venv Python (or $PYTHON).  Results go to
# bench/results/ (peers.md, peers.csv, peers.png, scaling.png).
set -eu
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-"$top/build"}
python=${PYTHON:-"$top/.venv/bin/python"}

if ! grep -q "subdir('bench')" "$top/meson.build"; then
  echo "run.sh: the top-level meson.build does not build bench/ yet (it needs subdir('bench'))" >&2
  exit 2
fi
if [ ! -x "$python" ]; then
  echo "run.sh: no Python at $python: run 'bash .ci/setup', then" >&2
  echo "        $top/.venv/bin/python -m pip install pybullet mujoco matplotlib" >&2
  exit 2
fi
if ! "$python" -c "import numpy, matplotlib" 2>/dev/null; then
  echo "run.sh: $python lacks numpy or matplotlib: $python -m pip install pybullet mujoco matplotlib" >&2
  exit 2
fi
pkg-config --exists ode 2>/dev/null || \
  echo "run.sh: ODE is not installed (apt-get install -y libode-dev): it will be left out" >&2

if [ ! -f "$build/build.ninja" ]; then
  meson setup "$build" "$top" --buildtype=release
fi
ninja -C "$build" -j1 bench/peers/peers_rbsim bench/peers/peers_quality bench/peers/peers_stream \
  bench/peers/peers_spawn
if pkg-config --exists ode 2>/dev/null; then
  # meson decides whether ODE was found at configure time; reconfigure if it was installed later
  [ -f "$build/bench/peers/peers_ode" ] || ninja -C "$build" -j1 bench/peers/peers_ode 2>/dev/null || \
    { meson setup --reconfigure "$build" "$top" >/dev/null && ninja -C "$build" -j1 bench/peers/peers_ode; }
fi
exec "$python" "$top/bench/peers/run.py" --build "$build" --results "$top/bench/results" "$@"
