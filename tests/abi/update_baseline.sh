#!/bin/sh
# Regenerate the committed ABI baseline from a build: tests/abi/update_baseline.sh BUILD_DIR
set -eu
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$top/build}
abidw --headers-dir "$top/lib/include/rbsim" --no-corpus-path \
  --out-file "$top/tests/abi/librbsim.abi" "$build/lib/librbsim.so"
echo "wrote tests/abi/librbsim.abi"
