#!/usr/bin/env bash
# Runs the test suite on build/ (made by tools/setup.sh). With CI=true or --sanitize it also
# builds the unit tests with AddressSanitizer + UBSan in build-asan/ and runs them.
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize=0
if [ "${CI:-}" = "true" ] || [ "${1:-}" = "--sanitize" ]; then sanitize=1; fi

if [ $sanitize -eq 1 ]; then
  echo "[test] sanitizer build (ASan + UBSan) of the unit tests in build-asan/"
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHS_SANITIZE=ON -DHS_WERROR=ON >/dev/null
  targets=$(cmake --build build-asan --target help | awk '/\.\.\. test_/{print $2}' | grep -v -E 'accuracy|_cli')
  # shellcheck disable=SC2086
  cmake --build build-asan -j2 --target $targets
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan -L unit --output-on-failure -j2
fi

echo "[test] full suite in build/"
ctest --test-dir build --output-on-failure -j2
