#!/bin/sh
# The soft method's sub-step tolerance on the peers piles: time against
# quality (see tolerance.py).
#   bench/peers/tolerance.sh [tolerance.py options]
# Builds peers_rbsim and peers_quality with meson in ./build (or $BUILD_DIR)
# and runs tolerance.py with the repository's .venv Python (or $PYTHON; it
# needs numpy, for scenes.py).  Results: bench/results/soft_tolerance.md, .csv.
set -eu
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-"$top/build"}
python=${PYTHON:-"$top/.venv/bin/python"}
if [ ! -x "$python" ] || ! "$python" -c "import numpy" 2>/dev/null; then
  echo "tolerance.sh: no Python with numpy at $python: run 'bash .ci/setup' first" >&2
  exit 2
fi
if [ ! -f "$build/build.ninja" ]; then
  meson setup "$build" "$top" --buildtype=release
fi
ninja -C "$build" -j1 bench/peers/peers_rbsim bench/peers/peers_quality
exec "$python" "$top/bench/peers/tolerance.py" --build "$build" --results "$top/bench/results" "$@"
