#!/bin/sh
# Run the full work-precision benchmark of the stepping methods and write
# bench/results/methods.csv, .md and .png (docs/methods.md).
#   usage: bench/methods/run.sh [BUILD_DIR]     (default: build)
# The build dir is set up if missing; the library is built (one job) and
# the benchmark compiled against it.  The plot uses .venv/bin/python when it
# exists (with matplotlib: .venv/bin/python -m pip install matplotlib), else
# python3; without matplotlib only the CSV and the table are written.
set -eu
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
case $build in /*) ;; *) build=$(pwd)/$build ;; esac
[ -f "$build/build.ninja" ] || meson setup "$build" "$top" --buildtype=release
meson compile -C "$build" -j 1 lib/rbsim:shared_library
exe="$build/bench_methods"
cc -std=c99 -O2 -D_POSIX_C_SOURCE=200809L -I"$top/lib/include" -I"$build/lib/include" \
   "$top/bench/methods/bench_methods.c" -o "$exe" -L"$build/lib" -lrbsim -lm \
   -Wl,-rpath,"$build/lib"
mkdir -p "$top/bench/results"
"$exe" --check --csv "$top/bench/results/methods.csv"
py="$top/.venv/bin/python"
[ -x "$py" ] || py=python3
"$py" "$top/bench/methods/plot.py" "$top/bench/results/methods.csv" "$top/bench/results/methods"
echo "wrote bench/results/methods.csv, methods.md and (with matplotlib) methods.png"
