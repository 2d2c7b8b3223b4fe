#!/bin/sh
# ABI check: the shared library exports rbs_ names only, and its ABI is
# compatible with the committed baseline (abidiff from abigail-tools).
# Added functions and members appended to public structs are fine
# (allowed.suppr); any other change (removed or changed function, a member
# inserted, removed or retyped, a changed enum value) fails.
# usage: check_abi.sh LIBRARY BASELINE HEADERS_DIR
set -eu
lib=$1; baseline=$2; headers=$3

bad=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TDBRVWi]$/ {print $3}' | sed 's/@.*//' \
      | grep -v '^rbs_' || true)
if [ -n "$bad" ]; then
  echo "exported names without the rbs_ prefix:"; echo "$bad"; exit 1
fi
echo "exports: $(nm -D --defined-only "$lib" | grep -c ' T rbs_') rbs_ functions, nothing else"

if ! command -v abidiff >/dev/null 2>&1; then
  echo "abidiff not installed (Debian package abigail-tools; .ci/setup installs it)"; exit 1
fi
set +e
abidiff --headers-dir2 "$headers" --no-added-syms \
  --suppressions "$(dirname "$0")/allowed.suppr" "$baseline" "$lib" > abidiff.out 2>&1
rc=$?
set -e
cat abidiff.out
# abidiff's exit status is a bit field: 1 error, 2 usage, 4 change, 8 incompatible;
# with the allowed changes suppressed, anything nonzero is a break.
if [ "$rc" -ne 0 ]; then
  echo "ABI check failed (abidiff status $rc): an incompatible change against $baseline."
  echo "If the break is intended, bump the major version and run tests/abi/update_baseline.sh."
  exit 1
fi
echo "ABI compatible with the baseline (abidiff status $rc)"
