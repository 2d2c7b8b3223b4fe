#!/usr/bin/env bash
# Fuzz rbsim with libFuzzer for a bounded time per harness.
#
#   tests/fuzz/run.sh [SECONDS_PER_HARNESS] [HARNESS...]
#
# Configures (once) a clang build with AddressSanitizer, UndefinedBehavior-
# Sanitizer and fuzzer coverage in $RBS_FUZZ_BUILD (default build-fuzz in
# the source tree), builds the harnesses fuzz_scene_json, fuzz_scene_text
# and fuzz_api, and runs each for SECONDS (default 60) starting from the seed
# corpus tests/fuzz/corpus/<harness>/ and tests/fuzz/regressions/<harness>/.
# New interesting inputs go to $RBS_FUZZ_BUILD/corpus/<harness>/ (the seed
# corpus is not modified).  A crash, sanitizer report, leak or time-out
# (an input taking longer than $RBS_FUZZ_TIMEOUT s, default 60) stops that
# harness, leaves the input as $RBS_FUZZ_BUILD/artifacts/<harness>-crash-*
# (or -timeout-*, -leak-*, -oom-*) and makes this script exit 1 after all
# harnesses ran.  Copy such a file into tests/fuzz/regressions/<harness>/ so
# `meson test --suite fuzz` replays it from then on.
#
# The seed is fixed (RBS_FUZZ_SEED, default 1); with RBS_FUZZ_RUNS=N each
# harness stops after N inputs (SECONDS still caps it), so a run is exactly
# repeatable: CI checks what was checked here, whatever the machine's speed.
# Unset RBS_FUZZ_RUNS and set another seed to explore.
# Needs clang and libFuzzer: on Debian 12, apt-get install clang libclang-rt-14-dev.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
secs=${1:-60}
shift || true
harnesses=${*:-scene_json scene_text api}
build=${RBS_FUZZ_BUILD:-$top/build-fuzz}
timeout=${RBS_FUZZ_TIMEOUT:-60}
cc=${RBS_FUZZ_CC:-clang}

if ! command -v "$cc" >/dev/null; then
  echo "fuzz: $cc not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
fi
if [ ! -f "$build/build.ninja" ]; then
  CC=$cc meson setup "$build" "$top" --buildtype=debugoptimized \
    -Db_sanitize=address,undefined -Db_lundef=false \
    -Dc_args=-fsanitize=fuzzer-no-link -Dsdl=disabled >"$build.setup.log" 2>&1 \
    || { echo "fuzz: meson setup failed, see $build.setup.log" >&2; exit 1; }
fi
targets=""
for h in $harnesses; do targets="$targets tests/fuzz/fuzz_$h"; done
# shellcheck disable=SC2086
ninja -C "$build" -j1 $targets >"$build/fuzz-build.log" 2>&1 \
  || { echo "fuzz: build failed, see $build/fuzz-build.log" >&2; tail -20 "$build/fuzz-build.log" >&2; exit 1; }

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
mkdir -p "$build/artifacts"
for h in $harnesses; do
  mkdir -p "$build/corpus/$h"
  echo "fuzz: $h for ${secs}s" >&2
  runs=""
  [ -n "${RBS_FUZZ_RUNS:-}" ] && runs="-runs=$RBS_FUZZ_RUNS"
  # shellcheck disable=SC2086
  "$build/tests/fuzz/fuzz_$h" -seed="${RBS_FUZZ_SEED:-1}" $runs -max_total_time="$secs" -timeout="$timeout" -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/artifacts/$h-" \
    "$build/corpus/$h" "$here/corpus/$h" "$here/regressions/$h" >"$build/fuzz-$h.log" 2>&1
  rc=$?
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$build/fuzz-$h.log" | sed "s/^/fuzz: $h: /" >&2
  if [ $rc -ne 0 ]; then
    echo "fuzz: $h FAILED (exit $rc); log $build/fuzz-$h.log; artifacts:" >&2
    ls "$build/artifacts/" | grep "^$h-" | sed 's/^/  /' >&2
    grep -E "ERROR|invariant|runtime error|SUMMARY" "$build/fuzz-$h.log" | head -5 >&2
    status=1
  fi
done
exit $status
